"""OpenStreetMap tags read as numbers and rules: lengths with units, counts, road widths, sidewalks.

OSM values are free text written by people: ``width=3 m``, ``width=12'6"``, ``width=3,5``,
``lanes=2;3``, ``width=variable``. Every reader here returns a value *and* what was wrong with the
text (a :class:`Reading`), never raises, and never returns a negative, NaN or infinite number, so a
city builder can use the value or fall back to a rule and count the reason.

Road widths follow the tag, then ``lanes`` × the class's lane width, then the class's default
(:data:`ROAD_CLASSES`; one-way ways without ``lanes`` get one lane's width more than half the
default; service roads by their ``service=*`` kind, :data:`SERVICE_WIDTHS`); painted cycle lanes add
:data:`CYCLE_LANE_WIDTH` each to a width not tagged; cycle tracks lie beside the carriageway
(:func:`cycle_tracks`). Sidewalks follow ``sidewalk=*`` and
``sidewalk:<side>=*`` (``separate``: mapped as its own way, so none is inferred), else the class's
rule. The defaults are the common values of the
highway classes as mapped in OSM: lanes of 3.0–3.5 m (2.5 m on service roads), sidewalks of 1.5 m,
none beside motorways, service roads, tracks, cycleways and paths.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass

__all__ = [
    "CYCLE_LANE_WIDTH",
    "CYCLE_TRACK_WIDTH",
    "DEFAULT_SIDEWALK_WIDTH",
    "MAX_LENGTH",
    "PASSAGE_CLEARANCE",
    "ROAD_CLASSES",
    "SERVICE_WIDTHS",
    "STOREY_HEIGHT",
    "Reading",
    "RoadClass",
    "SidewalkSides",
    "at_ground_level",
    "building_height",
    "cycle_tracks",
    "is_passage",
    "parse_count",
    "parse_length",
    "passage_clearance",
    "road_width",
    "sidewalks",
]

MAX_LENGTH = 10_000.0
"""Longest length accepted from a tag (m); a larger one is a typo or another unit."""
DEFAULT_SIDEWALK_WIDTH = 1.5
"""Width of a sidewalk whose width is not tagged (m)."""
STOREY_HEIGHT = 3.0
"""Height of one ``building:levels`` storey (m)."""
PASSAGE_CLEARANCE = 3.5
"""Headroom of a building passage whose ``maxheight`` is not tagged (m)."""

_UNITS = {
    "": 1.0,
    "m": 1.0,
    "meter": 1.0,
    "meters": 1.0,
    "metre": 1.0,
    "metres": 1.0,
    "cm": 0.01,
    "mm": 0.001,
    "km": 1000.0,
    "ft": 0.3048,
    "feet": 0.3048,
    "foot": 0.3048,
    "'": 0.3048,
    "in": 0.0254,
    "inch": 0.0254,
    "inches": 0.0254,
    '"': 0.0254,
    "mi": 1609.344,
}
_NUMBER = r"[0-9]+(?:[.,][0-9]+)?|[.,][0-9]+"
_FEET_INCHES = re.compile(rf"^({_NUMBER})\s*(?:'|ft)\s*({_NUMBER})\s*(?:\"|in)$")
_VALUE_UNIT = re.compile(rf"^({_NUMBER})\s*([a-z'\"]*)$")
_UNKNOWN = frozenset({"variable", "unknown", "default", "none", "no", "n/a", "?", "fixme"})


@dataclass(frozen=True)
class Reading:
    """A tag read as a number: ``value`` (None when unusable) and ``problem`` (None when clean).

    A value can come with a problem: ``5;6`` reads as 5 with "several values; the first is used".
    """

    value: float | None
    problem: str | None = None


def _number(text: str) -> float:
    return float(text.replace(",", "."))


def parse_length(text: object) -> Reading:
    """A length tag (``width``, ``height``, ``sidewalk:width``...) in meters.

    Accepts a number (decimal point or comma) with an optional unit (m, cm, mm, km, ft, ', in, ",
    mi), feet and inches (``12'6"``), a leading ``~``; takes the first of ``;``-separated values.
    Words such as ``variable`` or ``unknown``, negative, zero, non-finite and implausibly large
    (> :data:`MAX_LENGTH`) values give no value.
    """
    if text is None:
        return Reading(None, None)
    raw = str(text).strip().lower()
    if not raw:
        return Reading(None, "empty value")
    first, *others = (part.strip() for part in raw.split(";"))
    note = "several values; the first is used" if others else None
    first = first.lstrip("~≈ ").strip()
    if first in _UNKNOWN:
        return Reading(None, f"{text!r} is not a length")
    match = _FEET_INCHES.match(first)
    if match:
        value = _number(match.group(1)) * 0.3048 + _number(match.group(2)) * 0.0254
    else:
        match = _VALUE_UNIT.match(first)
        if match is None or match.group(2) not in _UNITS:
            return Reading(
                None, f"{text!r} is not a length (a number with an optional unit: 3.5, 3.5 m, 12')"
            )
        value = _number(match.group(1)) * _UNITS[match.group(2)]
    if not math.isfinite(value) or value <= 0.0:
        return Reading(None, f"{text!r} is not a positive length")
    if value > MAX_LENGTH:
        return Reading(None, f"{text!r} is longer than {MAX_LENGTH:g} m")
    return Reading(value, note)


def parse_count(text: object, *, integer: bool = True, limit: float = 1000.0) -> Reading:
    """A count tag (``lanes``, ``building:levels``): a non-negative number up to ``limit``.

    ``integer=False`` accepts fractions (``building:levels=1.5``: a half storey under the roof).
    The first of ``;``-separated values is used.
    """
    if text is None:
        return Reading(None, None)
    raw = str(text).strip()
    if not raw:
        return Reading(None, "empty value")
    first, *others = (part.strip() for part in raw.split(";"))
    note = "several values; the first is used" if others else None
    pattern = r"[0-9]+" if integer else _NUMBER
    if re.fullmatch(pattern, first) is None:
        kind = "a whole number" if integer else "a number"
        return Reading(None, f"{text!r} is not {kind}")
    value = _number(first)
    if not math.isfinite(value) or value > limit:
        return Reading(None, f"{text!r} is more than {limit:g}")
    return Reading(value, note)


@dataclass(frozen=True)
class RoadClass:
    """Defaults of one ``highway=*`` class.

    Attributes
    ----------
    width : float
        Carriageway width when neither ``width`` nor ``lanes`` is tagged (m).
    lane_width : float
        Width of one lane (m).
    sidewalks : bool
        Whether an untagged way of this class has a sidewalk on both sides.
    vehicles : bool
        Whether cars drive on it (a carriageway below the curb); False for footways and paths,
        which are walkable surfaces at sidewalk level.
    """

    width: float
    lane_width: float
    sidewalks: bool
    vehicles: bool = True


ROAD_CLASSES: dict[str, RoadClass] = {
    "motorway": RoadClass(11.0, 3.5, sidewalks=False),
    "motorway_link": RoadClass(5.0, 3.5, sidewalks=False),
    "trunk": RoadClass(10.0, 3.5, sidewalks=True),
    "trunk_link": RoadClass(5.0, 3.5, sidewalks=True),
    "primary": RoadClass(8.0, 3.5, sidewalks=True),
    "primary_link": RoadClass(4.5, 3.5, sidewalks=True),
    "secondary": RoadClass(7.0, 3.25, sidewalks=True),
    "secondary_link": RoadClass(4.5, 3.25, sidewalks=True),
    "tertiary": RoadClass(6.5, 3.0, sidewalks=True),
    "tertiary_link": RoadClass(4.0, 3.0, sidewalks=True),
    "unclassified": RoadClass(6.0, 3.0, sidewalks=True),
    "residential": RoadClass(6.5, 3.0, sidewalks=True),
    "living_street": RoadClass(5.0, 3.0, sidewalks=False),
    "road": RoadClass(6.0, 3.0, sidewalks=True),
    "service": RoadClass(4.0, 2.5, sidewalks=False),
    "track": RoadClass(3.0, 2.5, sidewalks=False),
    "busway": RoadClass(7.0, 3.5, sidewalks=False),
    "pedestrian": RoadClass(5.0, 2.5, sidewalks=False, vehicles=False),
    "footway": RoadClass(2.0, 2.0, sidewalks=False, vehicles=False),
    "path": RoadClass(1.5, 1.5, sidewalks=False, vehicles=False),
    "cycleway": RoadClass(2.0, 2.0, sidewalks=False, vehicles=False),
    "steps": RoadClass(1.5, 1.5, sidewalks=False, vehicles=False),
}
"""Defaults per ``highway=*`` value (widths in m). Sidewalks are inferred on both sides of residential
and larger roads; not beside motorways, service roads, tracks, living streets (shared surfaces) or
busways; footways, paths, cycleways, steps and pedestrian streets are themselves walked on."""


SERVICE_WIDTHS = {
    "parking_aisle": 5.5,
    "driveway": 3.0,
    "alley": 3.5,
    "drive-through": 3.0,
    "emergency_access": 3.5,
}
"""Carriageway of an untagged ``highway=service`` way by its ``service=*`` kind (m): a parking aisle lets
two cars pass between the bays, a driveway one."""
CYCLE_LANE_WIDTH = 1.5
"""Width a painted cycle lane (``cycleway[:side]=lane``) adds to a carriageway measured by its lanes (m)."""
CYCLE_TRACK_WIDTH = 1.8
"""Width of a cycle track beside the carriageway (``cycleway[:side]=track``) whose width is not tagged (m)."""
_TRACKS = ("track", "opposite_track")


def _is_yes(value: str | None) -> bool:
    return value is not None and value.strip().lower() not in ("no", "false", "0", "")


def _oneway(tags: Mapping[str, str]) -> bool:
    value = tags.get("oneway", "").strip().lower()
    return value in ("yes", "true", "1", "-1", "reversible") or tags.get("junction") == "roundabout"


def road_width(tags: Mapping[str, str]) -> tuple[float, str, list[str]]:
    """Carriageway width of a road way (m), what it came from, and problems with its tags.

    Parameters
    ----------
    tags : mapping
        The way's tags; ``highway`` names its class (unknown classes use ``road``'s defaults).

    Returns
    -------
    tuple of (float, str, list of str)
        The width; ``"width"``, ``"lanes"``, ``"default"`` or ``"default one-way"``; the problems
        of unreadable ``width`` / ``lanes`` values (each falls back to the next rule).
    """
    kind = ROAD_CLASSES.get(tags.get("highway", ""), ROAD_CLASSES["road"])
    problems = []
    for key in ("width", "est_width"):
        reading = parse_length(tags.get(key))
        if reading.problem:
            problems.append(f"{key}: {reading.problem}")
        if reading.value is not None:
            return reading.value, "width", problems
    lanes = parse_count(tags.get("lanes"), limit=20)
    if lanes.problem:
        problems.append(f"lanes: {lanes.problem}")
    cycle_lanes = _cycle_lanes(tags) * CYCLE_LANE_WIDTH
    if lanes.value:
        return lanes.value * kind.lane_width + cycle_lanes, "lanes", problems
    service = tags.get("service", "").strip().lower()
    if tags.get("highway") == "service" and service in SERVICE_WIDTHS:
        return SERVICE_WIDTHS[service], "default", problems
    if _oneway(tags) and kind.vehicles:
        return max(kind.lane_width, kind.width / 2.0) + cycle_lanes, "default one-way", problems
    return kind.width + cycle_lanes, "default", problems


def _cycle_lanes(tags: Mapping[str, str]) -> int:
    """Painted cycle lanes in the carriageway (0-2): ``cycleway=lane`` (both sides, one on a one-way
    road), ``cycleway:both=lane``, ``cycleway:left|right=lane``."""
    lane = ("lane",)
    if tags.get("cycleway:both", "").strip().lower() in lane:
        return 2
    sides = sum(tags.get(f"cycleway:{side}", "").strip().lower() in lane for side in ("left", "right"))
    if sides:
        return sides
    if tags.get("cycleway", "").strip().lower() in lane:
        return 1 if _oneway(tags) else 2
    return 0


def cycle_tracks(tags: Mapping[str, str]) -> tuple[float | None, float | None, tuple[str, ...]]:
    """Cycle tracks beside a road's carriageway, kerb-separated at sidewalk level: (left, right) widths
    (m; None: none) and problems with the width tags.

    ``cycleway:left|right=track`` name a side, ``cycleway:both=track`` both; ``cycleway=track`` is
    both sides of a two-way road and the right of a one-way one, ``cycleway=opposite_track`` the
    left. Widths come from ``cycleway:<side>:width``, ``cycleway:both:width``, ``cycleway:width``,
    else :data:`CYCLE_TRACK_WIDTH`. Tracks mapped as ways of their own (``separate``) add nothing.
    """

    def value(key: str) -> str:
        return (tags.get(key) or "").strip().lower()

    sides = {side: value(f"cycleway:{side}") in _TRACKS for side in ("left", "right")}
    if value("cycleway:both") in _TRACKS:
        sides = {"left": True, "right": True}
    elif not any(sides.values()):
        plain, against = value("cycleway"), value("oneway") == "-1"  # traffic against the way's points
        with_traffic = "left" if against else "right"
        sides = {
            side: (plain == "track" and (side == with_traffic or not _oneway(tags)))
            or (plain == "opposite_track" and side != with_traffic)
            for side in ("left", "right")
        }
    problems: list[str] = []
    widths = {
        side: (_side_width(tags, "cycleway", side, problems) or CYCLE_TRACK_WIDTH) if tracked else None
        for side, tracked in sides.items()
    }
    return widths["left"], widths["right"], tuple(dict.fromkeys(problems))


def _side_width(tags: Mapping[str, str], key: str, side: str, problems: list[str]) -> float | None:
    """The width of ``key`` on a side: ``<key>:<side>:width``, ``<key>:both:width``, ``<key>:width``
    (the first readable one), noting unreadable ones in ``problems``."""
    for name in (f"{key}:{side}:width", f"{key}:both:width", f"{key}:width"):
        reading = parse_length(tags.get(name))
        if reading.problem:
            problems.append(f"{name}: {reading.problem}")
        if reading.value is not None:
            return reading.value
    return None


@dataclass(frozen=True)
class SidewalkSides:
    """Sidewalk widths on each side of a way (m; None: no sidewalk), and why.

    ``separate`` sides are mapped as their own ``footway=sidewalk`` ways: nothing is added here.
    """

    left: float | None
    right: float | None
    source: str
    problems: tuple[str, ...] = ()


def _side_value(tags: Mapping[str, str], side: str) -> str | None:
    """``yes``/``no``/``separate`` for one side, from ``sidewalk:<side>``, ``sidewalk:both``, ``sidewalk``."""
    specific = tags.get(f"sidewalk:{side}") or tags.get("sidewalk:both")
    if specific is not None:
        value = specific.strip().lower()
        return "separate" if value == "separate" else ("yes" if _is_yes(value) else "no")
    general = tags.get("sidewalk")
    if general is None:
        return None
    value = general.strip().lower()
    if value == "separate":
        return "separate"
    if value in ("both", "yes"):
        return "yes"
    if value in ("left", "right"):
        return "yes" if value == side else "no"
    return "no"  # no, none, and values that say nothing usable


def sidewalks(tags: Mapping[str, str]) -> SidewalkSides:
    """Where a road way has sidewalks, and how wide: the tags first, else the class's rule.

    Widths come from ``sidewalk:<side>:width``, ``sidewalk:both:width``, ``sidewalk:width``, else
    :data:`DEFAULT_SIDEWALK_WIDTH`. A way tagged ``foot=no`` has none unless a side is tagged.
    """
    problems: list[str] = []
    widths = {
        side: width
        for side in ("left", "right")
        if (width := _side_width(tags, "sidewalk", side, problems)) is not None
    }
    sides = {side: _side_value(tags, side) for side in ("left", "right")}
    if all(value is None for value in sides.values()):
        kind = ROAD_CLASSES.get(tags.get("highway", ""), ROAD_CLASSES["road"])
        inferred = kind.sidewalks and kind.vehicles and tags.get("foot") != "no"
        inferred = inferred and tags.get("junction") != "roundabout"
        width = {side: widths.get(side, DEFAULT_SIDEWALK_WIDTH) if inferred else None for side in sides}
        return SidewalkSides(width["left"], width["right"], "rule", tuple(dict.fromkeys(problems)))
    width = {
        side: widths.get(side, DEFAULT_SIDEWALK_WIDTH) if sides[side] == "yes" else None for side in sides
    }
    return SidewalkSides(width["left"], width["right"], "tags", tuple(dict.fromkeys(problems)))


PASSAGE_COVERS = frozenset({"yes", "arcade", "colonnade"})
"""``covered=*`` values of a way that runs at ground level under a roof or a building's upper floors."""


def is_passage(tags: Mapping[str, str]) -> bool:
    """Whether a way runs at ground level under a building: ``tunnel=building_passage`` or
    ``covered=yes|arcade|colonnade``."""
    tunnel = (tags.get("tunnel") or "").strip().lower()
    return tunnel == "building_passage" or (tags.get("covered") or "").strip().lower() in PASSAGE_COVERS


def passage_clearance(tags: Mapping[str, str]) -> float:
    """Headroom over a building passage: its ``maxheight`` in metres, else :data:`PASSAGE_CLEARANCE`
    (``none``, ``default`` and unreadable values say nothing of the height)."""
    reading = parse_length(tags.get("maxheight"))
    return reading.value if reading.value is not None and reading.value > 0.0 else PASSAGE_CLEARANCE


def _below_zero(value: str | None) -> bool:
    return re.fullmatch(r"-[0-9]+(\.[0-9]+)?", (value or "").strip()) is not None


def at_ground_level(tags: Mapping[str, str]) -> bool:
    """False for ways below the ground: tunnels, ``layer`` < 0, ``level`` < 0.

    A building passage (:func:`is_passage`) is at ground level whatever its ``layer``: mappers give
    passages ``layer=-1`` to say they run under the building, not under the street.
    """
    if _below_zero(tags.get("level")):
        return False
    if is_passage(tags):
        return True
    return not _is_yes(tags.get("tunnel")) and not _below_zero(tags.get("layer"))


def building_height(tags: Mapping[str, str]) -> tuple[float | None, float, str, list[str]]:
    """Height and base height of a building (part) from its tags.

    ``height`` wins over ``building:levels`` × :data:`STOREY_HEIGHT` (+ ``roof:height``, or
    ``roof:levels`` storeys); the base is ``min_height``, else ``building:min_level`` storeys, else 0.

    Returns
    -------
    tuple of (float or None, float, str, list of str)
        Height above the ground of the top (None: not tagged, so the caller draws one); base height;
        ``"height"``, ``"levels"`` or ``"untagged"``; problems with the tags.
    """
    problems: list[str] = []

    def length(key: str) -> float | None:
        reading = parse_length(tags.get(key))
        if reading.problem:
            problems.append(f"{key}: {reading.problem}")
        return reading.value

    def levels(key: str) -> float | None:
        reading = parse_count(tags.get(key), integer=False, limit=300)
        if reading.problem:
            problems.append(f"{key}: {reading.problem}")
        return reading.value

    base = length("min_height")
    if base is None:
        min_level = levels("building:min_level")
        base = min_level * STOREY_HEIGHT if min_level is not None else 0.0
    height = length("height")
    if height is not None:
        source = "height"
    else:
        storeys = levels("building:levels")
        if storeys is None or storeys == 0:
            return None, base, "untagged", problems
        roof = length("roof:height")
        if roof is None:
            roof_levels = levels("roof:levels")
            roof = roof_levels * STOREY_HEIGHT if roof_levels is not None else 0.0
        height, source = storeys * STOREY_HEIGHT + roof, "levels"
    if height <= base:
        problems.append(f"height {height:g} m is not above the base {base:g} m; the base is ignored")
        base = 0.0
    return height, base, source, problems
