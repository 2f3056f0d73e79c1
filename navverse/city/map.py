"""The city map: what a city is made of, in a local metric frame, before any geometry.

One format, two producers: ``osm_city`` reads it from an OpenStreetMap file, ``synthetic_city``
draws it from a seed; the city geometry stage turns it into a scene. Everything downstream reads
only this, so synthetic cities exercise the same code as real ones.

Coordinates are meters in a local frame: x east, y north, origin at the map's ``frame`` origin
(a latitude/longitude projected with the recorded EPSG code; synthetic maps use EPSG 0 and origin
0, 0). Polygons are an exterior ring and holes, rings without the closing repeat. Every feature has
a map-wide unique ``id`` and, when it comes from OSM, the ``osm`` reference it was read from
(``way/123``); ``dropped`` counts what the producer left out, by reason.

The file is ``city_map.json`` (sorted keys, compact): the same map gives the same bytes.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from navverse.errors import NavverseError
from navverse.files import atomic_write

__all__ = [
    "CITY_MAP_FORMAT",
    "AreaClass",
    "Building",
    "CityMap",
    "CityMapError",
    "Crossing",
    "CrossingMarkings",
    "Frame",
    "LandArea",
    "Path2",
    "Poi",
    "Polygon2",
    "Road",
    "StreetFurniture",
    "Walkway",
    "read_city_map",
    "write_city_map",
]

CITY_MAP_FORMAT = "1.4"
"""Format of ``city_map.json``: a reader reads its own major version (1.1 added furniture ``shelter``,
1.2 building ``type`` and ``outline``, 1.3 road ``cycle_track_left`` / ``cycle_track_right``, 1.4
crossing ``markings``)."""
MAX_COORDINATE = 1e6
"""Largest |x| or |y| in a map (m): a city is far smaller; anything larger is a projection error."""

Coordinate = Annotated[float, Field(ge=-MAX_COORDINATE, le=MAX_COORDINATE, allow_inf_nan=False)]
Point2 = tuple[Coordinate, Coordinate]
Length = Annotated[float, Field(gt=0.0, le=10_000.0, allow_inf_nan=False)]
Height = Annotated[float, Field(ge=0.0, le=1000.0, allow_inf_nan=False)]
FeatureId = Annotated[str, Field(pattern=r"^[a-z][a-z0-9_]*-[0-9]+$")]
OsmRef = Annotated[str, Field(pattern=r"^(node|way|relation)/-?[0-9]+$")]
AreaClass = Literal["green", "water", "ground", "parking", "plaza", "pedestrian", "rail"]
"""Land classes: parks and lawns, water (not navigable), bare or unclassified open land, parking
areas, paved squares, pedestrian areas, railway track beds (not navigable). Open land that no area
covers is ``ground``."""
CrossingMarkings = Literal["zebra", "lines", "ladder", "dashes", "none"]
"""The paint on a crossing: zebra bars; two solid lines along its edges; ``ladder``: both; dashed edge
lines; ``none``: unpainted."""


class CityMapError(NavverseError):
    """A city map file that cannot be read, or a map that breaks the format's rules."""


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


def _ring(points: list[Point2], what: str) -> list[Point2]:
    distinct = {(round(x, 6), round(y, 6)) for x, y in points}
    if len(distinct) < 3:
        raise ValueError(f"{what} needs at least 3 distinct points")
    if points[0] == points[-1]:
        raise ValueError(f"{what} repeats its first point at the end; rings are written open")
    return points


class Polygon2(_Model):
    """A polygon: ``exterior`` ring and ``holes`` (courtyards), counter-clockwise or not."""

    exterior: list[Point2]
    holes: list[list[Point2]] = []

    @field_validator("exterior")
    @classmethod
    def _exterior(cls, value: list[Point2]) -> list[Point2]:
        return _ring(value, "an exterior ring")

    @field_validator("holes")
    @classmethod
    def _holes(cls, value: list[list[Point2]]) -> list[list[Point2]]:
        return [_ring(hole, "a hole") for hole in value]


class Path2(_Model):
    """A polyline of at least two distinct points."""

    points: list[Point2] = Field(min_length=2)

    @model_validator(mode="after")
    def _long_enough(self) -> Path2:
        if all(p == self.points[0] for p in self.points):
            raise ValueError("a path needs two distinct points")
        return self

    @property
    def length(self) -> float:
        """Length along the points (m)."""
        return sum(math.dist(a, b) for a, b in zip(self.points, self.points[1:], strict=False))


class Frame(_Model):
    """The local metric frame: EPSG code of the projection and the lat/lon of its origin."""

    epsg: Annotated[int, Field(ge=0, le=999_999)]
    origin_lat: Annotated[float, Field(ge=-90.0, le=90.0)]
    origin_lon: Annotated[float, Field(ge=-180.0, le=180.0)]


class Source(_Model):
    """Where the map came from: an OSM file (with its sha256 and attribution) or a synthetic seed."""

    kind: Literal["osm", "synthetic"]
    name: str
    sha256: Annotated[str, Field(pattern=r"^[0-9a-f]{64}$")] | None = None
    seed: Annotated[int, Field(ge=0)] | None = None
    attribution: str = ""


class Road(_Model):
    """A road way: its centre line, carriageway width and what lies on each side.

    ``sidewalk_left`` / ``sidewalk_right`` are widths (m) or None (none, or mapped as a separate
    walkway); left and right are as seen along the points. ``parking_left`` / ``parking_right``
    are widths of parking strips inside the carriageway edge (m) or None. ``cycle_track_left`` /
    ``cycle_track_right`` are widths of cycle tracks between the carriageway edge and the sidewalk, at
    sidewalk level behind the curb (m) or None.
    """

    id: FeatureId
    osm: OsmRef | None = None
    highway: str
    centerline: Path2
    width: Length
    width_source: Literal["width", "lanes", "default", "default one-way", "synthetic"]
    lanes: Annotated[int, Field(ge=0, le=20)] | None = None
    oneway: bool = False
    sidewalk_left: Length | None = None
    sidewalk_right: Length | None = None
    sidewalk_source: Literal["tags", "rule", "synthetic"] = "rule"
    parking_left: Length | None = None
    parking_right: Length | None = None
    cycle_track_left: Length | None = None
    cycle_track_right: Length | None = None
    kerb: Literal["raised", "lowered", "flush", "rolled"] | None = None
    surface: str | None = None
    name: str | None = None

    def sidewalk_edge(self, sign: float) -> float:
        """How far from the centre line the sidewalk on a side (``sign`` +1 left, -1 right) begins:
        the carriageway's half width, and the cycle track between them (m)."""
        track = self.cycle_track_left if sign > 0 else self.cycle_track_right
        return self.width / 2.0 + (track or 0.0)

    def reach(self) -> float:
        """How far the far edge of the road's wider side (carriageway, cycle track and sidewalk) is from
        its centre line (m)."""
        return max(
            self.sidewalk_edge(sign) + (walk or 0.0)
            for sign, walk in ((1.0, self.sidewalk_left), (-1.0, self.sidewalk_right))
        )


class Walkway(_Model):
    """A way walked on at sidewalk level: a mapped sidewalk, footway, path, steps or crossing."""

    id: FeatureId
    osm: OsmRef | None = None
    kind: Literal["sidewalk", "footway", "path", "steps", "crossing", "pedestrian", "cycleway"]
    centerline: Path2
    width: Length


class Crossing(_Model):
    """A pedestrian crossing where a road is crossed: at ``position``, across road ``road``, with the
    kerb at its ends and its ``markings`` (zebra in maps before format 1.4)."""

    id: FeatureId
    osm: OsmRef | None = None
    position: Point2
    road: FeatureId
    kerb: Literal["raised", "lowered", "flush", "rolled"] = "lowered"
    markings: CrossingMarkings = "zebra"


class LandArea(_Model):
    """An area of one land class."""

    id: FeatureId
    osm: OsmRef | None = None
    cls: AreaClass = Field(alias="class")
    polygon: Polygon2

    model_config = ConfigDict(extra="forbid", frozen=True, populate_by_name=True)


class Building(_Model):
    """A building footprint with its heights, entrances and what is in it (POIs refer to it).

    A building mapped in parts (``building:part``) is a feature per part, each naming the building's
    ``outline`` (and one for the rest of the outline no part covers, without it); ``type`` is the
    ``building=*`` value (``house``, ``apartments``, ``yes``...), for a part its building's.
    """

    id: FeatureId
    osm: OsmRef | None = None
    footprint: Polygon2
    height: Height
    base_height: Height = 0.0
    height_source: Literal["height", "levels", "drawn", "synthetic"]
    levels: Annotated[float, Field(ge=0.0, le=300.0)] | None = None
    entrances: list[Point2] = []
    name: str | None = None
    type: Annotated[str, Field(min_length=1, max_length=100)] | None = None
    outline: OsmRef | None = None

    @model_validator(mode="after")
    def _top_above_base(self) -> Building:
        if self.height <= self.base_height:
            raise ValueError(f"height {self.height} m must be above base_height {self.base_height} m")
        return self


class Poi(_Model):
    """A place of interest: its category (``cafe``, ``bank``...), name and the OSM tag it came from."""

    id: FeatureId
    osm: OsmRef | None = None
    position: Point2
    category: str
    tag: str
    name: str | None = None
    building: FeatureId | None = None


class StreetFurniture(_Model):
    """A mapped street object: a tree, lamp, bench, hydrant, bus stop... (``kind`` from its tag);
    ``shelter``: a bus stop with a shelter (``shelter=yes``)."""

    id: FeatureId
    osm: OsmRef | None = None
    position: Point2
    kind: str
    shelter: bool = False


class CityMap(_Model):
    """A whole city map (``city_map.json``)."""

    format_version: str = CITY_MAP_FORMAT
    source: Source
    frame: Frame
    window: tuple[Coordinate, Coordinate, Coordinate, Coordinate]
    roads: list[Road] = []
    walkways: list[Walkway] = []
    crossings: list[Crossing] = []
    areas: list[LandArea] = []
    buildings: list[Building] = []
    pois: list[Poi] = []
    furniture: list[StreetFurniture] = []
    dropped: dict[str, Annotated[int, Field(ge=1)]] = {}

    @field_validator("window")
    @classmethod
    def _window(cls, value: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
        min_x, min_y, max_x, max_y = value
        if not (min_x < max_x and min_y < max_y):
            raise ValueError("window is [min_x, min_y, max_x, max_y] with min < max")
        return value

    @model_validator(mode="after")
    def _references(self) -> CityMap:
        features = [*self.roads, *self.walkways, *self.crossings, *self.areas, *self.buildings]
        features += [*self.pois, *self.furniture]
        seen: set[str] = set()
        for feature in features:
            if feature.id in seen:
                raise ValueError(f"feature id {feature.id!r} is used twice")
            seen.add(feature.id)
        roads = {road.id for road in self.roads}
        for crossing in self.crossings:
            if crossing.road not in roads:
                raise ValueError(
                    f"crossing {crossing.id!r} names road {crossing.road!r}, which the map lacks"
                )
        buildings = {building.id for building in self.buildings}
        for poi in self.pois:
            if poi.building is not None and poi.building not in buildings:
                raise ValueError(f"poi {poi.id!r} names building {poi.building!r}, which the map lacks")
        return self


def write_city_map(city: CityMap, path: str | os.PathLike[str]) -> Path:
    """Write ``city`` as ``city_map.json`` (sorted keys, compact, atomically): same map, same bytes."""
    data = city.model_dump(mode="json", by_alias=True)
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)
    path = Path(path)
    with atomic_write(path) as handle:
        handle.write(text.encode())
    return path


def read_city_map(path: str | os.PathLike[str]) -> CityMap:
    """Read and validate a ``city_map.json``.

    Raises
    ------
    CityMapError
        If the file is missing, not JSON, of another major format version, or breaks the format.
    """
    path = Path(path)
    try:
        raw = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise CityMapError(f"city map {path} does not exist") from None
    except (OSError, ValueError) as exc:
        raise CityMapError(f"{path} is not a city map JSON file ({exc})") from None
    version = str(raw.get("format_version", "?")) if isinstance(raw, dict) else "?"
    if version.split(".")[0] != CITY_MAP_FORMAT.split(".")[0]:
        raise CityMapError(
            f"{path} is city map format {version}; this toolkit reads {CITY_MAP_FORMAT}: rebuild the city"
        )
    try:
        return CityMap.model_validate(raw)
    except ValidationError as exc:
        error = exc.errors()[0]
        where = ".".join(str(p) for p in error["loc"]) or "top level"
        raise CityMapError(f"{path} is not a valid city map: {where}: {error['msg']}") from None
