"""The windows of an OpenStreetMap file most worth building as a city scene, best first.

:func:`rank_windows` streams the file once through osmium and counts, per cell of a grid
:data:`CELLS_PER_SIDE` times finer than the window (``size_m / 5`` meters) in a local metric frame
(the UTM zone of the first position read, with its origin there):

- buildings: closed ways and multipolygon relations ``building=*`` that the reader makes buildings
  of (not ``no`` or ``roof``, at ground level), at the mean of their nodes (a relation: of the first
  nodes of its member ways);
- POIs: nodes and buildings with a place tag (:func:`~navverse.city.tag_tables.poi_of`);
- street length: ways ``highway=`` a road or walkway class of :data:`~navverse.city.tags.ROAD_CLASSES`
  (:data:`~navverse.city.tag_tables.ROAD_HIGHWAYS`, :data:`~navverse.city.tag_tables.WALKWAY_HIGHWAYS`;
  not areas, at ground level), each piece of a line (at most half a cell long) in the cell of its middle.

The candidate windows are the squares of 5 × 5 cells, slid over the grid a cell at a time. A
window's score is the mean of its buildings, POIs and street length, each as a fraction of the most
any window of the file has (1.0: the best window for all three). The windows listed are picked
greedily, best score first (ties: south first, then west), passing over any that would overlap one
already picked (centres less than a side apart both east-west and north-south), whose centre lies
outside the bounds the file declares (the ``osm_city`` stage refuses those; without bounds, outside
the extent of what was counted), that hold no building and no street, or that score under
:data:`MIN_SCORE` (all but empty). Data that fits in a window both ways gives one window: the data's
extent.

Memory: the grid's non-empty cells, positions projected in batches, and osmium's location indexes:
of every node (to give ways their geometry, as :mod:`.stream` does), and of the first node of every
way (multipolygon relations come after their ways in a file), in memory for files that can hold at
most :data:`~navverse.city.osm.stream.IN_MEMORY_INDEX_NODES` nodes, in temporary files beyond.
The same file and size give the same windows.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import osmium
import osmium.filter
import osmium.index
import osmium.osm

from navverse.city.map import CityMapError
from navverse.city.osm.files import (
    OSMIUM_ERRORS,
    OsmFile,
    Progress,
    check_osm_file,
    file_bounds,
    osmium_failure,
    osmium_file,
)
from navverse.city.osm.stream import location_indexes, most_nodes
from navverse.city.osm.window import MAX_WINDOW_SIDE, LocalFrame, LonLatBox
from navverse.city.tag_tables import (
    FEATURE_KEYS,
    ROAD_HIGHWAYS,
    WALKWAY_HIGHWAYS,
    building_value,
    is_area,
    poi_of,
    tag_value,
)
from navverse.city.tags import at_ground_level

__all__ = [
    "CELLS_PER_SIDE",
    "MAX_TOP",
    "MIN_SCORE",
    "MIN_WINDOW_SIDE",
    "STREET_HIGHWAYS",
    "WindowRank",
    "WindowRanking",
    "check_window_options",
    "rank_windows",
]

CELLS_PER_SIDE = 5
"""Cells along a window's side: windows slide by a fifth of their side."""
MIN_WINDOW_SIDE = 50.0
"""Smallest window side ranked (m)."""
MAX_TOP = 100
"""Most windows listed."""
MIN_SCORE = 0.05
"""Windows scoring less are not listed (a few sheds or a stretch of road at the edge of the data)."""
STREET_HIGHWAYS = ROAD_HIGHWAYS | WALKWAY_HIGHWAYS
"""``highway=*`` values whose length counts as street: the roads and walkways of a city map."""

_BATCH = 65_536
"""Positions gathered before they are projected and counted into cells."""
_PROGRESS_EVERY = 50_000
_KEY_OFFSET = 1 << 30
"""Cell indices are packed as ``(i + offset) << 31 | (j + offset)``: ±1e9 cells of at least 10 m."""
_EXTENT_MARGIN = 10.0
"""Meters added to each side of the data's extent when it is the one window (m)."""
_BUILDING, _POI = 0, 1


@dataclass(frozen=True)
class WindowRank:
    """One window of a file, as :func:`rank_windows` lists it.

    Attributes
    ----------
    rank : int
        1 for the best window.
    center : tuple of float
        ``(lat, lon)`` of the window's centre, in degrees rounded to 6 decimals (about 0.1 m).
    size_m : tuple of float
        ``(east-west, north-south)`` sides (m).
    buildings : int
        Buildings whose centre lies in the window.
    pois : int
        POIs in the window (on nodes and on buildings).
    street_m : float
        Length of roads and walkways in the window (m).
    score : float
        Mean of the three measures, each as a fraction of the most any window has (0 to 1).
    """

    rank: int
    center: tuple[float, float]
    size_m: tuple[float, float]
    buildings: int
    pois: int
    street_m: float
    score: float

    @property
    def street_km(self) -> float:
        """:attr:`street_m` in kilometres."""
        return self.street_m / 1000.0


@dataclass(frozen=True)
class WindowRanking:
    """What :func:`rank_windows` found in a file.

    Attributes
    ----------
    path : Path
        The file.
    format : str
        ``"xml"``, ``"xml.gz"``, ``"xml.bz2"`` or ``"pbf"`` (from its content).
    size_m : float
        The side of the windows asked for (m).
    windows : list of WindowRank
        Best first, none overlapping another.
    buildings, pois : int
        How many the whole file holds.
    street_m : float
        Street length of the whole file (m).
    extent : tuple of float
        ``(min_lon, min_lat, max_lon, max_lat)`` of the buildings, POIs and streets counted.
    extent_m : tuple of float
        East-west and north-south sides of :attr:`extent` in the local frame (m).
    bounds : tuple of float or None
        The bounds the file declares, if any (window centres lie inside them).
    """

    path: Path
    format: str
    size_m: float
    windows: list[WindowRank]
    buildings: int
    pois: int
    street_m: float
    extent: LonLatBox
    extent_m: tuple[float, float]
    bounds: LonLatBox | None


def _pack(i: np.ndarray, j: np.ndarray) -> np.ndarray:
    return ((i + _KEY_OFFSET) << 31) | (j + _KEY_OFFSET)


def _unpack(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return (keys >> 31) - _KEY_OFFSET, (keys & ((1 << 31) - 1)) - _KEY_OFFSET


def _group_sum(keys: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sorted unique keys and the sum of the rows of ``values`` (n, m) sharing each."""
    unique, inverse = np.unique(keys, return_inverse=True)
    sums = np.zeros((len(unique), values.shape[1]))
    np.add.at(sums, inverse, values)
    return unique, sums


class _Cells:
    """Counts per grid cell (buildings, POIs, street meters), and the extent of what was counted."""

    def __init__(self, cell: float) -> None:
        self.cell = cell
        self.frame: LocalFrame | None = None
        self.sums: dict[int, np.ndarray] = {}
        self.box = [math.inf, math.inf, -math.inf, -math.inf]  # lon/lat of every position counted
        self.rect = [math.inf, math.inf, -math.inf, -math.inf]  # the same in the local frame
        self._points: tuple[list[float], list[float], list[int]] = ([], [], [])
        self._lines: tuple[list[float], list[float], list[int]] = ([], [], [])
        self._line_id = 0

    def add_point(self, lon: float, lat: float, kind: int) -> None:
        """Count a building or a POI at a position."""
        lons, lats, kinds = self._points
        lons.append(lon)
        lats.append(lat)
        kinds.append(kind)
        if len(lons) >= _BATCH:
            self.flush()

    def add_line(self, lons: list[float], lats: list[float]) -> None:
        """Count a street line's length (positions in degrees, at least two)."""
        line_lons, line_lats, ids = self._lines
        line_lons.extend(lons)
        line_lats.extend(lats)
        ids.extend([self._line_id] * len(lons))
        self._line_id += 1
        if len(line_lons) >= _BATCH:
            self.flush()

    def _project(self, lons: list[float], lats: list[float]) -> tuple[np.ndarray, np.ndarray]:
        lon, lat = np.asarray(lons, dtype=float), np.asarray(lats, dtype=float)
        if self.frame is None:
            self.frame = LocalFrame.around(float(lat[0]), float(lon[0]))
        box, rect = self.box, self.rect
        box[:] = [
            min(box[0], lon.min()),
            min(box[1], lat.min()),
            max(box[2], lon.max()),
            max(box[3], lat.max()),
        ]
        xy = self.frame.project(lon, lat)
        x, y = xy[:, 0], xy[:, 1]
        rect[:] = [min(rect[0], x.min()), min(rect[1], y.min()), max(rect[2], x.max()), max(rect[3], y.max())]
        return x, y

    def _count(self, x: np.ndarray, y: np.ndarray, values: np.ndarray) -> None:
        i = np.floor(x / self.cell).astype(np.int64)
        j = np.floor(y / self.cell).astype(np.int64)
        keys, sums = _group_sum(_pack(i, j), values)
        for key, row in zip(keys.tolist(), sums, strict=True):
            held = self.sums.get(key)
            self.sums[key] = row if held is None else held + row

    def flush(self) -> None:
        """Project the positions gathered and count them into their cells."""
        lons, lats, kinds = self._points
        if lons:
            x, y = self._project(lons, lats)
            kind = np.asarray(kinds)
            values = np.column_stack([kind == _BUILDING, kind == _POI, np.zeros(len(kind))]).astype(float)
            self._count(x, y, values)
        line_lons, line_lats, ids = self._lines
        if line_lons:
            x, y = self._project(line_lons, line_lats)
            self._count_segments(x, y, np.asarray(ids))
        self._points = ([], [], [])
        self._lines = ([], [], [])

    def _count_segments(self, x: np.ndarray, y: np.ndarray, ids: np.ndarray) -> None:
        """Count the segments between consecutive positions of a line, cut into pieces of at most half
        a cell, each in the cell of its middle."""
        same = ids[1:] == ids[:-1]
        x0, y0, x1, y1 = x[:-1][same], y[:-1][same], x[1:][same], y[1:][same]
        length = np.hypot(x1 - x0, y1 - y0)
        pieces = np.maximum(1, np.ceil(length / (self.cell / 2.0))).astype(np.int64)
        segment = np.repeat(np.arange(len(length)), pieces)
        first = np.repeat(np.cumsum(pieces) - pieces, pieces)
        t = (np.arange(len(segment)) - first + 0.5) / pieces[segment]
        mid_x = x0[segment] + (x1 - x0)[segment] * t
        mid_y = y0[segment] + (y1 - y0)[segment] * t
        piece_length = (length / pieces)[segment]
        values = np.column_stack([np.zeros(len(segment)), np.zeros(len(segment)), piece_length])
        if len(segment):
            self._count(mid_x, mid_y, values)

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Cell indices i, j and their sums (n, 3), in key order."""
        keys = np.array(sorted(self.sums), dtype=np.int64)
        values = np.array([self.sums[key] for key in keys.tolist()]).reshape(len(keys), 3)
        i, j = _unpack(keys)
        return i, j, values


class _Scan:
    """What one streamed read hands over: buildings, POIs and street lines, into :class:`_Cells`."""

    def __init__(self, cells: _Cells, way_firsts: Any) -> None:
        self.cells = cells
        self.way_firsts = way_firsts  # way id -> location of its first node

    def node(self, node: Any) -> None:
        """Count a POI node."""
        location = node.location
        if location.valid() and poi_of(node.tags) is not None:
            self.cells.add_point(location.lon, location.lat, _POI)

    def way(self, way: Any) -> None:
        """Note where a way starts; count a building outline or a street line."""
        nodes = way.nodes
        if len(nodes) == 0:
            return
        first = nodes[0].location
        if way.id >= 0 and first.valid():
            self.way_firsts.set(way.id, first)
        tags = way.tags
        if "building" in tags:
            if len(nodes) >= 4 and nodes[0].ref == nodes[-1].ref and _is_building(tags):
                self._building(tags, [n.location for n in list(nodes)[:-1]])
        elif "highway" in tags and _is_street(tags):
            self._street(nodes)

    def relation(self, relation: Any) -> None:
        """Count a multipolygon building at the mean of its member ways' first nodes."""
        tags = relation.tags
        if tags.get("type") != "multipolygon" or not _is_building(tags):
            return
        locations = []
        for member in relation.members:
            if member.type == "w" and member.role in ("outer", "") and member.ref >= 0:
                try:
                    locations.append(self.way_firsts.get(member.ref))
                except KeyError:  # a member way the file does not hold
                    continue
        self._building(tags, locations)

    def _building(self, tags: Any, locations: list[Any]) -> None:
        valid = [(loc.lon, loc.lat) for loc in locations if loc.valid()]
        if not valid:
            return
        lon = math.fsum(p[0] for p in valid) / len(valid)
        lat = math.fsum(p[1] for p in valid) / len(valid)
        self.cells.add_point(lon, lat, _BUILDING)
        if poi_of(tags) is not None:
            self.cells.add_point(lon, lat, _POI)

    def _street(self, nodes: Any) -> None:
        """Count the runs of a street's nodes that have locations (a missing node breaks the line)."""
        lons: list[float] = []
        lats: list[float] = []
        for node in nodes:
            location = node.location
            if location.valid():
                lons.append(location.lon)
                lats.append(location.lat)
                continue
            if len(lons) >= 2:
                self.cells.add_line(lons, lats)
            lons, lats = [], []
        if len(lons) >= 2:
            self.cells.add_line(lons, lats)


def _is_building(tags: Any) -> bool:
    """Whether the reader makes a building of an outline with these tags."""
    value = building_value(tags)
    return value is not None and value != "roof" and at_ground_level(tags)


def _is_street(tags: Any) -> bool:
    """Whether the reader makes a road or walkway of a way with these tags."""
    return tag_value(tags, "highway") in STREET_HIGHWAYS and not is_area(tags) and at_ground_level(tags)


def _count_cells(osm_file: OsmFile, cell: float, progress: Progress | None) -> _Cells:
    """One streamed read of the file into cells of ``cell`` meters."""
    cells = _Cells(cell)
    node_filter = osmium.filter.KeyFilter(*FEATURE_KEYS)
    node_filter.enable_for(osmium.osm.NODE)
    relation_filter = osmium.filter.KeyFilter("building")
    relation_filter.enable_for(osmium.osm.RELATION)
    with location_indexes(most_nodes(osm_file), ("nodes", "ways")) as (nodes_index, ways_index):
        node_locations = osmium.index.create_map(nodes_index)
        way_firsts = osmium.index.create_map(ways_index)
        scan = _Scan(cells, way_firsts)
        handlers = {"n": scan.node, "w": scan.way, "r": scan.relation}
        processor = (
            osmium.FileProcessor(
                osmium_file(osm_file.path, osm_file.format),
                osmium.osm.NODE | osmium.osm.WAY | osmium.osm.RELATION,
            )
            .with_locations(node_locations)
            .with_filter(node_filter)
            .with_filter(relation_filter)
        )
        count = 0
        try:
            for obj in processor:
                handlers[obj.type_str()](obj)
                count += 1
                if progress is not None and count % _PROGRESS_EVERY == 0:
                    progress("read", count)
        except OSMIUM_ERRORS as exc:
            raise osmium_failure(osm_file.path, osm_file.format, exc) from None
        cells.flush()
    if progress is not None:
        progress("read", count)
    return cells


def _window_sums(
    i: np.ndarray, j: np.ndarray, values: np.ndarray, k: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The sums of every k × k square of cells holding data, by the cell of its south-west corner.

    Summed east-west, then north-south, over the non-empty cells only (a sparse grid: a region's
    file spans far more cells than hold data)."""
    shifts = np.arange(k)
    keys = _pack(np.repeat(i, k) - np.tile(shifts, len(i)), np.repeat(j, k))
    rows, sums = _group_sum(keys, np.repeat(values, k, axis=0))
    ri, rj = _unpack(rows)
    keys = _pack(np.repeat(ri, k), np.repeat(rj, k) - np.tile(shifts, len(rj)))
    corners, sums = _group_sum(keys, np.repeat(sums, k, axis=0))
    ci, cj = _unpack(corners)
    return ci, cj, sums


def _scores(sums: np.ndarray) -> np.ndarray:
    """Each window's mean of its measures as fractions of the most any window has (0 for a measure
    no window has)."""
    most = sums.max(axis=0)
    fractions = np.divide(sums, most, out=np.zeros_like(sums), where=most > 0)
    return fractions.mean(axis=1)


def _inside(bounds: LonLatBox | None, lon: float, lat: float) -> bool:
    return bounds is None or (bounds[0] <= lon <= bounds[2] and bounds[1] <= lat <= bounds[3])


def _pick(cells: _Cells, *, size_m: float, top: int, bounds: LonLatBox | None) -> list[WindowRank]:
    """The best ``top`` windows of :data:`CELLS_PER_SIDE` cells a side, none overlapping another."""
    k = CELLS_PER_SIDE
    ci, cj, sums = _window_sums(*cells.arrays(), k)
    scores = _scores(sums)
    keep = ((sums[:, 0] > 0) | (sums[:, 2] > 0)) & (scores >= MIN_SCORE)  # osm_city needs either
    ci, cj, sums, scores = ci[keep], cj[keep], sums[keep], scores[keep]
    order = np.lexsort((ci, cj, -scores))
    frame = cells.frame
    assert frame is not None
    picked: list[tuple[int, int]] = []
    windows: list[WindowRank] = []
    for index in order.tolist():
        corner = (int(ci[index]), int(cj[index]))
        if any(abs(corner[0] - a) < k and abs(corner[1] - b) < k for a, b in picked):
            continue
        x, y = (corner[0] + k / 2.0) * cells.cell, (corner[1] + k / 2.0) * cells.cell
        lons, lats = frame.lonlat(np.array([x]), np.array([y]))
        lon, lat = float(lons[0]), float(lats[0])
        if not _inside(bounds, lon, lat):
            continue
        picked.append(corner)
        row = sums[index]
        windows.append(
            WindowRank(
                rank=len(windows) + 1,
                center=(round(lat, 6), round(lon, 6)),
                size_m=(size_m, size_m),
                buildings=round(row[0]),
                pois=round(row[1]),
                street_m=float(row[2]),
                score=float(scores[index]),
            )
        )
        if len(windows) == top:
            break
    return windows


def _whole(cells: _Cells, totals: np.ndarray, *, size_m: float, bounds: LonLatBox | None) -> WindowRank:
    """The one window of data that fits in a window both ways: its extent (buildings are counted at
    their middle: :data:`_EXTENT_MARGIN` more each side), sides rounded up to 10 m, at least
    :data:`MIN_WINDOW_SIDE` and at most the window asked for."""
    frame = cells.frame
    assert frame is not None
    x0, y0, x1, y1 = cells.rect
    lons, lats = frame.lonlat(np.array([(x0 + x1) / 2.0]), np.array([(y0 + y1) / 2.0]))
    lon, lat = float(lons[0]), float(lats[0])
    if bounds is not None:  # the osm_city stage wants the centre inside the declared bounds
        lon, lat = min(max(lon, bounds[0]), bounds[2]), min(max(lat, bounds[1]), bounds[3])
    sides = tuple(
        min(size_m, max(MIN_WINDOW_SIDE, math.ceil(round(extent + 2.0 * _EXTENT_MARGIN, 2) / 10.0) * 10.0))
        for extent in (x1 - x0, y1 - y0)
    )
    return WindowRank(
        rank=1,
        center=(round(lat, 6), round(lon, 6)),
        size_m=(sides[0], sides[1]),
        buildings=round(totals[0]),
        pois=round(totals[1]),
        street_m=float(totals[2]),
        score=1.0,
    )


def check_window_options(*, size_m: float, top: int) -> None:
    """Refuse a window side outside [:data:`MIN_WINDOW_SIDE`, :data:`~.window.MAX_WINDOW_SIDE`] m or a
    ``top`` outside [1, :data:`MAX_TOP`].

    Raises
    ------
    CityMapError
        Saying what to give instead.
    """
    if not (isinstance(size_m, int | float) and MIN_WINDOW_SIDE <= size_m <= MAX_WINDOW_SIDE):
        raise CityMapError(
            f"a window side of {size_m!r} m: give one from {MIN_WINDOW_SIDE:g} to {MAX_WINDOW_SIDE:g} m"
        )
    if isinstance(top, bool) or not isinstance(top, int) or not 1 <= top <= MAX_TOP:
        raise CityMapError(f"{top!r} windows: give from 1 to {MAX_TOP} windows to list")


def rank_windows(
    path: str | os.PathLike[str],
    *,
    size_m: float = 500.0,
    top: int = 10,
    progress: Progress | None = None,
) -> WindowRanking:
    """The square windows of an OSM file with the most buildings, POIs and streets, best first.

    Parameters
    ----------
    path : path
        An OSM file (XML, gzipped or bzip2-compressed XML, or PBF; recognised by its content).
    size_m : float
        The windows' side (m), from :data:`MIN_WINDOW_SIDE` to 50 km.
    top : int
        How many windows to list at most (1 to :data:`MAX_TOP`); fewer where the data has no room
        for more without overlaps.
    progress : callable, optional
        ``progress("read", objects)`` every 50,000 OSM objects read, and at the end.

    Returns
    -------
    WindowRanking
        The windows (see the module for the counts, the score and the pick), and the file's totals.

    Raises
    ------
    CityMapError
        If the size or ``top`` is out of range, the file cannot be read
        (:func:`~navverse.city.osm.files.check_osm_file`), or it holds no building and no street.
    """
    check_window_options(size_m=size_m, top=top)
    size_m = float(size_m)
    osm_file = check_osm_file(path)
    bounds = file_bounds(osm_file.path, osm_file.format)
    cells = _count_cells(osm_file, size_m / CELLS_PER_SIDE, progress)
    _, _, values = cells.arrays()
    totals = values.sum(axis=0) if len(values) else np.zeros(3)
    if totals[0] == 0 and totals[2] == 0:
        raise CityMapError(
            f"{osm_file.path} holds no buildings and no streets (building=*, or highway= a road or "
            "walkway): give an OSM extract of a built-up area"
        )
    x0, y0, x1, y1 = cells.rect
    if x1 - x0 <= size_m and y1 - y0 <= size_m:
        windows = [_whole(cells, totals, size_m=size_m, bounds=bounds)]
    else:
        extent = (cells.box[0], cells.box[1], cells.box[2], cells.box[3])
        windows = _pick(cells, size_m=size_m, top=top, bounds=bounds or extent)
    if not windows:
        raise CityMapError(
            f"no window of {size_m:g} m of {osm_file.path} has its centre inside the bounds the file "
            "declares and a building or a street: try smaller windows"
        )
    return WindowRanking(
        path=osm_file.path,
        format=osm_file.format,
        size_m=size_m,
        windows=windows,
        buildings=round(totals[0]),
        pois=round(totals[1]),
        street_m=float(totals[2]),
        extent=(cells.box[0], cells.box[1], cells.box[2], cells.box[3]),
        extent_m=(x1 - x0, y1 - y0),
        bounds=bounds,
    )
