"""Per-area costs and excluded areas steer paths."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navverse.nav import NavMeshError, PathFinder
from tests.navverse.nav import scenes
from tests.navverse.nav.conftest import build_scene

START, END = [1.0, 0.5, 0.0], [19.0, 0.5, 0.0]  # a bit north of the dividing wall's axis


@pytest.fixture
def routes() -> PathFinder:
    return build_scene(scenes.two_routes())


def test_polygons_carry_the_area_types(routes: PathFinder):
    assert set(routes.polygon_area_types().tolist()) == {scenes.FLOOR, scenes.ROUTE_B}
    assert len(routes.polygons()) == len(routes.polygon_area_types())


def test_default_costs_take_the_shorter_north_route(routes: PathFinder):
    path = routes.find_path(START, END)
    assert path.points[:, 1].max() > 1.0  # around the wall's north side
    assert path.points[:, 1].min() > -1.0


def test_expensive_area_is_avoided_even_if_longer(routes: PathFinder):
    north = routes.find_path(START, END)
    routes.set_area_costs({scenes.ROUTE_B: 5.0})
    assert routes.area_costs == {scenes.ROUTE_B: 5.0}
    south = routes.find_path(START, END)
    assert south.points[:, 1].min() < -1.0  # around the wall's south side
    assert south.points[:, 1].max() < 1.0
    # A bit longer, and the reported distance is a length, not a cost.
    assert north.geodesic_distance < south.geodesic_distance < 1.15 * north.geodesic_distance
    # Back to uniform costs: back to the north route.
    routes.set_area_costs({})
    np.testing.assert_allclose(routes.find_path(START, END).points, north.points)


def test_excluded_areas(routes: PathFinder):
    routes.set_excluded_areas({scenes.ROUTE_B})
    assert routes.excluded_areas == {scenes.ROUTE_B}
    path = routes.find_path(START, END)
    assert path.points[:, 1].max() < 1.0
    # Snapping and islands still see the whole navmesh.
    assert routes.is_navigable([10.0, 3.0, 0.0])
    assert routes.num_islands == 1
    routes.set_excluded_areas({scenes.FLOOR, scenes.ROUTE_B})
    assert routes.geodesic_distance(START, END) == math.inf
    routes.set_excluded_areas(())
    assert math.isfinite(routes.geodesic_distance(START, END))


@pytest.mark.parametrize("costs", [{2: 0.5}, {64: 2.0}, {-1: 2.0}, {2: math.nan}])
def test_bad_costs_are_refused(routes: PathFinder, costs):
    with pytest.raises(NavMeshError):
        routes.set_area_costs(costs)


def test_bad_excluded_area_is_refused(routes: PathFinder):
    with pytest.raises(NavMeshError, match=r"0\.\.63"):
        routes.set_excluded_areas([70])
