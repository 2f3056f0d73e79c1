"""Population keeps the sidewalks passable: the bare and the populated navmesh have the same sidewalk
islands, no piece of sidewalk is cut off and every crosswalk is still on its street's island; and a
sidewalk blocked on purpose is caught."""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import LineString

from navverse import nav
from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan
from navverse.city.street_life.passability import sidewalk_passability
from navverse.city.street_life.populate import PopulateSettings, populate_city
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.scene.compose import ObjectPart, object_parts, replace_parts
from navverse.scene.geometry import MeshData
from navverse.scene.heights import SurfaceHeights

GEOMETRY = CityGeometry(junction_crosswalks=True)


@pytest.fixture(scope="module")
def street():
    city = synthetic_city(SyntheticCityParams(size=(260.0, 260.0)), seed=7)
    plan = geometry_plan(city, GEOMETRY)
    scene = city_scene(city, scene_id="passability", geometry=GEOMETRY, plan=plan)
    bare = build_scene_navmesh(scene, nav.OUTDOOR, jobs=2)
    return city, plan, scene, bare


def test_a_densely_populated_city_keeps_its_sidewalk_islands(street) -> None:
    city, plan, scene, bare = street
    dense = PopulateSettings(cars_per_km2=600.0, objects_per_km2=4000.0, group_objects_per_km2=2000.0)
    population = populate_city(scene, city, plan, np.random.default_rng(1), dense)
    assert len(population.scene.objects) > 300
    populated = build_scene_navmesh(population.scene, nav.OUTDOOR, jobs=2)
    result = sidewalk_passability(bare, populated, plan, SurfaceHeights(scene))
    assert result.points > 2000 and result.covered > 50  # objects took sidewalk away...
    assert result.crosswalks > 10
    assert result.cuts == 0 and result.crosswalks_cut == 0  # ...but cut none of it
    assert result.islands_after == result.islands_before and result.passable


def test_a_pen_on_a_sidewalk_is_a_cut(street) -> None:
    city, plan, scene, bare = street
    # Four walls around a 7 m square of sidewalk, mid-block on the longest street: the sidewalk inside
    # is cut off from the rest.
    road = max(
        (r for r in city.roads if r.sidewalk_left), key=lambda r: LineString(r.centerline.points).length
    )
    line = LineString(road.centerline.points)
    side = line.offset_curve(road.width / 2.0 + road.sidewalk_left / 2.0)
    middle = side.interpolate(0.5, normalized=True)
    assert plan.classes["sidewalk"].contains(middle)
    z = float(SurfaceHeights(scene)(np.array([[middle.x, middle.y]]))[0])
    half, thick, tall = 3.5, 0.3, 1.5
    walls = []
    for dx, dy, sx, sy in (
        (half, 0.0, thick, 2 * half + thick),
        (-half, 0.0, thick, 2 * half + thick),
        (0.0, half, 2 * half + thick, thick),
        (0.0, -half, 2 * half + thick, thick),
    ):
        walls.append(
            ObjectPart(
                category="construction_fence",
                mesh=MeshData.box((sx, sy, tall)),
                center=(middle.x + dx, middle.y + dy, z + tall / 2.0),
                size=(sx, sy, tall),
            )
        )
    penned = replace_parts(scene, objects=[*object_parts(scene), *walls])
    populated = build_scene_navmesh(penned, nav.OUTDOOR, jobs=2)
    result = sidewalk_passability(bare, populated, plan, SurfaceHeights(scene))
    assert result.cuts >= 1 and not result.passable
