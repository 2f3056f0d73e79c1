"""Point queries, random points, multi-goal paths, top-down views; off-mesh queries never crash."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navverse import nav
from navverse.nav import NavMeshError, PathFinder
from tests.navverse.nav import scenes
from tests.navverse.nav.conftest import build_scene

CLEARANCE = nav.INDOOR.agent_radius + nav.INDOOR.cell_size / 2
FAR = [100.0, 100.0, 0.0]


def test_snap_point(corridor_nav: PathFinder):
    snapped = corridor_nav.snap_point([5.0, 0.0, 0.4])
    assert snapped[:2] == pytest.approx([5.0, 0.0], abs=1e-5)
    assert 0.0 <= snapped[2] <= 0.1  # the navmesh floats at most a couple of voxels above the floor
    beside = corridor_nav.snap_point([5.0, 1.1, 0.0])  # in the eroded margin near the wall
    assert beside[1] == pytest.approx(1.2 - CLEARANCE, abs=0.01)
    batch = corridor_nav.snap_point([[5.0, 0.0, 0.4], FAR])
    assert batch.shape == (2, 3)
    assert np.isnan(batch[1]).all() and np.isfinite(batch[0]).all()
    assert np.isnan(corridor_nav.snap_point([5.0, 0.0, 5.0], max_vertical=1.0)).all()


def test_is_navigable(corridor_nav: PathFinder):
    assert corridor_nav.is_navigable([5.0, 0.0, 0.0])
    assert not corridor_nav.is_navigable([5.0, 1.0, 0.0])  # within agent_radius of the wall
    assert not corridor_nav.is_navigable([5.0, 0.0, 1.0])  # too high above the floor
    assert corridor_nav.is_navigable([5.0, 0.0, 1.0], max_y_delta=1.5)
    out = corridor_nav.is_navigable([[5.0, 0.0, 0.0], FAR, [np.nan, 0.0, 0.0]])
    assert out.tolist() == [True, False, False]


def test_distance_to_closest_obstacle(corridor_nav: PathFinder):
    # Walkable half-width 1.2 - clearance; distances are to the navmesh border.
    assert corridor_nav.distance_to_closest_obstacle([5.0, 0.0, 0.0]) == pytest.approx(
        1.2 - CLEARANCE, abs=0.01
    )
    assert corridor_nav.distance_to_closest_obstacle([5.0, 0.3, 0.0]) == pytest.approx(
        1.2 - CLEARANCE - 0.3, abs=0.01
    )
    assert corridor_nav.distance_to_closest_obstacle([5.0, 0.0, 0.0], max_search_radius=0.2) == pytest.approx(
        0.2
    )
    assert math.isnan(corridor_nav.distance_to_closest_obstacle(FAR))


def test_find_path_multi(l_nav: PathFinder):
    start = [2.0, 1.5, 0.0]
    ends = [[10.5, 10.0, 0.0], [6.0, 1.5, 0.0], FAR, [10.5, 5.0, 0.0]]
    multi = l_nav.find_path_multi(start, ends)
    assert multi.closest_end_index == 1
    single = l_nav.find_path(start, ends[1])
    assert multi.geodesic_distance == pytest.approx(single.geodesic_distance)
    np.testing.assert_allclose(multi.points, single.points)
    assert l_nav.geodesic_distance(start, ends) == pytest.approx(4.0, abs=0.01)
    # Of the two ends up leg B, the nearer one (index 1 here) wins.
    assert l_nav.find_path_multi(start, [ends[0], ends[3]]).closest_end_index == 1
    none = l_nav.find_path_multi(start, [FAR])
    assert none.closest_end_index == -1 and none.geodesic_distance == math.inf and len(none.points) == 0


def test_geodesic_prefers_path_over_straight_line(rooms_nav: PathFinder):
    # The other room is closer in a straight line but unreachable: the far corner of this room wins.
    start = [4.0, 2.5, 0.0]
    ends = [[8.0, 2.5, 0.0], [1.0, 1.0, 0.0]]
    multi = rooms_nav.find_path_multi(start, ends)
    assert multi.closest_end_index == 1


def test_off_mesh_and_invalid_queries_do_not_crash(box_nav: PathFinder):
    on = [2.0, 4.0, 0.0]
    for bad in (FAR, [np.nan, 0.0, 0.0], [np.inf, 1.0, 0.0], [1e30, 1e30, 1e30]):
        assert box_nav.find_path(on, bad).geodesic_distance == math.inf
        assert box_nav.find_path(bad, on).points.shape == (0, 3)
        assert box_nav.geodesic_distance(bad, bad) == math.inf
        assert np.isnan(box_nav.snap_point(bad)).all()
        assert box_nav.island_of(bad) == -1
        assert not box_nav.is_navigable(bad)
        assert math.isnan(box_nav.distance_to_closest_obstacle(bad))
        assert np.isnan(box_nav.get_random_navigable_point_near(bad, 1.0, 0)).all()
    with pytest.raises(NavMeshError, match="shape"):
        box_nav.find_path([1.0, 2.0], on)
    with pytest.raises(NavMeshError, match="shape"):
        box_nav.snap_point(np.zeros((2, 2)))
    with pytest.raises(NavMeshError):
        box_nav.snap_point("here")


def test_random_points_are_on_the_navmesh_and_deterministic(box_nav: PathFinder):
    rng = np.random.default_rng(7)
    points = np.array([box_nav.get_random_navigable_point(rng) for _ in range(200)])
    assert box_nav.is_navigable(points).all()
    again = np.random.default_rng(7)
    np.testing.assert_array_equal(points, [box_nav.get_random_navigable_point(again) for _ in range(200)])
    np.testing.assert_array_equal(
        box_nav.get_random_navigable_point(3), box_nav.get_random_navigable_point(3)
    )
    assert not np.array_equal(box_nav.get_random_navigable_point(3), box_nav.get_random_navigable_point(4))
    with pytest.raises(TypeError):
        box_nav.get_random_navigable_point(np.random.RandomState(0))


@pytest.mark.parametrize("preset", [nav.INDOOR, nav.OUTDOOR], ids=["indoor", "outdoor"])
def test_flat_floor_navmesh_is_flat(preset: nav.NavMeshSettings):
    # Height samples of the detail mesh and polygon corners agree: on a flat floor every point of
    # the navmesh has one height, and the surface area is the polygons' planar area.
    finder = build_scene(scenes.box_room(), preset)
    corners = np.vstack(finder.polygons())
    assert np.ptp(corners[:, 2]) < 1e-5
    rng = np.random.default_rng(2)
    heights = np.array([finder.get_random_navigable_point(rng)[2] for _ in range(500)])
    np.testing.assert_allclose(heights, corners[0, 2], atol=1e-5)
    assert corners[0, 2] == pytest.approx(0.0, abs=1e-5)  # on the floor (z = 0)
    planar = sum(
        0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))
        for p in finder.polygons()
    )
    assert finder.navigable_area == pytest.approx(planar, rel=1e-4)


def test_random_points_are_uniform_by_area(rooms_nav: PathFinder):
    rng = np.random.default_rng(11)
    islands = rooms_nav.island_of(np.array([rooms_nav.get_random_navigable_point(rng) for _ in range(2000)]))
    share = np.mean(islands == 0)
    assert share == pytest.approx(rooms_nav.island_area(0) / rooms_nav.navigable_area, abs=0.04)
    restricted = [rooms_nav.get_random_navigable_point(rng, island=1) for _ in range(50)]
    assert (rooms_nav.island_of(np.array(restricted)) == 1).all()
    with pytest.raises(NavMeshError, match="island 5"):
        rooms_nav.get_random_navigable_point(rng, island=5)


def test_random_point_near(rooms_nav: PathFinder):
    rng = np.random.default_rng(5)
    center = np.array([4.0, 2.5, 0.0])
    snapped = rooms_nav.snap_point(center)
    points = np.array([rooms_nav.get_random_navigable_point_near(center, 1.0, rng) for _ in range(100)])
    assert np.isfinite(points).all()
    assert (np.linalg.norm(points - snapped, axis=1) <= 1.0 + 1e-6).all()
    # Only the center's room, even though the other room is within 4 m.
    far = np.array([rooms_nav.get_random_navigable_point_near(center, 4.0, rng) for _ in range(100)])
    assert (rooms_nav.island_of(far) == rooms_nav.island_of(center)).all()
    assert np.array_equal(
        rooms_nav.get_random_navigable_point_near(center, 1.0, 9),
        rooms_nav.get_random_navigable_point_near(center, 1.0, 9),
    )


def test_topdown_view(l_nav: PathFinder):
    view = l_nav.get_topdown_view(0.05)
    assert view.image.dtype == bool
    assert view.image.sum() * 0.05**2 == pytest.approx(l_nav.navigable_area, rel=0.03)
    # Row 0 is the largest y: leg B (x ~ 10.5, y up to ~11) is at the top, leg A at the bottom.
    row, col = view.world_to_pixel([10.5, 11.0])
    assert view.image[row, col] and row < view.image.shape[0] // 4
    row, col = view.world_to_pixel([2.0, 1.5])
    assert view.image[row, col] and row > 3 * view.image.shape[0] // 4
    row, col = view.world_to_pixel([4.0, 8.0])  # inside the solid block
    assert not view.image[row, col]
    np.testing.assert_allclose(view.origin, [l_nav.bounds[0, 0], l_nav.bounds[1, 1]])


def test_topdown_view_by_height():
    builder, top = scenes.ramp(20.0)
    finder = build_scene(builder)
    low = finder.get_topdown_view(0.1, height=0.0, eps=0.2)
    high = finder.get_topdown_view(0.1, height=scenes.RAMP_RISE, eps=0.2)
    every = finder.get_topdown_view(0.1)
    assert low.image.sum() > 0 and high.image.sum() > 0
    assert not (low.image & high.image).any()
    assert (every.image | ~(low.image | high.image)).all()
    row, col = high.world_to_pixel([top + 1.5, 2.0])
    assert high.image[row, col] and not low.image[row, col]


def test_polygons_and_bounds(box_nav: PathFinder):
    polys = box_nav.polygons()
    assert len(polys) == box_nav.num_polygons
    assert all(p.ndim == 2 and p.shape[1] == 3 and 3 <= len(p) <= 6 for p in polys)
    lo, hi = box_nav.bounds
    every = np.vstack(polys)
    assert (every >= lo - 1e-4).all() and (every <= hi + 1e-4).all()
    assert lo[:2] == pytest.approx([CLEARANCE, CLEARANCE], abs=0.06)
    assert hi[:2] == pytest.approx([14 - CLEARANCE, 8 - CLEARANCE], abs=0.06)
    # Counter-clockwise seen from above (positive shoelace area in x, y).
    for p in polys:
        x, y = p[:, 0], p[:, 1]
        assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0
