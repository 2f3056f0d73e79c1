"""The fixed structure of a floorplan: floor, walls with doorway openings and lintels, ceiling, aprons.

Walls are boxes of :data:`~navverse.indoor.floorplan.WALL_THICKNESS` centred on the partition lines,
from the floor to the ceiling, with an opening (and a lintel above it, at :data:`DOOR_HEIGHT`) for
every doorway and exit. Outside every exit lies a walkable apron, so the doorway leads somewhere and
indoor-to-outdoor assembly has a landing to replace.
"""

from __future__ import annotations

from collections import defaultdict

from navverse.indoor.floorplan import WALL_THICKNESS, Floorplan
from navverse.scene.geometry import MeshData, Surface

__all__ = ["APRON_DEPTH", "DOOR_HEIGHT", "SLAB", "build_structure"]

DOOR_HEIGHT = 2.2
"""Height of doorway openings (m); the wall above is a lintel."""
APRON_DEPTH = 3.0
"""Depth of the walkable apron outside each exit (m)."""
SLAB = 0.1
"""Thickness of floor, ceiling and apron slabs (m)."""

_Line = tuple[str, float]  # ("x", y): a wall running along x at that y; ("y", x): along y at that x


def _merge(intervals: list[tuple[float, float]]) -> list[tuple[float, float]]:
    merged: list[list[float]] = []
    for lo, hi in sorted(intervals):
        if merged and lo <= merged[-1][1] + 1e-9:
            merged[-1][1] = max(merged[-1][1], hi)
        else:
            merged.append([lo, hi])
    return [(lo, hi) for lo, hi in merged]


def _subtract(
    intervals: list[tuple[float, float]], holes: list[tuple[float, float]]
) -> list[tuple[float, float]]:
    out = intervals
    for h0, h1 in holes:
        nxt = []
        for lo, hi in out:
            if h1 <= lo or h0 >= hi:
                nxt.append((lo, hi))
                continue
            if h0 > lo:
                nxt.append((lo, h0))
            if h1 < hi:
                nxt.append((h1, hi))
        out = nxt
    return [(lo, hi) for lo, hi in out if hi - lo > 1e-6]


def _wall_lines(plan: Floorplan) -> dict[_Line, list[tuple[float, float]]]:
    """Every room edge as an interval on its line, merged per line."""
    lines: dict[_Line, list[tuple[float, float]]] = defaultdict(list)
    for room in plan.rooms:
        r = room.rect
        lines[("x", r.y0)].append((r.x0, r.x1))
        lines[("x", r.y1)].append((r.x0, r.x1))
        lines[("y", r.x0)].append((r.y0, r.y1))
        lines[("y", r.x1)].append((r.y0, r.y1))
    return {line: _merge(spans) for line, spans in lines.items()}


def _box(x0: float, y0: float, z0: float, x1: float, y1: float, z1: float) -> MeshData:
    return MeshData.box((x1 - x0, y1 - y0, z1 - z0), center=((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2))


def _wall_box(line: _Line, lo: float, hi: float, z0: float, z1: float) -> MeshData:
    half = WALL_THICKNESS / 2
    axis, at = line
    if axis == "x":
        return _box(lo, at - half, z0, hi, at + half, z1)
    return _box(at - half, lo, z0, at + half, hi, z1)


def build_structure(plan: Floorplan) -> list[Surface]:
    """Floor, walls (with lintels), ceiling and exit aprons of a floorplan, as terrain surfaces.

    Returns
    -------
    list of Surface
        ``floor`` (terrain ``floor``), ``walls`` (``wall``), ``ceiling`` (``ceiling``) and, when the
        plan has exits, ``apron`` (``sidewalk``); each one merged mesh.
    """
    half = WALL_THICKNESS / 2
    height = plan.ceiling_height
    fp = plan.footprint
    openings: dict[_Line, list[tuple[float, float]]] = defaultdict(list)
    for door in (*plan.doors, *plan.exits):
        along = door.center[0] if door.axis == "x" else door.center[1]
        at = door.center[1] if door.axis == "x" else door.center[0]
        openings[(door.axis, at)].append((along - door.width / 2, along + door.width / 2))

    walls: list[MeshData] = []
    for line, spans in sorted(_wall_lines(plan).items()):
        # Extend each run by half a thickness so walls meet at corners.
        solid = _subtract([(lo - half, hi + half) for lo, hi in spans], openings.get(line, []))
        walls += [_wall_box(line, lo, hi, 0.0, height) for lo, hi in solid]
        if height - DOOR_HEIGHT > 0.05:
            walls += [_wall_box(line, lo, hi, DOOR_HEIGHT, height) for lo, hi in openings.get(line, [])]

    floor = _box(fp.x0 - half, fp.y0 - half, -SLAB, fp.x1 + half, fp.y1 + half, 0.0)
    ceiling = _box(fp.x0 - half, fp.y0 - half, height, fp.x1 + half, fp.y1 + half, height + SLAB)
    surfaces = [
        Surface("floor", "floor", floor),
        Surface("walls", "wall", MeshData.concatenate(walls)),
        Surface("ceiling", "ceiling", ceiling),
    ]
    aprons = []
    for ex in plan.exits:
        reach = ex.width / 2 + 1.0
        cx, cy = ex.center
        if ex.axis == "y":  # in a west or east wall
            x_in = cx - half if cx <= fp.x0 + 1e-9 else cx + half
            x_out = x_in - APRON_DEPTH if cx <= fp.x0 + 1e-9 else x_in + APRON_DEPTH
            aprons.append(_box(min(x_in, x_out), cy - reach, -SLAB, max(x_in, x_out), cy + reach, 0.0))
        else:  # in the south or north wall
            y_in = cy - half if cy <= fp.y0 + 1e-9 else cy + half
            y_out = y_in - APRON_DEPTH if cy <= fp.y0 + 1e-9 else y_in + APRON_DEPTH
            aprons.append(_box(cx - reach, min(y_in, y_out), -SLAB, cx + reach, max(y_in, y_out), 0.0))
    if aprons:
        surfaces.append(Surface("apron", "sidewalk", MeshData.concatenate(aprons)))
    return surfaces
