"""Geodesic distances on known geometry, connectivity, climb and slope limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navverse import nav
from navverse.nav import PathFinder
from tests.navverse.nav import scenes
from tests.navverse.nav.conftest import build_scene

CELL = nav.INDOOR.cell_size
# Obstacle faces at round coordinates fall in the middle of a voxel column, which is solid as a
# whole: the walkable area keeps agent_radius + half a cell away from them.
CLEARANCE = nav.INDOOR.agent_radius + CELL / 2


def assert_close_to_analytic(measured: float, analytic: float) -> None:
    assert abs(measured - analytic) <= 0.02 * analytic + CELL, (measured, analytic)


def test_straight_corridor(corridor_nav: PathFinder):
    path = corridor_nav.find_path([2.0, 0.0, 0.0], [18.0, 0.0, 0.0])
    assert path.found
    assert_close_to_analytic(path.geodesic_distance, 16.0)
    assert path.points.shape == (2, 3)  # nothing to go around
    np.testing.assert_allclose(path.points[[0, -1], :2], [[2, 0], [18, 0]], atol=1e-5)
    assert np.all(np.abs(path.points[:, 2]) < 0.15)  # on the floor, z up
    diagonal = corridor_nav.geodesic_distance([2.0, -0.4, 0.0], [18.0, 0.4, 0.0])
    assert_close_to_analytic(diagonal, math.hypot(16.0, 0.8))


def test_corridor_width_is_eroded_by_the_agent_radius(corridor_nav: PathFinder):
    lo, hi = corridor_nav.bounds
    assert hi[1] == pytest.approx(1.2 - CLEARANCE, abs=CELL)
    assert lo[1] == pytest.approx(-1.2 + CLEARANCE, abs=CELL)
    assert corridor_nav.num_islands == 1


def test_l_corridor_hugs_the_inner_corner(l_nav: PathFinder):
    start, end = (2.0, 1.5), (10.5, 10.0)
    path = l_nav.find_path([*start, 0.0], [*end, 0.0])
    analytic = scenes.taut_path_length(start, end, [scenes.disc(scenes.L_CORNER, CLEARANCE)])
    assert_close_to_analytic(path.geodesic_distance, analytic)
    # The path turns around the corner, keeping clear of it by about the agent radius.
    gaps = np.linalg.norm(path.points[:, :2] - np.array(scenes.L_CORNER), axis=1)
    assert gaps.min() == pytest.approx(CLEARANCE, abs=2 * CELL)
    assert len(path.points) >= 3


def test_room_with_a_box_goes_around_it(box_nav: PathFinder):
    x0, y0, x1, y1 = scenes.BOX_OBSTACLE
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    start, end = (2.0, 4.0), (12.0, 4.0)
    path = box_nav.find_path([*start, 0.0], [*end, 0.0])
    analytic = scenes.taut_path_length(start, end, [scenes.disc(c, CLEARANCE) for c in corners])
    assert_close_to_analytic(path.geodesic_distance, analytic)
    assert path.geodesic_distance > 10.0 + 0.5  # not through the box
    side = np.sign(path.points[1:-1, 1] - 4.0)
    assert np.all(side == side[0])  # one side of the box only
    # The box is solid: no navmesh inside it, one island in the room.
    assert box_nav.num_islands == 1
    assert not box_nav.is_navigable([7.0, 4.0, 0.0])


def test_closed_solids_are_hollow_without_interior_filling():
    hollow = build_scene(scenes.box_room(), fill_solid_interiors=False)
    # Plain Recast sees only surfaces: the floor inside the 1 m tall box becomes an island.
    assert hollow.num_islands == 2
    assert hollow.is_navigable([7.0, 4.0, 0.0])


def test_disconnected_rooms(rooms_nav: PathFinder):
    path = rooms_nav.find_path([2.5, 2.5, 0.0], [10.0, 2.5, 0.0])
    assert path.geodesic_distance == math.inf
    assert path.points.shape == (0, 3)
    assert not path.found
    assert rooms_nav.num_islands == 2
    a, b = rooms_nav.island_of([2.5, 2.5, 0.0]), rooms_nav.island_of([10.0, 2.5, 0.0])
    assert {a, b} == {0, 1}
    # Islands are numbered by decreasing area: the 6 m room is island 0.
    assert b == rooms_nav.largest_island == 0
    side = 2 * CLEARANCE
    assert rooms_nav.island_area(0) == pytest.approx((6 - side) * (5 - side), rel=0.03)
    assert rooms_nav.island_area(1) == pytest.approx((5 - side) * (5 - side), rel=0.03)
    assert rooms_nav.island_areas.sum() == pytest.approx(rooms_nav.navigable_area)
    # Within a room, paths still work.
    assert rooms_nav.geodesic_distance([1.0, 1.0, 0.0], [4.0, 4.0, 0.0]) == pytest.approx(
        math.hypot(3, 3), rel=0.02
    )


@pytest.mark.parametrize(("climb", "walkable"), [(0.30, True), (0.20, False)])
def test_step_height_against_max_climb(climb: float, walkable: bool):
    finder = build_scene(scenes.step(0.25), agent_max_climb=climb)
    distance = finder.geodesic_distance([2.0, 2.0, 0.0], [8.0, 2.0, 0.25])
    if walkable:
        assert 6.0 <= distance <= 6.0 + 0.25 + 2 * CELL  # across, plus the rise
        assert finder.num_islands == 1
    else:
        assert distance == math.inf
        assert finder.num_islands == 2
    # Both levels are navigable on their own.
    assert finder.is_navigable([2.0, 2.0, 0.0]) and finder.is_navigable([8.0, 2.0, 0.25])


def test_outdoor_climb_of_0_30_m_is_three_cells():
    # 0.30 / 0.10 is 2.999... in floating point; the climb must still be 3 cells.
    finder = build_scene(scenes.step(0.3), nav.OUTDOOR)
    assert math.isfinite(finder.geodesic_distance([2.0, 2.0, 0.0], [8.0, 2.0, 0.3]))


@pytest.mark.parametrize(("angle", "walkable"), [(20.0, True), (50.0, False)])
def test_ramp_slope_against_max_slope(angle: float, walkable: bool):
    builder, top = scenes.ramp(angle)
    finder = build_scene(builder)
    start, end = [1.0, 2.0, 0.0], [top + 2.0, 2.0, scenes.RAMP_RISE]
    distance = finder.geodesic_distance(start, end)
    if walkable:
        # 2 m of floor, the slanted ramp, 2 m of platform: the length follows the surface.
        analytic = 4.0 + scenes.RAMP_RISE / math.sin(math.radians(angle))
        assert_close_to_analytic(distance, analytic)
    else:
        assert distance == math.inf
        assert finder.island_of(start) != finder.island_of(end)
    assert finder.is_navigable(end)  # the platform itself is flat


def test_detail_mesh_without_height_samples(corridor_nav: PathFinder):
    # detail_sample_dist below 0.9 cells turns height sampling off; Recast's own switch for that
    # (a sample distance of 0) never returns in this Recast version, so the build must avoid it.
    flat = build_scene(scenes.corridor(), detail_sample_dist=0.0)
    assert flat.navigable_area == pytest.approx(corridor_nav.navigable_area, rel=0.01)
    assert flat.geodesic_distance([2.0, 0.0, 0.0], [18.0, 0.0, 0.0]) == pytest.approx(16.0, abs=CELL)
