"""What stands on a city's sidewalks: mapped street furniture where it is tagged, then a zone grammar.

:func:`plan_street_objects` returns :class:`Placement` records (category, position, heading, zone,
source), never geometry; :mod:`navverse.city.street_life.populate` turns them into objects.

1. **Mapped furniture** (``CityMap.furniture``: OSM nodes, or a synthetic city's own) is placed at
   its node, or up to ``snap`` (0.5 m) from it, where its footprint stands clear: off the road,
   the clear walkway, buildings and water, and off what is already placed. A bus stop tagged
   ``shelter=yes`` also gets a bus shelter behind or beside its sign, facing the street. The
   category follows the tag (:data:`MAPPED_CATEGORIES`); a traffic signal node lies on the road, so
   its light goes to the nearest furniture-zone point within ``signal_reach``. What cannot be
   placed is skipped and counted by reason.
2. **The zone grammar** then walks every sidewalk's furniture zone and frontage zone
   (:mod:`navverse.city.street_life.zones`) and proposes objects at the spacings of :data:`GRAMMAR`
   (lamps every ~30 m, street trees every ~10 m on residential streets, a hydrant every ~90 m,
   parking meters and ticket machines along parking strips, bins, signs and bollards by the
   junctions; benches, planters and drinking fountains by the facades of main roads, recycling
   bins on residential ones, A-frame signs, bike racks and cafe seating in front of shops and
   cafes). A proposal is kept if its footprint lies wholly inside its zone, clears what is placed,
   and no object of its category (mapped ones included) stands within ``spacing`` / 2 of it.

   **Budget.** When the proposals outnumber what the budget leaves after the mapped furniture, the
   budget is shared among the rules max-min fairly (:func:`fair_shares`: every rule gets an equal
   share, and what a rule with fewer proposals leaves over is shared by the others), and each rule
   keeps an evenly spread subset of its proposals. Lamps and trees, which propose the most, then
   thin out instead of spending the whole budget before the hydrants, signs and benches get any.
   Budget left by proposals that do not fit is shared again among the rules' remaining proposals.

Footprints are rectangles of the object's width and depth turned to its heading, except for objects
whose base is smaller than their top (:data:`BASE_FOOTPRINT`: a tree's trunk, a lamp's pole), which
stand on their base. Headings: the object's front (+y) faces the walkway from the furniture zone and
the street from the frontage zone.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry
from shapely.ops import nearest_points
from shapely.prepared import prep
from shapely.strtree import STRtree

from navverse.city.geometry.street_plan import StreetPlan
from navverse.city.geometry.surfaces import SHARED_SURFACE_HIGHWAYS
from navverse.city.map import CityMap
from navverse.city.shape_grid import ShapeGrid
from navverse.city.street_life.zones import StreetZones, ZoneSettings, sidewalk_split

__all__ = [
    "BASE_FOOTPRINT",
    "GRAMMAR",
    "MAPPED_CATEGORIES",
    "GrammarRule",
    "Placement",
    "StreetObjects",
    "fair_shares",
    "plan_street_objects",
]

SizeOf = Callable[[str], tuple[float, float, float]]
"""``size_of(category) -> (width, depth, height)`` of the object to place (m)."""

MAPPED_CATEGORIES: dict[str, str] = {
    "tree": "deciduous_tree",
    "street_lamp": "street_lamp",
    "bus_stop": "bus_stop_sign",
    "traffic_signals": "traffic_light",
    "bench": "park_bench",
    "waste_basket": "waste_bin",
    "bicycle_parking": "bike_rack",
    "post_box": "post_box",
    "vending_machine": "vending_machine",
    "fire_hydrant": "fire_hydrant",
}
"""Object category of each mapped furniture ``kind`` (the OSM tag value)."""

BASE_FOOTPRINT: dict[str, tuple[float, float]] = {
    "deciduous_tree": (0.3, 0.3),
    "conifer_tree": (0.4, 0.4),
    "birch_tree": (0.25, 0.25),
    "palm_tree": (0.4, 0.4),
    "street_lamp": (0.3, 0.3),
    "traffic_light": (0.3, 0.3),
    "bus_stop_sign": (0.3, 0.3),
    "street_sign": (0.3, 0.3),
    "stop_sign": (0.3, 0.3),
    "patio_umbrella": (0.6, 0.6),
}
"""Width and depth of what stands on the ground, for objects whose top is wider than their base (m)."""


@dataclass(frozen=True)
class GrammarRule:
    """One kind of object the grammar proposes along a zone.

    Attributes
    ----------
    category : str
        Object category.
    zone : {"furniture", "frontage"}
        The sidewalk zone it stands in; ``furniture`` rules use the verge on a road side whose
        sidewalk has no furniture zone.
    spacing : float
        Distance between two of them along the zone (m).
    roads : frozenset of str
        Road classes (``highway``) it lines; empty: every class.
    where : {"along", "ends", "parking", "places"}
        ``along`` the whole zone; at the zone's ``ends`` (by junctions); along ``parking`` strips;
        in front of ``places`` (POIs of ``place_categories``).
    place_categories : frozenset of str
        POI categories whose fronts it stands at (``where="places"``).
    at : float
        ``ends``: distance from each end of the zone; ``places``: distance to either side of the
        place's front (m).
    """

    category: str
    zone: str
    spacing: float
    roads: frozenset[str] = frozenset()
    where: str = "along"
    place_categories: frozenset[str] = frozenset()
    at: float = 6.0


_BIG = frozenset({"primary", "secondary", "tertiary", "trunk"})
_HOMES = frozenset({"residential", "unclassified", "living_street"})
_SHOPS = frozenset(
    {"bakery", "clothes", "convenience", "supermarket", "books", "florist", "hardware", "shop"}
)
_EATING = frozenset({"cafe", "restaurant", "fast_food", "bar", "pub", "ice_cream"})

GRAMMAR: tuple[GrammarRule, ...] = (
    GrammarRule("street_lamp", "furniture", 30.0),
    GrammarRule("deciduous_tree", "furniture", 10.0, roads=_HOMES),
    GrammarRule("birch_tree", "furniture", 14.0, roads=_BIG),
    GrammarRule("fire_hydrant", "furniture", 90.0),
    GrammarRule("parking_meter", "furniture", 15.0, where="parking"),
    GrammarRule("ticket_machine", "furniture", 90.0, where="parking"),
    GrammarRule("bollard", "furniture", 0.0, where="ends", at=3.0),
    GrammarRule("waste_bin", "furniture", 60.0, where="ends"),
    GrammarRule("street_sign", "furniture", 80.0, where="ends", roads=_BIG),
    GrammarRule("stop_sign", "furniture", 80.0, where="ends", roads=_HOMES, at=4.5),
    GrammarRule("post_box", "furniture", 300.0),
    GrammarRule("utility_box", "furniture", 150.0, roads=_BIG),
    GrammarRule("park_bench", "frontage", 45.0, roads=_BIG),
    GrammarRule("street_planter", "frontage", 35.0, roads=_BIG),
    GrammarRule("drinking_fountain", "frontage", 400.0, roads=_BIG),
    GrammarRule("recycling_bin", "frontage", 150.0, roads=_HOMES),
    GrammarRule("a_frame_sign", "frontage", 8.0, where="places", place_categories=_SHOPS | _EATING, at=1.5),
    GrammarRule("bike_rack", "frontage", 20.0, where="places", place_categories=_SHOPS | _EATING, at=5.0),
    GrammarRule("bistro_table", "frontage", 3.0, where="places", place_categories=_EATING, at=1.5),
    GrammarRule("newspaper_box", "frontage", 120.0, roads=_BIG),
)
"""The zone grammar, in the order its rules are applied (earlier rules take the space first)."""


@dataclass(frozen=True)
class Placement:
    """An object to place: category, ground position (m), heading of its front (radians from +x),
    the zone or area it stands in, and where it came from (``osm:node/123``, ``map:furniture-4``,
    ``grammar``)."""

    category: str
    x: float
    y: float
    heading: float
    zone: str
    source: str


@dataclass(frozen=True)
class StreetObjects:
    """The placements, and the mapped furniture that could not be placed, counted by reason."""

    placements: tuple[Placement, ...]
    skipped: dict[str, int]


def footprint(category: str, size: tuple[float, float, float], x: float, y: float, heading: float) -> Polygon:
    """The ground footprint of an object whose front faces ``heading`` (see :data:`BASE_FOOTPRINT`)."""
    width, depth = BASE_FOOTPRINT.get(category, (size[0], size[1]))
    # Local +y (front) along the heading, local +x to its right.
    fx, fy = math.cos(heading), math.sin(heading)
    rx, ry = fy, -fx
    corners = [(a * width / 2.0, b * depth / 2.0) for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    return Polygon([(x + u * rx + v * fx, y + u * ry + v * fy) for u, v in corners])


class _Occupancy:
    """Footprints placed so far (a grid index for overlap tests) and each category's positions."""

    def __init__(self, cell: float = 4.0) -> None:
        self.grid = ShapeGrid(cell)
        self.points: dict[str, list[tuple[float, float]]] = {}

    def clear(self, polygon: Polygon, gap: float) -> bool:
        grown = polygon.buffer(gap) if gap > 0 else polygon
        return not any(grown.intersects(other) for other in self.grid.candidates(grown))

    def near(self, category: str, x: float, y: float, distance: float) -> bool:
        return any(math.hypot(x - px, y - py) < distance for px, py in self.points.get(category, ()))

    def add(self, polygon: Polygon, category: str, x: float, y: float) -> None:
        self.grid.add(polygon)
        self.points.setdefault(category, []).append((x, y))


def _tangent(line: LineString, along: float) -> float:
    a = line.interpolate(max(0.0, along - 0.5))
    b = line.interpolate(min(line.length, along + 0.5))
    return math.atan2(b.y - a.y, b.x - a.x)


def plan_street_objects(
    city: CityMap,
    plan: StreetPlan,
    zones: StreetZones,
    size_of: SizeOf,
    rng: np.random.Generator,
    *,
    settings: ZoneSettings | None = None,
    grammar: tuple[GrammarRule, ...] = GRAMMAR,
    excluded: frozenset[str] = frozenset(),
    snap: float = 0.5,
    signal_reach: float = 12.0,
    budget: int | None = None,
) -> StreetObjects:
    """Place mapped street furniture, then the zone grammar (see the module docstring).

    Parameters
    ----------
    city, plan, zones : CityMap, StreetPlan, StreetZones
        The map, its ground plan and its zones.
    size_of : callable
        ``size_of(category) -> (width, depth, height)``: the size of the object that will stand
        there (drawn by the caller, in placement order).
    rng : numpy.random.Generator
        Draws where each grammar rule starts along a zone.
    settings : ZoneSettings, optional
        The settings the zones were laid with.
    grammar : tuple of GrammarRule
        The rules to apply.
    excluded : frozenset of str
        Categories never placed (mapped furniture of these kinds is skipped as ``excluded``).
    snap : float
        How far a mapped object may move from its node to stand clear (m).
    signal_reach : float
        How far from its node a traffic light may stand (m).
    budget : int, optional
        The most objects placed: mapped furniture first (a drawn subset if there is more of it),
        then the grammar until the budget is spent. None: no limit.
    """
    settings = settings or ZoneSettings()
    gap = settings.gap
    classes = plan.classes
    blocked = prep(
        classes["road"]
        .union(classes["crosswalk"])
        .union(classes["lowered_curb"])
        .union(classes["building"])
        .union(classes["water"])
        .union(classes["shared"])
        .union(zones.walkway)
        .buffer(-1e-6)
    )
    window = prep(Polygon.from_bounds(*city.window).buffer(-0.5))
    occupied = _Occupancy()
    placements: list[Placement] = []
    skipped: Counter[str] = Counter()

    def put(category: str, x: float, y: float, heading: float, zone: str, source: str) -> Polygon:
        shape = footprint(category, size_of(category), x, y, heading)
        occupied.add(shape, category, x, y)
        placements.append(Placement(category, float(x), float(y), float(heading), zone, source))
        return shape

    # 1. Mapped furniture, nearest road heading.
    lines = [LineString(r.centerline.points) for r in city.roads if r.highway not in SHARED_SURFACE_HIGHWAYS]
    tree = STRtree(lines) if lines else None
    signal_zone = _NearestZone(zones.furniture.union(zones.verge))
    offsets = [(0.0, 0.0)] + [
        (r * math.cos(a), r * math.sin(a))
        for r in (snap / 2.0, snap)
        for a in np.linspace(0, math.tau, 8, endpoint=False)
    ]
    mapped = list(city.furniture)
    if budget is not None and len(mapped) > budget:
        keep = set(rng.choice(len(mapped), size=budget, replace=False).tolist())
        skipped["mapped furniture: over the density cap"] += len(mapped) - budget
        mapped = [item for k, item in enumerate(mapped) if k in keep]
    for item in mapped:
        category = MAPPED_CATEGORIES.get(item.kind)
        source = f"osm:{item.osm}" if item.osm else f"map:{item.id}"
        if category is None:
            skipped[f"{item.kind}: no object category"] += 1
            continue
        if category in excluded:
            skipped[f"{category}: excluded by the recipe"] += 1
            continue
        x0, y0 = item.position
        if not window.contains(Point(x0, y0)):
            skipped[f"{category}: outside the window"] += 1
            continue
        heading = 0.0
        if tree is not None:
            line = lines[int(tree.nearest(Point(x0, y0)))]
            along = line.project(Point(x0, y0))
            near = line.interpolate(along)
            heading = math.atan2(y0 - near.y, x0 - near.x) + math.pi  # the front faces the street
        candidates = offsets
        if category == "traffic_light":
            target = signal_zone.nearest(x0, y0, signal_reach)
            if target is None:
                skipped[f"{category}: no furniture zone or verge within {signal_reach:g} m"] += 1
                continue
            candidates = [(target[0] - x0, target[1] - y0)]
        reason = None
        for dx, dy in candidates:
            shape = footprint(category, size_of(category), x0 + dx, y0 + dy, heading)
            if blocked.intersects(shape):
                reason = reason or _why(classes, zones, shape)
                continue
            if not occupied.clear(shape, gap):
                reason = reason or "overlaps another object"
                continue
            put(category, x0 + dx, y0 + dy, heading, _zone_of(zones, shape), source)
            reason = None
            break
        if reason is not None:
            skipped[f"{category}: {reason}"] += 1
        elif item.shelter and "bus_shelter" not in excluded:
            spot = _shelter_spot(x0 + dx, y0 + dy, heading, size_of("bus_shelter"), blocked, occupied, gap)
            if spot is None:
                skipped["bus_shelter: no room beside its stop"] += 1
            else:
                zone = _zone_of(zones, footprint("bus_shelter", size_of("bus_shelter"), *spot, heading))
                put("bus_shelter", *spot, heading, zone, source)

    # 2. The zone grammar: every rule's proposals, then a fair share of the budget to each rule.
    proposals = _proposals(city, zones, grammar, excluded, settings, size_of, rng, curb_width=plan.curb_width)
    left = None if budget is None else max(0, budget - len(placements))
    pools = [list(range(len(found))) for found in proposals]
    while any(pools) and (left is None or left > 0):
        wanted = [len(pool) for pool in pools]
        shares = wanted if left is None else fair_shares(wanted, left)
        for rule, found, pool, share in zip(grammar, proposals, pools, shares, strict=True):
            tried = set(_spread(len(pool), share))
            for k in sorted(tried):
                x, y, heading, zone, shape = found[pool[k]]
                if occupied.near(rule.category, x, y, rule.spacing / 2.0) or not occupied.clear(shape, gap):
                    continue
                put(rule.category, x, y, heading, zone, "grammar")
            pool[:] = [index for k, index in enumerate(pool) if k not in tried]
        if left is not None:
            left = max(0, budget - len(placements))  # type: ignore[operator]
    return StreetObjects(placements=tuple(placements), skipped=dict(sorted(skipped.items())))


Proposal = tuple[float, float, float, str, Polygon]
"""A grammar proposal: position, heading, zone and footprint."""


def _proposals(
    city: CityMap,
    zones: StreetZones,
    grammar: tuple[GrammarRule, ...],
    excluded: frozenset[str],
    settings: ZoneSettings,
    size_of: SizeOf,
    rng: np.random.Generator,
    *,
    curb_width: float,
) -> list[list[Proposal]]:
    """Each rule's proposals along every road side, whose footprints lie wholly in their zone."""
    zone_shapes = {
        name: prep(getattr(zones, name).buffer(1e-6)) for name in ("furniture", "frontage", "verge")
    }
    parking = prep(zones.parking.buffer(0.5))
    places = [(p.position, p.category) for p in city.pois]
    proposals: list[list[Proposal]] = []
    for rule in grammar:
        found: list[Proposal] = []
        proposals.append(found)
        if rule.category in excluded:
            continue
        size = size_of(rule.category)
        for road in city.roads:
            if road.highway in SHARED_SURFACE_HIGHWAYS or (rule.roads and road.highway not in rule.roads):
                continue
            line = LineString(road.centerline.points)
            for sign, walk in ((1.0, road.sidewalk_left), (-1.0, road.sidewalk_right)):
                if walk is None:
                    continue
                zone = rule.zone
                middle = _zone_line(
                    line, sign, road.sidewalk_edge(sign), walk, zone, settings, curb_width=curb_width
                )
                if middle is None and zone == "furniture":
                    zone = "verge"  # too narrow a sidewalk: lamps and trees stand beyond it
                    middle = _zone_line(
                        line, sign, road.sidewalk_edge(sign), walk, zone, settings, curb_width=curb_width
                    )
                if middle is None:
                    continue
                turn = math.pi if zone == "frontage" else 0.0
                for along in _stations(rule, middle, rng, places, parking):
                    point = middle.interpolate(along)
                    # Away from the road on this side: furniture faces the walkway that way, frontage
                    # objects face the street.
                    away = _tangent(middle, along) + sign * math.pi / 2.0
                    heading = math.remainder(away + turn, math.tau)
                    shape = footprint(rule.category, size, point.x, point.y, heading)
                    if zone_shapes[zone].contains(shape):
                        found.append((float(point.x), float(point.y), float(heading), zone, shape))
    return proposals


def fair_shares(wanted: list[int], budget: int) -> list[int]:
    """A max-min fair split of ``budget`` among claims of ``wanted``: claims are met smallest first,
    each with at most an equal share of what is left, so no claim gets less than an equal split
    unless it wanted less.

    >>> fair_shares([1000, 30, 5, 300], 100)
    [32, 30, 5, 33]
    """
    shares = [0] * len(wanted)
    order = sorted(range(len(wanted)), key=lambda k: (wanted[k], k))
    left = budget
    for rank, k in enumerate(order):
        open_claims = len(order) - rank
        shares[k] = min(wanted[k], left // open_claims + (1 if left % open_claims > 0 else 0))
        left -= shares[k]
    return shares


def _spread(count: int, share: int) -> list[int]:
    """``share`` indices spread evenly over ``range(count)``."""
    if share >= count:
        return list(range(count))
    if share <= 0:
        return []
    return sorted({int(k * count / share) for k in range(share)})


def _shelter_spot(
    x: float,
    y: float,
    heading: float,
    size: tuple[float, float, float],
    blocked: object,
    occupied: _Occupancy,
    gap: float,
) -> tuple[float, float] | None:
    """Where a bus shelter facing ``heading`` (the street) stands beside its stop at (x, y): behind
    it (away from the street) or beside it along the street, clear of what is blocked or placed."""
    back = (-math.cos(heading), -math.sin(heading))
    along = (-math.sin(heading), math.cos(heading))
    for behind in size[1] / 2.0 + np.arange(0.3, 5.0, 0.25):
        for side in (0.0, size[0] / 2.0 + 0.5, -size[0] / 2.0 - 0.5):
            cx = x + back[0] * float(behind) + along[0] * side
            cy = y + back[1] * float(behind) + along[1] * side
            shape = footprint("bus_shelter", size, cx, cy, heading)
            if not blocked.intersects(shape) and occupied.clear(shape, gap):  # type: ignore[attr-defined]
                return (cx, cy)
    return None


def _zone_line(
    line: LineString,
    sign: float,
    edge: float,
    walk: float,
    zone: str,
    settings: ZoneSettings,
    *,
    curb_width: float,
) -> LineString | None:
    """The middle line of a road side's zone (of its sidewalk, ``edge`` from the centre line on), or None
    if the side has no such zone."""
    furniture, frontage = sidewalk_split(walk, settings, curb_width=curb_width)
    if zone == "furniture":
        width, offset = furniture, edge + curb_width + furniture / 2.0
    elif zone == "frontage":
        width, offset = frontage, edge + walk - frontage / 2.0
    else:
        width, offset = settings.verge_width, edge + walk + settings.verge_width / 2.0
    if width <= 0:
        return None
    middle = line.offset_curve(sign * offset, quad_segs=4, join_style="mitre")
    if middle.is_empty or middle.geom_type != "LineString":
        return None
    return middle


def _stations(
    rule: GrammarRule,
    middle: LineString,
    rng: np.random.Generator,
    places: list[tuple[tuple[float, float], str]],
    parking: object,
) -> list[float]:
    """Where along a zone's middle line a rule proposes its objects."""
    length = middle.length
    if rule.where == "ends":
        return [s for s in (rule.at, length - rule.at) if 0.0 < s < length]
    if rule.where == "places":
        stations = []
        for position, category in places:
            if category not in rule.place_categories:
                continue
            point = Point(position)
            if middle.distance(point) > 25.0:
                continue
            along = middle.project(point)
            stations += [along + d for d in (-rule.at, rule.at) if 0.0 < along + d < length]
        return stations
    start = float(rng.uniform(0.3, 0.7)) * min(rule.spacing, length)
    stations = [float(s) for s in np.arange(start, length, rule.spacing)]
    if rule.where == "parking":
        stations = [s for s in stations if parking.intersects(middle.interpolate(s))]  # type: ignore[attr-defined]
    return stations


class _NearestZone:
    """Nearest points of a zone at least ``inset`` inside it (the default holds a 0.3 m pole base at
    any heading); parts too narrow for that are left out."""

    def __init__(self, zone: BaseGeometry, inset: float = 0.25) -> None:
        parts = []
        for part in getattr(zone, "geoms", [zone]):
            inner = part.buffer(-inset)
            if not inner.is_empty:
                parts.append(inner)
        self.parts = parts
        self.tree = STRtree(parts) if parts else None

    def nearest(self, x: float, y: float, reach: float) -> tuple[float, float] | None:
        """The zone point nearest to (x, y), if within ``reach``."""
        if self.tree is None:
            return None
        point = Point(x, y)
        best, best_distance = None, reach
        for index in self.tree.query(point.buffer(reach)):
            part = self.parts[int(index)]
            distance = part.distance(point)
            if distance <= best_distance:
                near = nearest_points(part, point)[0]
                best, best_distance = (near.x, near.y), distance
        return best


def _why(classes: dict[str, BaseGeometry], zones: StreetZones, shape: Polygon) -> str:
    """Why a footprint cannot stand where it is."""
    for cls, reason in (
        ("building", "inside a building"),
        ("water", "in water"),
        ("crosswalk", "on a crosswalk"),
        ("road", "on the carriageway"),
        ("shared", "on a shared street"),
    ):
        if classes[cls].intersects(shape):
            return reason
    return "in the clear walkway"


def _zone_of(zones: StreetZones, shape: Polygon) -> str:
    """The zone a placed footprint stands in: a sidewalk zone, or ``open`` (parks, plazas, ground)."""
    for name in ("furniture", "frontage", "verge"):
        if getattr(zones, name).intersects(shape):
            return name
    return "open"
