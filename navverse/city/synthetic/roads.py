"""Roads of synthetic cities: street styles by rank, road records, junction arms and crossings.

A street's rank picks its style: rank 0 ``secondary`` (``arterial_lanes`` lanes, ``arterial_sidewalk``
sidewalks), rank 1 ``tertiary`` (``collector_lanes``, ``collector_sidewalk``), rank 2 ``residential``
(two lanes, ``sidewalk``), of which a ``living_street_share`` become living streets (shared
surface, no sidewalks); a ``service_share`` of dead-end streets become ``service`` roads without
sidewalks. Lane widths are those of :data:`~navverse.city.tags.ROAD_CLASSES`.

Every end of a road at a node where two or more roads meet is an arm (a junction arm where three
or more meet). An arm's *clearance* is how far along it, from the node, its crosswalk
(``CROSSWALK_WIDTH`` wide, across the carriageway and its curbs) stays off the other roads'
carriageways and sidewalks: for another arm at angle θ and half street width h (carriageway and
sidewalk), 2 + h when θ ≥ 90°, else 2 + (h + a·cos θ)/sin θ with a the arm's half carriageway and
curbs (no crosswalk when θ < 11.5°). The crossing sits ``crossing_offset`` beyond the clearance, on
junction arms of roads with sidewalks on both sides, when the road is long enough for crossings at
both ends. Street furniture keeps clear of the clearance (and of the crosswalk) too.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from navverse.city.geometry.surfaces import CROSSWALK_WIDTH, CURB_WIDTH
from navverse.city.map import Crossing, Path2, Road
from navverse.city.synthetic.names import StreetNamer
from navverse.city.synthetic.params import SyntheticCityParams
from navverse.city.synthetic.streets import XY, Network, Window, node_pieces
from navverse.city.tags import ROAD_CLASSES

__all__ = ["Arm", "RoadStyle", "along", "crossings", "junction_arms", "road_records", "street_styles"]


@dataclass(frozen=True)
class RoadStyle:
    """How a street is built: OSM highway class, lanes, carriageway and sidewalk widths (m)."""

    highway: str
    lanes: int | None
    width: float
    sidewalk: float | None

    @property
    def half(self) -> float:
        """Half the street's width: half the carriageway plus one sidewalk (m)."""
        return self.width / 2.0 + (self.sidewalk or 0.0)


def _style(highway: str, lanes: int | None, sidewalk: float | None) -> RoadStyle:
    kind = ROAD_CLASSES[highway]
    width = lanes * kind.lane_width if lanes else kind.width
    return RoadStyle(highway, lanes, width, sidewalk)


def rank_styles(params: SyntheticCityParams) -> dict[int, RoadStyle]:
    """The style of each rank's ordinary street."""
    return {
        0: _style("secondary", params.arterial_lanes, params.arterial_sidewalk),
        1: _style("tertiary", params.collector_lanes, params.collector_sidewalk),
        2: _style("residential", 2, params.sidewalk),
    }


def street_styles(rng: np.random.Generator, network: Network, params: SyntheticCityParams) -> list[RoadStyle]:
    """A style for every street of ``network`` (one draw per residential street, in order)."""
    by_rank = rank_styles(params)
    styles = []
    for street in network.streets:
        style = by_rank[street.rank]
        draw = float(rng.uniform())
        if street.rank == 2 and street.kind == "stub" and draw < params.service_share:
            style = _style("service", None, None)
        elif street.rank == 2 and street.kind != "stub" and draw < params.living_street_share:
            style = _style("living_street", None, None)
        styles.append(style)
    return styles


def road_records(rng: np.random.Generator, network: Network, styles: list[RoadStyle]) -> list[Road]:
    """One road per piece of ``network``, named after its street (one name per street)."""
    namer = StreetNamer(rng)
    names: dict[int, str] = {}
    roads = []
    for index, piece in enumerate(network.pieces, start=1):
        style = styles[piece.street]
        if piece.street not in names:
            kind = network.streets[piece.street].kind
            key = style.highway if style.highway in ("living_street", "service") else kind
            key = key if key in ("ring", "stub", "living_street", "service") else style.highway
            names[piece.street] = namer.name(key)
        roads.append(
            Road(
                id=f"road-{index}",
                highway=style.highway,
                centerline=Path2(points=list(piece.points)),
                width=style.width,
                width_source="synthetic",
                lanes=style.lanes,
                sidewalk_left=style.sidewalk,
                sidewalk_right=style.sidewalk,
                sidewalk_source="synthetic",
                kerb="raised" if style.sidewalk else None,
                name=names[piece.street],
            )
        )
    return roads


def along(points: list[XY] | tuple[XY, ...], station: float) -> tuple[XY, XY]:
    """The point ``station`` meters along a polyline (clamped to it) and the unit tangent there."""
    remaining = max(0.0, station)
    segments = list(itertools.pairwise(points))
    for k, (a, b) in enumerate(segments):
        length = math.dist(a, b)
        if remaining <= length or k == len(segments) - 1:
            share = min(1.0, remaining / length) if length > 0 else 0.0
            ux, uy = (b[0] - a[0]) / length, (b[1] - a[1]) / length
            return (a[0] + share * (b[0] - a[0]), a[1] + share * (b[1] - a[1])), (ux, uy)
        remaining -= length
    raise ValueError("a polyline needs two points")


@dataclass(frozen=True)
class Arm:
    """A road's end at a junction: the road's index, whether the road starts there, the node,
    the clearance (m along the road from the node) and the crossing's station from that end, if any."""

    road: int
    start: bool
    node: XY
    clear: float
    crossing: float | None


def _direction(road: Road, *, start: bool) -> XY:
    points = road.centerline.points if start else road.centerline.points[::-1]
    length = road.centerline.length
    (x, y), _ = along(points, min(5.0, length / 2.0))
    dx, dy = x - points[0][0], y - points[0][1]
    norm = math.hypot(dx, dy) or 1.0
    return dx / norm, dy / norm


def junction_arms(roads: list[Road], network: Network, *, offset: float) -> list[Arm]:
    """The road ends at every node where two or more roads meet, with clearances and crossings.

    Parameters
    ----------
    roads : list of Road
        One road per piece of ``network``, in the same order.
    network : Network
        The pieces (their end points are the nodes).
    offset : float
        Distance from an arm's clearance to its crossing's centre (m).

    Returns
    -------
    list of Arm
        Every road end at such a node, with its clearance; a crossing station on the arms of nodes
        where three or more roads meet, if the road has sidewalks on both sides and room for
        crossings at both ends (see the module docstring).
    """
    arms: list[Arm] = []
    for node, ends in node_pieces(network).items():
        if len(ends) < 2:
            continue
        directions = [_direction(roads[i], start=start) for i, start in ends]
        for k, (index, start) in enumerate(ends):
            road = roads[index]
            a = road.width / 2.0 + 2.0 * CURB_WIDTH
            clear = CROSSWALK_WIDTH / 2.0
            for m, (other, _) in enumerate(ends):
                if m == k:
                    continue
                h = roads[other].width / 2.0 + max(
                    roads[other].sidewalk_left or 0.0, roads[other].sidewalk_right or 0.0
                )
                cos = max(
                    -1.0, min(1.0, directions[k][0] * directions[m][0] + directions[k][1] * directions[m][1])
                )
                sin = math.sqrt(1.0 - cos * cos)
                if cos <= 0.0:
                    need = CROSSWALK_WIDTH / 2.0 + h
                elif sin < 0.2:
                    need = math.inf  # nearly along another road: no room for a crosswalk
                else:
                    need = CROSSWALK_WIDTH / 2.0 + (h + a * cos) / sin
                clear = max(clear, need)
            station = clear + offset
            usable = len(ends) >= 3 and road.sidewalk_left is not None and road.sidewalk_right is not None
            room = station + CROSSWALK_WIDTH / 2.0 + 0.5 <= road.centerline.length / 2.0
            arms.append(Arm(index, start, node, clear, station if usable and room else None))
    return arms


def crossings(roads: list[Road], arms: list[Arm], window: Window) -> list[Crossing]:
    """A crossing at every arm that has room for one, strictly inside the window."""
    found: list[Crossing] = []
    min_x, min_y, max_x, max_y = window
    for arm in arms:
        if arm.crossing is None:
            continue
        road = roads[arm.road]
        points = road.centerline.points
        station = arm.crossing if arm.start else road.centerline.length - arm.crossing
        (x, y), _ = along(points, station)
        x, y = round(x, 3) + 0.0, round(y, 3) + 0.0
        if min_x + 1.0 < x < max_x - 1.0 and min_y + 1.0 < y < max_y - 1.0:
            found.append(Crossing(id=f"crossing-{len(found) + 1}", position=(x, y), road=road.id))
    return found
