"""A scene's navmesh: terrain classes as area types, costs by class name, navmesh.json, the overlay."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from navverse import nav
from navverse.nav import NavMeshError, PathFinder
from navverse.nav.scene_navmesh import (
    build_scene_navmesh,
    describe_navmesh,
    navmesh_overlay,
    read_navmesh_info,
    scene_area_types,
    scene_settings,
    write_navmesh_info,
)
from navverse.scene.geometry import Scene
from navverse.scene.terrain import terrain_classes
from tests.navverse.scene.conftest import build_scene

TABLE = (7.0, 5.0)  # tests/navverse/scene/conftest.py: a 1.2 m x 0.8 m x 0.75 m table


@pytest.fixture(scope="module")
def scene() -> Scene:
    return build_scene()


@pytest.fixture(scope="module")
def finder(scene: Scene) -> PathFinder:
    return build_scene_navmesh(scene, nav.OUTDOOR, area_costs={"road": 2.0, "sidewalk": 5.0})


def test_navigable_classes_are_numbered_in_order(scene: Scene):
    # floor, wall, ceiling, road: the two navigable ones get 1 and 2, the others 0.
    assert scene_area_types(scene.annotations) == {"floor": 1, "wall": 0, "ceiling": 0, "road": 2}


def test_polygons_carry_their_terrain_class(finder: PathFinder):
    assert set(np.unique(finder.polygon_area_types())) == {1, 2}
    floor_point, road_point = [8.0, 4.0, 0.0], [5.0, -2.5, -0.1]
    areas = finder.polygon_area_types()
    polygons = finder.polygons()
    for point, area in ((floor_point, 1), (road_point, 2)):
        xy = np.asarray(point[:2])
        assert any(_contains(p[:, :2], xy) and a == area for p, a in zip(polygons, areas, strict=True))


def _contains(polygon: np.ndarray, point: np.ndarray) -> bool:
    """Whether a convex counter-clockwise polygon contains a point."""
    edges = np.roll(polygon, -1, axis=0) - polygon
    rel = point - polygon
    return bool(np.all(edges[:, 0] * rel[:, 1] - edges[:, 1] * rel[:, 0] >= -1e-9))


def test_tops_of_obstacles_and_ceilings_are_never_walkable(finder: PathFinder):
    # Room floor and road are two islands; the ceiling and the table top (both facing up) are not
    # navmesh although the ceiling is a large flat surface.
    assert finder.num_islands == 2
    assert not finder.is_navigable([5.0, 4.0, 2.5])
    assert not finder.is_navigable([*TABLE, 0.75])
    assert finder.is_navigable([8.5, 2.0, 0.0])


def test_costs_name_classes_and_absent_classes_are_ignored(finder: PathFinder):
    assert finder.area_costs == {2: 2.0}  # road; the scene has no sidewalk


def test_costs_for_a_non_navigable_class_are_refused(scene: Scene):
    with pytest.raises(NavMeshError, match="terrain class 'wall', which is not navigable"):
        build_scene_navmesh(scene, nav.OUTDOOR, area_costs={"wall": 2.0})
    with pytest.raises(NavMeshError, match="excluded_classes names terrain class 'ceiling'"):
        build_scene_navmesh(scene, nav.OUTDOOR, excluded_classes=["ceiling"])


def test_excluded_classes(scene: Scene):
    finder = build_scene_navmesh(scene, nav.OUTDOOR, excluded_classes=["road"])
    assert finder.excluded_areas == {2}
    assert finder.geodesic_distance([2.0, -2.5, -0.1], [9.0, -2.5, -0.1]) == math.inf
    assert math.isfinite(finder.geodesic_distance([2.0, 4.0, 0.0], [9.0, 4.0, 0.0]))


def test_a_scene_without_navigable_classes(scene: Scene):
    only_walls = scene.annotations.model_copy(
        update={"terrain_classes": terrain_classes(["floor", "wall", "ceiling", "road"])}
    )
    classes = {n: c.model_copy(update={"navigable": False}) for n, c in only_walls.terrain_classes.items()}
    blocked = Scene(only_walls.model_copy(update={"terrain_classes": classes}), scene.surfaces, scene.objects)
    with pytest.raises(NavMeshError, match="no walkable surface: none of its terrain classes"):
        build_scene_navmesh(blocked, nav.OUTDOOR)


def test_navmesh_json_round_trip(scene: Scene, finder: PathFinder, tmp_path: Path):
    info = describe_navmesh(finder, scene.annotations, preset="outdoor")
    assert info.area_costs == {"road": 2.0}
    assert info.islands == 2 and sum(info.island_areas_m2) == pytest.approx(info.navigable_area_m2)
    assert info.settings == nav.OUTDOOR
    path = tmp_path / "navmesh.json"
    write_navmesh_info(info, path)
    first = path.read_bytes()
    assert read_navmesh_info(path) == info
    write_navmesh_info(read_navmesh_info(path), path)
    assert path.read_bytes() == first  # stable bytes
    path.write_text("{not json")
    with pytest.raises(NavMeshError, match="not a valid navmesh description"):
        read_navmesh_info(path)
    with pytest.raises(NavMeshError, match="cannot read"):
        read_navmesh_info(tmp_path / "missing.json")


def test_overlay_fills_polygons_and_draws_the_outline(finder: PathFinder):
    overlay = navmesh_overlay(finder)
    assert len(overlay.polygons) == len(finder.polygons())
    assert overlay.segments.shape[1:] == (2, 2) and len(overlay.segments) >= 8  # two rectangles at least
    area = sum(_shoelace(p) for p in overlay.polygons)
    assert area == pytest.approx(finder.navigable_area, rel=0.01)


def _shoelace(polygon: np.ndarray) -> float:
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def test_indoor_to_outdoor_scenes_get_fine_cells_over_their_indoor_buildings(scene: Scene):
    # The tiny scene is i2o with one indoor building, footprint 0..10 x 0..8, bounds -2..12 x -4..8.
    settings = scene_settings(nav.I2O.with_overrides({"tile_size": 32}), scene.annotations)
    margin = 10.0  # the i2o profile's fine_margin_m
    assert settings.fine_region == (-2.0, -4.0, 10.0 + min(margin, 2.0), 8.0)  # grown, then clipped
    indoor = scene.annotations.model_copy(update={"scene_type": "indoor"})
    assert scene_settings(nav.I2O, indoor) is nav.I2O  # other types keep their settings
    assert scene_settings(nav.OUTDOOR, scene.annotations) is nav.OUTDOOR  # no fine factor, no region
    no_building = scene.annotations.model_copy(update={"buildings": []})
    assert scene_settings(nav.I2O, no_building) is nav.I2O
    finder = build_scene_navmesh(scene, settings)
    coarse = build_scene_navmesh(scene, nav.OUTDOOR.with_overrides({"tile_size": 32}))
    # 5 cm cells near the building: its floor keeps more of its area than at 10 cm.
    assert finder.navigable_area > coarse.navigable_area
    start, goal = [8.5, 7.1, 0.0], [1.5, 7.1, 0.0]  # clear of the chairs and the table
    assert finder.geodesic_distance(start, goal) == pytest.approx(7.0, abs=0.05)


def test_costs_and_exclusions_by_class_name_on_a_saved_scene_navmesh(scene: Scene, tmp_path: Path):
    from navverse.nav.scene_navmesh import load_scene_navmesh
    from navverse.scene.directory import SceneFiles

    built = build_scene_navmesh(scene, nav.OUTDOOR)
    files = SceneFiles(tmp_path)
    built.save(files.navmesh)
    write_navmesh_info(describe_navmesh(built, scene.annotations, preset="outdoor"), files.navmesh_info)
    loaded = load_scene_navmesh(tmp_path)
    areas = scene_area_types(scene.annotations)
    assert loaded.area_names == areas
    loaded.set_area_costs({"road": 5})  # by the name a recipe uses
    assert loaded.area_costs == {areas["road"]: 5.0}
    loaded.set_excluded_areas(["road"])
    assert loaded.excluded_areas == {areas["road"]}
    with pytest.raises(NavMeshError, match=r"names area 'lava'; this navmesh's areas: .*road"):
        loaded.set_area_costs({"lava": 2})
    with pytest.raises(NavMeshError, match="no named areas"):
        PathFinder.load(files.navmesh).set_area_costs({"road": 2})
    with pytest.raises(NavMeshError, match="is not a number"):
        loaded.set_area_costs({"road": "five"})
