"""Terrain with relief: seeded hills or a DEM, graded so that every road stays within its class's grade.

A relief is a :class:`HeightGrid`: heights on a regular raster over the map's window (nodes
:data:`RASTER_CELL` apart, coarser for large windows), bilinear between nodes. It comes from

- :func:`hills`: a sum of :data:`WAVES` plane sinusoids of random direction, wavelength and phase,
  drawn from ``numpy.random.default_rng(seed)``, scaled so that the window's highest and lowest
  nodes are ``relief_height`` apart (:class:`ReliefSettings`);
- or a digital elevation model sampled in the map's frame (:mod:`navverse.city.geometry.dem`).

:func:`graded` then limits its grades, the steepest rise per meter, node to node: each node gets the
limit of the roads whose corridor (carriageway, sidewalks and :data:`CORRIDOR_MARGIN`) covers it
(:data:`GRADE_LIMITS` by ``highway=*``, the strictest where corridors meet), :data:`WATER_GRADE_LIMIT`
on water and :data:`LAND_GRADE_LIMIT` elsewhere. With ``d`` the least cost of a path between two
nodes, a path's cost being its length times the limits along it (times :data:`GRADE_MARGIN`), the
lower envelope ``L(p) = min_q z(q) + d(p, q)`` and the upper one ``U(p) = max_q z(q) - d(p, q)``
both rise at most ``d`` between any two nodes, and so does their mean, the graded relief: a road
climbs no more than its limit along or across it, and a relief that keeps within the limits
everywhere is left as it is (one that does not is changed only around where it does not). Both
envelopes are one Dijkstra search each over the raster's nodes (16 neighbours: the grid's distances
within 3 % of straight ones), from a virtual node joined to every node. The graded relief is 0 at
the window's centre.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Annotated

import numpy as np
import shapely
from pydantic import Field
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra
from shapely.geometry import LineString, Polygon
from shapely.geometry.base import BaseGeometry

from navverse.city.map import CityMap
from navverse.settings import Settings

__all__ = [
    "CORRIDOR_MARGIN",
    "DEFAULT_GRADE_LIMIT",
    "GRADE_LIMITS",
    "GRADE_MARGIN",
    "LAND_GRADE_LIMIT",
    "RASTER_CELL",
    "WATER_GRADE_LIMIT",
    "WAVES",
    "HeightGrid",
    "ReliefSettings",
    "grade_limit",
    "graded",
    "hills",
    "raster_nodes",
    "relief_terrain",
]

GRADE_LIMITS: dict[str, float] = {
    "motorway": 0.06,
    "motorway_link": 0.06,
    "trunk": 0.07,
    "trunk_link": 0.07,
    "primary": 0.08,
    "primary_link": 0.08,
    "busway": 0.08,
    "secondary": 0.10,
    "secondary_link": 0.10,
    "tertiary": 0.10,
    "tertiary_link": 0.10,
    "unclassified": 0.12,
    "residential": 0.12,
    "road": 0.12,
    "living_street": 0.15,
    "service": 0.15,
    "track": 0.15,
    "pedestrian": 0.15,
}
"""Steepest grade (rise per meter) of a road along its centre line, by ``highway=*`` class: the usual
maxima of road design guides (freeways 3–6 %, arterials 6–8 %, collectors about 10 %, local streets
12–15 %), the middle of each range for the class and the top of it for the smallest."""
DEFAULT_GRADE_LIMIT = 0.12
"""Grade limit of a road whose class :data:`GRADE_LIMITS` does not list."""
LAND_GRADE_LIMIT = 0.30
"""Steepest grade of the ground away from roads and water (about 17°, well within the navmesh's 45°)."""
WATER_GRADE_LIMIT = 0.001
"""Steepest grade under water: ponds lie level, a river falls at most 0.1 % along its course."""
GRADE_MARGIN = 0.9
"""The relief is graded to this share of each limit, so that the raster's distances (within 3 % of
straight ones) and the mesh's facets stay under the limit."""
CORRIDOR_MARGIN = 2.0
"""How far beyond a road's sidewalks (or carriageway edge) its grade limit holds (m)."""
RASTER_CELL = 2.0
"""Spacing of the relief's raster nodes (m) for windows of up to :data:`MAX_RASTER_NODES` nodes."""
MAX_RASTER_NODES = 250_000
"""Most nodes of a relief raster; larger windows get a coarser raster."""
WAVES = 6
"""Sinusoids summed by :func:`hills`."""
WAVELENGTH_SPREAD = 0.35
"""Each sinusoid's wavelength is ``relief_wavelength`` times ``exp(u)``, ``u`` uniform within ± this."""


class ReliefSettings(Settings):
    """Synthetic hills: how high and how far apart (0 m high, the default, leaves the terrain flat)."""

    relief_height: Annotated[float, Field(ge=0.0, le=100.0)] = 0.0
    """Height of seeded hills (m): the window's highest and lowest ground are this far apart before
    the roads are graded (:mod:`navverse.city.geometry.terrain`); drawn from the target's seed. 0,
    the default, leaves the terrain flat (or on the ``slope``'s plane)."""
    relief_wavelength: Annotated[float, Field(ge=50.0, le=5000.0)] = 300.0
    """Typical distance between hilltops (m): the sinusoids' wavelengths lie within 0.7 and 1.4 times it."""


@dataclass(frozen=True)
class HeightGrid:
    """Heights on a regular raster in the map's frame, bilinear between nodes and held beyond the edge.

    Attributes
    ----------
    x0, y0 : float
        The first node (m).
    cell : float
        Spacing of the nodes (m).
    heights : ndarray, shape (ny, nx)
        Heights (m); row ``j``, column ``i`` is the node at ``(x0 + i * cell, y0 + j * cell)``.
    """

    x0: float
    y0: float
    cell: float
    heights: np.ndarray

    def __call__(self, points: np.ndarray) -> np.ndarray:
        """Heights at xy ``points`` (N, 2+), shape (N,)."""
        points = np.atleast_2d(np.asarray(points, dtype=np.float64))
        ny, nx = self.heights.shape
        u = np.clip((points[:, 0] - self.x0) / self.cell, 0.0, nx - 1.0)
        v = np.clip((points[:, 1] - self.y0) / self.cell, 0.0, ny - 1.0)
        i = np.minimum(np.floor(u).astype(np.int64), nx - 2)
        j = np.minimum(np.floor(v).astype(np.int64), ny - 2)
        s, t = u - i, v - j
        h = self.heights
        bottom = h[j, i] * (1.0 - s) + h[j, i + 1] * s
        top = h[j + 1, i] * (1.0 - s) + h[j + 1, i + 1] * s
        return bottom * (1.0 - t) + top * t

    @property
    def nodes(self) -> np.ndarray:
        """The xy of every node, row by row, shape (ny * nx, 2)."""
        ny, nx = self.heights.shape
        xs = self.x0 + self.cell * np.arange(nx)
        ys = self.y0 + self.cell * np.arange(ny)
        gx, gy = np.meshgrid(xs, ys)
        return np.column_stack([gx.ravel(), gy.ravel()])

    def with_heights(self, heights: np.ndarray) -> HeightGrid:
        """The same raster with other heights."""
        return HeightGrid(self.x0, self.y0, self.cell, np.asarray(heights, dtype=np.float64))


def raster_nodes(window: tuple[float, float, float, float]) -> HeightGrid:
    """A raster of zeros whose nodes cover ``window`` (min_x, min_y, max_x, max_y) and a cell beyond.

    Nodes lie :data:`RASTER_CELL` apart, or farther for windows that would need more than
    :data:`MAX_RASTER_NODES` nodes; the window's centre is the middle node.
    """
    min_x, min_y, max_x, max_y = window
    width, height = max_x - min_x, max_y - min_y
    cell = max(
        RASTER_CELL, math.sqrt((width + 2 * RASTER_CELL) * (height + 2 * RASTER_CELL) / MAX_RASTER_NODES)
    )
    nx = math.ceil(width / cell / 2.0) * 2 + 3  # odd: the window's centre is a node
    ny = math.ceil(height / cell / 2.0) * 2 + 3
    x0 = (min_x + max_x) / 2.0 - (nx - 1) * cell / 2.0
    y0 = (min_y + max_y) / 2.0 - (ny - 1) * cell / 2.0
    return HeightGrid(x0, y0, cell, np.zeros((ny, nx)))


def _centre(window: tuple[float, float, float, float]) -> np.ndarray:
    return np.array([[(window[0] + window[2]) / 2.0, (window[1] + window[3]) / 2.0]])


def hills(
    window: tuple[float, float, float, float], *, height: float, wavelength: float, seed: int
) -> HeightGrid:
    """Smooth seeded hills over ``window``: :data:`WAVES` plane sinusoids, ``height`` from lowest to highest.

    Parameters
    ----------
    window : tuple of float
        min_x, min_y, max_x, max_y (m).
    height : float
        Difference of the highest and the lowest node within the window (m).
    wavelength : float
        Typical wavelength (m); each sinusoid's is within 0.7 and 1.4 times it.
    seed : int
        Seed of ``numpy.random.default_rng``: the same seed and window, the same hills.

    Returns
    -------
    HeightGrid
        0 at the window's centre.
    """
    grid = raster_nodes(window)
    rng = np.random.default_rng(seed)
    direction = rng.uniform(0.0, 2.0 * math.pi, WAVES)
    spread = rng.uniform(-WAVELENGTH_SPREAD, WAVELENGTH_SPREAD, WAVES)
    phase = rng.uniform(0.0, 2.0 * math.pi, WAVES)
    amplitude = rng.uniform(0.5, 1.0, WAVES)
    number = 2.0 * math.pi / (wavelength * np.exp(spread))
    wave = np.column_stack([np.cos(direction), np.sin(direction)]) * number[:, None]

    def field(points: np.ndarray) -> np.ndarray:
        return np.sin(points @ wave.T + phase) @ amplitude

    nodes = grid.nodes
    values = field(nodes) - field(_centre(window))[0]
    inside = _inside(nodes, window)
    span = float(values[inside].max() - values[inside].min()) if inside.any() else 0.0
    scale = height / span if span > 0.0 else 0.0
    return grid.with_heights((values * scale).reshape(grid.heights.shape))


def _inside(nodes: np.ndarray, window: tuple[float, float, float, float]) -> np.ndarray:
    min_x, min_y, max_x, max_y = window
    return (nodes[:, 0] >= min_x) & (nodes[:, 0] <= max_x) & (nodes[:, 1] >= min_y) & (nodes[:, 1] <= max_y)


def grade_limit(highway: str) -> float:
    """The steepest grade a road of class ``highway`` may have (:data:`GRADE_LIMITS`)."""
    return GRADE_LIMITS.get(highway, DEFAULT_GRADE_LIMIT)


def _limits(grid: HeightGrid, city: CityMap) -> np.ndarray:
    """The grade limit at every node (row by row): roads' corridors, water, land."""
    limits = np.full(grid.heights.size, LAND_GRADE_LIMIT)
    points = shapely.points(grid.nodes)

    def apply(shapes: Iterable[tuple[BaseGeometry, float]]) -> None:
        shapes = [(g, v) for g, v in shapes if not g.is_empty]
        if not shapes:
            return
        tree = shapely.STRtree([g for g, _ in shapes])
        values = np.array([v for _, v in shapes])
        node, shape = tree.query(points, predicate="intersects")
        np.minimum.at(limits, node, values[shape])

    apply(
        (Polygon(a.polygon.exterior, a.polygon.holes).buffer(0), WATER_GRADE_LIMIT)
        for a in city.areas
        if a.cls == "water"
    )
    apply(
        (
            LineString(road.centerline.points).buffer(
                road.reach() + CORRIDOR_MARGIN,
                quad_segs=4,
            ),
            grade_limit(road.highway),
        )
        for road in city.roads
    )
    return limits


_NEIGHBOURS = ((0, 1), (1, 0), (1, 1), (1, -1), (1, 2), (2, 1), (1, -2), (2, -1))
"""Offsets (row, column) to half of a node's 16 neighbours; the other half are their opposites."""


def _graph(limits: np.ndarray, shape: tuple[int, int], cell: float) -> csr_matrix:
    """The raster's nodes joined to their 16 neighbours, each edge costing its length times the mean
    of its ends' limits (times :data:`GRADE_MARGIN`), plus a last, virtual node (no edges yet)."""
    ny, nx = shape
    index = np.arange(ny * nx).reshape(shape)
    rows, cols, costs = [], [], []
    for dj, di in _NEIGHBOURS:
        j0, j1 = max(0, -dj), ny - max(0, dj)
        i0, i1 = max(0, -di), nx - max(0, di)
        a = index[j0:j1, i0:i1].ravel()
        b = index[j0 + dj : j1 + dj, i0 + di : i1 + di].ravel()
        cost = cell * math.hypot(di, dj) * GRADE_MARGIN * (limits[a] + limits[b]) / 2.0
        rows += [a, b]
        cols += [b, a]
        costs += [cost, cost]
    n = ny * nx + 1
    return csr_matrix((np.concatenate(costs), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def _envelope(graph: csr_matrix, heights: np.ndarray) -> np.ndarray:
    """``min_q heights[q] + d(p, q)`` at every node p: a Dijkstra search from the virtual node, joined
    to every node q at ``heights[q]`` (shifted to stay positive)."""
    n = len(heights)
    low = float(heights.min())
    start = csr_matrix(
        (heights - low + 1.0, (np.full(n, n), np.arange(n))), shape=graph.shape
    )  # +1: no zero-cost edge
    distance = dijkstra(graph + start, directed=True, indices=n)
    return distance[:n] + low - 1.0


def graded(grid: HeightGrid, city: CityMap) -> HeightGrid:
    """``grid`` with its grades limited by the roads, water and land of ``city`` (see the module docstring).

    Returns
    -------
    HeightGrid
        The mean of the lower and the upper envelope, 0 at the window's centre.
    """
    heights = grid.heights.ravel()
    graph = _graph(_limits(grid, city), grid.heights.shape, grid.cell)
    lower = _envelope(graph, heights)
    upper = -_envelope(graph, -heights)
    result = grid.with_heights(((lower + upper) / 2.0).reshape(grid.heights.shape))
    return result.with_heights(result.heights - result(_centre(city.window))[0])


def relief_terrain(
    city: CityMap,
    settings: ReliefSettings,
    *,
    seed: int,
    dem: HeightGrid | None = None,
    plane: tuple[float, float] = (0.0, 0.0),
) -> HeightGrid | None:
    """The graded relief of ``city``: a DEM's or seeded hills', on a plane; None when there is neither.

    Parameters
    ----------
    city : CityMap
        The map: its window, roads and water.
    settings : ReliefSettings
        The hills' height and wavelength (ignored when ``dem`` is given).
    seed : int
        The hills' seed.
    dem : HeightGrid, optional
        Heights sampled from a DEM (:func:`navverse.city.geometry.dem.read_dem`).
    plane : tuple of float
        A rise per meter east and north added before grading (the ``slope``).

    Returns
    -------
    HeightGrid or None
        Graded (:func:`graded`); None for ``relief_height`` 0 and no DEM.
    """
    if dem is not None:
        raw = dem
    elif settings.relief_height > 0.0:
        raw = hills(
            city.window, height=settings.relief_height, wavelength=settings.relief_wavelength, seed=seed
        )
    else:
        return None
    if plane != (0.0, 0.0):
        raw = raw.with_heights(raw.heights + (raw.nodes @ np.asarray(plane)).reshape(raw.heights.shape))
    return graded(raw, city)
