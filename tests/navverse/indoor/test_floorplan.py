"""Floorplans partition the footprint, connect every room to the spine, and open to the outside."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import Point, box
from shapely.ops import unary_union

from navverse.indoor.floorplan import WALL_THICKNESS, generate_floorplan
from navverse.indoor.programs import BUILDING_TYPES, PROGRAMS
from navverse.indoor.structure import DOOR_HEIGHT, build_structure

CASES = [(t, seed) for t in BUILDING_TYPES for seed in (0, 1, 2)]


@pytest.mark.parametrize(("building_type", "seed"), CASES)
def test_rooms_tile_the_footprint(building_type: str, seed: int):
    plan = generate_floorplan(PROGRAMS[building_type], np.random.default_rng(seed))
    rects = [box(r.rect.x0, r.rect.y0, r.rect.x1, r.rect.y1) for r in plan.rooms]
    fp = plan.footprint
    assert unary_union(rects).symmetric_difference(box(fp.x0, fp.y0, fp.x1, fp.y1)).area < 1e-6
    assert sum(r.area for r in rects) == pytest.approx(fp.area)  # no overlaps
    program = PROGRAMS[building_type]
    assert plan.spine.room_type == program.spine.room_type
    for room in plan.rooms[1:]:
        spec = next(s for s in program.rooms if s.room_type == room.room_type)
        assert min(room.rect.width, room.rect.depth) >= min(spec.min_width, room.rect.depth) - 1e-9


@pytest.mark.parametrize(("building_type", "seed"), CASES)
def test_every_side_room_has_a_doorway_onto_the_spine(building_type: str, seed: int):
    plan = generate_floorplan(PROGRAMS[building_type], np.random.default_rng(seed))
    spine = box(plan.spine.rect.x0, plan.spine.rect.y0, plan.spine.rect.x1, plan.spine.rect.y1)
    lo, hi = PROGRAMS[building_type].door_width
    assert {d.rooms[1] for d in plan.doors} == {r.id for r in plan.rooms[1:]}
    for door in plan.doors:
        assert door.rooms[0] == plan.spine.id
        room = plan.room(door.rooms[1])
        shared = spine.intersection(box(room.rect.x0, room.rect.y0, room.rect.x1, room.rect.y1))
        assert shared.distance(Point(door.center)) < 1e-9  # on the shared wall
        assert lo - 0.05 <= door.width <= hi + 0.05 and door.width >= 1.5  # a 1.2 m robot passes
        # Clear of the room's corners, and facing from the spine into the room.
        along = door.center[0] if door.axis == "x" else door.center[1]
        ends = (room.rect.x0, room.rect.x1) if door.axis == "x" else (room.rect.y0, room.rect.y1)
        assert ends[0] + door.width / 2 + 0.3 <= along <= ends[1] - door.width / 2 - 0.3
        step = 0.5 * np.array([math.cos(door.facing), math.sin(door.facing)])
        inside = Point(np.asarray(door.center) + step)
        assert box(room.rect.x0, room.rect.y0, room.rect.x1, room.rect.y1).contains(inside)


@pytest.mark.parametrize("building_type", BUILDING_TYPES)
def test_exits_are_in_the_exterior_wall_and_face_out(building_type: str):
    plan = generate_floorplan(PROGRAMS[building_type], np.random.default_rng(0))
    fp = box(plan.footprint.x0, plan.footprint.y0, plan.footprint.x1, plan.footprint.y1)
    assert len(plan.exits) == PROGRAMS[building_type].exits
    for ex in plan.exits:
        assert fp.exterior.distance(Point(ex.center)) < 1e-9
        outward = np.asarray(ex.center) + 0.5 * np.array([math.cos(ex.facing), math.sin(ex.facing)])
        assert not fp.contains(Point(outward))
        assert ex.width >= 1.8


def test_same_seed_same_plan_other_seed_other_plan():
    program = PROGRAMS["office"]
    a, b = (generate_floorplan(program, np.random.default_rng(7)) for _ in range(2))
    assert a == b
    assert generate_floorplan(program, np.random.default_rng(8)) != a


def test_entrance_rooms_sit_by_the_entrance():
    for seed in range(5):
        plan = generate_floorplan(PROGRAMS["office"], np.random.default_rng(seed))
        reception = next(r for r in plan.rooms if r.room_type == "reception")
        assert reception.rect.x0 == 0.0  # at the west end, where the first exit is
        assert plan.exits[0].center[0] == 0.0


def _solid_at(surface, point) -> bool:
    """Whether a point is inside one of a merged-box surface's boxes (12 triangles each)."""
    v = surface.mesh.vertices.reshape(-1, 8, 3)
    lo, hi = v.min(axis=1), v.max(axis=1)
    return bool(((lo <= point) & (point <= hi)).all(axis=1).any())


@pytest.mark.parametrize("building_type", BUILDING_TYPES)
def test_walls_open_at_doorways_with_lintels_above(building_type: str):
    plan = generate_floorplan(PROGRAMS[building_type], np.random.default_rng(3))
    surfaces = {s.name: s for s in build_structure(plan)}
    walls = surfaces["walls"]
    for door in (*plan.doors, *plan.exits):
        x, y = door.center
        assert not _solid_at(walls, np.array([x, y, 1.0]))  # passable at robot height
        assert _solid_at(walls, np.array([x, y, (DOOR_HEIGHT + plan.ceiling_height) / 2]))  # lintel
        offset = door.width / 2 + 0.1
        side = np.array([offset, 0.0, 1.0]) if door.axis == "x" else np.array([0.0, offset, 1.0])
        assert _solid_at(walls, np.array([x, y, 0.0]) + side)  # wall right beside the opening
    # Corners of the footprint are solid, the room centres free.
    fp = plan.footprint
    assert _solid_at(walls, np.array([fp.x0, fp.y0, 1.0]))
    for room in plan.rooms:
        c = ((room.rect.x0 + room.rect.x1) / 2, (room.rect.y0 + room.rect.y1) / 2, 1.0)
        assert not _solid_at(walls, np.array(c))
    assert {"floor", "walls", "ceiling", "apron"} == set(surfaces)
    floor_top = surfaces["floor"].mesh.vertices[:, 2].max()
    assert floor_top == pytest.approx(0.0, abs=1e-9)
    assert surfaces["ceiling"].mesh.vertices[:, 2].min() == pytest.approx(plan.ceiling_height)
    assert WALL_THICKNESS > 0.1
