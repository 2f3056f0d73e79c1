"""Geodesic distances are the exact shortest paths of the navmesh's free space."""

from __future__ import annotations

import numpy as np
import pytest

from navverse import nav
from navverse.nav import PathFinder
from tests.navverse.nav import scenes
from tests.navverse.nav.exact import ExactPaths

TILE_SIZES = [0, 48, 32, 24, 16]


def cluttered_hall() -> scenes.MeshBuilder:
    """A 24 m x 16 m hall with 14 boxes of varied sizes: many corners, many wrong-side detours."""
    b = scenes.MeshBuilder().floor(0, 0, 24, 16).walls(0, 0, 24, 16)
    rng = np.random.default_rng(3)
    for _ in range(14):
        x, y = rng.uniform(1.5, 21.0), rng.uniform(1.5, 13.0)
        sx, sy = rng.uniform(0.3, 2.5, size=2)
        b.box((x, y, 0), (x + sx, y + sy, 1.5), scenes.WALL)
    return b


def random_pairs(finder: PathFinder, count: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(seed)

    def point() -> np.ndarray:
        return finder.get_random_navigable_point(rng, island=finder.largest_island)

    return [(point(), point()) for _ in range(count)]


@pytest.mark.parametrize("tile_size", TILE_SIZES)
@pytest.mark.parametrize("scene", [scenes.hall_with_pillars, cluttered_hall], ids=["pillars", "cluttered"])
def test_geodesics_are_exact(scene, tile_size: int):
    vertices, faces, areas = scene().arrays()
    settings = nav.OUTDOOR.model_copy(update={"tile_size": tile_size})
    finder = nav.build(vertices, faces, settings, area_types=areas)
    exact = ExactPaths(finder)
    errors = []
    for start, end in random_pairs(finder, 150, seed=tile_size):
        reference = exact.distance(start, end)
        if reference < 0.5:
            continue
        path = finder.find_path(start, end)
        polyline = float(np.linalg.norm(np.diff(path.points[:, :2], axis=0), axis=1).sum())
        assert path.geodesic_distance == pytest.approx(polyline, rel=1e-4)  # flat floor: 3-D = 2-D
        errors.append(path.geodesic_distance / reference - 1.0)
    assert len(errors) > 100
    assert max(errors) < 1e-4, max(errors)  # never longer than the shortest path...
    assert min(errors) > -1e-4, min(errors)  # ...and never shorter (it is a real path)


def test_multi_goal_picks_the_exactly_nearest():
    vertices, faces, areas = cluttered_hall().arrays()
    finder = nav.build(vertices, faces, nav.OUTDOOR, area_types=areas)
    exact = ExactPaths(finder)
    rng = np.random.default_rng(9)
    for _ in range(20):
        start = finder.get_random_navigable_point(rng)
        ends = np.array([finder.get_random_navigable_point(rng) for _ in range(5)])
        multi = finder.find_path_multi(start, ends)
        distances = [exact.distance(start, end) for end in ends]
        assert multi.closest_end_index == int(np.argmin(distances))
        assert multi.geodesic_distance == pytest.approx(min(distances), rel=1e-4)
