"""The 2-D ground plan of a city: disjoint classes that tile the window, at the widths of the map."""

from __future__ import annotations

import pytest
from shapely.geometry import Point, box

from navverse.city.geometry.surfaces import CROSSWALK_WIDTH, CURB_WIDTH, SURFACE_CLASSES, plan_surfaces
from navverse.city.map import Building, CityMap, Crossing, Frame, LandArea, Path2, Polygon2, Road, Source


def _t_junction() -> CityMap:
    """Main street along x (7 m, sidewalks both sides 2 m), a side street north (6 m, sidewalk east only)."""
    main = Road(
        id="road-1",
        highway="secondary",
        centerline=Path2(points=[(-50.0, 0.0), (50.0, 0.0)]),
        width=7.0,
        width_source="width",
        sidewalk_left=2.0,
        sidewalk_right=2.0,
    )
    side = Road(
        id="road-2",
        highway="residential",
        centerline=Path2(points=[(0.0, 0.0), (0.0, 50.0)]),
        width=6.0,
        width_source="default",
        sidewalk_right=1.5,
    )
    return CityMap(
        source=Source(kind="synthetic", name="t", seed=0),
        frame=Frame(epsg=0, origin_lat=0.0, origin_lon=0.0),
        window=(-40.0, -40.0, 40.0, 40.0),
        roads=[main, side],
        crossings=[Crossing(id="crossing-1", position=(25.0, 0.0), road="road-1")],
        buildings=[
            Building(
                id="building-1",
                footprint=Polygon2(exterior=[(-30.0, -30.0), (-10.0, -30.0), (-10.0, -8.0), (-30.0, -8.0)]),
                height=12.0,
                height_source="height",
            )
        ],
        areas=[
            LandArea(
                id="area-1", cls="green", polygon=Polygon2(exterior=[(10, 10), (35, 10), (35, 35), (10, 35)])
            )
        ],
    )


@pytest.fixture(scope="module")
def plan():
    return plan_surfaces(_t_junction(), curb_width=CURB_WIDTH, crosswalk_width=CROSSWALK_WIDTH)


def test_the_classes_tile_the_window_without_overlap(plan):
    assert set(plan) == set(SURFACE_CLASSES)
    window = box(-40.0, -40.0, 40.0, 40.0)
    assert sum(g.area for g in plan.values()) == pytest.approx(window.area, rel=1e-6)
    names = list(plan)
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            assert plan[a].intersection(plan[b]).area < 1e-6, (a, b)


def _class_at(plan, x: float, y: float) -> str:
    point = Point(x, y)
    (cls,) = [c for c, g in plan.items() if g.contains(point)]
    return cls


def test_widths_follow_the_map(plan):
    # Across the main street at x = -25 going north: road to 3.5 m, curb strip, sidewalk to 5.5 m.
    assert _class_at(plan, -25.0, 3.4) == "road"
    assert _class_at(plan, -25.0, 3.5 + CURB_WIDTH / 2) == "curb"
    assert _class_at(plan, -25.0, 5.4) == "sidewalk"
    assert _class_at(plan, -25.0, 5.6) == "ground"
    # The side street: road to 3 m either side; sidewalk only on its right (east, walking north).
    assert _class_at(plan, 2.9, 25.0) == "road"
    assert _class_at(plan, 4.4, 25.0) == "sidewalk"
    assert _class_at(plan, -4.0, 25.0) == "ground"


def test_the_crossing_makes_a_crosswalk_with_lowered_curbs(plan):
    assert _class_at(plan, 25.0, 0.0) == "crosswalk"
    assert _class_at(plan, 25.0, 3.5 + CURB_WIDTH / 2) == "lowered_curb"
    assert _class_at(plan, 10.0, 3.5 + CURB_WIDTH / 2) == "curb"


def test_buildings_and_land_areas_take_their_place(plan):
    assert _class_at(plan, -20.0, -20.0) == "building"
    assert _class_at(plan, -20.0, -7.0) == "ground"  # beyond the sidewalk (-5.5) and short of it
    assert _class_at(plan, 30.0, 30.0) == "green"
    # The junction is filled: no gap where the side street meets the main street.
    assert _class_at(plan, 3.2, 3.2) in ("road", "curb")


def test_ground_under_a_raised_building_keeps_its_own_class():
    # A footbridge building over a railway (base 3 m) and a passage's raised piece over a sidewalk: the
    # rail and the sidewalk beneath stay rail and sidewalk (the track is not walked on beneath it).
    city = _t_junction()
    rail = LandArea(
        id="area-2", cls="rail", polygon=Polygon2(exterior=[(-40, 20), (-5, 20), (-5, 30), (-40, 30)])
    )
    bridge = Building(
        id="building-2",
        footprint=Polygon2(exterior=[(-25.0, 15.0), (-20.0, 15.0), (-20.0, 35.0), (-25.0, 35.0)]),
        height=6.0,
        base_height=3.0,
        height_source="height",
    )
    over = Building(
        id="building-3",
        footprint=Polygon2(exterior=[(-35.0, -6.0), (-25.0, -6.0), (-25.0, -3.0), (-35.0, -3.0)]),
        height=12.0,
        base_height=3.5,
        height_source="height",
    )
    city = city.model_copy(
        update={"areas": [*city.areas, rail], "buildings": [*city.buildings, bridge, over]}
    )
    plan = plan_surfaces(city, curb_width=CURB_WIDTH, crosswalk_width=CROSSWALK_WIDTH)
    assert plan["rail"].contains(Point(-22.5, 25.0)) and not plan["building"].intersects(Point(-22.5, 25.0))
    assert plan["sidewalk"].contains(Point(-30.0, -5.0))
    assert plan["building"].contains(Point(-20.0, -20.0))  # standing on the ground: its own class
