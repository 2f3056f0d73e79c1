"""A populated synthetic city: cars on the road clear of crosswalks, junctions and sidewalks; objects
out of the clear walkway, on the ground, within the caps; the same seed gives the same scene."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from shapely.geometry import Polygon

from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan
from navverse.city.street_life.objects import footprint
from navverse.city.street_life.populate import CAR_TYPES, PopulateSettings, populate_city
from navverse.city.street_life.zones import street_zones
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city
from navverse.scene.directory import read_annotations, write_scene_dir

GEOMETRY = CityGeometry(junction_crosswalks=True)


def _populated(seed: int, settings: PopulateSettings | None = None, *, side: float = 300.0):
    city = synthetic_city(SyntheticCityParams(size=(side, side)), seed=4)
    plan = geometry_plan(city, GEOMETRY)
    scene = city_scene(city, scene_id="populated", geometry=GEOMETRY, plan=plan)
    return city, plan, populate_city(scene, city, plan, np.random.default_rng(seed), settings)


@pytest.fixture(scope="module")
def populated():
    return _populated(
        0, PopulateSettings(cars_per_km2=600.0, objects_per_km2=2000.0, group_objects_per_km2=2000.0)
    )


def _box(center, size, yaw) -> Polygon:
    c, s = math.cos(yaw), math.sin(yaw)
    half = np.array(size[:2]) / 2.0
    corners = [(a * half[0], b * half[1]) for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    return Polygon([(center[0] + u * c - v * s, center[1] + u * s + v * c) for u, v in corners])


def test_cars_park_on_the_road_never_on_crosswalks_junctions_or_sidewalks(populated) -> None:
    city, plan, population = populated
    zones = street_zones(city, plan)
    cars = [o.annotation for o in population.scene.objects if o.annotation.category in CAR_TYPES]
    assert len(cars) == sum(population.counts["cars"].values()) >= 40
    crosswalks = plan.classes["crosswalk"].union(plan.classes["lowered_curb"])
    for car in cars:
        shape = _box(car.center, car.size, car.yaw)
        assert car.zone in ("curbside", "parking_lane", "parking_lot") and car.source == "parking"
        if car.zone != "parking_lot":
            assert shape.difference(plan.classes["road"]).area < 1e-4
            assert shape.intersection(zones.junctions).area < 1e-6
        assert shape.intersection(crosswalks).area < 1e-6
        assert shape.intersection(plan.classes["sidewalk"]).area < 1e-6


def test_street_objects_keep_out_of_the_walkway_and_stand_on_the_ground(populated) -> None:
    city, plan, population = populated
    zones = street_zones(city, plan)
    objects = [o.annotation for o in population.scene.objects if o.annotation.category not in CAR_TYPES]
    assert len(objects) > 50
    for obj in objects:
        shape = footprint(obj.category, obj.size, obj.center[0], obj.center[1], obj.yaw + math.pi / 2.0)
        assert shape.intersection(zones.walkway).area < 1e-6, obj
        assert shape.intersection(plan.classes["road"]).area < 1e-6, obj
    bottoms = np.array([o.center[2] - o.size[2] / 2.0 for o in objects])
    on_ground = np.array([o.group is None for o in objects])  # group members may stand on others
    assert np.all(np.abs(bottoms[on_ground]) < 1e-4)  # flat city: sidewalks and verges at 0 (float32 casts)
    assert np.all(bottoms > -1e-4)


def test_caps_and_counts(populated) -> None:
    city, _, population = populated
    x0, y0, x1, y1 = city.window
    area = (x1 - x0) * (y1 - y0) / 1e6
    counts = population.counts
    assert sum(counts["cars"].values()) <= 600.0 * area
    sources = counts["sources"]
    assert sources["map"] + sources["grammar"] <= 2000.0 * area  # street objects
    assert sources["group"] <= 2000.0 * area  # contextual group members
    assert sources["parking"] == sum(counts["cars"].values())
    assert sum(counts["zones"].values()) == len(population.scene.objects)
    stats = population.scene.annotations.statistics.objects_per_category
    assert stats == counts["objects"]
    # Measured across every sidewalk with the objects standing: at least 2 r_robot + 0.1 m clear.
    clearance = counts["walkway_clearance_m"]
    assert clearance["transects"] > 100 and clearance["min"] >= 1.3 - 0.01


def test_excluded_categories_are_never_placed() -> None:
    _, _, population = _populated(1, PopulateSettings(exclude=["street_lamp", "sedan"]), side=180.0)
    categories = {o.annotation.category for o in population.scene.objects}
    assert categories and not categories & {"street_lamp", "sedan"}


def test_the_same_seed_writes_the_same_bytes(tmp_path: Path) -> None:
    written = []
    for run in ("a", "b"):
        _, _, population = _populated(7, side=150.0)
        (tmp_path / run).mkdir()
        write_scene_dir(population.scene, tmp_path / run)
        written.append({p.name: p.read_bytes() for p in (tmp_path / run).iterdir()})
    assert written[0] == written[1]
    other = _populated(8, side=150.0)[2].scene.annotations.objects
    assert [o.center for o in other] != [o.center for o in read_annotations(tmp_path / "a").objects]


def _body(client, mesh, center, yaw, mass: float, directory: Path) -> int:
    """A PyBullet body of a mesh's convex parts, at its pose (static when ``mass`` is 0)."""
    import pybullet

    from navverse.sim.collision import convex_parts, hulls_file

    hulls = list(convex_parts(mesh))
    shape = client.createCollisionShape(pybullet.GEOM_MESH, fileName=str(hulls_file(hulls, directory)))
    orientation = pybullet.getQuaternionFromEuler((0.0, 0.0, yaw))
    return client.createMultiBody(
        baseMass=mass, baseCollisionShapeIndex=shape, basePosition=center, baseOrientation=orientation
    )


def test_stacked_items_rest_on_their_supports_under_physics(populated, tmp_path: Path) -> None:
    from navverse.sim.bullet import connect, pybullet

    _, _, population = populated
    objects = population.scene.objects
    grouped = [o for o in objects if o.annotation.group]
    assert {o.annotation.source for o in grouped} and all(
        o.annotation.source.startswith("group:") for o in grouped
    )
    counts = population.counts["groups"]
    assert len(counts) >= 5  # several kinds of group in one small city
    stacked = []
    for item in grouped:
        below = [
            o
            for o in grouped
            if o is not item
            and o.annotation.group == item.annotation.group
            and abs(
                (o.annotation.center[2] + o.annotation.size[2] / 2.0)
                - (item.annotation.center[2] - item.annotation.size[2] / 2.0)
            )
            < 0.05
            and math.dist(o.annotation.center[:2], item.annotation.center[:2])
            < max(o.annotation.size[:2]) / 2.0
        ]
        if below and item.annotation.center[2] - item.annotation.size[2] / 2.0 > 0.1:
            stacked.append((item, below[0]))
    assert stacked, "no stacked item in the populated city"
    for item, support in stacked[:6]:
        client = connect()
        try:
            client.setGravity(0.0, 0.0, -9.81)
            client.setTimeStep(1.0 / 240.0)
            ground_plane = client.createCollisionShape(pybullet.GEOM_PLANE)
            client.createMultiBody(baseMass=0.0, baseCollisionShapeIndex=ground_plane)
            a = support.annotation
            _body(client, support.mesh, a.center, a.yaw, 0.0, tmp_path)
            b = item.annotation
            body = _body(client, item.mesh, b.center, b.yaw, 0.5, tmp_path)
            for _ in range(480):  # 2 s
                client.stepSimulation()
            position, _ = client.getBasePositionAndOrientation(body)
        finally:
            client.disconnect()
        # It neither fell (it started on the support, not above or through it) nor slid off.
        assert abs(position[2] - b.center[2]) < 0.015, (b.category, a.category, position, b.center)
        assert math.dist(position[:2], b.center[:2]) < 0.05, (b.category, a.category)
