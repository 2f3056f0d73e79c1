"""Street objects: mapped furniture at its node (or skipped with a reason), the grammar in its zones,
nothing in the clear walkway, on the road or in a building, nothing overlapping."""

from __future__ import annotations

import math
from collections import Counter

import numpy as np
import pytest
from shapely.geometry import LineString
from shapely.strtree import STRtree

from navverse.city.geometry.scene import CityGeometry, geometry_plan
from navverse.city.map import StreetFurniture
from navverse.city.street_life.objects import MAPPED_CATEGORIES, fair_shares, footprint, plan_street_objects
from navverse.city.street_life.zones import street_zones
from navverse.city.synthetic.generator import SyntheticCityParams, synthetic_city

# Stand-in sizes (width, depth, height): the planner only needs footprints.
SIZES = {
    "street_lamp": (0.4, 1.2, 6.0),
    "deciduous_tree": (4.0, 4.0, 8.0),
    "birch_tree": (3.0, 3.0, 9.0),
    "fire_hydrant": (0.45, 0.35, 0.8),
    "parking_meter": (0.3, 0.25, 1.4),
    "waste_bin": (0.5, 0.5, 0.9),
    "street_sign": (0.6, 0.1, 2.6),
    "utility_box": (0.9, 0.4, 1.3),
    "park_bench": (1.6, 0.6, 0.85),
    "street_planter": (1.2, 0.6, 0.7),
    "a_frame_sign": (0.6, 0.5, 1.0),
    "bistro_table": (0.6, 0.6, 0.75),
    "newspaper_box": (0.5, 0.45, 1.1),
    "bus_stop_sign": (0.4, 0.1, 2.8),
    "traffic_light": (0.4, 0.4, 3.5),
    "bike_rack": (2.0, 0.6, 0.9),
    "post_box": (0.5, 0.5, 1.3),
    "vending_machine": (0.9, 0.8, 1.9),
    "ticket_machine": (0.6, 0.5, 1.95),
    "bollard": (0.4, 0.4, 1.2),
    "stop_sign": (0.92, 0.1, 3.0),
    "drinking_fountain": (0.95, 0.65, 1.1),
    "recycling_bin": (1.6, 0.6, 1.2),
    "bus_shelter": (3.5, 1.6, 2.6),
}


@pytest.fixture(scope="module")
def street():
    city = synthetic_city(SyntheticCityParams(size=(400.0, 400.0)), seed=2)
    plan = geometry_plan(city, CityGeometry(junction_crosswalks=True))
    zones = street_zones(city, plan)
    placed = plan_street_objects(city, plan, zones, SIZES.__getitem__, np.random.default_rng(4))
    return city, plan, zones, placed


def _shapes(placed):
    return [footprint(p.category, SIZES[p.category], p.x, p.y, p.heading) for p in placed.placements]


def test_nothing_stands_in_the_walkway_on_the_road_or_in_a_building(street) -> None:
    _, plan, zones, placed = street
    assert len(placed.placements) > 300
    blocked = [zones.walkway, plan.classes["road"], plan.classes["crosswalk"], plan.classes["building"]]
    for shape in _shapes(placed):
        for area in blocked:
            assert shape.intersection(area).area < 1e-6


def test_no_two_objects_overlap(street) -> None:
    _, _, _, placed = street
    shapes = _shapes(placed)
    tree = STRtree(shapes)
    for i, shape in enumerate(shapes):
        for j in tree.query(shape, predicate="intersects"):
            assert j == i


def test_mapped_furniture_stands_at_its_node_or_is_skipped_with_a_reason(street) -> None:
    city, _, _, placed = street
    mapped = {f"map:{f.id}": f for f in city.furniture}
    placed_mapped = [p for p in placed.placements if p.source in mapped and p.category != "bus_shelter"]
    for p in placed_mapped:
        item = mapped[p.source]
        assert p.category == MAPPED_CATEGORIES[item.kind]
        if item.kind != "traffic_signals":  # a signal's light moves off the road to the corner
            assert math.dist((p.x, p.y), item.position) <= 0.5 + 1e-9
    # Shelters stand beside the stops tagged with one, under the stop's source.
    shelters = [p for p in placed.placements if p.category == "bus_shelter"]
    assert all(mapped[p.source].kind == "bus_stop" and mapped[p.source].shelter for p in shelters)
    stops = [p for p in placed_mapped if mapped[p.source].shelter]
    unsheltered = placed.skipped.get("bus_shelter: no room beside its stop", 0)
    assert stops and len(shelters) + unsheltered == len(stops)
    skipped = sum(n for reason, n in placed.skipped.items() if not reason.startswith("bus_shelter:"))
    assert len(placed_mapped) + skipped == len(city.furniture)
    assert all(":" in reason for reason in placed.skipped)  # "<category>: <why>"
    kinds = Counter(mapped[p.source].kind for p in placed_mapped)
    assert kinds["tree"] > 50 and kinds["street_lamp"] > 20


def test_the_grammar_fills_zones_and_the_budget_holds(street) -> None:
    city, plan, zones, placed = street
    grammar = Counter((p.category, p.zone) for p in placed.placements if p.source == "grammar")
    assert grammar and all(zone in ("furniture", "frontage", "verge") for _, zone in grammar)
    again = plan_street_objects(city, plan, zones, SIZES.__getitem__, np.random.default_rng(4))
    assert again == placed
    capped = plan_street_objects(city, plan, zones, SIZES.__getitem__, np.random.default_rng(4), budget=100)
    assert len(capped.placements) == 100 and capped.skipped["mapped furniture: over the density cap"] > 0


def test_fair_shares_meet_small_claims_and_split_the_rest_evenly() -> None:
    assert fair_shares([1000, 30, 5, 300], 100) == [32, 30, 5, 33]
    assert fair_shares([4, 2], 10) == [4, 2]
    assert sum(fair_shares([7, 7, 7], 10)) == 10
    assert fair_shares([], 5) == []


def test_a_tight_budget_is_shared_by_the_rules_not_spent_on_the_first(street) -> None:
    """Lamps and trees alone would fill a small budget; shared fairly, the rarer rules still place."""
    city, plan, zones, _ = street
    bare = city.model_copy(update={"furniture": ()})
    full = plan_street_objects(bare, plan, zones, SIZES.__getitem__, np.random.default_rng(4))
    every = Counter(p.category for p in full.placements)
    budget = every["street_lamp"] // 2
    capped = plan_street_objects(
        bare, plan, zones, SIZES.__getitem__, np.random.default_rng(4), budget=budget
    )
    got = Counter(p.category for p in capped.placements)
    assert len(capped.placements) == budget
    assert set(got) == set(every)  # every category the uncapped grammar places still appears
    # Uncapped, lamps and trees are most of what stands; capped, no category takes much more than
    # an equal share.
    assert every["street_lamp"] + every["deciduous_tree"] > 0.6 * sum(every.values())
    assert max(got.values()) <= 2 * budget / len(every)


def _stops_by_parks(city, plan, count: int):
    """Bus stop nodes at the kerb of sidewalks with park land behind them."""
    green = plan.classes["green"].union(plan.classes["ground"])
    stops = []
    for road in city.roads:
        line = LineString(road.centerline.points)
        for sign, walk in ((1.0, road.sidewalk_left), (-1.0, road.sidewalk_right)):
            if walk is None or line.length < 40.0:
                continue
            behind = line.offset_curve(sign * (road.width / 2.0 + walk + 2.0))
            kerb = line.offset_curve(sign * (road.width / 2.0 + 0.5))
            if behind.is_empty or kerb.is_empty:
                continue
            middle = behind.interpolate(0.5, normalized=True)
            if green.contains(middle.buffer(1.2)):
                stops.append(kerb.interpolate(0.5, normalized=True))
    return [
        StreetFurniture(id=f"stop-{i}", position=(p.x, p.y), kind="bus_stop", shelter=True)
        for i, p in enumerate(stops[:count])
    ]


def test_a_bus_stop_with_a_shelter_gets_one_beside_it(street) -> None:
    city, plan, zones, _ = street
    stops = _stops_by_parks(city, plan, 6)
    assert len(stops) >= 2
    sizes = {**SIZES, "bus_shelter": (3.0, 1.5, 2.5)}
    sheltered = city.model_copy(update={"furniture": stops})
    placed = plan_street_objects(sheltered, plan, zones, sizes.__getitem__, np.random.default_rng(4))
    signs = {p.source: p for p in placed.placements if p.category == "bus_stop_sign"}
    shelters = [p for p in placed.placements if p.category == "bus_shelter"]
    assert len(shelters) >= 2
    assert len(shelters) + placed.skipped.get("bus_shelter: no room beside its stop", 0) == len(signs)
    for shelter in shelters:
        sign = signs[shelter.source]
        assert math.dist((shelter.x, shelter.y), (sign.x, sign.y)) < 7.0
        shape = footprint("bus_shelter", sizes["bus_shelter"], shelter.x, shelter.y, shelter.heading)
        for area in (zones.walkway, plan.classes["road"], plan.classes["building"]):
            assert shape.intersection(area).area < 1e-6
