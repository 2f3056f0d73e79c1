from __future__ import annotations

import itertools

import pytest

from navverse.errors import SceneError
from navverse.scene.terrain import DEFAULT_TERRAIN_CLASSES, terrain_classes


def test_defaults_are_read_only() -> None:
    with pytest.raises(TypeError):
        DEFAULT_TERRAIN_CLASSES["lava"] = DEFAULT_TERRAIN_CLASSES["floor"]  # type: ignore[index]


def test_default_roles() -> None:
    navigable = {name for name, tc in DEFAULT_TERRAIN_CLASSES.items() if tc.navigable}
    assert navigable == {
        "floor",
        "sidewalk",
        "road",
        "curb",
        "crosswalk",
        "green",
        "ground",
        "parking",
        "plaza",
    }
    preferred = {name for name, tc in DEFAULT_TERRAIN_CLASSES.items() if tc.preferred}
    assert preferred == {"floor", "sidewalk", "crosswalk", "plaza"}
    assert not DEFAULT_TERRAIN_CLASSES["ceiling"].show_in_bev
    assert DEFAULT_TERRAIN_CLASSES["water"].friction < DEFAULT_TERRAIN_CLASSES["green"].friction


def test_default_colors_are_distinguishable() -> None:
    for (a, ta), (b, tb) in itertools.combinations(DEFAULT_TERRAIN_CLASSES.items(), 2):
        distance = sum((x - y) ** 2 for x, y in zip(ta.color, tb.color, strict=True)) ** 0.5
        assert distance > 30, (a, b)


def test_pick_and_override() -> None:
    picked = terrain_classes(["road", "sidewalk", "road"], overrides={"road": 0.5})
    assert list(picked) == ["road", "sidewalk"]
    assert picked["road"].friction == 0.5
    assert picked["road"].color == DEFAULT_TERRAIN_CLASSES["road"].color
    assert DEFAULT_TERRAIN_CLASSES["road"].friction == 0.85


def test_unknown_class_lists_known_ones() -> None:
    with pytest.raises(SceneError, match=r"unknown terrain class 'lava'.*sidewalk"):
        terrain_classes(["floor", "lava"])


@pytest.mark.parametrize(("overrides", "message"), [({"road": -0.1}, ">= 0"), ({"water": 0.1}, "not among")])
def test_bad_overrides(overrides: dict[str, float], message: str) -> None:
    with pytest.raises(SceneError, match=message):
        terrain_classes(["road"], overrides=overrides)
