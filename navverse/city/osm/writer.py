"""Writing a city map as an OpenStreetMap XML file, so that OSM tools (osmnx, JOSM) can open it.

Coordinates go from the map's local frame to latitude/longitude through an azimuthal equidistant
projection centred on the frame's origin (a synthetic map's origin is 0°, 0°). Roads become
``highway`` ways with ``lanes``, ``width``, ``oneway`` and ``sidewalk`` tags, crossings
``highway=crossing`` nodes inserted into the road they cross (with ``kerb``, and
``crossing:markings`` unless zebra: ``no`` for none), buildings ``building=yes`` ways with
``height`` and ``building:levels``, land areas closed ways of the tag their class comes from.
Shared points become one node, ids count up from 1 in a fixed order: the same map gives the same
bytes.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from pathlib import Path
from xml.sax.saxutils import quoteattr

from pyproj import Transformer
from shapely.geometry import LineString, Point

from navverse.city.map import CityMap, Crossing, Road
from navverse.files import atomic_write

__all__ = ["AREA_TAGS", "write_osm"]

AREA_TAGS = {
    "green": {"leisure": "park"},
    "water": {"natural": "water"},
    "ground": {"landuse": "brownfield"},
    "parking": {"amenity": "parking"},
    "plaza": {"place": "square", "highway": "pedestrian", "area": "yes"},
    "pedestrian": {"highway": "pedestrian", "area": "yes"},
}
"""The OSM tags written for each land class."""


class _Nodes:
    """Node ids by (rounded) local coordinate, with the tags of tagged nodes."""

    def __init__(self) -> None:
        self.ids: dict[tuple[float, float], int] = {}
        self.tags: dict[int, dict[str, str]] = {}

    def id(self, point: tuple[float, float], tags: dict[str, str] | None = None) -> int:
        key = (round(point[0], 3), round(point[1], 3))
        node = self.ids.setdefault(key, len(self.ids) + 1)
        if tags:
            self.tags.setdefault(node, {}).update(tags)
        return node


def _road_tags(road: Road) -> dict[str, str]:
    tags = {"highway": road.highway, "width": f"{road.width:g}"}
    if road.lanes is not None:
        tags["lanes"] = str(road.lanes)
    if road.oneway:
        tags["oneway"] = "yes"
    sides = {"left": road.sidewalk_left, "right": road.sidewalk_right}
    present = [side for side, width in sides.items() if width is not None]
    tags["sidewalk"] = {0: "no", 1: present[0] if present else "no", 2: "both"}[len(present)]
    for side in present:
        tags[f"sidewalk:{side}:width"] = f"{sides[side]:g}"
    for side, track in (("left", road.cycle_track_left), ("right", road.cycle_track_right)):
        if track is not None:
            tags[f"cycleway:{side}"] = "track"
            tags[f"cycleway:{side}:width"] = f"{track:g}"
    if road.name:
        tags["name"] = road.name
    return tags


def _crossing_tags(crossing: Crossing) -> dict[str, str]:
    """A crossing node's tags: ``crossing:markings`` only where they are not zebra, which a reader
    takes for a crossing that does not say."""
    tags = {"highway": "crossing", "kerb": crossing.kerb}
    if crossing.markings != "zebra":
        tags["crossing:markings"] = "no" if crossing.markings == "none" else crossing.markings
    return tags


def _road_points(road: Road, crossings: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The road's points with its crossings inserted in order along it."""
    line = LineString(road.centerline.points)
    stations = [(line.project(Point(p)), 0, p) for p in road.centerline.points]
    stations += [(line.project(Point(p)), 1, p) for p in crossings]
    return [point for _, _, point in sorted(stations)]


def _xml(city: CityMap) -> Iterator[str]:
    nodes = _Nodes()
    ways: list[tuple[list[int], dict[str, str]]] = []
    crossings_of: dict[str, list[tuple[float, float]]] = {}
    for crossing in city.crossings:
        crossings_of.setdefault(crossing.road, []).append(crossing.position)
        nodes.id(crossing.position, _crossing_tags(crossing))
    for road in city.roads:
        points = _road_points(road, crossings_of.get(road.id, []))
        ways.append(([nodes.id(p) for p in points], _road_tags(road)))
    for building in city.buildings:
        ring = [nodes.id(p) for p in building.footprint.exterior]
        tags = {"building": "yes", "height": f"{building.height:g}"}
        if building.levels is not None:
            tags["building:levels"] = f"{building.levels:g}"
        ways.append(([*ring, ring[0]], tags))
    for area in city.areas:
        ring = [nodes.id(p) for p in area.polygon.exterior]
        ways.append(([*ring, ring[0]], dict(AREA_TAGS[area.cls])))
    to_geographic = Transformer.from_crs(
        f"+proj=aeqd +lat_0={city.frame.origin_lat} +lon_0={city.frame.origin_lon} +datum=WGS84 +units=m",
        "EPSG:4326",
        always_xy=True,
    )
    yield "<?xml version='1.0' encoding='UTF-8'?>\n"
    yield '<osm version="0.6" generator="navverse">\n'
    min_x, min_y, max_x, max_y = city.window
    corners = [to_geographic.transform(x, y) for x in (min_x, max_x) for y in (min_y, max_y)]
    lons, lats = [lon for lon, _ in corners], [lat for _, lat in corners]
    yield (
        f'  <bounds minlat="{min(lats):.8f}" minlon="{min(lons):.8f}" '
        f'maxlat="{max(lats):.8f}" maxlon="{max(lons):.8f}"/>\n'
    )
    for (x, y), node in sorted(nodes.ids.items(), key=lambda item: item[1]):
        lon, lat = to_geographic.transform(x, y)
        tags = nodes.tags.get(node)
        head = f'  <node id="{node}" version="1" lat="{lat:.8f}" lon="{lon:.8f}"'
        yield head + (">\n" + "".join(_tag_lines(tags)) + "  </node>\n" if tags else "/>\n")
    for index, (refs, tags) in enumerate(ways, start=1):
        yield f'  <way id="{index}" version="1">\n'
        yield "".join(f'    <nd ref="{ref}"/>\n' for ref in refs)
        yield "".join(_tag_lines(tags))
        yield "  </way>\n"
    yield "</osm>\n"


def _tag_lines(tags: dict[str, str] | None) -> Iterable[str]:
    return [f"    <tag k={quoteattr(k)} v={quoteattr(v)}/>\n" for k, v in sorted((tags or {}).items())]


def write_osm(city: CityMap, path: str | os.PathLike[str]) -> Path:
    """Write ``city`` as OSM XML at ``path`` (atomically); returns the path."""
    path = Path(path)
    with atomic_write(path, mode="w") as handle:
        for chunk in _xml(city):
            handle.write(chunk)
    return path
