"""Storefronts of map places that the street rule alone would lose: a place set back from the street
gets a storefront whose door faces the sidewalk across its forecourt (not across a barrier); a
facade whose segment cuts across a bent wall takes its storefront where the wall is; every category
has its turn before any has a second storefront."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon

from navverse.city.geometry.scene import CityGeometry, city_scene, geometry_plan
from navverse.city.map import Building, CityMap, Frame, LandArea, Path2, Poi, Polygon2, Road, Source
from navverse.city.places import storefronts as placing
from navverse.city.places.storefronts import StorefrontSettings, place_storefronts

GEOMETRY = CityGeometry()
ROAD = Road(
    id="road-1",
    highway="residential",
    centerline=Path2(points=[(-60.0, 0.0), (60.0, 0.0)]),
    width=7.0,
    width_source="width",
    sidewalk_left=2.0,
    sidewalk_right=2.0,
)
"""A street along y = 0: carriageway to |y| = 3.5, sidewalks to |y| = 5.5."""


def _building(number: int, exterior: list[tuple[float, float]]) -> Building:
    return Building(
        id=f"building-{number}",
        footprint=Polygon2(exterior=exterior),
        height=9.0,
        height_source="height",
    )


def _box(number: int, x0: float, y0: float, x1: float, y1: float) -> Building:
    return _building(number, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)])


def _poi(number: int, xy: tuple[float, float], tag: str, *, building: int | None = None) -> Poi:
    value = tag.partition("=")[2]
    return Poi(
        id=f"poi-{number}",
        position=xy,
        category=value,
        tag=tag,
        name=f"Place {number}",
        building=None if building is None else f"building-{building}",
    )


def _city(buildings: list[Building], pois: list[Poi], *, land: list[LandArea] | None = None) -> CityMap:
    return CityMap(
        source=Source(kind="synthetic", name="fallbacks", seed=0),
        frame=Frame(epsg=0, origin_lat=0.0, origin_lon=0.0),
        window=(-60.0, -60.0, 60.0, 60.0),
        roads=[ROAD],
        buildings=buildings,
        areas=land or [],
        pois=pois,
    )


def _place(city: CityMap, settings: StorefrontSettings | None = None):
    plan = geometry_plan(city, GEOMETRY)
    scene = city_scene(city, scene_id="fallbacks", geometry=GEOMETRY, plan=plan)
    settings = settings or StorefrontSettings()
    return plan, place_storefronts(scene, city, plan, np.random.default_rng(0), settings)


# -------------------------------------------------------------------------------------------- set back


def _set_back_city(*, land: list[LandArea] | None = None) -> CityMap:
    """A 20 x 12 m building whose front (y = 18) stands 12.5 m behind the sidewalk (y = 5.5)."""
    return _city(
        [_box(1, -10.0, 18.0, 10.0, 30.0)],
        [_poi(1, (2.0, 24.0), "shop=bakery", building=1)],
        land=land,
    )


def test_a_place_set_back_from_the_street_faces_the_sidewalk_across_its_forecourt() -> None:
    plan, result = _place(_set_back_city())
    (store,) = result.scene.annotations.storefronts
    assert store.place_category == "bakery" and store.poi == "poi-1"
    assert store.center[1] == pytest.approx(18.0, abs=0.5)  # set into the front, towards the street
    assert store.facing == pytest.approx(-math.pi / 2)
    assert result.counts["set_back"] == 1 and result.counts["lost"] == {}
    # the door faces the sidewalk 12.5 m away, across open ground
    door = np.asarray(store.entrance[:2])
    assert plan.classes["sidewalk"].distance(Point(door)) == pytest.approx(12.5 - 0.6, abs=0.3)
    assert not LineString([door, (door[0], 5.6)]).intersects(plan.classes["building"])


def test_a_set_back_place_does_not_face_the_sidewalk_across_water() -> None:
    pond = LandArea(
        id="land-1",
        cls="water",
        polygon=Polygon2(exterior=[(-40.0, 8.0), (40.0, 8.0), (40.0, 14.0), (-40.0, 14.0)]),
    )
    _, result = _place(_set_back_city(land=[pond]))
    assert result.scene.annotations.storefronts == []
    ((category, reasons),) = result.counts["lost"].items()
    assert category == "bakery" and sum(reasons.values()) == 1


def test_a_set_back_storefront_needs_the_approach_setting() -> None:
    _, result = _place(_set_back_city(), StorefrontSettings(approach_distance=6.0))
    assert result.scene.annotations.storefronts == []
    assert result.counts["lost"] == {"bakery": {"no sidewalk in front": 1}}


# ------------------------------------------------------------------------------------------ bent wall


def test_a_storefront_goes_where_a_bent_facade_has_its_wall() -> None:
    # The front turns by less than the facade rule's 10 degrees twice, so it is one facade whose segment
    # (y = 5.5) leaves the wall (up to 0.5 m behind it) over x in (0, 15): a recess carved there
    # would miss the wall. The place is over that stretch.
    front = [(-15.0, 5.5), (0.0, 5.5), (5.0, 6.0), (15.0, 5.5)]
    building = _building(1, [*front, (15.0, 17.5), (-15.0, 17.5)])
    city = _city([building], [_poi(1, (8.0, 11.0), "shop=florist", building=1)])
    _, result = _place(city, StorefrontSettings(approach_distance=0.0))
    (annotation,) = result.scene.annotations.buildings
    (facade,) = [f for f in annotation.facades if f.normal[1] < -0.99]
    assert facade.segment == ((-15.0, 5.5), (15.0, 5.5))  # one facade across the bend
    (store,) = result.scene.annotations.storefronts
    assert store.facade == facade.id and store.place_category == "florist"
    # on the straight stretch of the wall (within the probes' spacing), its recess carved in full
    assert store.center[0] + store.size[0] / 2 <= 0.0 + placing._WALL_STEP + 0.1
    assert Polygon(annotation.footprint).exterior.distance(Point(store.center[0], 5.5)) < 1e-6
    assert result.counts["rejected"] == {}


# ------------------------------------------------------------------------------------------- rounds


def test_every_category_has_its_turn_before_any_has_a_second_storefront() -> None:
    # The front has room for two 4 m storefronts. The first cafe is far from any building (lost);
    # in turns of places the second bank would take the last room before the second cafe's turn.
    pois = [
        _poi(1, (0.0, -55.0), "amenity=cafe"),
        _poi(2, (3.0, 10.0), "amenity=cafe", building=1),
        _poi(3, (3.0, 10.0), "amenity=cafe", building=1),
        _poi(4, (-3.0, 10.0), "amenity=bank", building=1),
        _poi(5, (-3.0, 10.0), "amenity=bank", building=1),
    ]
    city = _city([_box(1, -4.5, 5.5, 4.5, 17.5)], pois)
    _, result = _place(city, StorefrontSettings(max_width=4.0, approach_distance=0.0))
    placed = sorted(s.place_category for s in result.scene.annotations.storefronts)
    assert placed == ["bank", "cafe"]
    assert result.counts["lost"] == {
        "bank": {"no room on the facade": 1},
        "cafe": {"no facade within reach": 1, "no room on the facade": 1},
    }


class _Room:
    """A placer with room for `room` storefronts that loses the places named in `lost`."""

    def __init__(self, room: int, lost: set[str]) -> None:
        self.room, self.lost, self.tried = room, lost, []

    def place_map_place(self, candidate: placing._Candidate) -> bool:
        self.tried.append(candidate.name)
        if candidate.name in self.lost or self.room == 0:
            return False
        self.room -= 1
        return True


def test_rounds_give_each_category_a_storefront_first_the_rarer_first() -> None:
    names = [("c1", "cafe"), ("c2", "cafe"), ("c3", "cafe"), ("b1", "bank"), ("r1", "bar"), ("r2", "bar")]
    candidates = [placing._Candidate(category=c, name=n, poi=None) for n, c in names]
    placer = _Room(room=4, lost={"b1", "c1"})
    placing._in_rounds(placer, placing._by_category(candidates))
    assert placer.tried == ["b1", "r1", "c1", "c2", "r2", "c3"]
    assert placer.room == 0
