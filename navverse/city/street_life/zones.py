"""Where things may stand in a street: sidewalk zones, parking bands on the road, junctions.

A sidewalk is read across, from the road to the buildings, as three zones (the street-design
grammar of the NACTO *Urban Street Design Guide* and of MetaUrban's sidewalk layouts):

- the **furniture zone** beside the curb: lamps, trees, hydrants, signs, bins, bollards, meters;
- the **walkway**, which stays clear: ``clear_width`` (1.5 m, the ADA/NACTO minimum pedestrian
  through zone) where the sidewalk allows it, else ``min_clear`` (2 r_robot + 0.1 m for Spot),
  else the whole sidewalk (no furniture at all on a sidewalk narrower than that);
- the **frontage zone** by the property line or facade: benches, planters, A-frame signs, cafe seating.

Beyond a sidewalk's outer edge, open land (ground, green, plaza) ``verge_width`` deep is the
**verge**, where a street whose sidewalk is too narrow for a furniture zone has its lamps and trees.

Zones are laid per road side from the road's own sidewalk width (:class:`~navverse.city.map.Road`),
cut to the plan's sidewalk class (so crosswalks, other roads and buildings are never in them),
and kept ``crosswalk_margin`` away from crosswalks and out of junction corners, where people wait
and cross. Mapped separate sidewalks and footways are all walkway.

On the road, **parking bands** run along the curb: the mapped ``parking:*`` strips, and on
residential streets a band on the right curb where the carriageway is ``curbside_min_width`` wide
(one lane is left), on both curbs from ``curbside_both_width``. Both end ``corner_clearance`` (5 m)
before a junction, ``crosswalk_margin`` before a crosswalk and ``driveway_margin`` beside a
driveway (a service road joining the street).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated

import numpy as np
from pydantic import Field
from shapely.geometry import LineString, Polygon
from shapely.geometry.base import BaseGeometry
from shapely.prepared import prep
from shapely.strtree import STRtree

from navverse.city.geometry.street_plan import StreetPlan
from navverse.city.geometry.surfaces import QUAD_SEGMENTS, SHARED_SURFACE_HIGHWAYS, carriageways
from navverse.city.map import CityMap, Road
from navverse.city.precision import difference, intersection, snapped, union_of
from navverse.settings import Settings

__all__ = [
    "CURBSIDE_HIGHWAYS",
    "StreetZones",
    "ZoneSettings",
    "sidewalk_split",
    "street_zones",
    "walkway_clearance",
]

CURBSIDE_HIGHWAYS = frozenset({"residential", "unclassified", "tertiary"})
"""Streets along whose curbs cars plausibly park when nothing is mapped."""


ZoneWidth = Annotated[float, Field(ge=0.0, le=5.0)]
"""A zone's width across the sidewalk (m), 0 to 5."""
Clearance = Annotated[float, Field(ge=0.0, le=30.0)]
"""A distance kept clear (m), 0 to 30."""
RoadWidth = Annotated[float, Field(ge=0.0, le=40.0)]
"""A carriageway width (m), 0 to 40."""


class ZoneSettings(Settings):
    """Widths of the sidewalk zones and the clearances around crossings and junctions (m; see the
    module docstring). The curb strip's width is the street plan's own
    (:attr:`~navverse.city.geometry.street_plan.StreetPlan.curb_width`)."""

    clear_width: Annotated[float, Field(ge=0.8, le=5.0)] = 1.5
    """The walkway kept clear on sidewalks wide enough (the ADA/NACTO pedestrian through zone)."""
    min_clear: Annotated[float, Field(ge=0.8, le=5.0)] = 1.3
    """The walkway kept clear where ``clear_width`` does not fit (else the whole sidewalk)."""
    furniture_width: ZoneWidth = 0.9
    """Widest furniture zone, beside the curb."""
    frontage_width: ZoneWidth = 0.9
    """Widest frontage zone, by the facades."""
    min_zone_width: Annotated[float, Field(ge=0.0, le=2.0)] = 0.3
    """Narrowest furniture or frontage zone laid (a narrower one is left to the walkway)."""
    crosswalk_margin: Clearance = 1.0
    """Distance zones and parking bands keep from crosswalks."""
    corner_clearance: Clearance = 5.0
    """Distance parking bands and zones keep from a junction's carriageways."""
    driveway_margin: Clearance = 1.5
    """Distance parking bands keep beside a driveway (a service road joining the street)."""
    curbside_band: Annotated[float, Field(ge=1.5, le=4.0)] = 2.2
    """Width of an unmapped parking band along a residential curb."""
    curbside_min_width: RoadWidth = 6.0
    """Carriageway width from which a residential street has a parking band on its right curb."""
    curbside_both_width: RoadWidth = 9.0
    """Carriageway width from which a residential street has parking bands on both curbs."""
    verge_width: ZoneWidth = 1.2
    """Depth of the verge: open land beyond a sidewalk's outer edge where furniture may stand."""
    gap: Annotated[float, Field(ge=0.0, le=5.0)] = 0.3
    """Free space kept between a new object's footprint and the footprints already standing."""


@dataclass(frozen=True)
class StreetZones:
    """The zones of a city's streets (all in the scene frame, m).

    Attributes
    ----------
    furniture, walkway, frontage : BaseGeometry
        The three sidewalk zones; they tile the plan's sidewalk class.
    parking : BaseGeometry
        Mapped parking strips on the road.
    curbside : BaseGeometry
        Residential curb bands where parking is plausible (none where a strip is mapped).
    junctions : BaseGeometry
        Where carriageways of different roads meet, grown by ``corner_clearance``.
    verge : BaseGeometry
        Open land (ground, green, plaza) along the sidewalks' outer edges, ``verge_width`` deep:
        where furniture stands on streets whose sidewalks are too narrow for a furniture zone.
    """

    furniture: BaseGeometry
    walkway: BaseGeometry
    frontage: BaseGeometry
    parking: BaseGeometry
    curbside: BaseGeometry
    junctions: BaseGeometry
    verge: BaseGeometry


def _grow(geometry: BaseGeometry, distance: float) -> BaseGeometry:
    """``geometry`` grown by at least ``distance`` everywhere (its polygonal arcs circumscribe the circle)."""
    return geometry.buffer(distance / math.cos(math.pi / (4 * QUAD_SEGMENTS)), quad_segs=QUAD_SEGMENTS)


def _band(line: LineString, sign: float, inner: float, outer: float) -> BaseGeometry:
    """The strip between offsets ``inner`` and ``outer`` (m) on one side of ``line`` (+1 left, -1 right)."""
    if outer <= inner:
        return Polygon()

    def side(distance: float) -> BaseGeometry:
        if distance <= 0:
            return Polygon()
        return line.buffer(sign * distance, single_sided=True, join_style="round", quad_segs=QUAD_SEGMENTS)

    return side(outer).difference(side(inner))


def sidewalk_split(width: float, settings: ZoneSettings, *, curb_width: float) -> tuple[float, float]:
    """Furniture and frontage widths on a sidewalk ``width`` wide, ``curb_width`` of curb strip included."""
    usable = width - curb_width
    walk = (
        settings.clear_width
        if usable - settings.clear_width >= settings.min_zone_width
        else settings.min_clear
    )
    spare = usable - walk
    if spare < settings.min_zone_width:
        return 0.0, 0.0
    furniture = min(settings.furniture_width, spare)
    frontage = min(settings.frontage_width, spare - furniture)
    return furniture, (frontage if frontage >= settings.min_zone_width else 0.0)


def _junctions(city: CityMap, lanes: dict[str, BaseGeometry], grow: float) -> BaseGeometry:
    """Where carriageways of two roads meet (roads sharing an end joint included), grown by ``grow``."""
    ids = list(lanes)
    tree = STRtree([lanes[i] for i in ids])
    meets = []
    for a, road_id in enumerate(ids):
        for b in tree.query(lanes[road_id], predicate="intersects"):
            if b <= a:
                continue
            meets.append(lanes[road_id].intersection(lanes[ids[b]]))
    return snapped(_grow(union_of(meets), grow)) if meets else Polygon()


def _curbside(road: Road, sign: float, walk_width: float | None, settings: ZoneSettings) -> bool:
    """Whether cars plausibly park along this curb of an untagged residential street."""
    if road.highway not in CURBSIDE_HIGHWAYS or walk_width is None:
        return False
    if road.parking_left is not None or road.parking_right is not None:
        return False
    if road.width >= settings.curbside_both_width:
        return True
    return road.width >= settings.curbside_min_width and sign < 0


def street_zones(city: CityMap, plan: StreetPlan, settings: ZoneSettings | None = None) -> StreetZones:
    """Lay the sidewalk zones and parking bands of a city.

    Parameters
    ----------
    city : CityMap
        The map the plan was made from.
    plan : StreetPlan
        Its ground plan (:func:`~navverse.city.geometry.street_plan.street_plan`).
    settings : ZoneSettings, optional
        Zone widths and clearances.
    """
    settings = settings or ZoneSettings()
    classes = plan.classes
    sidewalk = classes["sidewalk"]
    road = classes["road"]
    crosswalks = classes["crosswalk"].union(classes["lowered_curb"])
    lanes = carriageways(city)
    junctions = _junctions(city, lanes, settings.corner_clearance)
    near_crossing = snapped(_grow(crosswalks, settings.crosswalk_margin))
    driveways = _grow(
        union_of([lanes[r.id] for r in city.roads if r.highway == "service"]), settings.driveway_margin
    )

    furniture, frontage, parking, curbside, verge = [], [], [], [], []
    for r in city.roads:
        line = LineString(r.centerline.points)
        half = r.width / 2.0
        shared = r.highway in SHARED_SURFACE_HIGHWAYS
        for sign, walk_width, park_width in (
            (1.0, r.sidewalk_left, r.parking_left),
            (-1.0, r.sidewalk_right, r.parking_right),
        ):
            if walk_width is not None and not shared:
                f_width, fr_width = sidewalk_split(walk_width, settings, curb_width=plan.curb_width)
                edge = r.sidewalk_edge(sign)  # beyond the carriageway and its cycle track
                start = edge + plan.curb_width
                furniture.append(_band(line, sign, start, start + f_width))
                frontage.append(_band(line, sign, edge + walk_width - fr_width, edge + walk_width))
                verge.append(_band(line, sign, edge + walk_width, edge + walk_width + settings.verge_width))
            if shared:
                continue
            if park_width is not None:
                parking.append(_band(line, sign, half - park_width, half))
            elif _curbside(r, sign, walk_width, settings):
                curbside.append(_band(line, sign, half - settings.curbside_band, half))
    keep_clear = union_of([near_crossing, junctions])
    furniture_zone = difference(intersection(union_of(furniture), sidewalk), keep_clear)
    frontage_zone = difference(
        difference(intersection(union_of(frontage), sidewalk), keep_clear), furniture_zone
    )
    walkway = difference(difference(sidewalk, furniture_zone), frontage_zone)
    open_land = union_of([classes["ground"], classes["green"], classes["plaza"]])
    verge_zone = difference(intersection(union_of(verge), open_land), keep_clear)
    on_road_clear = union_of([near_crossing, junctions, driveways])
    parking_zone = difference(intersection(union_of(parking), road), on_road_clear)
    curbside_zone = difference(
        difference(intersection(union_of(curbside), road), on_road_clear), parking_zone
    )
    return StreetZones(
        furniture=furniture_zone,
        walkway=walkway,
        frontage=frontage_zone,
        parking=parking_zone,
        curbside=curbside_zone,
        junctions=junctions,
        verge=verge_zone,
    )


def walkway_clearance(
    city: CityMap, zones: StreetZones, walkway: BaseGeometry | None = None, *, step: float = 5.0
) -> np.ndarray:
    """Clear walkway widths measured across every sidewalk (m), one per transect.

    Transects run across each road side's sidewalk every ``step`` meters, from the curb strip to
    the sidewalk's outer edge; those within 1 m of a junction zone, and those whose outer end is not
    on the walkway (another street's sidewalk or a building takes over there), are left out. The
    width is the length of the transect on ``walkway`` (by default the zones' own; pass the walkway
    minus whatever stands on it to measure what is left clear).
    """
    walkway = zones.walkway if walkway is None else walkway
    junctions = prep(zones.junctions.buffer(1.0))
    on_walkway = prep(walkway.buffer(1e-6))
    parts = [p for p in getattr(walkway, "geoms", [walkway]) if not p.is_empty]
    tree = STRtree(parts)
    widths = []
    for road in city.roads:
        if road.highway in SHARED_SURFACE_HIGHWAYS:
            continue
        line = LineString(road.centerline.points)
        for sign, width in ((1.0, road.sidewalk_left), (-1.0, road.sidewalk_right)):
            if width is None:
                continue
            for along in np.arange(step / 2.0, line.length - step / 2.0, step):
                edge = road.sidewalk_edge(sign)
                cut = _transect(line, float(along), sign, edge + 0.2, edge + width)
                if cut is None or junctions.intersects(cut):
                    continue
                if not on_walkway.contains(cut.interpolate(cut.length - 0.05)):
                    continue
                widths.append(sum(parts[int(i)].intersection(cut).length for i in tree.query(cut)))
    return np.asarray(widths, dtype=np.float64)


def _transect(line: LineString, along: float, sign: float, start: float, end: float) -> LineString | None:
    """The segment across ``line`` at ``along``, from ``start`` to ``end`` meters on one side."""
    ahead = line.interpolate(min(line.length, along + 0.5))
    behind = line.interpolate(max(0.0, along - 0.5))
    dx, dy = ahead.x - behind.x, ahead.y - behind.y
    norm = math.hypot(dx, dy)
    if norm == 0:
        return None
    here = line.interpolate(along)
    nx, ny = -dy / norm * sign, dx / norm * sign
    return LineString([(here.x + nx * start, here.y + ny * start), (here.x + nx * end, here.y + ny * end)])
