"""From the OSM objects of a window to numbered city map features, clipped, repaired, counted.

What each feature is made from is summed up in :mod:`navverse.city.osm.reader` (the tag tables are in
:mod:`.osm_classes`). Every builder here counts what it leaves out or repairs in ``dropped``, by
reason, and numbers features in the order (OSM type, OSM id, part), so the same input gives the
same map.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from shapely.geometry import MultiPolygon, Point, Polygon
from shapely.geometry.base import BaseGeometry
from shapely.strtree import STRtree

from navverse.city.map import (
    Building,
    Crossing,
    LandArea,
    Path2,
    Poi,
    Road,
    StreetFurniture,
    Walkway,
)
from navverse.city.osm.geometry import (
    DEGENERATE,
    Rect,
    as_line,
    clip_line_pieces,
    clip_polygon,
    polygon2,
    repaired,
    ring_polygon,
)
from navverse.city.osm.stream import OsmExtract, OsmMultipolygon, OsmWay
from navverse.city.tag_tables import (
    MAX_BUILDING_HEIGHT,
    ROAD_HIGHWAYS,
    TYPE_RANK,
    building_value,
    count_problems,
    drawn_storeys,
    furniture_kind,
    is_area,
    is_oneway,
    kerb_of,
    land_class,
    parking_sides,
    poi_of,
    tag_value,
    text_value,
    walkway_kind,
)
from navverse.city.tags import (
    ROAD_CLASSES,
    STOREY_HEIGHT,
    at_ground_level,
    building_height,
    parse_count,
    parse_length,
    road_width,
    sidewalks,
)

__all__ = ["Features", "build_features"]

_DUPLICATE_OUTLINE = "way repeating its multipolygon's outline (the multipolygon is kept)"
Key = tuple[int, int, int]


@dataclass
class Features:
    """The features of a map, numbered, and what was dropped or repaired by reason."""

    roads: list[Road] = field(default_factory=list)
    walkways: list[Walkway] = field(default_factory=list)
    crossings: list[Crossing] = field(default_factory=list)
    areas: list[LandArea] = field(default_factory=list)
    buildings: list[Building] = field(default_factory=list)
    pois: list[Poi] = field(default_factory=list)
    furniture: list[StreetFurniture] = field(default_factory=list)
    dropped: Counter[str] = field(default_factory=Counter)


def _numbered(drafts: list[tuple[Key, dict[str, Any]]], prefix: str, model: Any) -> list[Any]:
    drafts.sort(key=lambda draft: draft[0])
    return [model(id=f"{prefix}-{n}", **fields) for n, (_, fields) in enumerate(drafts, 1)]


@dataclass
class _Outline:
    """A polygon source (closed way or multipolygon) of one kind: a building or a land class."""

    osm_type: str
    osm_id: int
    tags: dict[str, str]
    kind: str
    geometry: BaseGeometry
    refs: frozenset[int]

    @property
    def key(self) -> tuple[int, int]:
        """(type rank, OSM id): the order features are numbered in."""
        return TYPE_RANK[self.osm_type], self.osm_id


class _Builder:
    def __init__(self, extract: OsmExtract, rect: Rect, seed: int) -> None:
        self.extract, self.rect, self.seed = extract, rect, seed
        self.dropped: Counter[str] = Counter(extract.dropped)
        self.ways = [extract.ways[i] for i in sorted(extract.ways)]
        self.nodes = [extract.nodes[i] for i in sorted(extract.nodes)]

    # Lines ---------------------------------------------------------------------------------------

    def _road_fields(self, way: OsmWay) -> tuple[dict[str, Any], bool]:
        tags = way.tags
        width, width_source, problems = road_width(tags)
        sides = sidewalks(tags)
        lanes = parse_count(tags.get("lanes"), limit=20)
        problems = [*problems, *sides.problems] + ([f"lanes: {lanes.problem}"] if lanes.problem else [])
        count_problems(problems, self.dropped)
        parking_left, parking_right = parking_sides(tags, self.dropped)
        fields: dict[str, Any] = {
            "osm": f"way/{way.id}",
            "highway": tag_value(tags, "highway"),
            "width": width,
            "width_source": width_source,
            "lanes": int(lanes.value) if lanes.value is not None else None,
            "oneway": is_oneway(tags),
            "sidewalk_left": sides.left,
            "sidewalk_right": sides.right,
            "sidewalk_source": sides.source,
            "parking_left": parking_left,
            "parking_right": parking_right,
            "kerb": kerb_of(tags.get("kerb"), self.dropped, default=None),
            "surface": text_value(tags.get("surface")),
            "name": text_value(tags.get("name")),
        }
        reverse = tag_value(tags, "oneway") == "-1"
        if reverse:  # traffic runs against the way: turn it, so the points follow the traffic
            for a, b in (("sidewalk_left", "sidewalk_right"), ("parking_left", "parking_right")):
                fields[a], fields[b] = fields[b], fields[a]
        return fields, reverse

    def roads(self) -> tuple[list[Road], dict[int, list[tuple[str, Any]]]]:
        """Roads, numbered, and for each road way its pieces (id, line) for the crossings."""
        drafts: list[tuple[Key, dict[str, Any]]] = []
        for way in self.ways:
            if tag_value(way.tags, "highway") not in ROAD_HIGHWAYS or is_area(way.tags):
                continue
            if not at_ground_level(way.tags):
                self.dropped["road not at ground level (tunnel, covered or layer < 0)"] += 1
                continue
            pieces = clip_line_pieces(way.xy, self.rect, self.dropped)
            if not pieces:
                continue
            fields, reverse = self._road_fields(way)
            for n, piece in enumerate(pieces):
                if reverse:
                    piece = Path2(points=piece.points[::-1])
                drafts.append(((1, way.id, n), {**fields, "centerline": piece}))
        roads = _numbered(drafts, "road", Road)
        by_way: dict[int, list[tuple[str, Any]]] = {}
        for road in roads:
            by_way.setdefault(int(road.osm.split("/")[1]), []).append((road.id, as_line(road.centerline)))
        return roads, by_way

    def walkways(self) -> list[Walkway]:
        """Walkways (sidewalks, footways, paths, steps, crossings, cycleways, pedestrian ways)."""
        drafts: list[tuple[Key, dict[str, Any]]] = []
        for way in self.ways:
            kind = walkway_kind(way.tags)
            if kind is None:
                continue
            if not at_ground_level(way.tags):
                self.dropped["walkway not at ground level (tunnel, covered or layer < 0)"] += 1
                continue
            pieces = clip_line_pieces(way.xy, self.rect, self.dropped)
            if not pieces:
                continue
            reading = parse_length(way.tags.get("width"))
            if reading.problem:
                count_problems([f"width: {reading.problem}"], self.dropped)
            width = reading.value or ROAD_CLASSES[tag_value(way.tags, "highway") or "footway"].width
            for n, piece in enumerate(pieces):
                fields = {"osm": f"way/{way.id}", "kind": kind, "centerline": piece, "width": width}
                drafts.append(((1, way.id, n), fields))
        return _numbered(drafts, "walkway", Walkway)

    def crossings(self, roads_by_way: dict[int, list[tuple[str, Any]]]) -> list[Crossing]:
        """Crossing nodes on a road way, each naming the road piece it lies on."""
        nodes = {n.id: n for n in self.nodes if tag_value(n.tags, "highway") == "crossing"}
        on_ways: dict[int, set[int]] = {}
        for way in self.ways:
            if way.id in roads_by_way:
                for ref in way.refs:
                    if ref in nodes:
                        on_ways.setdefault(ref, set()).add(way.id)
        drafts: list[tuple[Key, dict[str, Any]]] = []
        for node in nodes.values():
            if tag_value(node.tags, "crossing") == "no":
                self.dropped["crossing node tagged crossing=no"] += 1
                continue
            point = Point(node.xy)
            candidates = [
                (line.distance(point), int(road_id.split("-")[1]), road_id)
                for way_id in sorted(on_ways.get(node.id, ()))
                for road_id, line in roads_by_way[way_id]
            ]
            near = [c for c in candidates if c[0] <= 0.01]
            if not near:
                self.dropped["crossing node not on a road"] += 1
                continue
            kerb = kerb_of(node.tags.get("kerb"), self.dropped, default="lowered")
            fields = {
                "osm": f"node/{node.id}",
                "position": _point(node.xy),
                "road": min(near)[2],
                "kerb": kerb,
            }
            drafts.append(((0, node.id, 0), fields))
        return _numbered(drafts, "crossing", Crossing)

    # Polygons ------------------------------------------------------------------------------------

    def _kind(self, tags: Mapping[str, str], *, relation: bool) -> str | None:
        if building_value(tags) is not None:
            if building_value(tags) == "roof":
                self.dropped["building=roof (open sides; not a building block)"] += 1
                return None
            if not at_ground_level(tags):
                self.dropped["building not at ground level (layer < 0)"] += 1
                return None
            return "building"
        cls = land_class(tags, relation=relation)
        if cls is None and "building:part" in tags:
            self.dropped["building:part (ignored; the building outline carries the building)"] += 1
        if cls is not None and not at_ground_level(tags):
            self.dropped["area not at ground level (tunnel, covered or layer < 0)"] += 1
            return None
        return cls

    def _way_outline(self, way: OsmWay, kind: str) -> _Outline | None:
        if not way.closed:
            self.dropped["building or area way that is not a closed ring"] += 1
            return None
        missing = int(np.count_nonzero(~np.isfinite(way.xy).all(axis=1)))
        polygon = ring_polygon(way.xy)
        if missing:
            reason = "skipped them" if polygon is not None else "too few nodes left; dropped"
            self.dropped[f"polygon way with missing nodes ({reason})"] += 1
        if polygon is None:
            return None
        geometry = repaired(polygon, self.dropped)
        if geometry is None:
            return None
        return _Outline("way", way.id, way.tags, kind, geometry, frozenset(way.refs))

    def _relation_outline(self, relation: OsmMultipolygon, kind: str) -> _Outline | None:
        polygons = [
            p for outer, inners in relation.polygons if (p := ring_polygon(outer, inners)) is not None
        ]
        if not polygons:
            self.dropped["multipolygon that could not be assembled"] += 1
            return None
        geometry = repaired(MultiPolygon(polygons) if len(polygons) > 1 else polygons[0], self.dropped)
        if geometry is None:
            return None
        return _Outline("relation", relation.id, relation.tags, kind, geometry, relation.refs)

    def outlines(self) -> list[_Outline]:
        """Building and land-class polygons of multipolygons and closed ways, repaired, in id order."""
        outlines: list[_Outline] = []
        relation_rings: set[tuple[str, frozenset[int]]] = set()
        for relation_id in sorted(self.extract.multipolygons):
            relation = self.extract.multipolygons[relation_id]
            kind = self._kind(relation.tags, relation=True)
            if kind is not None and (outline := self._relation_outline(relation, kind)) is not None:
                outlines.append(outline)
                relation_rings.update((kind, ring) for ring in relation.outer_refs)
        for way in self.ways:
            kind = self._kind(way.tags, relation=False)
            if kind is None:
                continue
            if (kind, frozenset(way.refs)) in relation_rings:
                self.dropped[_DUPLICATE_OUTLINE] += 1
                continue
            if (outline := self._way_outline(way, kind)) is not None:
                outlines.append(outline)
        outlines.sort(key=lambda outline: outline.key)
        return outlines

    def areas(self, outlines: list[_Outline]) -> list[LandArea]:
        """Land areas: the land-class outlines clipped to the window, a feature per part."""
        drafts: list[tuple[Key, dict[str, Any]]] = []
        for outline in outlines:
            if outline.kind == "building":
                continue
            for n, part in enumerate(self._parts(outline.geometry)):
                fields = {
                    "osm": f"{outline.osm_type}/{outline.osm_id}",
                    "cls": outline.kind,
                    "polygon": part[1],
                }
                drafts.append(((*outline.key, n), fields))
        return _numbered(drafts, "area", LandArea)

    def _parts(self, geometry: BaseGeometry) -> Iterator[tuple[Polygon, Any]]:
        for part in clip_polygon(geometry, self.rect, self.dropped):
            polygon = polygon2(part)
            if polygon is None:
                self.dropped[DEGENERATE] += 1
            else:
                yield part, polygon

    def _height(self, outline: _Outline) -> dict[str, Any]:
        tags = outline.tags
        height, base, source, problems = building_height(tags)
        count_problems(problems, self.dropped)
        levels = parse_count(tags.get("building:levels"), integer=False, limit=300).value
        if (height is not None and height > MAX_BUILDING_HEIGHT) or base > MAX_BUILDING_HEIGHT / 2:
            self.dropped["implausible building height (a height is drawn instead)"] += 1
            height, base = None, 0.0
        if height is None:
            storeys = drawn_storeys(tags, seed=self.seed, osm_type=outline.osm_type, osm_id=outline.osm_id)
            height, source = base + storeys * STOREY_HEIGHT, "drawn"
            levels = levels or float(storeys)
        return {"height": height, "base_height": base, "height_source": source, "levels": levels}

    def buildings(self, outlines: list[_Outline]) -> tuple[list[Building], list[tuple[Key, str, Polygon]]]:
        """Buildings (a feature per clipped part) and, per part, its key, id and shape for the POIs."""
        entrances = {n.id: n.xy for n in self.nodes if tag_value(n.tags, "entrance") not in (None, "no")}
        drafts: list[tuple[Key, dict[str, Any]]] = []
        shapes: dict[Key, Polygon] = {}
        for outline in outlines:
            if outline.kind != "building":
                continue
            parts = list(self._parts(outline.geometry))
            if not parts:
                continue
            common = {"osm": f"{outline.osm_type}/{outline.osm_id}", **self._height(outline)}
            common["name"] = text_value(outline.tags.get("name"))
            doors = [entrances[ref] for ref in outline.refs if ref in entrances]
            for n, (shape, footprint) in enumerate(parts):
                on = sorted(_point(xy) for xy in doors if shape.distance(Point(xy)) <= 0.01)
                key = (*outline.key, n)
                drafts.append((key, {**common, "footprint": footprint, "entrances": on}))
                shapes[key] = shape
        order = sorted(shapes)
        buildings = _numbered(drafts, "building", Building)
        return buildings, [(key, b.id, shapes[key]) for key, b in zip(order, buildings, strict=True)]

    # Points --------------------------------------------------------------------------------------

    def pois(self, outlines: list[_Outline], buildings: list[tuple[Key, str, Polygon]]) -> list[Poi]:
        """Places of building outlines (inside them) and of nodes (naming the building they are in)."""
        drafts: list[tuple[Key, dict[str, Any]]] = []
        first_part = {key[:2]: (building_id, shape) for key, building_id, shape in buildings if key[2] == 0}
        for outline in outlines:
            poi = poi_of(outline.tags) if outline.kind == "building" else None
            if poi is None or outline.key not in first_part:
                continue
            building_id, shape = first_part[outline.key]
            position = _point(shape.representative_point().coords[0])
            drafts.append(
                (
                    (*outline.key, 0),
                    self._poi(outline.osm_type, outline.osm_id, poi, outline.tags, position, building_id),
                )
            )
        tree = STRtree([shape for _, _, shape in buildings]) if buildings else None
        for node in self.nodes:
            poi = poi_of(node.tags)
            if poi is None:
                continue
            inside = None
            if tree is not None:
                point = Point(node.xy)
                hits = [buildings[i] for i in tree.query(point, predicate="intersects")]
                if hits:
                    inside = min(hits, key=lambda hit: (hit[2].area, hit[0]))[1]
            drafts.append(
                ((0, node.id, 0), self._poi("node", node.id, poi, node.tags, _point(node.xy), inside))
            )
        return _numbered(drafts, "poi", Poi)

    @staticmethod
    def _poi(
        osm_type: str,
        osm_id: int,
        poi: tuple[str, str],
        tags: Mapping[str, str],
        position: tuple[float, float],
        building: str | None,
    ) -> dict[str, Any]:
        return {
            "osm": f"{osm_type}/{osm_id}",
            "position": position,
            "category": poi[0],
            "tag": poi[1],
            "name": text_value(tags.get("name")),
            "building": building,
        }

    def furniture(self) -> list[StreetFurniture]:
        """Street furniture nodes."""
        drafts: list[tuple[Key, dict[str, Any]]] = []
        for node in self.nodes:
            kind = furniture_kind(node.tags)
            if kind is not None:
                shelter = kind == "bus_stop" and node.tags.get("shelter") == "yes"
                record = {
                    "osm": f"node/{node.id}",
                    "position": _point(node.xy),
                    "kind": kind,
                    "shelter": shelter,
                }
                drafts.append(((0, node.id, 0), record))
        return _numbered(drafts, "furniture", StreetFurniture)


def _point(xy: Iterable[float]) -> tuple[float, float]:
    x, y = xy
    return round(float(x), 3) + 0.0, round(float(y), 3) + 0.0


def build_features(extract: OsmExtract, rect: Rect, *, seed: int) -> Features:
    """Turn what the reader kept into numbered city map features, clipped to ``rect``.

    Parameters
    ----------
    extract : OsmExtract
        Nodes, ways and multipolygons of the window, in the local frame.
    rect : (min_x, min_y, max_x, max_y)
        The window (m).
    seed : int
        Seed of the drawn heights of untagged buildings.
    """
    builder = _Builder(extract, rect, seed)
    roads, roads_by_way = builder.roads()
    features = Features(roads=roads, walkways=builder.walkways())
    features.crossings = builder.crossings(roads_by_way)
    outlines = builder.outlines()
    features.areas = builder.areas(outlines)
    features.buildings, shapes = builder.buildings(outlines)
    features.pois = builder.pois(outlines, shapes)
    features.furniture = builder.furniture()
    features.dropped = builder.dropped
    return features
