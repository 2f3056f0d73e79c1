from __future__ import annotations

import json
from pathlib import Path

import pytest
from pydantic import ValidationError

from navverse.errors import SceneError
from navverse.scene import (
    SCENE_FORMAT_VERSION,
    ObjectAnnotation,
    Scene,
    SceneAnnotations,
    load_annotations,
    save_annotations,
)


def _object(object_id: int, **changes: object) -> ObjectAnnotation:
    fields = {
        "id": object_id,
        "category": "chair",
        "prim_path": f"/World/Objects/chair_{object_id:04d}",
        "center": (1.0, 2.0, 0.4),
        "size": (0.5, 0.6, 0.9),
        "yaw": 0.5,
    }
    fields.update(changes)
    return ObjectAnnotation(**fields)


def test_goal_radius_is_half_the_larger_horizontal_extent() -> None:
    assert _object(1, size=(0.4, 1.6, 3.0)).goal_radius == pytest.approx(0.8)


def test_duplicate_object_ids_are_rejected(tiny_scene: Scene) -> None:
    data = tiny_scene.annotations.model_dump()
    data["objects"][1]["id"] = data["objects"][0]["id"]
    with pytest.raises(ValidationError, match="object ids must be unique"):
        SceneAnnotations.model_validate(data)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"category": "  "}, "non-empty"),
        ({"prim_path": "/World/chair_0001"}, "/World/Objects"),
        ({"size": (0.5, 0.0, 0.9)}, "greater than 0"),
        ({"id": 0}, "greater than or equal to 1"),
        ({"yaw": float("nan")}, "finite"),
    ],
)
def test_invalid_object_fields_are_rejected(changes: dict[str, object], message: str) -> None:
    with pytest.raises(ValidationError, match=message):
        _object(1, **changes)


def test_models_are_frozen_and_forbid_unknown_keys(tiny_scene: Scene) -> None:
    with pytest.raises(ValidationError):
        tiny_scene.annotations.scene_id = "other"  # type: ignore[misc]
    data = tiny_scene.annotations.model_dump()
    data["regions"]["entrances"] = []
    with pytest.raises(ValidationError, match="entrances"):
        SceneAnnotations.model_validate(data)


def test_rooms_and_doors(tiny_scene: Scene) -> None:
    data = tiny_scene.annotations.model_dump()
    square = [(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)]
    data["regions"]["rooms"] = [
        {"id": 1, "room_type": "kitchen", "polygon": square},
        {"id": 2, "room_type": "hallway", "polygon": [(4.0, 0.0), (6.0, 0.0), (6.0, 4.0)]},
    ]
    door = {"id": 1, "center": (4.0, 2.0, 0.0), "width": 1.6, "facing": 0.0, "rooms": (1, 2)}
    data["regions"]["doors"] = [door]
    regions = SceneAnnotations.model_validate(data).regions
    assert [r.room_type for r in regions.rooms] == ["kitchen", "hallway"]
    assert regions.doors[0].rooms == (1, 2)
    data["regions"]["doors"][0]["rooms"] = (1, 7)
    with pytest.raises(ValidationError, match=r"doors name rooms that do not exist: \[7\]"):
        SceneAnnotations.model_validate(data)
    data["regions"]["rooms"][1]["room_type"] = "Living Room"
    with pytest.raises(ValidationError):
        SceneAnnotations.model_validate(data)


def test_newer_minor_with_unknown_fields_asks_for_an_update(tiny_scene: Scene, tmp_path: Path) -> None:
    data = tiny_scene.annotations.model_dump(mode="json")
    major, minor = SCENE_FORMAT_VERSION.split(".")
    data["format_version"] = f"{major}.{int(minor) + 1}"
    data["lighting"] = {"sun": 1.0}
    with pytest.raises(SceneError, match=r"newer than this toolkit's .* update navverse"):
        load_annotations(_write_raw(tmp_path / "scene.json", data))


def test_terrain_class_key_must_match_its_name(tiny_scene: Scene) -> None:
    data = tiny_scene.annotations.model_dump()
    data["terrain_classes"]["pavement"] = data["terrain_classes"].pop("road")
    with pytest.raises(ValidationError, match="pavement"):
        SceneAnnotations.model_validate(data)


def test_save_load_round_trip_is_exact_and_deterministic(tiny_scene: Scene, tmp_path: Path) -> None:
    first, second = tmp_path / "a.json", tmp_path / "b.json"
    save_annotations(tiny_scene.annotations, first)
    loaded = load_annotations(first)
    save_annotations(loaded, second)
    assert loaded == tiny_scene.annotations
    assert first.read_bytes() == second.read_bytes()
    text = first.read_text()
    assert text.endswith("}\n")
    assert list(json.loads(text)) == list(SceneAnnotations.model_fields)
    assert '"yaw": -1.2' in text  # floats as repr, not rounded


def _write_raw(path: Path, data: object) -> Path:
    path.write_text(json.dumps(data))
    return path


def test_wrong_major_format_version_is_a_scene_error(tiny_scene: Scene, tmp_path: Path) -> None:
    data = tiny_scene.annotations.model_dump(mode="json")
    data["format_version"] = "2.0"
    data["new_field_of_v2"] = 1
    with pytest.raises(SceneError, match=r"version 2\.0.*reads version 1\.x.*navverse build tiny_room"):
        load_annotations(_write_raw(tmp_path / "scene.json", data))


def test_newer_minor_version_of_same_major_loads(tiny_scene: Scene, tmp_path: Path) -> None:
    data = tiny_scene.annotations.model_dump(mode="json")
    major = SCENE_FORMAT_VERSION.split(".")[0]
    data["format_version"] = f"{major}.7"
    assert load_annotations(_write_raw(tmp_path / "scene.json", data)).format_version == f"{major}.7"


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (None, "not found"),
        ("{not json", "not valid JSON"),
        ("[1, 2]", "JSON object"),
        ('{"scene_id": "x"}', "no valid format_version"),
    ],
)
def test_unreadable_annotations_are_scene_errors(content: str | None, message: str, tmp_path: Path) -> None:
    path = tmp_path / "scene.json"
    if content is not None:
        path.write_text(content)
    with pytest.raises(SceneError, match=message) as info:
        load_annotations(path)
    assert "navverse build" in str(info.value)


def test_invalid_content_is_a_scene_error_naming_the_field(tiny_scene: Scene, tmp_path: Path) -> None:
    data = tiny_scene.annotations.model_dump(mode="json")
    data["objects"][0]["size"] = [1.0, -1.0, 1.0]
    with pytest.raises(SceneError, match=r"objects\.0\.size\.1"):
        load_annotations(_write_raw(tmp_path / "scene.json", data))
