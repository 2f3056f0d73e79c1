from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from navverse.errors import SceneError
from navverse.scene.annotations import (
    SCENE_FORMAT_VERSION,
    ObjectAnnotation,
    SceneAnnotations,
    footprint_facades,
    load_annotations,
    nearest_facade,
    save_annotations,
)
from navverse.scene.geometry import Scene


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
    data["buildings"][0]["entrances"] = []
    with pytest.raises(ValidationError, match="entrances"):
        SceneAnnotations.model_validate(data)


def test_rooms_and_doors_belong_to_a_building(tiny_scene: Scene) -> None:
    data = tiny_scene.annotations.model_dump()
    square = [(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)]
    data["buildings"][0]["rooms"] = [
        {"id": 1, "room_type": "kitchen", "polygon": square},
        {"id": 2, "room_type": "hallway", "polygon": [(4.0, 0.0), (6.0, 0.0), (6.0, 4.0)]},
    ]
    door = {"id": 1, "center": (4.0, 2.0, 0.0), "width": 1.6, "facing": 0.0, "rooms": (1, 2)}
    data["buildings"][0]["doors"] = [door]
    annotations = SceneAnnotations.model_validate(data)
    assert [r.room_type for r in annotations.rooms] == ["kitchen", "hallway"]
    assert annotations.doors[0].rooms == (1, 2)
    assert annotations.building_of(room=2).id == 1 and annotations.building_of(exit=1).id == 1
    data["buildings"][0]["doors"][0]["rooms"] = (1, 7)
    with pytest.raises(ValidationError, match=r"building 1: doors name rooms it does not have: \[7\]"):
        SceneAnnotations.model_validate(data)
    data["buildings"][0]["doors"][0]["rooms"] = (1, 2)
    data["buildings"][0]["rooms"][1]["room_type"] = "Living Room"
    with pytest.raises(ValidationError):
        SceneAnnotations.model_validate(data)


def test_ids_are_unique_across_buildings_and_references_must_exist(tiny_scene: Scene) -> None:
    data = tiny_scene.annotations.model_dump()
    second = {**data["buildings"][0], "id": 2}  # same exit and facade ids again
    data["buildings"].append(second)
    with pytest.raises(ValidationError, match="exit ids must be unique in the scene"):
        SceneAnnotations.model_validate(data)
    data = tiny_scene.annotations.model_dump()
    data["storefronts"][0]["facade"] = 99
    with pytest.raises(ValidationError, match="facade 99, which is not a facade of its building 1"):
        SceneAnnotations.model_validate(data)
    data["storefronts"][0]["building"] = 5
    with pytest.raises(ValidationError, match="names building 5, which does not exist"):
        SceneAnnotations.model_validate(data)
    data = tiny_scene.annotations.model_dump()
    data["buildings"][0]["exits"][0]["facade"] = 42
    with pytest.raises(ValidationError, match=r"exits name facades it does not have: \[42\]"):
        SceneAnnotations.model_validate(data)


def test_the_indoor_region_is_the_footprints_of_indoor_buildings(tiny_scene: Scene) -> None:
    ann = tiny_scene.annotations
    assert ann.indoor_polygons == [ann.buildings[0].footprint]
    outdoor = ann.model_copy(update={"buildings": [ann.buildings[0].model_copy(update={"indoor": False})]})
    assert outdoor.indoor_polygons == []


def test_footprint_facades_point_outwards_in_either_orientation() -> None:
    square = [(0.0, 0.0), (4.0, 0.0), (4.0, 2.0), (0.0, 2.0)]
    for footprint in (square, square[::-1]):
        facades = footprint_facades(footprint, height=3.0, first_id=5)
        assert [f.id for f in facades] == [5, 6, 7, 8]
        for facade in facades:
            outward = np.mean(facade.segment, axis=0) - (2.0, 1.0)  # from the centre to the edge's middle
            assert np.dot(facade.normal, outward) > 0
    south = footprint_facades(square, height=3.0)[0]
    assert south.normal == pytest.approx((0.0, -1.0)) and south.width == pytest.approx(4.0)
    assert south.facing == pytest.approx(-math.pi / 2)
    assert nearest_facade(footprint_facades(square, height=3.0), (3.9, 1.0)).id == 2


def _format_1_1(annotations: SceneAnnotations) -> dict:
    """The annotations as a format 1.1 file had them: one ``regions`` object, no buildings."""
    data = annotations.model_dump(mode="json")
    buildings = data.pop("buildings")
    data["format_version"] = "1.1"
    data["regions"] = {
        "indoor": [b["footprint"] for b in buildings if b["indoor"]],
        "rooms": [r for b in buildings for r in b["rooms"]],
        "doors": [d for b in buildings for d in b["doors"]],
        "exits": [{k: v for k, v in e.items() if k != "facade"} for b in buildings for e in b["exits"]],
        "indoor_anchor": data.pop("indoor_anchor"),
    }
    for storefront in data["storefronts"]:
        del storefront["building"], storefront["facade"]
    return data


def test_format_1_files_are_upgraded(tiny_scene: Scene, tmp_path: Path) -> None:
    data = _format_1_1(tiny_scene.annotations)
    data["regions"]["rooms"] = [{"id": 3, "room_type": "hall", "polygon": [(1, 1), (9, 1), (9, 7), (1, 7)]}]
    loaded = load_annotations(_write_raw(tmp_path / "scene.json", data))
    assert loaded.format_version == SCENE_FORMAT_VERSION
    (building,) = loaded.buildings
    assert building.indoor and building.footprint == tiny_scene.annotations.buildings[0].footprint
    assert [r.id for r in building.rooms] == [3]
    assert building.base_height == 0.0 and building.height == pytest.approx(2.5)
    assert len(building.facades) == 4
    assert building.exits[0].facade == 1  # the south facade, which the exit opens in
    assert loaded.indoor_anchor == (5.0, 4.0, 0.0)
    assert loaded.indoor_polygons == tiny_scene.annotations.indoor_polygons
    data["regions"] = {}
    assert load_annotations(_write_raw(tmp_path / "empty.json", data)).buildings == []


def test_a_newer_minor_is_read_without_the_fields_it_added(tiny_scene: Scene, tmp_path: Path) -> None:
    data = tiny_scene.annotations.model_dump(mode="json")
    major, minor = SCENE_FORMAT_VERSION.split(".")
    data["format_version"] = f"{major}.{int(minor) + 1}"
    data["lighting"] = {"sun": 1.0}
    data["buildings"][0]["roof"] = "gabled"
    data["terrain_classes"]["road"]["albedo"] = 0.3
    loaded = load_annotations(_write_raw(tmp_path / "scene.json", data))
    assert loaded.buildings == tiny_scene.annotations.buildings
    assert loaded.terrain_classes == tiny_scene.annotations.terrain_classes
    data["buildings"][0]["height"] = -1.0  # a known field that is wrong is still an error
    with pytest.raises(SceneError, match="height"):
        load_annotations(_write_raw(tmp_path / "bad.json", data))


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
    data["format_version"] = "3.0"
    data["new_field_of_v3"] = 1
    with pytest.raises(
        SceneError, match=r"version 3\.0.*reads versions 1\.x and 2\.x.*navverse build --verify tiny_room"
    ):
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
