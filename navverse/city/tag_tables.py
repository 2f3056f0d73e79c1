"""Which OSM tags make which city map feature, and how their attributes read.

The tables here (land classes, places, street furniture, parking strips, the drawn heights of
untagged buildings) and the road and walkway classes of :data:`~navverse.city.tags.ROAD_CLASSES`
are summed up in :mod:`navverse.city.osm.reader`. Functions take a way's or node's tags and never raise;
those that meet a value they cannot use count it in a ``dropped`` counter, by reason.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Mapping

import numpy as np

from navverse.city.map import AreaClass, CrossingMarkings
from navverse.city.tags import ROAD_CLASSES, parse_length

__all__ = [
    "DRAWN_STOREYS",
    "FEATURE_KEYS",
    "FURNITURE",
    "LAND_CLASSES",
    "MAX_BUILDING_HEIGHT",
    "PARKING_WIDTHS",
    "POI_AMENITIES",
    "RAIL_WIDTHS",
    "ROAD_HIGHWAYS",
    "TYPE_RANK",
    "WALKWAY_HIGHWAYS",
    "WATERWAY_WIDTHS",
    "building_value",
    "count_problems",
    "crossing_markings",
    "drawn_storeys",
    "furniture_kind",
    "is_area",
    "is_oneway",
    "is_raised",
    "kerb_of",
    "land_class",
    "parking_sides",
    "poi_of",
    "tag_value",
    "text_value",
    "walkway_kind",
]

FEATURE_KEYS = (
    "highway",
    "building",
    "building:part",
    "landuse",
    "leisure",
    "natural",
    "waterway",
    "amenity",
    "place",
    "shop",
    "craft",
    "office",
    "emergency",
    "entrance",
    "railway",
)
"""Tag keys the reader keeps objects for; objects with none of them are skipped."""

ROAD_HIGHWAYS = frozenset(name for name, kind in ROAD_CLASSES.items() if kind.vehicles)
WALKWAY_HIGHWAYS = frozenset(name for name, kind in ROAD_CLASSES.items() if not kind.vehicles)

LAND_CLASSES: tuple[tuple[str, frozenset[str], AreaClass], ...] = (
    ("natural", frozenset({"water"}), "water"),
    ("waterway", frozenset({"riverbank"}), "water"),
    ("landuse", frozenset({"reservoir", "basin"}), "water"),
    ("amenity", frozenset({"parking"}), "parking"),
    ("place", frozenset({"square"}), "plaza"),
    ("highway", frozenset({"pedestrian"}), "plaza"),
    ("highway", frozenset({"footway"}), "pedestrian"),
    ("leisure", frozenset({"park", "garden", "pitch", "playground"}), "green"),
    ("landuse", frozenset({"grass", "meadow", "forest", "recreation_ground", "village_green"}), "green"),
    ("natural", frozenset({"wood", "scrub", "grassland"}), "green"),
    ("landuse", frozenset({"brownfield", "construction"}), "ground"),
    ("natural", frozenset({"bare_rock", "sand"}), "ground"),
)
"""Land classes by tag, the first match winning (highway areas only with ``area=yes`` on a way)."""

POI_AMENITIES = frozenset(
    {
        "bank",
        "bar",
        "biergarten",
        "bureau_de_change",
        "cafe",
        "car_rental",
        "cinema",
        "clinic",
        "college",
        "dentist",
        "doctors",
        "fast_food",
        "food_court",
        "ice_cream",
        "internet_cafe",
        "kindergarten",
        "library",
        "marketplace",
        "money_transfer",
        "nightclub",
        "payment_centre",
        "pharmacy",
        "post_office",
        "pub",
        "restaurant",
        "school",
        "theatre",
        "university",
        "veterinary",
    }
)
"""``amenity=*`` values that are places a pedestrian enters from the street (POIs)."""
_POI_KEYS = ("amenity", "shop", "craft", "office")

FURNITURE: tuple[tuple[str, frozenset[str]], ...] = (
    ("natural", frozenset({"tree"})),
    ("highway", frozenset({"street_lamp", "bus_stop", "traffic_signals"})),
    ("amenity", frozenset({"bench", "waste_basket", "bicycle_parking", "post_box", "vending_machine"})),
    ("emergency", frozenset({"fire_hydrant"})),
)
"""Street furniture by node tag: ``kind`` is the tag's value."""

PARKING_WIDTHS = {"parallel": 2.0, "diagonal": 4.5, "perpendicular": 5.0}
"""Width of a parking strip by orientation (m), unless ``parking:<side>:width`` says otherwise."""
_PARKING_NEW = frozenset({"lane", "street_side", "half_on_kerb", "shoulder", "yes"})
_PARKING_OLD = {
    "parallel": "parallel",
    "inline": "parallel",
    "marked": "parallel",
    "yes": "parallel",
    "diagonal": "diagonal",
    "perpendicular": "perpendicular",
    "orthogonal": "perpendicular",
}

DRAWN_STOREYS: tuple[tuple[frozenset[str], tuple[int, int]], ...] = (
    (
        frozenset({"garage", "garages", "shed", "hut", "carport", "kiosk", "cabin", "toilets", "service"}),
        (1, 1),
    ),
    (frozenset({"house", "detached", "semidetached_house", "terrace", "bungalow", "farm"}), (1, 2)),
    (frozenset({"industrial", "warehouse", "factory", "manufacture"}), (2, 3)),
    (
        frozenset(
            {"apartments", "commercial", "office", "retail", "hotel", "dormitory", "hospital", "civic"}
        ),
        (2, 5),
    ),
)
"""Storeys drawn for a building without ``height`` or ``building:levels``, by ``building=*`` value:
uniform whole numbers in the range; other values draw 1-3."""
_DEFAULT_STOREYS = (1, 3)
MAX_BUILDING_HEIGHT = 1000.0
"""Tallest building height read from tags (m); a taller one is a typo and gets a drawn height."""

_KERBS = {
    "raised": "raised",
    "lowered": "lowered",
    "flush": "flush",
    "rolled": "rolled",
    "no": "flush",
    "yes": "raised",
    "regular": "raised",
    "normal": "raised",
}
_MARKINGS: dict[str, CrossingMarkings] = {
    "no": "none",
    "yes": "zebra",
    "lines:dashed": "dashes",
    "dashes": "dashes",
    "dots": "dashes",
    "surface": "none",
    "pictograms": "none",
}
_MARKING_FAMILIES: tuple[tuple[str, CrossingMarkings], ...] = (
    ("zebra", "zebra"),
    ("lines", "lines"),
    ("ladder", "ladder"),
)  # crossing:markings=<family>* (zebra:double, lines:paired, ladder:skewed...)
_CROSSING_REFS: dict[str, CrossingMarkings] = {
    "zebra": "zebra",
    "pelican": "dashes",
    "toucan": "dashes",
    "puffin": "dashes",
    "pegasus": "dashes",
}
_CROSSING_KINDS: dict[str, CrossingMarkings] = {
    "zebra": "zebra",
    "marked": "zebra",
    "uncontrolled": "zebra",
    "traffic_signals": "lines",
    "unmarked": "none",
}
RAIL_WIDTHS = {
    "rail": 3.5,
    "light_rail": 3.0,
    "narrow_gauge": 3.0,
    "subway": 3.5,
    "funicular": 2.5,
    "preserved": 3.0,
    "monorail": 2.0,
}
"""Width of the ballast strip of a ``railway=*`` track at ground level (m): the track bed a robot must
not cross but at a level crossing (a road or footway over it). ``railway=tram`` is not here: trams
run in the street, level with it."""
WATERWAY_WIDTHS = {"river": 12.0, "canal": 8.0, "stream": 2.5, "ditch": 1.5, "drain": 1.5}
"""Width of a ``waterway=*`` line with no ``width`` tag (m); rivers mapped as areas are areas."""
TYPE_RANK = {"node": 0, "way": 1, "relation": 2}
"""Sort rank of OSM object types: features are numbered by (type, id, part)."""


def tag_value(tags: Mapping[str, str], key: str) -> str | None:
    """A tag's value, stripped and lower-case (None: not tagged)."""
    value = tags.get(key)
    return value.strip().lower() if value is not None else None


def text_value(value: str | None) -> str | None:
    """A free-text value (``name``, ``surface``) stripped, None when empty."""
    return (value.strip() or None) if value is not None else None


def is_area(tags: Mapping[str, str]) -> bool:
    """Whether a way is tagged ``area=yes`` (a highway area, not a line)."""
    return tag_value(tags, "area") == "yes"


def is_raised(tags: Mapping[str, str]) -> bool:
    """Whether a way is a bridge: ``bridge=*`` (not ``no``), ``man_made=bridge``, or ``layer`` above 0."""
    bridge = tag_value(tags, "bridge")
    if (bridge is not None and bridge not in ("no", "false", "0")) or tag_value(tags, "man_made") == "bridge":
        return True
    layer = (tags.get("layer") or "").strip()
    return layer.isdigit() and int(layer) > 0


def is_oneway(tags: Mapping[str, str]) -> bool:
    """Whether traffic runs one way (``oneway=yes|true|1|-1|reversible``, roundabouts)."""
    return tag_value(tags, "oneway") in ("yes", "true", "1", "-1", "reversible") or (
        tag_value(tags, "junction") == "roundabout"
    )


def count_problems(problems: Iterable[str], dropped: Counter[str]) -> None:
    """Count tag problems (``"<key>: <what>"`` from :mod:`navverse.city.tags`) by tag key."""
    for problem in dict.fromkeys(problems):
        key, sep, _ = problem.partition(": ")
        if sep and " " not in key:
            dropped[f"tag {key} not read cleanly (a rule or its first value used)"] += 1
        elif "not above the base" in problem:
            dropped["building base not below its top (base ignored)"] += 1
        else:
            dropped["tag not read cleanly"] += 1


def kerb_of(value: str | None, dropped: Counter[str], *, default: str | None) -> str | None:
    """The kerb of a ``kerb=*`` value (``no``: flush, ``yes``: raised); unknown values give ``default``."""
    if value is None:
        return default
    kerb = _KERBS.get(value.strip().lower())
    if kerb is None:
        dropped["unknown kerb value (default used)"] += 1
        return default
    return kerb


def crossing_markings(tags: Mapping[str, str], dropped: Counter[str]) -> CrossingMarkings:
    """The paint on a crossing node: by ``crossing:markings`` where it says (an unknown value is
    counted and passed over), else by ``crossing_ref`` (``zebra``; the signalled ``pelican``,
    ``toucan``, ``puffin``, ``pegasus``: dashes), else by ``crossing`` (``traffic_signals``: lines,
    ``unmarked``: none); zebra when none of them tells."""
    value = tag_value(tags, "crossing:markings")
    if value is not None:
        markings = _MARKINGS.get(value) or next(
            (paint for family, paint in _MARKING_FAMILIES if value.startswith(family)), None
        )
        if markings is not None:
            return markings
        dropped["unknown crossing:markings value (other crossing tags used)"] += 1
    reference = _CROSSING_REFS.get(tag_value(tags, "crossing_ref") or "")
    if reference is not None:
        return reference
    return _CROSSING_KINDS.get(tag_value(tags, "crossing") or "", "zebra")


def walkway_kind(tags: Mapping[str, str]) -> str | None:
    """The walkway kind of a way (None: not a walkway): sidewalk, crossing, footway, path, steps..."""
    highway = tag_value(tags, "highway")
    if highway not in WALKWAY_HIGHWAYS or is_area(tags):
        return None
    if highway in ("footway", "path"):
        sub = tag_value(tags, "footway")
        if sub in ("sidewalk", "crossing"):
            return sub
    return highway


def land_class(tags: Mapping[str, str], *, relation: bool) -> AreaClass | None:
    """The land class of a polygon's tags (None: none); buildings and underground parking have none."""
    if building_value(tags) is not None:
        return None
    for key, values, cls in LAND_CLASSES:
        if tag_value(tags, key) not in values:
            continue
        if key == "highway" and not (relation or is_area(tags)):
            continue
        if cls == "parking" and tag_value(tags, "parking") in ("underground", "multi-storey", "rooftop"):
            return None
        return cls
    return None


def building_value(tags: Mapping[str, str]) -> str | None:
    """The ``building=*`` value, or None when there is none or it is ``no``."""
    value = tag_value(tags, "building")
    return None if value in (None, "no") else value


def poi_of(tags: Mapping[str, str]) -> tuple[str, str] | None:
    """``(category, "key=value")`` of a place of interest (amenity, then shop, craft, office), or None."""
    for key in _POI_KEYS:
        value = tag_value(tags, key)
        if value is None or value in ("no", ""):
            continue
        if key == "amenity" and value not in POI_AMENITIES:
            continue
        return (key if value == "yes" else value), f"{key}={value}"
    return None


def furniture_kind(tags: Mapping[str, str]) -> str | None:
    """The street furniture kind of a node's tags (its tag value), or None."""
    for key, values in FURNITURE:
        value = tag_value(tags, key)
        if value in values:
            return value
    return None


def parking_sides(tags: Mapping[str, str], dropped: Counter[str]) -> tuple[float | None, float | None]:
    """Widths of the parking strips on the left and right (m; None: none), as seen along the way.

    Reads ``parking:<side>=lane|street_side|half_on_kerb|shoulder|yes`` with
    ``parking:<side>:orientation``, else the older ``parking:lane:<side>=parallel|diagonal|
    perpendicular|...`` (``both`` for either side); ``on_kerb``, ``no`` and ``separate`` give none.
    """
    widths: list[float | None] = []
    for side in ("left", "right"):
        new = tag_value(tags, f"parking:{side}") or tag_value(tags, "parking:both")
        if new is not None:
            orientation = None
            if new in _PARKING_NEW:
                orientation = (
                    tag_value(tags, f"parking:{side}:orientation")
                    or tag_value(tags, "parking:both:orientation")
                    or "parallel"
                )
        else:
            old = tag_value(tags, f"parking:lane:{side}") or tag_value(tags, "parking:lane:both")
            orientation = _PARKING_OLD.get(old) if old is not None else None
        if orientation is None:
            widths.append(None)
            continue
        width = None
        for key in (f"parking:{side}:width", "parking:both:width"):
            reading = parse_length(tags.get(key))
            if reading.problem:
                count_problems([f"{key}: {reading.problem}"], dropped)
            if reading.value is not None:
                width = reading.value
                break
        widths.append(width if width is not None else PARKING_WIDTHS.get(orientation, 2.0))
    return widths[0], widths[1]


def drawn_storeys(tags: Mapping[str, str], *, seed: int, osm_type: str, osm_id: int) -> int:
    """Storeys of an untagged building, drawn from :data:`DRAWN_STOREYS` with a generator seeded from
    ``seed`` and the OSM object (so the result does not depend on reading order)."""
    value = building_value(tags) or "yes"
    low, high = next((span for values, span in DRAWN_STOREYS if value in values), _DEFAULT_STOREYS)
    rng = np.random.default_rng([seed, TYPE_RANK[osm_type], int(osm_id < 0), abs(osm_id)])
    return int(rng.integers(low, high + 1))
