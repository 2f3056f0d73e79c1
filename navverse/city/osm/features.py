"""From the OSM objects of a window to numbered city map features, clipped, repaired, counted.

What each feature is made from is summed up in :mod:`navverse.city.osm.reader` (the tag tables are in
:mod:`.osm_classes`). Every builder here counts what it leaves out or repairs in ``dropped``, by
reason, and numbers features in the order (OSM type, OSM id, part), so the same input gives the
same map.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from itertools import pairwise
from typing import Any

import numpy as np
from shapely import unary_union
from shapely.geometry import LineString, MultiPolygon, Point, Polygon
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
    polygon_of,
    repaired,
    ring_polygon,
)
from navverse.city.osm.stream import OsmExtract, OsmMultipolygon, OsmWay
from navverse.city.precision import difference, intersection
from navverse.city.tag_tables import (
    MAX_BUILDING_HEIGHT,
    RAIL_WIDTHS,
    ROAD_HIGHWAYS,
    TYPE_RANK,
    WATERWAY_WIDTHS,
    building_value,
    count_problems,
    crossing_markings,
    drawn_storeys,
    furniture_kind,
    is_area,
    is_oneway,
    is_raised,
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
    cycle_tracks,
    is_passage,
    parse_count,
    parse_length,
    passage_clearance,
    road_width,
    sidewalks,
)

__all__ = ["Features", "build_features"]

_DUPLICATE_OUTLINE = "way repeating its multipolygon's outline (the multipolygon is kept)"
_BUILDING_KINDS = ("building", "part")
_SIDEWALK_KINDS = frozenset({"sidewalk", "footway", "path"})
"""Mapped walkways that stand for a road's sidewalk when they run beside it."""
_SEPARATE_REACH = 6.0
"""How far beyond a road's edge a mapped walkway beside it may run and still be its sidewalk (m)."""
_SEPARATE_SHARE = 0.5
"""Share of a road's length a mapped walkway beside it must run along to replace its inferred sidewalk."""
_UNDOUBLED = {
    "sidewalk": "inferred sidewalk left out (a mapped sidewalk runs beside the road)",
    "cycle_track": "cycle track of the road's tags left out (a mapped cycleway runs beside the road)",
}
_PARALLEL_DEG = 25.0
"""Largest angle between a road and a walkway running along it (degrees)."""
_SMALLEST_PIECE = 1.0
"""Smallest area of a building part kept (m²)."""
_SLIVER = 0.25
"""Half the width of the thinnest rest of an outline its parts leave uncovered that still stands (m)."""
_LOWEST_SPAN = 1.0
"""Least height of a building above a passage's headroom for it to be drawn over the passage (m)."""
_PASSAGE_REACH = 1.0
"""How far a building passage's ground runs on past each end of its way (m)."""
_RAISED = "building raised over a passage at ground level (tunnel=building_passage, covered)"
_OPEN = "building left open over a passage (lower than the passage's headroom)"
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

    def grounded(
        self, roads: list[Road], walkways: list[Walkway], areas: list[LandArea]
    ) -> tuple[list[Road], list[Walkway]]:
        """Roads and walkways without the bridges that are not level with the streets.

        A bridge (``bridge=*``, ``man_made=bridge``, or a ``layer`` above 0) over water or a railway
        that crosses no way at ground level is kept, level with the streets it joins. One that crosses
        a road or walkway below it (an overpass, a footbridge over a street) is left out, so no
        junction is made where there is none, and so is one over neither water nor rail (a viaduct
        over land, whose ground beneath is not its deck). Each is counted.
        """
        raised = {way.id for way in self.ways if is_raised(way.tags)}
        if not raised:
            return roads, walkways

        features = [*roads, *walkways]
        below = [as_line(f.centerline) for f in features if _way_id(f) not in raised]
        tree = STRtree(below) if below else None
        spanned = [polygon_of(a.polygon) for a in areas if a.cls in ("water", "rail")]
        spans = STRtree(spanned) if spanned else None
        left_out: set[str] = set()
        for feature in features:
            if _way_id(feature) not in raised:
                continue
            line = as_line(feature.centerline)
            if tree is not None and len(tree.query(line, predicate="crosses")) > 0:
                reason = "bridge over a way at ground level (left out)"
            elif spans is None or len(spans.query(line, predicate="intersects")) == 0:
                reason = "bridge over neither water nor rail (left out)"
            else:
                self.dropped["bridge over water or rail (kept level with the streets)"] += 1
                continue
            left_out.add(feature.id)
            self.dropped[reason] += 1
        return [r for r in roads if r.id not in left_out], [w for w in walkways if w.id not in left_out]

    def line_areas(self) -> list[tuple[Key, dict[str, Any]]]:
        """Railway track beds and waterways mapped as lines, as land areas of their width.

        ``railway=*`` tracks of :data:`~navverse.city.tag_tables.RAIL_WIDTHS` at ground level become
        ``rail``; ``waterway=*`` lines of :data:`~navverse.city.tag_tables.WATERWAY_WIDTHS` (``width``
        when tagged) at ground level become ``water`` (culverts are tunnels, so left out).
        """
        drafts: list[tuple[Key, dict[str, Any]]] = []
        for way in self.ways:
            if is_area(way.tags) or land_class(way.tags, relation=False) is not None:
                continue
            railway, waterway = tag_value(way.tags, "railway"), tag_value(way.tags, "waterway")
            if railway in RAIL_WIDTHS:
                cls, width = "rail", RAIL_WIDTHS[railway]
            elif waterway in WATERWAY_WIDTHS:
                cls, width = "water", parse_length(way.tags.get("width")).value or WATERWAY_WIDTHS[waterway]
            else:
                continue
            if not at_ground_level(way.tags) or is_raised(way.tags):
                self.dropped[f"{cls} line not at ground level (tunnel, bridge or layer)"] += 1
                continue
            lines = [as_line(piece) for piece in clip_line_pieces(way.xy, self.rect, self.dropped)]
            if not lines:
                continue
            strip = unary_union([line.buffer(width / 2.0, cap_style="flat") for line in lines])
            for n, (_, polygon) in enumerate(self._parts(strip)):
                drafts.append(((1, way.id, n), {"osm": f"way/{way.id}", "cls": cls, "polygon": polygon}))
        return drafts

    def undoubled(self, roads: list[Road], walkways: list[Walkway]) -> list[Road]:
        """Roads without the sidewalks and cycle tracks beside them that mapped ways already are.

        A side whose sidewalk comes from the class rule (the way says nothing of its sidewalks) loses
        it when mapped sidewalks, footways or paths run parallel to the road (within
        :data:`_PARALLEL_DEG`) within :data:`_SEPARATE_REACH` of its edge along at least
        :data:`_SEPARATE_SHARE` of its length; a side's cycle track, when mapped cycleways do.
        """
        sidewalks = [as_line(w.centerline) for w in walkways if w.kind in _SIDEWALK_KINDS]
        cycleways = [as_line(w.centerline) for w in walkways if w.kind == "cycleway"]
        trees = {"sidewalk": STRtree(sidewalks) if sidewalks else None}
        trees["cycle_track"] = STRtree(cycleways) if cycleways else None
        mapped = {"sidewalk": sidewalks, "cycle_track": cycleways}
        kept = []
        for road in roads:
            line = as_line(road.centerline)
            update: dict[str, None] = {}
            for what, tree in trees.items():
                if tree is None or (what == "sidewalk" and road.sidewalk_source != "rule"):
                    continue
                for side, sign in (("left", 1.0), ("right", -1.0)):
                    if getattr(road, f"{what}_{side}") is None:
                        continue
                    band = line.buffer(sign * (road.width / 2.0 + _SEPARATE_REACH), single_sided=True)
                    near = [mapped[what][i] for i in tree.query(band, predicate="intersects").tolist()]
                    if _parallel_length(line, near, band) >= _SEPARATE_SHARE * line.length:
                        update[f"{what}_{side}"] = None
                        self.dropped[_UNDOUBLED[what]] += 1
            kept.append(road.model_copy(update=update) if update else road)
        return kept

    def passages(self, roads: list[Road], walkways: list[Walkway]) -> list[tuple[Polygon, float]]:
        """The ground each kept building passage (:func:`~navverse.city.tags.is_passage`) runs on, as
        wide as the way and :data:`_PASSAGE_REACH` longer at each end (its end nodes often stop short
        of the walls it passes), with its headroom (``maxheight``, else the default)."""
        found = []
        for feature in [*roads, *walkways]:
            way = self.extract.ways.get(_way_id(feature))
            if way is not None and is_passage(way.tags):
                line = _prolonged(as_line(feature.centerline), _PASSAGE_REACH)
                found.append(
                    (line.buffer(feature.width / 2.0, cap_style="flat"), passage_clearance(way.tags))
                )
        return found

    def _road_fields(self, way: OsmWay) -> tuple[dict[str, Any], bool]:
        tags = way.tags
        width, width_source, problems = road_width(tags)
        sides = sidewalks(tags)
        lanes = parse_count(tags.get("lanes"), limit=20)
        problems = [*problems, *sides.problems] + ([f"lanes: {lanes.problem}"] if lanes.problem else [])
        count_problems(problems, self.dropped)
        parking_left, parking_right = parking_sides(tags, self.dropped)
        track_left, track_right, track_problems = cycle_tracks(tags)
        count_problems(list(track_problems), self.dropped)
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
            "cycle_track_left": track_left,
            "cycle_track_right": track_right,
            "kerb": kerb_of(tags.get("kerb"), self.dropped, default=None),
            "surface": text_value(tags.get("surface")),
            "name": text_value(tags.get("name")),
        }
        reverse = tag_value(tags, "oneway") == "-1"
        if reverse:  # traffic runs against the way: turn it, so the points follow the traffic
            for a in ("sidewalk", "parking", "cycle_track"):
                fields[f"{a}_left"], fields[f"{a}_right"] = fields[f"{a}_right"], fields[f"{a}_left"]
        return fields, reverse

    def roads(self) -> list[Road]:
        """Roads, numbered."""
        drafts: list[tuple[Key, dict[str, Any]]] = []
        for way in self.ways:
            if tag_value(way.tags, "highway") not in ROAD_HIGHWAYS or is_area(way.tags):
                continue
            if not at_ground_level(way.tags):
                self.dropped["road not at ground level (tunnel, layer or level < 0)"] += 1
                continue
            pieces = clip_line_pieces(way.xy, self.rect, self.dropped)
            if not pieces:
                continue
            fields, reverse = self._road_fields(way)
            for n, piece in enumerate(pieces):
                if reverse:
                    piece = Path2(points=piece.points[::-1])
                drafts.append(((1, way.id, n), {**fields, "centerline": piece}))
        return _numbered(drafts, "road", Road)

    def walkways(self) -> list[Walkway]:
        """Walkways (sidewalks, footways, paths, steps, crossings, cycleways, pedestrian ways)."""
        drafts: list[tuple[Key, dict[str, Any]]] = []
        for way in self.ways:
            kind = walkway_kind(way.tags)
            if kind is None:
                continue
            if not at_ground_level(way.tags):
                self.dropped["walkway not at ground level (tunnel, layer or level < 0)"] += 1
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
        """Crossing nodes on a road way, each naming the road piece it lies on, with its kerb and markings
        (:func:`~navverse.city.tag_tables.crossing_markings`)."""
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
                "markings": crossing_markings(node.tags, self.dropped),
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
        if tag_value(tags, "building:part") not in (None, "no"):
            if not at_ground_level(tags):
                self.dropped["building:part not at ground level (layer < 0)"] += 1
                return None
            return "part"
        cls = land_class(tags, relation=relation)
        if cls is not None and not at_ground_level(tags):
            self.dropped["area not at ground level (tunnel, layer or level < 0)"] += 1
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
        """Land areas: the land-class outlines clipped to the window, a feature per part, and the
        railways and waterways mapped as lines (:meth:`line_areas`)."""
        drafts: list[tuple[Key, dict[str, Any]]] = self.line_areas()
        for outline in outlines:
            if outline.kind in _BUILDING_KINDS:
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

    def _height(self, outline: _Outline, *, inherited: dict[str, Any] | None = None) -> dict[str, Any]:
        """Height, base, where the height came from and levels of a building or part.

        An untagged part takes the height of its building (``inherited``); an untagged building
        gets drawn storeys.
        """
        tags = outline.tags
        height, base, source, problems = building_height(tags)
        count_problems(problems, self.dropped)
        levels = parse_count(tags.get("building:levels"), integer=False, limit=300).value
        if (height is not None and height > MAX_BUILDING_HEIGHT) or base > MAX_BUILDING_HEIGHT / 2:
            self.dropped["implausible building height (a height is drawn instead)"] += 1
            height, base = None, 0.0
        if height is None and inherited is not None and inherited["height"] > base:
            return {**inherited, "base_height": base}
        if height is None:
            storeys = drawn_storeys(tags, seed=self.seed, osm_type=outline.osm_type, osm_id=outline.osm_id)
            height, source = base + storeys * STOREY_HEIGHT, "drawn"
            levels = levels or float(storeys)
        return {"height": height, "base_height": base, "height_source": source, "levels": levels}

    def _parts_of(
        self, outlines: list[_Outline]
    ) -> tuple[dict[tuple[int, int], list[_Outline]], list[_Outline]]:
        """The ``building:part`` outlines of each building (by its key), and the parts of no building.

        A part belongs to the smallest building outline holding most of it (half its area or more);
        the others stand as buildings of their own.
        """
        buildings = [o for o in outlines if o.kind == "building"]
        tree = STRtree([o.geometry for o in buildings]) if buildings else None
        parts_of: dict[tuple[int, int], list[_Outline]] = {}
        loose: list[_Outline] = []
        for part in (o for o in outlines if o.kind == "part"):
            hosts = [] if tree is None else [buildings[i] for i in tree.query(part.geometry).tolist()]
            area = part.geometry.area
            hosts = [h for h in hosts if h.geometry.intersection(part.geometry).area >= 0.5 * area]
            if hosts:
                host = min(hosts, key=lambda h: (h.geometry.area, h.key))
                parts_of.setdefault(host.key, []).append(part)
            else:
                loose.append(part)
        return parts_of, loose

    def _pieces(
        self, outline: _Outline, parts: list[_Outline]
    ) -> list[tuple[_Outline, BaseGeometry, dict[str, Any]]]:
        """What stands on a building's outline: its parts (clipped to it, each with its heights) and
        the rest of the outline no part covers (with the outline's heights), or the outline alone."""
        own = self._height(outline)
        if not parts:
            return [(outline, outline.geometry, own)]
        pieces = []
        for part in parts:
            shape = repaired(part.geometry.intersection(outline.geometry), self.dropped)
            if shape is not None and shape.area >= _SMALLEST_PIECE:
                pieces.append((part, shape, self._height(part, inherited=own)))
        rest = outline.geometry.difference(unary_union([part.geometry for part in parts]))
        rest = repaired(rest, self.dropped) if not rest.is_empty else None
        if rest is not None and not rest.buffer(-_SLIVER).is_empty:
            pieces.append((outline, rest, own))
        return sorted(pieces, key=lambda piece: piece[0].key)

    def _over_passages(
        self,
        pieces: list[tuple[_Outline, BaseGeometry, dict[str, Any]]],
        passages: list[tuple[Polygon, float]],
        grounds: STRtree | None,
    ) -> list[tuple[_Outline, BaseGeometry, dict[str, Any]]]:
        """Pieces of a building with the ground of the passages through them freed: over a passage the
        piece stands from the passage's headroom up (none at all when its top is less than
        :data:`_LOWEST_SPAN` above the headroom); elsewhere it stands as it was. ``grounds`` indexes
        the passages' ground (None: no passage)."""
        if grounds is None:
            return pieces
        out = []
        for source, geometry, heights in pieces:
            rest = geometry
            for index in sorted(grounds.query(geometry).tolist()):  # in the passages' order
                ground, clearance = passages[index]
                if heights["base_height"] >= clearance or not ground.intersects(rest):
                    continue
                under = repaired(intersection(rest, ground), self.dropped)
                if under is None or under.area < _SMALLEST_PIECE:
                    continue
                rest = difference(rest, ground)
                if heights["height"] - clearance >= _LOWEST_SPAN:
                    out.append((source, under, {**heights, "base_height": clearance}))
                    self.dropped[_RAISED] += 1
                else:
                    self.dropped[_OPEN] += 1
            rest = repaired(rest, self.dropped) if not rest.is_empty else None
            if rest is not None:
                out.append((source, rest, heights))
        return out

    def buildings(
        self, outlines: list[_Outline], passages: list[tuple[Polygon, float]]
    ) -> tuple[list[Building], dict[tuple[int, int], tuple[str, Polygon]]]:
        """Buildings (a feature per clipped part of each building or ``building:part``) and, for the
        POIs, the id and shape of each outline's largest ground-level feature by the outline's key.

        A building mapped with ``building:part`` outlines stands as its parts (each with its own
        heights, an untagged one with the building's), plus the rest of its outline no part covers;
        the outline is not counted twice. Parts inside no building stand on their own. Over the
        ``passages`` (ground, headroom) a building stands from the headroom up.
        """
        entrances = {n.id: n.xy for n in self.nodes if tag_value(n.tags, "entrance") not in (None, "no")}
        grounds = STRtree([ground for ground, _ in passages]) if passages else None
        parts_of, loose = self._parts_of(outlines)
        drafts: list[tuple[Key, dict[str, Any]]] = []
        shapes: dict[Key, tuple[tuple[int, int], Polygon, float]] = {}
        owners = [(o, parts_of.get(o.key, [])) for o in outlines if o.kind == "building"]
        owners += [(part, []) for part in loose]
        for outline, parts in owners:
            kind = building_value(outline.tags) or tag_value(outline.tags, "building:part")
            refs = set(outline.refs).union(*(part.refs for part in parts))
            doors = [entrances[ref] for ref in sorted(refs) if ref in entrances]
            numbers: Counter[tuple[int, int]] = Counter()
            pieces = self._over_passages(self._pieces(outline, parts), passages, grounds)
            for source, geometry, heights in pieces:
                common = {"osm": f"{source.osm_type}/{source.osm_id}", **heights}
                common["name"] = text_value(outline.tags.get("name"))
                common["type"] = kind
                if source is not outline:
                    common["outline"] = f"{outline.osm_type}/{outline.osm_id}"
                for shape, footprint in self._parts(geometry):
                    on = sorted(_point(xy) for xy in doors if shape.distance(Point(xy)) <= 0.01)
                    key = (*source.key, numbers[source.key])
                    numbers[source.key] += 1
                    if key in shapes:  # a part shared by two buildings is drawn once
                        continue
                    drafts.append((key, {**common, "footprint": footprint, "entrances": on}))
                    shapes[key] = (outline.key, shape, heights["base_height"])
        order = sorted(shapes)
        buildings = _numbered(drafts, "building", Building)
        largest: dict[tuple[int, int], tuple[float, str, Polygon]] = {}
        for key, building in zip(order, buildings, strict=True):
            owner, shape, base = shapes[key]
            rank = (base > 0.0, -shape.area)
            if owner not in largest or rank < largest[owner][0]:
                largest[owner] = (rank, building.id, shape)
        return buildings, {owner: (bid, shape) for owner, (_, bid, shape) in largest.items()}

    # Points --------------------------------------------------------------------------------------

    def pois(
        self,
        outlines: list[_Outline],
        buildings: list[Building],
        by_outline: dict[tuple[int, int], tuple[str, Polygon]],
    ) -> list[Poi]:
        """Places of building outlines (inside them) and of nodes (naming the building they are in)."""
        drafts: list[tuple[Key, dict[str, Any]]] = []
        for outline in outlines:
            poi = poi_of(outline.tags) if outline.kind in _BUILDING_KINDS else None
            if poi is None or outline.key not in by_outline:
                continue
            building_id, shape = by_outline[outline.key]
            position = _point(shape.representative_point().coords[0])
            drafts.append(
                (
                    (*outline.key, 0),
                    self._poi(outline.osm_type, outline.osm_id, poi, outline.tags, position, building_id),
                )
            )
        ground = [(b, polygon_of(b.footprint)) for b in buildings if b.base_height == 0.0]
        tree = STRtree([shape for _, shape in ground]) if ground else None
        for node in self.nodes:
            poi = poi_of(node.tags)
            if poi is None:
                continue
            inside = None
            if tree is not None:
                point = Point(node.xy)
                hits = [ground[i] for i in tree.query(point, predicate="intersects")]
                if hits:
                    inside = min(hits, key=lambda hit: (hit[1].area, int(hit[0].id.split("-")[1])))[0].id
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


def _pieces_by_way(roads: list[Road]) -> dict[int, list[tuple[str, LineString]]]:
    """For each road way, its pieces (road id, line): what crossing nodes are matched against."""
    by_way: dict[int, list[tuple[str, LineString]]] = {}
    for road in roads:
        by_way.setdefault(int(str(road.osm).split("/")[1]), []).append((road.id, as_line(road.centerline)))
    return by_way


def _parallel_length(road: LineString, walkways: list[LineString], band: BaseGeometry) -> float:
    """Length of the ``walkways`` inside ``band`` that run parallel to ``road`` (either direction)."""
    total = 0.0
    cos_limit = math.cos(math.radians(_PARALLEL_DEG))
    for walkway in walkways:
        inside = walkway.intersection(band)
        for piece in getattr(inside, "geoms", [inside]):
            if not isinstance(piece, LineString) or piece.is_empty:
                continue
            coords = np.asarray(piece.coords)
            for a, b in pairwise(coords):
                length = float(np.hypot(*(b - a)))
                if length == 0.0:
                    continue
                along = road.project(Point((a + b) / 2.0))
                ahead = np.asarray(road.interpolate(min(road.length, along + 0.5)).coords[0])
                behind = np.asarray(road.interpolate(max(0.0, along - 0.5)).coords[0])
                direction = ahead - behind
                norm = float(np.hypot(*direction))
                if norm and abs(float(np.dot(direction, b - a))) >= cos_limit * norm * length:
                    total += length
    return total


def _prolonged(line: LineString, reach: float) -> LineString:
    """``line`` made ``reach`` longer at each end, straight on along its end segments."""
    points = np.asarray(line.coords, dtype=float)[:, :2]
    ends = []
    for end, before in ((points[0], points[1]), (points[-1], points[-2])):
        step = end - before
        norm = float(np.hypot(*step))
        ends.append(end + step / norm * reach if norm > 0.0 else end)
    return LineString([ends[0], *points, ends[1]])


def _way_id(feature: Road | Walkway) -> int:
    return int((feature.osm or "way/0").split("/")[1])


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
    outlines = builder.outlines()
    areas = builder.areas(outlines)
    roads, walkways = builder.grounded(builder.roads(), builder.walkways(), areas)
    features = Features(roads=builder.undoubled(roads, walkways), walkways=walkways, areas=areas)
    features.crossings = builder.crossings(_pieces_by_way(roads))
    features.buildings, by_outline = builder.buildings(outlines, builder.passages(roads, walkways))
    features.pois = builder.pois(outlines, features.buildings, by_outline)
    features.furniture = builder.furniture()
    features.dropped = builder.dropped
    return features
