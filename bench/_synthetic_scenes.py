"""Synthetic navmesh benchmark scenes, generated deterministically from a seed (numpy only).

Two scenes, both made of closed solids wound counter-clockwise seen from outside (normals point
out, floors face +z), z up, meters:

- :func:`indoor_building`: a one-storey building (floor slab, walls forming rooms off two crossing
  corridors, doorways of 1.8-2.4 m) furnished with finely tessellated solids of revolution
  (columns, round tables, stools, balls, planters) until a triangle budget is spent.
- :func:`outdoor_city`: a square city: a ground of closed slabs, a street grid whose roads lie
  0.2 m below the sidewalks (so every block has a 0.2 m curb), and box buildings on the blocks.

Area types per triangle: :data:`FLOOR_AREA` (floors, sidewalks), :data:`ROAD_AREA` (roads) and
:data:`OBSTACLE_AREA` (walls, furniture, buildings; never walkable).

This module is a helper of ``bench/navmesh.py``; run directly, it prints the sizes of the quick
scenes.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from navverse.assets.primitives import boxes

__all__ = [
    "FLOOR_AREA",
    "OBSTACLE_AREA",
    "ROAD_AREA",
    "MeshAccumulator",
    "Scene",
    "indoor_building",
    "outdoor_city",
    "solid_of_revolution",
]

OBSTACLE_AREA = 0
"""Area type of walls, furniture and buildings (never walkable)."""
FLOOR_AREA = 1
"""Area type of indoor floors and sidewalks."""
ROAD_AREA = 2
"""Area type of roads."""

WALL_HEIGHT = 2.8
WALL_THICKNESS = 0.2
CORRIDOR_WIDTH = 2.4
DOOR_WIDTH_RANGE = (1.8, 2.4)
CURB_HEIGHT = 0.2


@dataclass(frozen=True, eq=False)
class Scene:
    """A triangle mesh with one area type per triangle.

    Attributes
    ----------
    name : str
        Short name (``"indoor"``, ``"outdoor"``).
    vertices : ndarray, shape (N, 3)
        Vertex positions (m), z up.
    faces : ndarray of int32, shape (M, 3)
        Triangles, counter-clockwise seen from outside.
    area_types : ndarray of uint8, shape (M,)
        Area type per triangle.
    description : str
        What the scene holds, for reports.
    counts : dict of str to int
        Object counts by kind (rooms, doors, buildings, ...).
    """

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    area_types: np.ndarray
    description: str
    counts: dict[str, int] = field(default_factory=dict)

    @property
    def num_triangles(self) -> int:
        """Number of triangles."""
        return len(self.faces)


class MeshAccumulator:
    """Collects closed solids into one mesh with an area type per triangle."""

    def __init__(self) -> None:
        self._vertices: list[np.ndarray] = []
        self._faces: list[np.ndarray] = []
        self._areas: list[np.ndarray] = []
        self._num_vertices = 0
        self._num_faces = 0

    @property
    def num_triangles(self) -> int:
        """Triangles added so far."""
        return self._num_faces

    def add_mesh(self, vertices: np.ndarray, faces: np.ndarray, area: int) -> None:
        """Add one mesh (its faces index its own vertices) with one area type for all its triangles."""
        self._vertices.append(np.asarray(vertices, dtype=np.float64))
        self._faces.append(np.asarray(faces, dtype=np.int64) + self._num_vertices)
        self._areas.append(np.full(len(faces), area, dtype=np.uint8))
        self._num_vertices += len(vertices)
        self._num_faces += len(faces)

    def add_boxes(self, lo: np.ndarray, hi: np.ndarray, areas: np.ndarray | int) -> None:
        """Add axis-aligned boxes from corners ``lo`` to ``hi`` (both shape (K, 3)), 12 triangles each.

        Parameters
        ----------
        lo, hi : ndarray, shape (K, 3)
            Minimum and maximum corners; every extent must be positive.
        areas : ndarray of int, shape (K,), or int
            Area type per box.
        """
        vertices, faces = boxes(lo, hi)
        count = len(vertices) // 8
        box_areas = np.broadcast_to(np.asarray(areas, dtype=np.uint8), (count,))
        self._vertices.append(vertices)
        self._faces.append(faces + self._num_vertices)
        self._areas.append(np.repeat(box_areas, len(faces) // count))
        self._num_vertices += len(vertices)
        self._num_faces += len(faces)

    def scene(self, name: str, description: str, counts: dict[str, int]) -> Scene:
        """The accumulated mesh as a :class:`Scene`."""
        return Scene(
            name=name,
            vertices=np.ascontiguousarray(np.vstack(self._vertices)),
            faces=np.ascontiguousarray(np.vstack(self._faces), dtype=np.int32),
            area_types=np.concatenate(self._areas),
            description=description,
            counts=counts,
        )


# ---------------------------------------------------------------------- solids of revolution


def solid_of_revolution(
    radii: np.ndarray, heights: np.ndarray, segments: int, phase: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """A closed, watertight solid: a profile revolved about the z axis.

    Parameters
    ----------
    radii, heights : ndarray, shape (P,)
        The profile from the bottom pole to the top pole, going up the solid's outside: the first
        and last radius must be 0, all others positive.
    segments : int
        Number of segments around the axis (at least 3).
    phase : float
        Angle (rad) of the first segment.

    Returns
    -------
    vertices : ndarray, shape (2 + (P - 2) * segments, 3)
    faces : ndarray, shape (2 * segments * (P - 2), 3)
        Triangles counter-clockwise seen from outside.
    """
    radii = np.asarray(radii, dtype=np.float64)
    heights = np.asarray(heights, dtype=np.float64)
    if radii[0] != 0 or radii[-1] != 0 or (radii[1:-1] <= 0).any() or len(radii) < 3 or segments < 3:
        raise ValueError("a profile runs from one pole (radius 0) to the other through positive radii")
    rings = len(radii) - 2
    angles = phase + np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    ring_r = radii[1:-1, None]
    ring_z = np.broadcast_to(heights[1:-1, None], (rings, segments))
    ring_xyz = np.stack([ring_r * np.cos(angles), ring_r * np.sin(angles), ring_z], axis=-1).reshape(-1, 3)
    bottom, top = 0, 1 + rings * segments
    vertices = np.vstack([[0.0, 0.0, heights[0]], ring_xyz, [0.0, 0.0, heights[-1]]])

    seg = np.arange(segments)
    nxt = (seg + 1) % segments
    ring_index = 1 + np.arange(rings)[:, None] * segments  # (rings, 1)
    a = (ring_index[:-1] + seg).ravel()  # ring j, segment i
    b = (ring_index[:-1] + nxt).ravel()  # ring j, segment i + 1
    c = (ring_index[1:] + nxt).ravel()  # ring j + 1, segment i + 1
    d = (ring_index[1:] + seg).ravel()  # ring j + 1, segment i
    sides = np.concatenate([np.stack([a, b, c], axis=1), np.stack([a, c, d], axis=1)])
    first, last = 1 + seg, 1 + (rings - 1) * segments + seg
    first_next, last_next = 1 + nxt, 1 + (rings - 1) * segments + nxt
    bottom_fan = np.stack([np.full(segments, bottom), first_next, first], axis=1)
    top_fan = np.stack([np.full(segments, top), last, last_next], axis=1)
    return vertices, np.vstack([bottom_fan, sides, top_fan])


def _densify_profile(radii: list[float], heights: list[float], points: int) -> tuple[np.ndarray, np.ndarray]:
    """Subdivide a profile polyline into about ``points`` points, keeping every original corner."""
    r = np.asarray(radii, dtype=np.float64)
    z = np.asarray(heights, dtype=np.float64)
    lengths = np.hypot(np.diff(r), np.diff(z))
    pieces = np.maximum(1, np.round(lengths / lengths.sum() * (points - 1)).astype(int))
    out_r, out_z = [r[:1]], [z[:1]]
    for k, n in enumerate(pieces):
        t = np.arange(1, n + 1) / n
        out_r.append(r[k] + t * (r[k + 1] - r[k]))
        out_z.append(z[k] + t * (z[k + 1] - z[k]))
    return np.concatenate(out_r), np.concatenate(out_z)


def _furniture_profile(kind: str, rng: np.random.Generator) -> tuple[list[float], list[float], float]:
    """Key points of a furniture profile (radii, heights) and its footprint radius."""
    if kind == "column":
        r = rng.uniform(0.2, 0.35)
        return [0, r, r, 0], [0, 0, WALL_HEIGHT, WALL_HEIGHT], r
    if kind == "table":
        base, stem, top, height = rng.uniform(0.2, 0.3), rng.uniform(0.04, 0.07), rng.uniform(0.4, 0.6), 0.75
        return (
            [0, base, base, stem, stem, top, top, 0],
            [0, 0, 0.04, 0.04, height - 0.05, height - 0.05, height, height],
            top,
        )
    if kind == "stool":
        r, h = rng.uniform(0.18, 0.3), rng.uniform(0.4, 0.5)
        return [0, r, r, 0], [0, 0, h, h], r
    if kind == "ball":
        r = rng.uniform(0.25, 0.45)
        phi = np.linspace(0.0, np.pi, 25)
        radii = r * np.sin(phi)
        radii[[0, -1]] = 0.0  # exact poles
        return list(radii), list(r - r * np.cos(phi)), r
    # planter: a bulging pot
    r0, bulge, h = rng.uniform(0.15, 0.25), rng.uniform(0.05, 0.15), rng.uniform(0.6, 1.2)
    t = np.linspace(0.0, 1.0, 13)
    side_r = r0 + bulge * np.sin(np.pi * t)
    return [0, *side_r, 0], [0, *(h * t), h], r0 + bulge


FURNITURE_KINDS = ("column", "table", "stool", "ball", "planter")
FURNITURE_SEGMENTS = (96, 128, 160)
FURNITURE_PROFILE_POINTS = 40


def _furniture(
    radii: list[float], heights: list[float], center: np.ndarray, segments: int, phase: float
) -> tuple[np.ndarray, np.ndarray]:
    """A tessellated solid of revolution standing on the floor (z = 0) at ``center`` (x, y)."""
    r, z = _densify_profile(radii, heights, FURNITURE_PROFILE_POINTS)
    vertices, faces = solid_of_revolution(r, z, segments, phase=phase)
    vertices[:, :2] += center
    return vertices, faces


# ---------------------------------------------------------------------- indoor


@dataclass(frozen=True)
class _Room:
    """An axis-aligned room interior [x0, x1] x [y0, y1]."""

    x0: float
    y0: float
    x1: float
    y1: float

    @property
    def area(self) -> float:
        return (self.x1 - self.x0) * (self.y1 - self.y0)


@dataclass
class _Layout:
    """Walls (as boxes), rooms and doorway centers of a floor plan (corridors are not rooms)."""

    wall_lo: list[tuple[float, float, float]] = field(default_factory=list)
    wall_hi: list[tuple[float, float, float]] = field(default_factory=list)
    rooms: list[_Room] = field(default_factory=list)
    doors: list[tuple[float, float]] = field(default_factory=list)

    def wall(self, axis: int, at: float, start: float, end: float, doors: list[tuple[float, float]]) -> None:
        """A wall along ``axis`` (0 = x, 1 = y) on the line ``at``, from ``start`` to ``end``.

        ``doors`` are (center, width) openings along the wall.
        """
        half = WALL_THICKNESS / 2
        cuts = [start - half]
        for center, width in sorted(doors):
            cuts += [center - width / 2, center + width / 2]
            self.doors.append((center, at) if axis == 0 else (at, center))
        cuts.append(end + half)
        for a, b in zip(cuts[::2], cuts[1::2], strict=True):
            if axis == 0:
                self.wall_lo.append((a, at - half, 0.0))
                self.wall_hi.append((b, at + half, WALL_HEIGHT))
            else:
                self.wall_lo.append((at - half, a, 0.0))
                self.wall_hi.append((at + half, b, WALL_HEIGHT))


def _door(rng: np.random.Generator, start: float, end: float) -> tuple[float, float]:
    """A doorway (center, width) on a wall piece from ``start`` to ``end``, clear of its ends."""
    width = rng.uniform(*DOOR_WIDTH_RANGE)
    margin = width / 2 + 0.4
    return float(rng.uniform(start + margin, end - margin)), float(width)


def _split(rng: np.random.Generator, start: float, end: float, low: float, high: float) -> list[float]:
    """Cut points that split [start, end] into pieces between ``low`` and ``low + high`` long."""
    cuts = [start]
    while end - cuts[-1] > high:
        cuts.append(cuts[-1] + rng.uniform(low, high))
    if end - cuts[-1] < low and len(cuts) > 1:
        cuts.pop()
    return [*cuts, end]


def _quadrant(
    rng: np.random.Generator, layout: _Layout, x0: float, x1: float, y0: float, y1: float, corridor_y: float
) -> None:
    """Rooms of one quadrant [x0, x1] x [y0, y1]: columns of two rooms, split at the middle.

    The quadrant's side on the line ``corridor_y`` (``y0`` or ``y1``) faces the main corridor:
    every room in the row along it has a door onto the corridor and one into the room behind it;
    neighbouring rooms share a door half of the time.
    """
    mid_y = (y0 + y1) / 2
    xs = _split(rng, x0, x1, 5.0, 9.0)
    corridor_doors = []
    for a, b in itertools.pairwise(xs):
        corridor_doors.append(_door(rng, a, b))
        layout.wall(0, mid_y, a, b, [_door(rng, a, b)])
        layout.rooms += [_Room(a, y0, b, mid_y), _Room(a, mid_y, b, y1)]
    layout.wall(0, corridor_y, x0, x1, corridor_doors)
    for x in xs[1:-1]:
        for a, b in ((y0, mid_y), (mid_y, y1)):
            layout.wall(1, x, a, b, [_door(rng, a, b)] if rng.random() < 0.5 else [])


def _floor_plan(rng: np.random.Generator, width: float, depth: float) -> _Layout:
    """Exterior walls, a corridor along x and one along y through the middle, and rooms off them."""
    layout = _Layout()
    half = CORRIDOR_WIDTH / 2
    cx, cy = width / 2, depth / 2
    for axis, at, length in ((0, 0.0, width), (0, depth, width), (1, 0.0, depth), (1, width, depth)):
        layout.wall(axis, at, 0.0, length, [])
    for x0, x1 in ((0.0, cx - half), (cx + half, width)):
        _quadrant(rng, layout, x0, x1, 0.0, cy - half, corridor_y=cy - half)
        _quadrant(rng, layout, x0, x1, cy + half, depth, corridor_y=cy + half)
    # Walls along the cross corridor, with a door into the end room of every row.
    for x in (cx - half, cx + half):
        for a, b in ((0.0, cy - half), (cy + half, depth)):
            mid = (a + b) / 2
            layout.wall(1, x, a, b, [_door(rng, a, mid), _door(rng, mid, b)])
    return layout


def _place_furniture(
    rng: np.random.Generator,
    mesh: MeshAccumulator,
    layout: _Layout,
    target_triangles: int,
    *,
    door_clearance: float = 1.8,
    wall_clearance: float = 0.25,
    gap: float = 0.9,
) -> dict[str, int]:
    """Furnish the rooms (not the corridors) until the mesh has ``target_triangles`` triangles.

    Rejection sampling: a candidate (kind, size, room, position) is kept when it stays ``gap``
    away from every placed object, ``wall_clearance`` away from its room's walls and
    ``door_clearance`` (plus its radius) away from every doorway center. Returns the count per kind.

    Raises
    ------
    RuntimeError
        When the budget of tries runs out before the triangle target is reached.
    """
    weights = np.array([room.area for room in layout.rooms])
    weights /= weights.sum()
    doors = np.array(layout.doors)
    centers = np.empty((0, 2))
    radii = np.empty(0)
    counts = dict.fromkeys(FURNITURE_KINDS, 0)
    max_tries = 1000 + target_triangles // 100
    for _ in range(max_tries):
        if mesh.num_triangles >= target_triangles:
            return counts
        kind = FURNITURE_KINDS[rng.integers(len(FURNITURE_KINDS))]
        profile_r, profile_z, radius = _furniture_profile(kind, rng)
        room = layout.rooms[rng.choice(len(layout.rooms), p=weights)]
        margin = WALL_THICKNESS / 2 + wall_clearance + radius
        if min(room.x1 - room.x0, room.y1 - room.y0) <= 2 * margin:
            continue
        center = rng.uniform([room.x0 + margin, room.y0 + margin], [room.x1 - margin, room.y1 - margin])
        if np.hypot(*(doors - center).T).min() < door_clearance + radius:
            continue
        if len(radii) and (np.hypot(*(centers - center).T) - radii).min() < radius + gap:
            continue
        segments = int(rng.choice(FURNITURE_SEGMENTS))
        vertices, faces = _furniture(profile_r, profile_z, center, segments, phase=rng.uniform(0, 2 * np.pi))
        mesh.add_mesh(vertices, faces, OBSTACLE_AREA)
        centers = np.vstack([centers, center])
        radii = np.append(radii, radius)
        counts[kind] += 1
    raise RuntimeError(
        f"could not furnish the building up to {target_triangles} triangles in {max_tries} tries: "
        "lower the triangle target or enlarge the building"
    )


def indoor_building(
    seed: int, *, width: float = 60.0, depth: float = 40.0, target_triangles: int = 2_000_000
) -> Scene:
    """A furnished one-storey building of about ``target_triangles`` triangles.

    Parameters
    ----------
    seed : int
        Seed of the only random generator used.
    width, depth : float
        Outer size (m) along x and y; the building spans [0, width] x [0, depth].
    target_triangles : int
        Furniture is added until the mesh has at least this many triangles.

    Returns
    -------
    Scene
        Floor slab (area 1), walls and furniture (area 0).
    """
    rng = np.random.default_rng(seed)
    layout = _floor_plan(rng, width, depth)
    mesh = MeshAccumulator()
    half = WALL_THICKNESS / 2
    mesh.add_boxes(
        np.array([[-half, -half, -0.2]]), np.array([[width + half, depth + half, 0.0]]), FLOOR_AREA
    )
    mesh.add_boxes(np.array(layout.wall_lo), np.array(layout.wall_hi), OBSTACLE_AREA)
    furniture = _place_furniture(rng, mesh, layout, target_triangles)
    counts = {"rooms": len(layout.rooms), "doorways": len(layout.doors), "wall_boxes": len(layout.wall_lo)}
    counts |= {f"furniture_{kind}": n for kind, n in furniture.items()}
    description = (
        f"{width:g} m x {depth:g} m building, {counts['rooms']} rooms, {counts['doorways']} doorways, "
        f"{sum(furniture.values())} tessellated furniture solids"
    )
    return mesh.scene("indoor", description, counts)


# ---------------------------------------------------------------------- outdoor


def _street_axis(
    rng: np.random.Generator, size: float, block: tuple[float, float], road: tuple[float, float]
) -> tuple[np.ndarray, np.ndarray]:
    """Breakpoints along one axis: block, road, block, ..., block, spanning [0, size].

    Returns
    -------
    edges : ndarray, shape (K + 1,)
        Interval boundaries from 0 to ``size``.
    is_road : ndarray of bool, shape (K,)
        Whether each interval is a road.
    """
    blocks, roads = [rng.uniform(*block)], []
    while sum(blocks) + sum(roads) < size:
        roads.append(rng.uniform(*road))
        blocks.append(rng.uniform(*block))
    if len(blocks) > 1:
        blocks.pop()
        roads.pop()
    scale = (size - sum(roads)) / sum(blocks)  # stretch the blocks so the intervals span [0, size]
    lengths = [blocks[0] * scale]
    for r, b in zip(roads, blocks[1:], strict=True):
        lengths += [r, b * scale]
    edges = np.concatenate([[0.0], np.cumsum(lengths)])
    edges[-1] = size
    is_road = np.arange(len(lengths)) % 2 == 1
    return edges, is_road


def _ground(
    mesh: MeshAccumulator, xs: np.ndarray, ys: np.ndarray, road_x: np.ndarray, road_y: np.ndarray
) -> int:
    """Ground slabs, one per grid cell: blocks (top at 0, sidewalks) and roads (top at -0.2).

    Returns the number of road slabs.
    """
    gx0, gy0 = np.meshgrid(xs[:-1], ys[:-1], indexing="ij")
    gx1, gy1 = np.meshgrid(xs[1:], ys[1:], indexing="ij")
    road = (road_x[:, None] | road_y[None, :]).ravel()
    top = np.where(road, -CURB_HEIGHT, 0.0)
    lo = np.column_stack([gx0.ravel(), gy0.ravel(), np.full(road.size, -1.0)])
    hi = np.column_stack([gx1.ravel(), gy1.ravel(), top])
    mesh.add_boxes(lo, hi, np.where(road, ROAD_AREA, FLOOR_AREA))
    return int(road.sum())


def _block_buildings(
    rng: np.random.Generator, x0: float, y0: float, x1: float, y1: float, lot_size: float
) -> list[tuple[float, float, float, float, float]]:
    """Buildings (x0, y0, x1, y1, height) on one block: a grid of lots behind a 3-5 m sidewalk."""
    sidewalk = rng.uniform(3.0, 5.0)
    bx0, by0, bx1, by1 = x0 + sidewalk, y0 + sidewalk, x1 - sidewalk, y1 - sidewalk
    nx = max(1, round((bx1 - bx0) / lot_size))
    ny = max(1, round((by1 - by0) / lot_size))
    lx, ly = np.linspace(bx0, bx1, nx + 1), np.linspace(by0, by1, ny + 1)
    buildings = []
    for i in range(nx):
        for j in range(ny):
            if rng.random() < 0.12:  # an empty lot: a small square
                continue
            gaps = rng.uniform(1.5, 4.0, size=4)
            height = float(np.clip(rng.lognormal(np.log(14.0), 0.5), 6.0, 40.0))
            buildings.append(
                (lx[i] + gaps[0], ly[j] + gaps[1], lx[i + 1] - gaps[2], ly[j + 1] - gaps[3], height)
            )
    return buildings


def outdoor_city(
    seed: int,
    *,
    size: float = 1000.0,
    block_range: tuple[float, float] = (60.0, 120.0),
    road_width_range: tuple[float, float] = (10.0, 16.0),
    lot_size: float = 34.0,
) -> Scene:
    """A square city of box buildings on blocks between roads 0.2 m below the sidewalks.

    Parameters
    ----------
    seed : int
        Seed of the only random generator used.
    size : float
        Side (m); the city spans [0, size] x [0, size].
    block_range, road_width_range : tuple of float
        Ranges (m) of block sides (before stretching to fit ``size``) and road widths.
    lot_size : float
        Approximate lot side (m): each block holds a grid of lots, most with one building.

    Returns
    -------
    Scene
        Ground slabs (blocks: area 1, roads: area 2) and buildings (area 0), all closed boxes.
    """
    rng = np.random.default_rng(seed)
    xs, road_x = _street_axis(rng, size, block_range, road_width_range)
    ys, road_y = _street_axis(rng, size, block_range, road_width_range)
    mesh = MeshAccumulator()
    road_slabs = _ground(mesh, xs, ys, road_x, road_y)
    buildings = []
    for i in np.flatnonzero(~road_x):
        for j in np.flatnonzero(~road_y):
            buildings += _block_buildings(rng, xs[i], ys[j], xs[i + 1], ys[j + 1], lot_size)
    footprints = np.array(buildings)
    lo = np.column_stack([footprints[:, 0], footprints[:, 1], np.zeros(len(footprints))])
    hi = footprints[:, [2, 3, 4]]
    mesh.add_boxes(lo, hi, OBSTACLE_AREA)
    blocks = int((~road_x).sum() * (~road_y).sum())
    counts = {"blocks": blocks, "road_slabs": road_slabs, "buildings": len(buildings)}
    description = (
        f"{size:g} m x {size:g} m city, {blocks} blocks, {len(buildings)} buildings "
        f"(6-40 m), roads {CURB_HEIGHT:g} m below the sidewalks"
    )
    return mesh.scene("outdoor", description, counts)


if __name__ == "__main__":
    for demo in (
        indoor_building(0, width=30.0, depth=20.0, target_triangles=300_000),
        outdoor_city(0, size=200.0, block_range=(40.0, 70.0)),
    ):
        print(f"{demo.name}: {demo.num_triangles:,} triangles; {demo.description}")
