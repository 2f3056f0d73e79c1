"""Seeded navmesh paths within a length range."""

from __future__ import annotations

import numpy as np
import pytest

from navverse import nav
from navverse.nav import NavMeshError
from navverse.nav.sampling import sample_paths
from navverse.nav.scene_navmesh import build_scene_navmesh
from tests.navverse.scene.conftest import build_scene


@pytest.fixture(scope="module")
def finder() -> nav.PathFinder:
    return build_scene_navmesh(build_scene(), nav.OUTDOOR)


def test_paths_are_in_range_on_one_island_and_seeded(finder: nav.PathFinder):
    paths = sample_paths(finder, 3, 12, min_length=4.0, max_length=9.0)
    assert len(paths) == 12
    for path in paths:
        assert 4.0 <= path.geodesic_distance <= 9.0
        assert {finder.island_of(p) for p in path.points} == {finder.largest_island}
        horizontal = np.linalg.norm(np.diff(path.points, axis=0), axis=1).sum()
        assert horizontal == pytest.approx(path.geodesic_distance, rel=1e-3)
    again = sample_paths(finder, np.random.default_rng(3), 12, min_length=4.0, max_length=9.0)
    assert all(np.array_equal(a.points, b.points) for a, b in zip(paths, again, strict=True))
    other = sample_paths(finder, 4, 12, min_length=4.0, max_length=9.0)
    assert not all(np.array_equal(a.points, b.points) for a, b in zip(paths, other, strict=True))


def test_an_impossible_range_says_so(finder: nav.PathFinder):
    with pytest.raises(NavMeshError, match=r"found only 0 of 2 paths of 500\.0-900\.0 m"):
        sample_paths(finder, 0, 2, min_length=500.0, max_length=900.0, max_tries=20)
