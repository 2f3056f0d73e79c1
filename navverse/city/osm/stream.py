"""Streaming an OpenStreetMap file through osmium, keeping only what a window needs.

:func:`read_extract` reads the file with pyosmium's ``FileProcessor`` (which reads it twice:
relations first, for the multipolygon assembler, then everything) and keeps, projected to the
window's local frame:

- tagged nodes with a key of interest that lie in the window;
- ways with a key of interest whose bounding box meets the window's lat/lon box, with their node
  ids and positions (a node missing from the file is a NaN row);
- multipolygon relations with a key of interest, assembled by osmium's area assembler, whose
  bounding box meets the window's lat/lon box.

Memory: the Python side holds only those objects. Osmium keeps the location of every node of the
file in its location index, to give ways their geometry: in memory (``flex_mem``, about 16 bytes a
node) when the file's decompressed size (:class:`~navverse.city.osm.files.OsmFile`) leaves room for at most
:data:`IN_MEMORY_INDEX_NODES` nodes (a node takes at least 30 bytes of XML, 3 of a PBF block), else
in a sparse index file in a temporary directory (``sparse_file_array``, 16 bytes a node on disk,
paged in by the OS; ``TMPDIR`` chooses the disk). The area assembler
keeps the multipolygon relations with a key of interest and their member ways until each is built;
the ids of those member ways are kept in an osmium ``IdSet``.

Osmium's assembler needs ways sorted by id, each once (as ``osmium sort``, Geofabrik and the OSM
API write them). A file of at most :data:`MAX_SORT_BYTES` that is not is sorted in memory first
(pyosmium's ``MergeInputReader``, keeping one copy, the newest version, of an object the file holds
twice) into a temporary PBF; a larger one is refused with the command that sorts it. Objects with
negative ids (unsaved editor objects) get no location from osmium's index: their ways count as
missing nodes.
"""

from __future__ import annotations

import array
import math
import os
import sys
import tempfile
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import osmium
import osmium.filter
import osmium.geom
import osmium.index
import osmium.osm
import shapely

from navverse.city.map import CityMapError
from navverse.city.osm.files import (
    OSMIUM_ERRORS,
    OSMIUM_FORMATS,
    OsmFile,
    Progress,
    osmium_failure,
    osmium_file,
)
from navverse.city.osm.window import LonLatBox, Window

__all__ = [
    "DUPLICATE",
    "IN_MEMORY_INDEX_NODES",
    "MAX_SORT_BYTES",
    "OsmExtract",
    "OsmMultipolygon",
    "OsmNode",
    "OsmWay",
    "location_indexes",
    "most_nodes",
    "read_extract",
]

IN_MEMORY_INDEX_NODES = 4_000_000
"""Files that can hold at most this many nodes keep osmium's node location index in memory (at most
64 MB); larger ones on disk."""
_FEWEST_BYTES_PER_NODE = {"xml": 30, "xml.gz": 30, "xml.bz2": 30, "pbf": 3}
MAX_SORT_BYTES = 128 * 1024**2
"""Largest unsorted file (or one holding an object twice) sorted in memory before reading."""
DUPLICATE = "duplicate OSM object (one copy kept)"
_PROGRESS_EVERY = 50_000
_ORDER_WORDS = ("out of order", "twice in input")


@dataclass(frozen=True)
class OsmNode:
    """A tagged node in the window: its id, local position and tags."""

    id: int
    xy: tuple[float, float]
    tags: dict[str, str]


@dataclass(frozen=True)
class OsmWay:
    """A way whose bounding box meets the window: node ids, local positions (NaN rows: missing nodes)."""

    id: int
    tags: dict[str, str]
    refs: tuple[int, ...]
    xy: np.ndarray

    @property
    def closed(self) -> bool:
        """Whether the way ends at the node it starts from (and has at least 4 node references)."""
        return len(self.refs) >= 4 and self.refs[0] == self.refs[-1]


@dataclass(frozen=True)
class OsmMultipolygon:
    """A multipolygon relation assembled by osmium: per outer ring, the ring and its inner rings (local,
    closed), and the node ids of each outer ring."""

    id: int
    tags: dict[str, str]
    polygons: list[tuple[np.ndarray, list[np.ndarray]]]
    outer_refs: list[frozenset[int]]

    @property
    def refs(self) -> frozenset[int]:
        """Node ids of all outer rings."""
        return frozenset().union(*self.outer_refs)


@dataclass
class OsmExtract:
    """What :func:`read_extract` kept, and what it counted as dropped or repaired (by reason)."""

    nodes: dict[int, OsmNode] = field(default_factory=dict)
    ways: dict[int, OsmWay] = field(default_factory=dict)
    multipolygons: dict[int, OsmMultipolygon] = field(default_factory=dict)
    dropped: Counter[str] = field(default_factory=Counter)
    extent: LonLatBox | None = None

    def extend(self, box: LonLatBox) -> None:
        """Grow :attr:`extent` (the lat/lon box of the data of interest read) by ``box``."""
        if self.extent is None:
            self.extent = box
        else:
            e = self.extent
            self.extent = (min(e[0], box[0]), min(e[1], box[1]), max(e[2], box[2]), max(e[3], box[3]))


class _Ids:
    """A set of OSM ids: osmium's compact ``IdSet`` for ids >= 0, a Python set for negative ones
    (editors give unsaved objects negative ids, which ``IdSet`` refuses)."""

    def __init__(self) -> None:
        self._positive = osmium.index.IdSet()
        self._negative: set[int] = set()

    def add(self, object_id: int) -> bool:
        """Add an id; return whether it was there already."""
        if object_id >= 0:
            seen = self._positive.get(object_id)
            self._positive.set(object_id)
        else:
            seen = object_id in self._negative
            self._negative.add(object_id)
        return seen

    def __contains__(self, object_id: int) -> bool:
        return self._positive.get(object_id) if object_id >= 0 else object_id in self._negative


class _RelationMembers:
    """First-pass handler: the ways that are members of multipolygon relations of interest."""

    def __init__(self) -> None:
        self.ways = _Ids()

    def relation(self, relation: Any) -> None:
        """Note the member ways of a multipolygon relation (osmium's first pass reads relations)."""
        if relation.tags.get("type") != "multipolygon":
            return
        for member in relation.members:
            if member.type == "w":
                self.ways.add(member.ref)


def most_nodes(osm_file: OsmFile) -> int:
    """The most nodes the file can hold, from its size: what decides where location indexes live."""
    return osm_file.data_bytes // _FEWEST_BYTES_PER_NODE[osm_file.format]


@contextmanager
def location_indexes(most: int, names: tuple[str, ...] = ("nodes",)) -> Iterator[list[str]]:
    """Osmium location index specifications (for ``osmium.index.create_map`` or ``with_locations``),
    one per name, for a file of at most ``most`` nodes: in memory up to
    :data:`IN_MEMORY_INDEX_NODES`, else in files of a temporary directory removed afterwards."""
    if most <= IN_MEMORY_INDEX_NODES:
        yield ["flex_mem" for _ in names]
    else:
        with tempfile.TemporaryDirectory(prefix="navverse-osm-") as directory:
            yield [f"sparse_file_array,{os.path.join(directory, name + '.idx')}" for name in names]


_WKB = osmium.geom.WKBFactory()


def _way_envelope(way: Any) -> LonLatBox | None:
    """A way's lat/lon envelope from the WKB line osmium builds in C++ (None when a node has no
    location, or the way has one node): several times faster than walking the nodes in Python."""
    try:
        wkb = bytes.fromhex(_WKB.create_linestring(way, use_nodes=osmium.geom.ALL))
    except OSMIUM_ERRORS:
        return None
    values = array.array("d")
    values.frombytes(wkb[9:])  # byte order, geometry type, point count, then x y pairs
    if (wkb[0] == 1) != (sys.byteorder == "little"):
        values.byteswap()
    lons, lats = values[0::2], values[1::2]
    return (min(lons), min(lats), max(lons), max(lats))


def _area_envelope(area: Any) -> LonLatBox | None:
    """A multipolygon's lat/lon envelope from the WKB osmium builds in C++ (None: not assembled)."""
    try:
        geometry = shapely.from_wkb(_WKB.create_multipolygon(area))
    except OSMIUM_ERRORS:
        return None
    if geometry.is_empty:
        return None
    low_lon, low_lat, high_lon, high_lat = shapely.bounds(geometry).tolist()
    return (low_lon, low_lat, high_lon, high_lat)


def _way_geometry(way: Any) -> tuple[tuple[int, ...], list[float], list[float]]:
    """A way's node ids and positions, node by node (NaN for a node without a location)."""
    refs, lons, lats = [], [], []
    for node in way.nodes:
        refs.append(node.ref)
        location = node.location
        if location.valid():
            lons.append(location.lon)
            lats.append(location.lat)
        else:
            lons.append(math.nan)
            lats.append(math.nan)
    return tuple(refs), lons, lats


def _nan_box(lons: list[float], lats: list[float]) -> LonLatBox | None:
    valid = [(lon, lat) for lon, lat in zip(lons, lats, strict=True) if not math.isnan(lon)]
    if not valid:
        return None
    return (
        min(p[0] for p in valid),
        min(p[1] for p in valid),
        max(p[0] for p in valid),
        max(p[1] for p in valid),
    )


class _Collector:
    """Second-pass logic: keep what the window needs from each object osmium hands over."""

    def __init__(
        self,
        window: Window,
        keys: tuple[str, ...],
        members: _RelationMembers,
        duplicates: frozenset[tuple[str, int]],
    ) -> None:
        self.window, self.keys, self.members, self.duplicates = window, keys, members, duplicates
        self.extract = OsmExtract()
        self.member_ways_in_window: set[int] = set()
        self.expected_relations: set[int] = set()

    def _relevant(self, tags: Any) -> bool:
        return any(key in tags for key in self.keys)

    def _first(self, kind: str, object_id: int, kept: dict[int, Any]) -> bool:
        """Whether an object is seen for the first time (a repeat, or one a sort removed, is counted)."""
        if object_id in kept:
            self.extract.dropped[DUPLICATE] += 1
            return False
        if (kind, object_id) in self.duplicates:
            self.extract.dropped[DUPLICATE] += 1
        return True

    def node(self, node: Any) -> None:
        """Keep a tagged node of interest that lies in the window."""
        location = node.location
        if not location.valid():
            self.extract.dropped["node without a valid location (anywhere in the file)"] += 1
            return
        lon, lat = location.lon, location.lat
        self.extract.extend((lon, lat, lon, lat))
        if not self.window.contains_lonlat(lon, lat):
            return
        x, y = (float(v) for v in self.window.project([lon], [lat])[0])
        if not self.window.contains(x, y):
            return
        if not self._first("n", node.id, self.extract.nodes):
            return
        self.extract.nodes[node.id] = OsmNode(node.id, (x, y), dict(node.tags))

    def way(self, way: Any) -> None:
        """Keep a way of interest whose envelope meets the window; note multipolygon members there."""
        relevant, member = self._relevant(way.tags), way.id in self.members.ways
        if not (relevant or member):
            return
        refs, lons, lats = None, None, None
        box = _way_envelope(way)  # the common case, fast; node by node when nodes are missing
        if box is None:
            refs, lons, lats = _way_geometry(way)
            box = _nan_box(lons, lats)
        if box is None:
            if relevant and refs:
                self.extract.dropped["way whose nodes are all missing (anywhere in the file)"] += 1
            return
        if relevant:
            self.extract.extend(box)
        if not self.window.meets(box):
            return
        if member:
            self.member_ways_in_window.add(way.id)
        if not relevant:
            return
        if not self._first("w", way.id, self.extract.ways):
            return
        if refs is None:
            refs, lons, lats = _way_geometry(way)
        xy = self.window.project(lons, lats)
        self.extract.ways[way.id] = OsmWay(way.id, dict(way.tags), refs, xy)

    def relation(self, relation: Any) -> None:
        """Expect an assembled multipolygon for a relation with a member way in the window."""
        if relation.tags.get("type") != "multipolygon":
            return
        if any(m.type == "w" and m.ref in self.member_ways_in_window for m in relation.members):
            self.expected_relations.add(relation.id)

    def area(self, area: Any) -> None:
        """Keep a multipolygon of interest assembled by osmium whose envelope meets the window."""
        if area.from_way():
            return  # closed ways are read as ways, so broken rings can be repaired
        relation_id = area.orig_id()
        box = _area_envelope(area)
        if box is None:
            return  # not assembled: finish() counts it if the window needed it
        self.extract.extend(box)
        if not self.window.meets(box) or not self._first("r", relation_id, self.extract.multipolygons):
            return
        polygons, outer_refs = [], []
        for outer in area.outer_rings():
            outer_refs.append(frozenset(n.ref for n in outer))
            outer_xy = self.window.project(*zip(*[(n.lon, n.lat) for n in outer], strict=True))
            inners = [
                self.window.project(*zip(*[(n.lon, n.lat) for n in inner], strict=True))
                for inner in area.inner_rings(outer)
            ]
            polygons.append((outer_xy, inners))
        self.extract.multipolygons[relation_id] = OsmMultipolygon(
            relation_id, dict(area.tags), polygons, outer_refs
        )

    def finish(self) -> OsmExtract:
        """The extract, with the multipolygons the window needed but osmium could not assemble counted."""
        missing = self.expected_relations - set(self.extract.multipolygons)
        if missing:
            self.extract.dropped["multipolygon that could not be assembled"] += len(missing)
        return self.extract


class _UnsortedError(Exception):
    """Osmium's assembler met a way out of order, or twice."""


def _stream(
    path: Path,
    source: Path,
    fmt: str,
    collector: _Collector,
    *,
    most_nodes: int,
    progress: Progress | None,
) -> OsmExtract:
    """One read of ``path`` through osmium into ``collector`` (errors name ``source``)."""
    keys = collector.keys
    area_filter = osmium.filter.KeyFilter(*keys)
    main_filter = osmium.filter.KeyFilter(*keys)
    main_filter.enable_for(osmium.osm.NODE | osmium.osm.RELATION | osmium.osm.AREA)
    handlers = {"n": collector.node, "w": collector.way, "r": collector.relation, "a": collector.area}
    with location_indexes(most_nodes) as (index,):
        processor = (
            osmium.FileProcessor(osmium_file(path, fmt))
            .with_locations(index)
            .with_areas(area_filter, collector.members)
            .with_filter(main_filter)
        )
        objects = iter(processor)
        count = 0
        while True:
            try:
                obj = next(objects)
            except StopIteration:
                break
            except OSMIUM_ERRORS as exc:
                if any(words in str(exc).lower() for words in _ORDER_WORDS):
                    raise _UnsortedError(str(exc)) from None
                raise osmium_failure(source, fmt, exc) from None
            handler = handlers.get(obj.type_str())
            if handler is not None:
                handler(obj)
            count += 1
            if progress is not None and count % _PROGRESS_EVERY == 0:
                progress("read", count)
    if progress is not None:
        progress("read", count)
    return collector.finish()


def _sorted_copy(path: Path, fmt: str, target: Path) -> frozenset[tuple[str, int]]:
    """Write ``path`` sorted, each object once, to the PBF ``target``; return the objects it held twice."""
    seen = {kind: _Ids() for kind in "nwr"}
    duplicates: set[tuple[str, int]] = set()
    try:
        for obj in osmium.FileProcessor(osmium_file(path, fmt)):  # a plain read: nothing here needs order
            kind = obj.type_str()
            if kind in seen and seen[kind].add(obj.id):
                duplicates.add((kind, obj.id))
        merger = osmium.MergeInputReader()
        named = target.with_name(f"input.{OSMIUM_FORMATS[fmt]}")  # this reader guesses by the name
        named.symlink_to(path.resolve())
        merger.add_file(str(named))
        writer = osmium.SimpleWriter(str(target))
        try:
            merger.apply(writer, simplify=True)
        finally:
            writer.close()
    except OSMIUM_ERRORS as exc:
        raise osmium_failure(path, fmt, exc) from None
    return frozenset(duplicates)


def read_extract(
    osm_file: OsmFile,
    window: Window,
    *,
    keys: tuple[str, ...],
    progress: Progress | None = None,
) -> OsmExtract:
    """Stream an OSM file and keep the tagged nodes, ways and multipolygons of interest in ``window``.

    Parameters
    ----------
    osm_file : OsmFile
        A file checked by :func:`~navverse.city.osm.files.check_osm_file`.
    window : Window
        What to keep.
    keys : tuple of str
        Tag keys of interest: objects with none of them are skipped (but for the member ways of
        multipolygons, which the assembler needs).
    progress : callable, optional
        ``progress("read", objects)`` every 50,000 objects handed over by osmium.

    Raises
    ------
    CityMapError
        If osmium cannot read the file (truncated, damaged, malformed), or it is unsorted and larger
        than :data:`MAX_SORT_BYTES`.
    """
    path, fmt = osm_file.path, osm_file.format
    most = most_nodes(osm_file)

    def collector(duplicates: frozenset[tuple[str, int]]) -> _Collector:
        """A fresh collector (each read starts from nothing)."""
        return _Collector(window, keys, _RelationMembers(), duplicates)

    try:
        return _stream(path, path, fmt, collector(frozenset()), most_nodes=most, progress=progress)
    except _UnsortedError as exc:
        problem = str(exc)
    size = os.path.getsize(path)
    if size > MAX_SORT_BYTES:
        raise CityMapError(
            f"{path} is not sorted by type and id, or holds a way twice ({problem}), and at "
            f"{size / 1024**2:.0f} MiB is too large to sort in memory: sort it first, e.g. "
            f"`osmium sort {path.name} -o sorted.osm.pbf` (osmium-tool)"
        )
    with tempfile.TemporaryDirectory(prefix="navverse-osm-") as directory:
        target = Path(directory) / "sorted.osm.pbf"
        duplicates = _sorted_copy(path, fmt, target)
        try:
            return _stream(target, path, "pbf", collector(duplicates), most_nodes=most, progress=progress)
        except _UnsortedError as exc:  # not expected of a sorted copy; say so rather than loop
            raise CityMapError(f"{path} could not be read even sorted ({exc})") from None
