"""Street furniture of synthetic cities, all of it on the sidewalks.

Along each road, between the ends' clearances (past the crosswalk at a junction, see
:mod:`.synthetic_roads`), on sidewalks at least 1.2 m wide, objects stand at the *kerb line*
(0.5 m inside the sidewalk; trees at up to 0.8 m) or at the *building line* (0.4 m from the
sidewalk's outer edge, on sidewalks 2.4 m wide or more; else the kerb line):

=================  =============================================================================
kind               where
=================  =============================================================================
traffic_signals    a pole on each side of every crosswalk of a junction that an arterial reaches
bus_stop           arterials, about every ``bus_stop_spacing`` m, a stop on each side (the second
                   15 m on), each with a bench at the building line and a waste basket; a
                   ``bus_shelter_share`` of the stops are tagged with a shelter
street_lamp        every ``lamp_spacing`` m, both sides staggered on arterials, one side elsewhere
tree               every ``tree_spacing`` m on both sides of tree-lined streets (a
                   ``tree_street_share`` of residential streets, twice that of arterials)
fire_hydrant       about every ``hydrant_spacing`` m, at the kerb line
bench              about every ``bench_spacing`` m per side, with a waste basket 1.5 m on
waste_basket       with benches and bus stops
bicycle_parking    arterials, about every 250 m per side, at the building line
post_box           about every 500 m of street
vending_machine    about every 1000 m of street, at the building line
=================  =============================================================================

"About every d m" is a Poisson count of mean (usable length) / d at uniform stations. Objects are
placed in the table's order and an object closer than 1 m to one already placed is left out, as is
any object on a carriageway or its curb (another road's, near a junction), over water (but lamps on
bridges) or outside the window.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon, box

from navverse.city.geometry.surfaces import CROSSWALK_WIDTH, CURB_WIDTH
from navverse.city.map import Road, StreetFurniture
from navverse.city.synthetic.params import SyntheticCityParams
from navverse.city.synthetic.roads import Arm, along
from navverse.city.synthetic.streets import XY, Window

__all__ = ["MIN_SPACING", "street_furniture"]

MIN_SPACING = 1.0
"""Least distance between two pieces of furniture (m)."""
ARTERIALS = frozenset({"secondary", "tertiary"})


class _Road:
    """A road's usable stretch and its sides: stations from ``start`` to ``end`` (m)."""

    def __init__(self, road: Road, clear_start: float, clear_end: float) -> None:
        self.road = road
        self.points = road.centerline.points
        self.length = road.centerline.length
        self.start, self.end = clear_start, self.length - clear_end
        self.half = road.width / 2.0

    @property
    def usable(self) -> float:
        return max(0.0, self.end - self.start)

    def sidewalk(self, side: int) -> float:
        width = self.road.sidewalk_left if side > 0 else self.road.sidewalk_right
        return width or 0.0

    def kerb(self, side: int, inset: float = 0.5) -> float | None:
        """Distance from the centre line of the kerb line on ``side`` (+1 left, -1 right)."""
        return self.half + inset if self.sidewalk(side) >= 1.2 else None

    def inner(self, side: int) -> float | None:
        """Distance from the centre line of the building line (the kerb line on narrow sidewalks)."""
        width = self.sidewalk(side)
        if width >= 2.4:
            return self.half + width - 0.4
        return self.kerb(side)

    def at(self, station: float, side: int, offset: float) -> XY:
        (x, y), (ux, uy) = along(self.points, station)
        return x - side * uy * offset, y + side * ux * offset

    def stations(self, spacing: float, phase: float) -> Iterator[float]:
        station = self.start + phase
        while station <= self.end:
            yield station
            station += spacing


def _clearances(roads: list[Road], arms: list[Arm]) -> dict[tuple[int, bool], float]:
    clear: dict[tuple[int, bool], float] = {}
    for arm in arms:
        value = arm.crossing + CROSSWALK_WIDTH / 2.0 + 0.5 if arm.crossing is not None else arm.clear + 0.5
        key = (arm.road, arm.start)
        clear[key] = max(clear.get(key, 0.0), value)
    return clear


def street_furniture(
    rng: np.random.Generator,
    roads: list[Road],
    arms: list[Arm],
    water: Polygon | None,
    window: Window,
    params: SyntheticCityParams,
) -> list[StreetFurniture]:
    """Street furniture along the roads' sidewalks (see the module docstring).

    Parameters
    ----------
    rng : numpy.random.Generator
        Draws phases, counts, stations and sides.
    roads : list of Road
        The city's roads.
    arms : list of Arm
        Their ends at nodes (:func:`~navverse.city.synthetic.roads.junction_arms`): clearances and crossings.
    water : shapely.Polygon or None
        The river, if any.
    window : tuple of float
        ``(min_x, min_y, max_x, max_y)``.
    params : SyntheticCityParams
        Spacings and shares.

    Returns
    -------
    list of StreetFurniture
        Numbered ``furniture-1``, ``furniture-2``... in the order placed.
    """
    clear = _clearances(roads, arms)
    stretches = [
        _Road(road, clear.get((i, True), 1.0), clear.get((i, False), 1.0)) for i, road in enumerate(roads)
    ]
    candidates: list[tuple[str, XY, bool]] = []

    def put(
        kind: str, stretch: _Road, station: float, side: int, offset: float | None, *, shelter: bool = False
    ) -> None:
        if offset is not None and stretch.start <= station <= stretch.end:
            candidates.append((kind, stretch.at(station, side, offset), shelter))

    # Traffic signals beside the crosswalks of junctions an arterial reaches.
    arterial_nodes = {arm.node for arm in arms if roads[arm.road].highway in ARTERIALS}
    for arm in arms:
        if arm.crossing is None or arm.node not in arterial_nodes:
            continue
        stretch = stretches[arm.road]
        beyond = arm.crossing + CROSSWALK_WIDTH / 2.0 + 0.6
        station = beyond if arm.start else stretch.length - beyond
        for side in (1, -1):
            offset = stretch.kerb(side)
            if offset is not None:
                candidates.append(("traffic_signals", stretch.at(station, side, offset), False))
    # Bus stops (with a bench and a waste basket) along arterials.
    for stretch in stretches:
        if stretch.road.highway not in ARTERIALS or stretch.usable < 20.0:
            continue
        for _ in range(int(rng.poisson(stretch.usable / params.bus_stop_spacing))):
            station = float(rng.uniform(stretch.start, stretch.end))
            for side, shift in ((-1, 0.0), (1, 15.0 if station + 15.0 <= stretch.end else -15.0)):
                shelter = float(rng.uniform()) < params.bus_shelter_share
                put("bus_stop", stretch, station + shift, side, stretch.kerb(side), shelter=shelter)
                put("bench", stretch, station + shift + 2.0, side, stretch.inner(side))
                put("waste_basket", stretch, station + shift + 3.5, side, stretch.inner(side))
    # Street lamps and trees at regular spacing.
    tree_lined: dict[str | None, bool] = {}
    for stretch in stretches:
        arterial = stretch.road.highway in ARTERIALS
        sides = (1, -1) if arterial else ((1,) if float(rng.uniform()) < 0.5 else (-1,))
        phase = float(rng.uniform(0.0, params.lamp_spacing))
        for side in sides:
            shift = params.lamp_spacing / 2.0 if side < 0 and arterial else 0.0
            for station in stretch.stations(params.lamp_spacing, (phase + shift) % params.lamp_spacing):
                put("street_lamp", stretch, station, side, stretch.kerb(side))
        name = stretch.road.name
        if name not in tree_lined:
            share = min(1.0, params.tree_street_share * (2.0 if arterial else 1.0))
            tree_lined[name] = float(rng.uniform()) < share
        if tree_lined[name]:
            phase = float(rng.uniform(0.0, params.tree_spacing))
            for side in (1, -1):
                inset = min(0.8, stretch.sidewalk(side) / 2.0)
                for station in stretch.stations(params.tree_spacing, phase):
                    put("tree", stretch, station, side, stretch.kerb(side, inset))
    # Objects scattered along the streets.
    for stretch in stretches:
        arterial = stretch.road.highway in ARTERIALS
        usable = stretch.usable
        if usable <= 0.0:
            continue
        for _ in range(int(rng.poisson(usable / params.hydrant_spacing))):
            side = 1 if float(rng.uniform()) < 0.5 else -1
            put(
                "fire_hydrant",
                stretch,
                float(rng.uniform(stretch.start, stretch.end)),
                side,
                stretch.kerb(side, 0.4),
            )
        for side in (1, -1):
            for _ in range(int(rng.poisson(usable / params.bench_spacing))):
                station = float(rng.uniform(stretch.start, stretch.end))
                put("bench", stretch, station, side, stretch.inner(side))
                put("waste_basket", stretch, station + 1.5, side, stretch.inner(side))
            if arterial:
                for _ in range(int(rng.poisson(usable / 250.0))):
                    station = float(rng.uniform(stretch.start, stretch.end))
                    put("bicycle_parking", stretch, station, side, stretch.inner(side))
        for kind, spacing, inner in (("post_box", 500.0, False), ("vending_machine", 1000.0, True)):
            for _ in range(int(rng.poisson(usable / spacing))):
                side = 1 if float(rng.uniform()) < 0.5 else -1
                station = float(rng.uniform(stretch.start, stretch.end))
                put(kind, stretch, station, side, stretch.inner(side) if inner else stretch.kerb(side))
    return _kept(candidates, roads, water, window)


def _kept(
    candidates: list[tuple[str, XY, bool]], roads: list[Road], water: Polygon | None, window: Window
) -> list[StreetFurniture]:
    """The candidates off every carriageway and curb, off the water (but lamps), in the window,
    at least :data:`MIN_SPACING` from those kept before them."""
    if not candidates:
        return []
    xy = np.array([p for _, p, _ in candidates])
    carriageways = [
        LineString(road.centerline.points).buffer(road.width / 2.0 + CURB_WIDTH + 0.2) for road in roads
    ]
    tree = shapely.STRtree(carriageways)
    points = shapely.points(xy)
    on_road = np.zeros(len(candidates), dtype=bool)
    on_road[tree.query(points, predicate="intersects")[0]] = True
    inside = shapely.contains_xy(box(*window).buffer(-0.5), xy[:, 0], xy[:, 1])
    wet = (
        shapely.contains_xy(water.buffer(0.5), xy[:, 0], xy[:, 1])
        if water is not None
        else np.zeros(len(candidates), dtype=bool)
    )
    kept: list[StreetFurniture] = []
    cells: dict[tuple[int, int], list[XY]] = {}
    for k, (kind, (x, y), shelter) in enumerate(candidates):
        if on_road[k] or not inside[k] or (wet[k] and kind != "street_lamp"):
            continue
        x, y = round(x, 3) + 0.0, round(y, 3) + 0.0
        cx, cy = math.floor(x / MIN_SPACING), math.floor(y / MIN_SPACING)
        near = (p for i in (-1, 0, 1) for j in (-1, 0, 1) for p in cells.get((cx + i, cy + j), []))
        if any(math.dist(p, (x, y)) < MIN_SPACING for p in near):
            continue
        cells.setdefault((cx, cy), []).append((x, y))
        kept.append(
            StreetFurniture(id=f"furniture-{len(kept) + 1}", position=(x, y), kind=kind, shelter=shelter)
        )
    return kept
