"""Generated buildings: connected for the robot, richly furnished, physically plausible, deterministic."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from shapely.geometry import Polygon

from navverse import nav
from navverse.assets.library import asset
from navverse.errors import SceneError
from navverse.indoor import BUILDING_TYPES, BuildingOptions, ExtraFurniture, generate_building
from navverse.indoor.occupancy import footprint_corners
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.scene.annotations import save_annotations
from navverse.scene.categories import CategoryRule
from navverse.scene.geometry import Scene


@pytest.fixture(scope="module", params=BUILDING_TYPES)
def building(request: pytest.FixtureRequest) -> Scene:
    return generate_building(request.param, np.random.default_rng(0), scene_id=f"{request.param}-0")


def _footprint(obj) -> Polygon:
    return Polygon(footprint_corners(obj.center, obj.size, obj.yaw))


def _bottom(obj) -> float:
    return obj.center[2] - obj.size[2] / 2


def test_connected_for_the_robot_with_reachable_exits(building: Scene):
    finder = build_scene_navmesh(building, nav.INDOOR)
    # Nearly all of the robot's navigable floor is one island...
    assert finder.island_areas[0] >= 0.95 * finder.navigable_area
    # ...which holds every exit, every doorway and a point of every room.
    ann = building.annotations
    for point in [e.center for e in ann.exits] + [d.center for d in ann.doors]:
        assert finder.island_of([point[0], point[1], 0.0]) == finder.largest_island
    for room in ann.rooms:
        xs, ys = zip(*room.polygon, strict=True)
        center = [(min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2, 0.0]
        assert finder.island_of(center, max_horizontal=3.0) == finder.largest_island, room.room_type


def test_richly_furnished(building: Scene):
    ann = building.annotations
    assert len(ann.objects) >= 20
    assert len(ann.statistics.objects_per_category) >= 10
    assert sum(ann.statistics.objects_per_category.values()) == len(ann.objects)


def test_no_interpenetration_and_objects_stand_on_something(building: Scene):
    ann = building.annotations
    floor = [o for o in ann.objects if abs(_bottom(o)) < 1e-6]
    lifted = [o for o in ann.objects if abs(_bottom(o)) >= 1e-6]
    assert len(floor) >= 15
    for a, b in itertools.combinations(floor, 2):
        assert _footprint(a).intersection(_footprint(b)).area <= 1e-4, (a.prim_path, b.prim_path)  # 1 cm²
    rooms = [Polygon(r.polygon) for r in ann.rooms]
    for obj in ann.objects:  # inside a room, clear of the walls (the room polygons run along wall centres)
        assert any(room.buffer(-0.079).contains(_footprint(obj)) for room in rooms), obj.prim_path
    for obj in lifted:
        placement = asset(obj.category).placement
        if placement == "wall_mounted":
            continue
        assert placement == "surface", obj.prim_path
        # It stands on the top of a support area of a floor piece it lies within.
        carriers = [
            c for c in floor
            if _footprint(c).buffer(1e-6).contains(_footprint(obj))
            and any(abs(c.center[2] - c.size[2] / 2 + a.height - _bottom(obj)) < 1e-6
                    for a in asset(c.category).support_areas(c.size))
        ]  # fmt: skip
        assert carriers, obj.prim_path


def test_room_types_match_the_program(building: Scene):
    from navverse.indoor import PROGRAMS

    program = PROGRAMS[building.scene_id.rsplit("-", 1)[0]]
    rooms = building.annotations.rooms
    assert rooms[0].room_type == program.spine.room_type
    assert {r.room_type for r in rooms[1:]} <= {spec.room_type for spec in program.rooms}
    assert len(building.annotations.doors) == len(rooms) - 1


def test_same_seed_same_bytes_other_seed_other_layout(tmp_path):
    paths = []
    for name, seed in (("a", 3), ("b", 3), ("c", 4)):
        scene = generate_building("apartment", np.random.default_rng(seed), scene_id="flat")
        path = tmp_path / f"{name}.json"
        save_annotations(scene.annotations, path)
        paths.append(path.read_bytes())
    assert paths[0] == paths[1]
    assert paths[0] != paths[2]


def test_options_exclude_add_and_rename():
    rules = [
        CategoryRule(pattern=r"^(office_)?chair_", category="seat"),
        CategoryRule(pattern=r"^trash_can_"),
    ]
    options = BuildingOptions(
        exclude_categories=["potted_plant"],
        extra_furniture=[ExtraFurniture(room_type="corridor", category="fire_extinguisher", count=2)],
        category_rules=rules,
    )
    scene = generate_building("office", np.random.default_rng(1), scene_id="office-1", options=options)
    counts = scene.annotations.statistics.objects_per_category
    assert "potted_plant" not in counts
    assert counts.get("fire_extinguisher", 0) >= 1
    assert counts.get("seat", 0) >= 4 and "chair" not in counts and "office_chair" not in counts
    assert "trash_can" not in counts  # dropped from the annotations...
    assert any(s.name == "unannotated" for s in scene.surfaces)  # ...but still there as geometry
    seat_paths = [o.prim_path for o in scene.annotations.objects if o.category == "seat"]
    assert all("chair_" in p for p in seat_paths)  # prim names keep the asset name


def test_unknown_building_type():
    with pytest.raises(SceneError, match="unknown building type 'castle'; choose from: apartment"):
        generate_building("castle", np.random.default_rng(0), scene_id="x")
