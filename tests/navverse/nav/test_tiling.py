"""Tiled builds agree with single-tile builds, and do not depend on the number of threads."""

from __future__ import annotations

import numpy as np
import pytest

from navverse import nav
from navverse.nav import PathFinder
from tests.navverse.nav import scenes
from tests.navverse.nav.conftest import build_scene

PAIRS = [
    ((1.0, 1.0), (29.0, 19.0)),
    ((1.0, 19.0), (29.0, 1.0)),
    ((3.0, 5.0), (22.0, 17.0)),
    ((10.0, 1.0), (10.0, 19.0)),
    ((28.0, 8.0), (2.0, 9.0)),
    ((15.0, 2.0), (26.0, 12.0)),
]


@pytest.fixture(scope="module")
def single() -> PathFinder:
    return build_scene(scenes.hall_with_pillars(), nav.OUTDOOR, tile_size=0)


@pytest.fixture(scope="module")
def tiled() -> PathFinder:
    return build_scene(scenes.hall_with_pillars(), nav.OUTDOOR, tile_size=48)


def test_tiled_build_has_many_tiles(single: PathFinder, tiled: PathFinder):
    assert single.num_tiles == 1
    assert tiled.num_tiles >= 20  # 30 m x 20 m in 4.8 m tiles
    assert tiled.num_islands == single.num_islands == 1


def test_same_navigable_area(single: PathFinder, tiled: PathFinder):
    assert tiled.navigable_area == pytest.approx(single.navigable_area, rel=0.01)


@pytest.mark.parametrize(("a", "b"), PAIRS)
def test_same_geodesic_distances(single: PathFinder, tiled: PathFinder, a, b):
    d_single = single.geodesic_distance([*a, 0.0], [*b, 0.0])
    d_tiled = tiled.geodesic_distance([*a, 0.0], [*b, 0.0])
    assert np.isfinite(d_single)
    assert d_tiled == pytest.approx(d_single, rel=0.02)


def test_thread_count_does_not_change_the_navmesh():
    vertices, faces, areas = scenes.hall_with_pillars().arrays()
    settings = nav.OUTDOOR.model_copy(update={"tile_size": 32})
    one = nav.build(vertices, faces, settings, area_types=areas, jobs=1)
    four = nav.build(vertices, faces, settings, area_types=areas, jobs=4)
    assert one.num_tiles > 4
    assert one.to_bytes() == four.to_bytes()


def test_settings_tile_size_validation():
    with pytest.raises(ValueError, match="tile_size"):
        nav.INDOOR.model_validate({**nav.INDOOR.model_dump(), "tile_size": 8})


@pytest.mark.parametrize("preset", [nav.INDOOR, nav.OUTDOOR], ids=["indoor", "outdoor"])
def test_open_ground_paths_are_straight_across_tiles(preset: nav.NavMeshSettings):
    # On an empty slab every pair sees each other: the geodesic is the straight line even when the
    # two points lie in different tiles, whose single large polygons have far-off edge midpoints.
    vertices, faces, areas = scenes.MeshBuilder().floor(0, 0, 60, 60).arrays()
    finder = nav.build(vertices, faces, preset, area_types=areas)
    assert finder.num_tiles > 4
    rng = np.random.default_rng(4)
    starts = [finder.get_random_navigable_point(rng) for _ in range(300)]
    ends = [finder.get_random_navigable_point(rng) for _ in range(300)]
    excess = [
        finder.geodesic_distance(a, b) / np.linalg.norm((b - a)[:2]) - 1.0
        for a, b in zip(starts, ends, strict=True)
    ]
    assert max(excess) < 1e-4
