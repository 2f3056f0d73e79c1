"""Storefronts in a synthetic city: set into road-facing facades with a carved recess, standing on the
ground, never overlapping each other, a building or a street object, doors onto the sidewalk, signs
seen from it; map places keep their names; the same seed gives the same storefronts."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from shapely.geometry import LineString, Point, Polygon

from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan
from navverse.city.places.storefronts import STOREFRONT_CATEGORY, StorefrontSettings, place_storefronts
from navverse.city.street_life.populate import PopulateSettings, populate_city
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city
from navverse.scene.heights import SurfaceHeights

GEOMETRY = CityGeometry(junction_crosswalks=True)
SETTINGS = StorefrontSettings(fill_per_km2=600.0)


def _placed(seed: int):
    city = synthetic_city(SyntheticCityParams(size=(220.0, 220.0)), seed=4)
    plan = geometry_plan(city, GEOMETRY)
    scene = city_scene(city, scene_id="shops", geometry=GEOMETRY, plan=plan)
    populated = populate_city(
        scene, city, plan, np.random.default_rng(1), PopulateSettings(objects_per_km2=3000.0)
    ).scene
    return (
        city,
        plan,
        populated,
        place_storefronts(populated, city, plan, np.random.default_rng(seed), SETTINGS),
    )


@pytest.fixture(scope="module")
def placed():
    return _placed(0)


def _box(center, size, yaw) -> Polygon:
    c, s = math.cos(yaw), math.sin(yaw)
    hx, hy = size[0] / 2.0, size[1] / 2.0
    corners = [(u * hx, v * hy) for u, v in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    return Polygon([(center[0] + u * c - v * s, center[1] + u * s + v * c) for u, v in corners])


def _storefront_objects(scene):
    return [o for o in scene.objects if o.annotation.category == STOREFRONT_CATEGORY]


def test_counts_add_up_and_map_places_keep_their_names(placed) -> None:
    city, _, _, result = placed
    stores = result.scene.annotations.storefronts
    counts = result.counts
    assert len(stores) == counts["placed"] == len(_storefront_objects(result.scene)) >= 15
    assert counts["places"] + counts["filled"] == counts["placed"] + sum(counts["rejected"].values())
    assert sum(counts["categories"].values()) == len(stores) and len(counts["categories"]) >= 8
    pois = {p.id: p for p in city.pois}
    from_map = [s for s in stores if s.poi is not None]
    assert from_map, "some storefronts stand for the map's places"
    for store in from_map:
        assert store.name == pois[store.poi].name
    assert all(s.poi is None and s.osm is None and s.name for s in stores if s not in from_map)


def test_storefronts_face_the_road_on_their_facade(placed) -> None:
    _, _, _, result = placed
    buildings = {b.id: b for b in result.scene.annotations.buildings}
    for store in result.scene.annotations.storefronts:
        facade = next(f for f in buildings[store.building].facades if f.id == store.facade)
        assert facade.road is not None
        assert math.isclose(store.facing, facade.facing, abs_tol=1e-9)
        # the storefront's back is inside the building, its front out of it
        normal = np.array(facade.normal)
        line = LineString(facade.segment)
        assert line.distance(Point(store.center[:2])) < store.size[1] / 2
        behind = np.asarray(store.center[:2]) - normal * store.size[1] / 2 + normal * 0.01
        assert Polygon(buildings[store.building].footprint).buffer(1e-6).contains(Point(behind))


def test_storefronts_stand_on_the_ground_in_front(placed) -> None:
    _, _, populated, result = placed
    ground = SurfaceHeights(populated)
    for store, obj in zip(
        result.scene.annotations.storefronts, _storefront_objects(result.scene), strict=True
    ):
        bottom = obj.world_mesh().vertices[:, 2].min()
        normal = np.array([math.cos(store.facing), math.sin(store.facing)])
        front = np.asarray(store.center[:2]) + normal * (store.size[1] / 2 + 0.3)
        assert abs(bottom - ground(front)[0]) < 0.02, store.id  # neither floating nor sunk
        assert abs(store.entrance[2] - ground(np.asarray(store.entrance[:2]))[0]) < 1e-6


def test_storefronts_overlap_no_neighbour(placed) -> None:
    _, _, _, result = placed
    ann = result.scene.annotations
    stores = _storefront_objects(result.scene)
    boxes = [_box(o.annotation.center, o.annotation.size, o.annotation.yaw) for o in stores]
    for i, a in enumerate(boxes):
        for b in boxes[i + 1 :]:
            assert a.intersection(b).area < 1e-6
    others = [o.annotation for o in result.scene.objects if o.annotation.category != STOREFRONT_CATEGORY]
    for box in boxes:
        for other in others:
            assert box.intersection(_box(other.center, other.size, other.yaw)).area < 1e-6, other.prim_path
    for store, box in zip(ann.storefronts, boxes, strict=True):
        for building in ann.buildings:
            if building.id != store.building:
                assert box.intersection(Polygon(building.footprint)).area < 1e-6


def test_each_facade_behind_a_storefront_has_its_opening(placed) -> None:
    _, _, populated, result = placed
    before = {s.name: s.mesh for s in populated.surfaces if s.name.startswith("building_")}
    after = {s.name: s.mesh for s in result.scene.surfaces if s.name.startswith("building_")}
    removed: dict[str, float] = {}
    for store in result.scene.annotations.storefronts:
        name = f"building_{store.building:04d}"
        removed[name] = removed.get(name, 0.0) + store.size[0] * 0.4 * store.size[2]  # width, depth, height
    for name, expected in removed.items():
        volume = [
            trimesh.Trimesh(m.vertices, m.faces, process=False).volume for m in (before[name], after[name])
        ]
        assert after[name].num_faces > before[name].num_faces
        assert volume[0] - volume[1] == pytest.approx(expected, rel=1e-3), name
    untouched = set(before) - set(removed)
    assert all(
        after[n] is before[n] or np.array_equal(after[n].vertices, before[n].vertices) for n in untouched
    )


def test_doors_open_onto_the_sidewalk(placed) -> None:
    _, plan, _, result = placed
    walkable = plan.classes["sidewalk"].union(plan.classes["plaza"]).union(plan.classes["pedestrian"])
    for store in result.scene.annotations.storefronts:
        normal = np.array([math.cos(store.facing), math.sin(store.facing)])
        start = np.asarray(store.entrance[:2])
        assert LineString([start, start + normal * SETTINGS.sidewalk_gap]).intersects(walkable)


def test_the_same_seed_gives_the_same_storefronts(placed) -> None:
    again = _placed(0)[3]
    assert again.scene.annotations.model_dump() == placed[3].scene.annotations.model_dump()
    assert again.counts == placed[3].counts
