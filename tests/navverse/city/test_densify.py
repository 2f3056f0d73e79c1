"""Densifying the neighbourhood of an i2o scene's exit: street objects, cars and storefronts are added
only inside the region, clear of what stands, of the doorway and of the buildings; the same seed gives
the same scene; nothing is added where the region holds no street."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon

from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan
from navverse.city.i2o.assembly import assemble_i2o
from navverse.city.i2o.densify import DensifySettings, base_footprint, densify_neighbourhood
from navverse.city.places.storefronts import StorefrontSettings
from navverse.city.street_life.populate import PopulateSettings, populate_city
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city
from navverse.indoor.building import BuildingOptions, generate_building

GEOMETRY = CityGeometry(junction_crosswalks=True)
SPARSE = PopulateSettings(cars_per_km2=40.0, objects_per_km2=150.0, group_objects_per_km2=0.0)


@pytest.fixture(scope="module")
def town():
    city_map = synthetic_city(SyntheticCityParams(size=(220.0, 220.0)), seed=4)
    plan = geometry_plan(city_map, GEOMETRY)
    scene = city_scene(city_map, scene_id="town", geometry=GEOMETRY, plan=plan)
    populated = populate_city(scene, city_map, plan, np.random.default_rng(1), SPARSE).scene
    cafe = generate_building(
        "cafe", np.random.default_rng(3), scene_id="cafe", options=BuildingOptions(length=14.0)
    )
    joined = assemble_i2o(populated, plan, cafe, scene_id="cafe-town").scene
    return joined, city_map, plan


def _densify(town, seed: int, **settings):
    scene, city_map, plan = town
    anchor = scene.annotations.indoor_anchor
    doorway = Point(anchor[0], anchor[1]).buffer(3.5)
    region = Point(anchor[0], anchor[1]).buffer(50.0)
    result = densify_neighbourhood(
        scene,
        city_map,
        plan,
        np.random.default_rng(seed),
        region=region,
        keep_clear=[doorway],
        settings=DensifySettings(**settings),
        populate=PopulateSettings(),
        storefronts=StorefrontSettings(),
    )
    return result, region, doorway


@pytest.fixture(scope="module")
def densified(town):
    return _densify(town, 7, objects_nearby=25, cars_nearby=6, storefronts_nearby=0)


def _new_objects(before, after):
    return after.annotations.objects[len(before.annotations.objects) :]


def test_objects_and_cars_are_added_inside_the_region_only(town, densified) -> None:
    result, region, _ = densified
    new = _new_objects(town[0], result.scene)
    cars = [o for o in new if o.category in ("sedan", "hatchback", "suv", "van", "pickup_truck")]
    assert sum(result.counts["objects"].values()) == len(new) - len(cars)
    assert sum(result.counts["cars"].values()) == len(cars)
    assert 10 <= len(new) - len(cars) <= 25 and 1 <= len(cars) <= 6
    assert result.counts["candidates"]["objects"] >= len(new) - len(cars)
    for obj in new:
        assert region.contains(Point(obj.center[0], obj.center[1])), obj.category


def test_new_objects_keep_clear_of_what_stands_the_doorway_and_the_buildings(town, densified) -> None:
    result, _, doorway = densified
    before = town[0]
    standing = shapely.union_all([base_footprint(o) for o in before.annotations.objects])
    buildings = shapely.union_all([Polygon(b.footprint) for b in result.scene.annotations.buildings])
    new = _new_objects(before, result.scene)
    boxes = [base_footprint(o) for o in new]  # a tree's canopy may overhang, its trunk may not
    for obj, box in zip(new, boxes, strict=True):
        assert box.intersection(standing).area < 1e-6, obj.category
        assert box.intersection(doorway).area < 1e-6, obj.category
        assert box.intersection(buildings).area < 1e-6, obj.category
    for i, a in enumerate(boxes):  # and of one another
        for b in boxes[i + 1 :]:
            assert a.intersection(b).area < 1e-6


def test_new_objects_stand_on_the_ground(town, densified) -> None:
    from navverse.scene.heights import SurfaceHeights

    result, _, _ = densified
    new = _new_objects(town[0], result.scene)
    ground = SurfaceHeights(town[0])(np.array([o.center[:2] for o in new]))
    bottoms = np.array([o.center[2] - o.size[2] / 2.0 for o in new])
    assert np.abs(bottoms - ground).max() < 0.02


def test_the_same_seed_gives_the_same_scene_and_another_seed_another(town, densified) -> None:
    again, _, _ = _densify(town, 7, objects_nearby=25, cars_nearby=6, storefronts_nearby=0)
    other, _, _ = _densify(town, 8, objects_nearby=25, cars_nearby=6, storefronts_nearby=0)
    first = densified[0].scene.annotations.objects
    assert [o.center for o in again.scene.annotations.objects] == [o.center for o in first]
    assert [o.center for o in other.scene.annotations.objects] != [o.center for o in first]


def test_storefronts_are_added_up_to_the_count(town) -> None:
    result, region, _ = _densify(town, 7, objects_nearby=0, cars_nearby=0, storefronts_nearby=4)
    stores = result.scene.annotations.storefronts
    inside = [s for s in stores if region.contains(Point(s.entrance[0], s.entrance[1]))]
    assert len(inside) == 4 and result.counts["storefronts"]["placed"] >= 4
    assert not result.counts["objects"] and not result.counts["cars"]


def test_a_region_without_street_gains_nothing(town) -> None:
    scene, city_map, plan = town
    x0, y0, _, _ = city_map.window
    result = densify_neighbourhood(
        scene,
        city_map,
        plan,
        np.random.default_rng(0),
        region=Point(x0 - 500.0, y0 - 500.0).buffer(20.0),
        settings=DensifySettings(objects_nearby=10, cars_nearby=5, storefronts_nearby=3),
        populate=PopulateSettings(),
        storefronts=StorefrontSettings(),
    )
    assert len(result.scene.annotations.objects) == len(scene.annotations.objects)
    assert result.counts["candidates"] == {"objects": 0, "cars": 0}
