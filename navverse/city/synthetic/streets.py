"""Street networks of synthetic cities: grid, radial and organic layouts, clipped and cleaned.

A network is a list of :class:`Piece` s, polylines with coordinates rounded to the millimetre that
meet only at their end points: a junction is an end point the pieces share exactly, so the
carriageways buffered from them union cleanly. Every piece belongs to a :class:`Street` (a grid line,
a ring, a spoke, a lattice row or column, a dead end) carrying its rank: 0 a major arterial, 1 a
minor arterial, 2 a residential street.

Layouts (each planar by construction, nothing is noded afterwards):

- :func:`grid_network`: lines every ``block`` meters each way, the spacing jittered;
- :func:`radial_network`: rings around a centre (near the window's centre), spokes from the
  innermost ring outward, their number doubled at the ring where the arc between two spokes would
  grow beyond 1.3 blocks;
- :func:`organic_network`: a lattice, turned by a random angle, whose nodes are jittered (less than a
  quarter of the spacing each way, so straight edges cannot cross), thinned to a random spanning tree
  plus most other edges (some removed edges keep a dead-end stub from one end), then bent by a smooth
  displacement field whose gradient stays below 1 (a one-to-one map, so curves cannot cross either).

Cleaning (:func:`clip`, :func:`cut_at_water`, :func:`main_component`, :func:`merge_chains`) keeps
the pieces in the window, stops streets at a river except the chosen bridges, keeps the largest
connected network and joins pieces of one street that meet at a node no other street reaches.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import LineString, MultiLineString, Point, Polygon, box
from shapely.geometry.base import BaseGeometry

from navverse.city.clipping import clip_segment

__all__ = [
    "Network",
    "Piece",
    "Street",
    "clip",
    "cut_at_water",
    "grid_network",
    "main_component",
    "merge_chains",
    "node_pieces",
    "organic_network",
    "radial_network",
]

XY = tuple[float, float]
Window = tuple[float, float, float, float]
ARC_STEP = 6.0
"""Longest chord of a curved street (m): a 6 m chord of a 50 m radius arc is 9 cm off the arc."""


@dataclass(frozen=True)
class Street:
    """A street the pieces of a network are drawn from: its rank (0 major arterial, 1 minor arterial,
    2 residential) and what it is (``line``, ``ring``, ``spoke``, ``row``, ``stub``)."""

    rank: int
    kind: str


@dataclass(frozen=True)
class Piece:
    """A polyline of a network (millimetre coordinates, no repeated points) and its street's index."""

    points: tuple[XY, ...]
    street: int

    @property
    def length(self) -> float:
        """Length along the points (m)."""
        return sum(math.dist(a, b) for a, b in itertools.pairwise(self.points))


@dataclass
class Network:
    """Streets and the pieces drawn from them; ``squares`` are points whose block is a square."""

    streets: list[Street]
    pieces: list[Piece]
    squares: list[XY] = field(default_factory=list)


def _mm(point: Sequence[float]) -> XY:
    return (round(float(point[0]), 3) + 0.0, round(float(point[1]), 3) + 0.0)


def _piece(points: Iterable[Sequence[float]], street: int) -> Piece | None:
    """A piece from ``points`` rounded to the millimetre (repeats dropped), None if under 2 points."""
    kept: list[XY] = []
    for point in points:
        rounded = _mm(point)
        if not kept or rounded != kept[-1]:
            kept.append(rounded)
    return Piece(tuple(kept), street) if len(kept) >= 2 else None


def _add(pieces: list[Piece], points: Iterable[Sequence[float]], street: int) -> None:
    piece = _piece(points, street)
    if piece is not None:
        pieces.append(piece)


def _lines(rng: np.random.Generator, start: float, end: float, spacing: float, jitter: float) -> list[float]:
    """Positions from ``start`` to before ``end``, ``spacing`` apart on average (jittered)."""
    positions = [start]
    while positions[-1] + spacing * (1.0 + jitter) < end:
        positions.append(positions[-1] + spacing * (1.0 + jitter * float(rng.uniform(-1.0, 1.0))))
    return positions


def _rank(index: int, every: int) -> int:
    """Rank of the ``index``-th parallel street: every ``every``-th one an arterial, alternately
    major and minor, the first a few streets in from the edge."""
    if index % every != every // 2:
        return 2
    return 0 if (index // every) % 2 == 0 else 1


def grid_network(
    rng: np.random.Generator,
    window: Window,
    *,
    block: tuple[float, float],
    jitter: float,
    arterial_every: int,
) -> Network:
    """Streets along x and y across the whole window.

    Parameters
    ----------
    rng : numpy.random.Generator
        Draws the spacing.
    window : tuple of float
        ``(min_x, min_y, max_x, max_y)``.
    block : tuple of float
        Mean spacing of the streets along x and along y (m); the first is half a block in.
    jitter : float
        Each spacing is ``block`` × (1 ± up to ``jitter``).
    arterial_every : int
        Every n-th street each way is an arterial (see :func:`_rank`).

    Returns
    -------
    Network
        One street per grid line, one piece per stretch between crossing lines.
    """
    min_x, min_y, max_x, max_y = window
    xs = _lines(rng, min_x + block[0] / 2.0, max_x, block[0], jitter)
    ys = _lines(rng, min_y + block[1] / 2.0, max_y, block[1], jitter)
    streets: list[Street] = []
    pieces: list[Piece] = []
    for i, x in enumerate(xs):
        streets.append(Street(_rank(i, arterial_every), "line"))
        stops = [min_y, *ys, max_y]
        for a, b in itertools.pairwise(stops):
            _add(pieces, [(x, a), (x, b)], len(streets) - 1)
    for j, y in enumerate(ys):
        streets.append(Street(_rank(j, arterial_every), "line"))
        stops = [min_x, *xs, max_x]
        for a, b in itertools.pairwise(stops):
            _add(pieces, [(a, y), (b, y)], len(streets) - 1)
    return Network(streets, pieces)


def _arc(centre: XY, radius: float, start: float, end: float, first: XY, last: XY) -> list[XY]:
    """Points along a circle from angle ``start`` to ``end`` (counter-clockwise), ending exactly at
    the given end points."""
    steps = max(1, math.ceil(radius * (end - start) / ARC_STEP))
    inner = [
        (centre[0] + radius * math.cos(a), centre[1] + radius * math.sin(a))
        for a in np.linspace(start, end, steps + 1)[1:-1]
    ]
    return [first, *inner, last]


def radial_network(
    rng: np.random.Generator,
    window: Window,
    *,
    block: tuple[float, float],
    jitter: float,
    arterial_every: int,
) -> Network:
    """Rings around a centre and spokes outward from the innermost ring.

    Parameters
    ----------
    rng : numpy.random.Generator
        Draws the centre (within 10 % of the window's size of its middle), the spacing of the rings
        and the angles of the spokes.
    window : tuple of float
        ``(min_x, min_y, max_x, max_y)``.
    block : tuple of float
        Spoke spacing along the rings and ring spacing (m). The innermost ring has four spokes or
        more, about ``block[0]`` apart; spokes double at the ring where they would grow more than
        1.3 blocks apart.
    jitter : float
        Ring spacing is ``block[1]`` × (1 ± up to ``jitter``); spoke angles vary as much.
    arterial_every : int
        Every n-th ring is a ``tertiary`` arterial; the innermost ring's spokes are ``secondary``.

    Returns
    -------
    Network
        Streets for spokes and rings, pieces between their crossings; ``squares`` holds the centre
        (the block inside the innermost ring is a square).
    """
    min_x, min_y, max_x, max_y = window
    width, height = max_x - min_x, max_y - min_y
    centre = (
        (min_x + max_x) / 2.0 + width * 0.1 * float(rng.uniform(-1.0, 1.0)),
        (min_y + max_y) / 2.0 + height * 0.1 * float(rng.uniform(-1.0, 1.0)),
    )
    reach = max(math.dist(centre, corner) for corner in itertools.product((min_x, max_x), (min_y, max_y)))
    ring_gap, arc_gap = block[1], block[0]
    radii = [max(0.6 * ring_gap, arc_gap * 4.0 / (2.0 * math.pi))]
    while radii[-1] < reach:
        radii.append(radii[-1] + ring_gap * (1.0 + jitter * float(rng.uniform(-1.0, 1.0))))
    if len(radii) > 1:
        radii.pop()  # beyond every corner: wholly outside the window
    outer = reach + ring_gap
    # Spokes: (angle, first ring); the first ones split the innermost ring in about one block arcs.
    count = max(4, round(2.0 * math.pi * radii[0] / arc_gap))
    turn = float(rng.uniform(0.0, 2.0 * math.pi))
    spread = math.pi / count * jitter
    spokes = [
        (turn + 2.0 * math.pi * k / count + spread * float(rng.uniform(-1, 1)), 0) for k in range(count)
    ]
    for k, radius in enumerate(radii[1:], start=1):
        active = sorted(a for a, _ in spokes)
        if 2.0 * math.pi * radius / len(active) > 1.3 * arc_gap:
            gaps = [*itertools.pairwise(active), (active[-1], active[0] + 2.0 * math.pi)]
            for a, b in gaps:
                mid = (a + b) / 2.0 + (b - a) * 0.25 * jitter * float(rng.uniform(-1.0, 1.0))
                spokes.append((mid, k))
    spokes = [(a % (2.0 * math.pi), k) for a, k in spokes]

    def at(radius: float, angle: float) -> XY:
        return _mm((centre[0] + radius * math.cos(angle), centre[1] + radius * math.sin(angle)))

    streets: list[Street] = []
    pieces: list[Piece] = []
    for angle, first in sorted(spokes, key=lambda s: (s[1], s[0])):
        streets.append(Street(0 if first == 0 else 2, "spoke"))
        stops = [at(r, angle) for r in radii[first:]] + [at(outer, angle)]
        for a, b in itertools.pairwise(stops):
            _add(pieces, [a, b], len(streets) - 1)
    for k, radius in enumerate(radii):
        rank = 1 if k % arterial_every == arterial_every // 2 else 2
        streets.append(Street(rank, "ring"))
        active = sorted(a for a, first in spokes if first <= k)
        for a, b in [*itertools.pairwise(active), (active[-1], active[0] + 2.0 * math.pi)]:
            _add(pieces, _arc(centre, radius, a, b, at(radius, a), at(radius, b)), len(streets) - 1)
    return Network(streets, pieces, squares=[_mm(centre)])


class _Disjoint:
    """Union-find over hashable items."""

    def __init__(self) -> None:
        self.parent: dict[object, object] = {}

    def find(self, item: object) -> object:
        parent = self.parent.setdefault(item, item)
        if parent != item:
            parent = self.parent[item] = self.find(parent)
        return parent

    def union(self, a: object, b: object) -> bool:
        ra, rb = self.find(a), self.find(b)
        if ra == rb:
            return False
        self.parent[rb] = ra
        return True


def _warp(
    rng: np.random.Generator, amplitude: float, spacing: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Three sine waves: amplitudes, wave vectors, phases, displacement directions, with the sum of
    amplitude × wave number at most 0.6 so the displacement is one-to-one."""
    waves = 3
    directions = rng.uniform(0.0, 2.0 * math.pi, size=(waves, 2))
    wavelength = np.maximum(
        rng.uniform(3.0, 6.0, size=waves) * spacing, 2.0 * math.pi * amplitude * waves / 0.6
    )
    vectors = (
        np.stack([np.cos(directions[:, 0]), np.sin(directions[:, 0])], axis=1)
        * (2.0 * math.pi / wavelength)[:, None]
    )
    pushes = np.stack([np.cos(directions[:, 1]), np.sin(directions[:, 1])], axis=1) * amplitude
    phases = rng.uniform(0.0, 2.0 * math.pi, size=waves)
    return vectors, phases, pushes, wavelength


def _warped(points: np.ndarray, warp: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    vectors, phases, pushes, _ = warp
    return points + np.sin(points @ vectors.T + phases) @ pushes


def organic_network(
    rng: np.random.Generator,
    window: Window,
    *,
    block: tuple[float, float],
    node_jitter: float,
    removal: float,
    dead_ends: float,
    curviness: float,
    arterial_every: int,
) -> Network:
    """An irregular network: a turned, jittered, thinned and bent lattice (see the module docstring).

    Parameters
    ----------
    rng : numpy.random.Generator
        Draws the lattice's turn, the junction displacements, the spanning tree, the removals and
        the bending waves.
    window : tuple of float
        ``(min_x, min_y, max_x, max_y)``.
    block : tuple of float
        Lattice spacing along its rows and columns (m).
    node_jitter : float
        Junction displacement, as a share of ``block`` each way (under 0.25; zero across arterials).
    removal : float
        Share of residential edges outside the spanning tree that are removed.
    dead_ends : float
        Share of removed edges that keep 35–60 % of their length from one end as a dead end.
    curviness : float
        Amplitude of each of the three displacement waves (m); their wavelengths are 3–6 blocks, and
        longer when needed to keep the displacement one-to-one.
    arterial_every : int
        Every n-th lattice row and column is an arterial.

    Returns
    -------
    Network
        A street per lattice row and column and per dead end.
    """
    min_x, min_y, max_x, max_y = window
    centre = np.array([(min_x + max_x) / 2.0, (min_y + max_y) / 2.0])
    radius = math.hypot(max_x - min_x, max_y - min_y) / 2.0 + 2.0 * max(block) + curviness
    turn = float(rng.uniform(0.0, math.pi / 2.0))
    rotation = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    ni, nj = (math.ceil(radius / block[0]), math.ceil(radius / block[1]))
    index = [(i, j) for j in range(-nj, nj + 1) for i in range(-ni, ni + 1)]
    shake = rng.uniform(-node_jitter, node_jitter, size=(len(index), 2))
    # Nodes of an arterial row (column) keep their place across it, so arterials run smoothly.
    for k, (i, j) in enumerate(index):
        shake[k, 1] *= _rank(j + 1000 * arterial_every, arterial_every) == 2
        shake[k, 0] *= _rank(i + 1000 * arterial_every, arterial_every) == 2
    local = (np.array(index, dtype=float) + shake) * np.array(block)
    position = {ij: centre + rotation @ p for ij, p in zip(index, local, strict=True)}
    near = {ij for ij, p in position.items() if math.dist(p, centre) <= radius}
    # Edges along rows (varying i, street per j) and columns (varying j, street per i).
    streets: list[Street] = []
    street_of: dict[tuple[str, int], int] = {}
    edges: list[tuple[tuple[int, int], tuple[int, int], int]] = []
    for i, j in index:
        for di, dj, kind, line in ((1, 0, "row", j), (0, 1, "col", i)):
            other = (i + di, j + dj)
            if (i, j) not in near or other not in near:
                continue
            key = (kind, line)
            if key not in street_of:
                street_of[key] = len(streets)
                streets.append(Street(_rank(line + 1000 * arterial_every, arterial_every), "row"))
            edges.append(((i, j), other, street_of[key]))
    # A random spanning tree (arterials first), then each other residential edge kept or removed.
    draws = rng.uniform(size=len(edges))
    order = sorted(range(len(edges)), key=lambda e: (streets[edges[e][2]].rank == 2, draws[e]))
    tree = _Disjoint()
    in_tree = [False] * len(edges)
    for e in order:
        in_tree[e] = tree.union(edges[e][0], edges[e][1])
    warp = _warp(rng, curviness, float(np.mean(block)))
    nodes = sorted({ij for a, b, _ in edges for ij in (a, b)})
    bent = dict(zip(nodes, _warped(np.array([position[ij] for ij in nodes]), warp), strict=True))
    pieces: list[Piece] = []
    for e, (a, b, street) in enumerate(edges):
        share = 1.0
        if streets[street].rank == 2 and not in_tree[e] and float(rng.uniform()) < removal:
            if float(rng.uniform()) >= dead_ends:
                continue
            share = float(rng.uniform(0.35, 0.6))  # a dead end: part of the edge from one end
        start, end = (a, b) if float(rng.uniform()) < 0.5 else (b, a)
        steps = max(1, math.ceil(math.dist(position[start], position[end]) * share / ARC_STEP))
        reach = position[start] + (position[end] - position[start]) * share
        curve = _warped(np.linspace(position[start], reach, steps + 1), warp)
        curve[0] = bent[start]
        if share == 1.0:
            curve[-1] = bent[end]
        else:
            streets.append(Street(2, "stub"))
            street = len(streets) - 1
        _add(pieces, [_mm(p) for p in curve], street)
    return Network(streets, pieces)


def _clipped_part(a: XY, b: XY, window: Window) -> tuple[XY, XY] | None:
    """The part of segment ``a``-``b`` in the closed ``window`` (Liang-Barsky); end points inside
    are returned as they are."""
    span = clip_segment(a, b, window)
    if span is None:
        return None
    t0, t1 = span
    dx, dy = b[0] - a[0], b[1] - a[1]
    start = a if t0 == 0.0 else (a[0] + t0 * dx, a[1] + t0 * dy)
    end = b if t1 == 1.0 else (a[0] + t1 * dx, a[1] + t1 * dy)
    return start, end


def clip(network: Network, window: Window, *, shortest: float = 2.0) -> Network:
    """The pieces' parts inside ``window`` (pieces leaving and re-entering it are split), parts
    shorter than ``shortest`` meters dropped."""
    pieces: list[Piece] = []
    for piece in network.pieces:
        runs: list[list[XY]] = []
        current: list[XY] = []
        for a, b in itertools.pairwise(piece.points):
            part = _clipped_part(a, b, window)
            if part is None:
                if current:
                    runs.append(current)
                current = []
                continue
            if current and current[-1] == part[0]:
                current.append(part[1])
            else:
                if current:
                    runs.append(current)
                current = [part[0], part[1]]
            if part[1] != b:
                runs.append(current)
                current = []
        if current:
            runs.append(current)
        for run in runs:
            clipped = _piece(run, piece.street)
            if clipped is not None and clipped.length >= shortest:
                pieces.append(clipped)
    return Network(network.streets, pieces, network.squares)


def _line_parts(geometry: object) -> list[LineString]:
    parts = getattr(geometry, "geoms", [geometry])
    return [part for part in parts if isinstance(part, LineString) and not part.is_empty]


def _land(window: Window, cut: BaseGeometry) -> list[Polygon]:
    """The polygons of the window minus ``cut``."""
    rest = box(*window).difference(cut)
    return [g for g in getattr(rest, "geoms", [rest]) if isinstance(g, Polygon) and not g.is_empty]


def _side(shores: list[Polygon], point: XY) -> int | None:
    """Index of the shore polygon ``point`` is on (its boundary included), or None."""
    where = Point(point)
    return next((k for k, shore in enumerate(shores) if shore.distance(where) <= 1e-6), None)


def cut_at_water(
    network: Network,
    rng: np.random.Generator,
    water: Polygon,
    banks: dict[int, Polygon],
    *,
    bridges: int,
    window: Window,
    shortest: float = 8.0,
) -> tuple[Network, int]:
    """Streets stopped at the water's banks, but for a few bridges.

    Parameters
    ----------
    network : Network
        The streets, clipped to the window.
    rng : numpy.random.Generator
        Breaks ties between equally good bridges.
    water : shapely.Polygon
        The river.
    banks : dict
        Per street rank, where its centre lines stop: the water grown by the embankment and that
        rank's half street width.
    bridges : int
        Most streets kept whole across the water. A bridge crosses the water once, from one shore
        to the other (the two largest pieces of land beyond the banks, in the window); arterials
        first, then the most square to the water, 120 m apart at least.
    window : tuple of float
        ``(min_x, min_y, max_x, max_y)``.
    shortest : float
        Stubs left shorter than this (m) are dropped.

    Returns
    -------
    tuple of (Network, int)
        The cut network and the number of bridges kept.
    """
    lines = [LineString(piece.points) for piece in network.pieces]
    wet: dict[int, list[int]] = {}  # street -> its pieces reaching its bank
    for index, (piece, line) in enumerate(zip(network.pieces, lines, strict=True)):
        if line.intersects(banks[network.streets[piece.street].rank]):
            wet.setdefault(piece.street, []).append(index)
    # The two largest pieces of land beyond each rank's banks: the shores a bridge must join.
    land = {rank: sorted(_land(window, bank), key=lambda p: -p.area)[:2] for rank, bank in banks.items()}
    shores = {street: land[network.streets[street].rank] for street in wet}
    candidates: list[tuple[float, int, BaseGeometry]] = []
    for street, indices in wet.items():
        ends: dict[XY, int] = {}
        for i in indices:
            for end in (network.pieces[i].points[0], network.pieces[i].points[-1]):
                ends[end] = ends.get(end, 0) + 1
        loose = [end for end, count in ends.items() if count == 1]
        if len(loose) != 2 or len({_side(shores[street], end) for end in loose} - {None}) != 2:
            continue  # not one run from one shore to another
        over = _line_parts(
            shapely.line_merge(MultiLineString([lines[i] for i in indices]).intersection(water))
        )
        if len(over) != 1:
            continue
        # Longer than the narrowest way across: the street meets the water at a slant.
        slant = over[0].length / max(1.0, 2.0 * water.exterior.distance(over[0].centroid))
        score = network.streets[street].rank + 0.5 * slant + 0.3 * float(rng.uniform())
        candidates.append((score, street, over[0].centroid))
    chosen: list[tuple[int, BaseGeometry]] = []
    for _, street, middle in sorted(candidates, key=lambda c: (c[0], c[1])):
        if len(chosen) < bridges and all(middle.distance(other) > 120.0 for _, other in chosen):
            chosen.append((street, middle))
    whole = {i for street, _ in chosen for i in wet[street]}
    pieces: list[Piece] = []
    for index, (piece, line) in enumerate(zip(network.pieces, lines, strict=True)):
        bank = banks[network.streets[piece.street].rank]
        if index in whole or not line.intersects(bank):
            pieces.append(piece)
            continue
        for part in _line_parts(line.difference(bank)):
            kept = _piece(part.coords, piece.street)
            if kept is not None and kept.length >= shortest:
                pieces.append(kept)
    return Network(network.streets, pieces, network.squares), len(chosen)


def node_pieces(network: Network) -> dict[XY, list[tuple[int, bool]]]:
    """Pieces at each node: ``(piece index, True if the piece starts there)``, in piece order."""
    at: dict[XY, list[tuple[int, bool]]] = {}
    for index, piece in enumerate(network.pieces):
        at.setdefault(piece.points[0], []).append((index, True))
        at.setdefault(piece.points[-1], []).append((index, False))
    return at


def main_component(network: Network) -> Network:
    """The largest connected set of pieces (by length)."""
    sets = _Disjoint()
    for piece in network.pieces:
        sets.union(piece.points[0], piece.points[-1])
    length: dict[object, float] = {}
    for piece in network.pieces:
        root = sets.find(piece.points[0])
        length[root] = length.get(root, 0.0) + piece.length
    if not length:
        return Network(network.streets, [], network.squares)
    best = max(length, key=lambda root: length[root])
    pieces = [piece for piece in network.pieces if sets.find(piece.points[0]) == best]
    return Network(network.streets, pieces, network.squares)


def merge_chains(network: Network) -> Network:
    """Pieces of one street meeting at a node no other piece reaches joined into one; a closed
    loop becomes one piece starting and ending at the same node."""
    at = node_pieces(network)
    used = [False] * len(network.pieces)

    def follow(points: list[XY], street: int, start: int) -> list[XY]:
        """Extend ``points`` past their last node while a single same-street piece continues."""
        while True:
            here = at[points[-1]]
            others = [(i, s) for i, s in here if not used[i]]
            if len(here) != 2 or len(others) != 1:
                return points
            index, starts = others[0]
            piece = network.pieces[index]
            if piece.street != street or index == start:
                return points
            used[index] = True
            more = piece.points if starts else piece.points[::-1]
            points = points + list(more[1:])

    pieces: list[Piece] = []
    for index, piece in enumerate(network.pieces):
        if used[index]:
            continue
        used[index] = True
        forward = follow(list(piece.points), piece.street, index)
        backward = follow(forward[::-1], piece.street, index)
        merged = _piece(backward[::-1], piece.street)
        if merged is not None:
            pieces.append(merged)
    return Network(network.streets, pieces, network.squares)
