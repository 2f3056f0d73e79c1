"""Closed solid parts for object builders, and the :class:`Assembly` that colours and joins them.

Every function returns a :data:`Solid`, a ``(vertices (N, 3) float64, faces (M, 3) int64)`` pair that
is a closed, consistently wound surface with outward normals (counter-clockwise seen from outside).
Simple shapes (boxes, frustums, ellipsoids) are built with numpy; extrusions, revolutions, convex hulls
and booleans go through manifold3d, whose results are deterministic and watertight.

Coordinates are the builder's *floor frame*: x = width, y = depth (front towards +y), z = height with
the object's bottom at ``z = 0``; :mod:`navverse.assets.library` centres the result afterwards.
Circular shapes use section counts that are multiples of 4 and start at angle 0, so their bounding
box reaches the full radius along both perpendicular axes.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import manifold3d
import numpy as np
from numpy.typing import ArrayLike

from navverse.assets.materials import RGB
from navverse.assets.primitives import boxes
from navverse.scene.geometry import MeshData, apply_linear, snap_to_grid

__all__ = [
    "Assembly",
    "Solid",
    "align",
    "bar",
    "box",
    "box_at",
    "cylinder",
    "difference",
    "ellipsoid",
    "extrude",
    "extrude_along",
    "frustum",
    "hull",
    "revolve",
    "rotate",
    "rounded_prism",
    "torus",
    "translate",
]

Solid = tuple[np.ndarray, np.ndarray]
"""``(vertices, faces)`` of a closed solid with outward-facing triangles."""


def _vec3(value: ArrayLike) -> np.ndarray:
    return np.asarray(value, dtype=np.float64).reshape(3)


def box(lo: ArrayLike, hi: ArrayLike) -> Solid:
    """An axis-aligned box between corners `lo` and `hi` (``hi > lo`` on every axis)."""
    return boxes(_vec3(lo), _vec3(hi))


def box_at(center: ArrayLike, size: ArrayLike) -> Solid:
    """An axis-aligned box of `size` centred at `center`."""
    c, s = _vec3(center), _vec3(size)
    return box(c - 0.5 * s, c + 0.5 * s)


def _perpendicular_frame(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors ``e1, e2`` with ``(e1, e2, axis)`` right-handed; ``e1 = x`` for a z axis."""
    ref = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = ref - ref.dot(axis) * axis
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(axis, e1)


def frustum(
    p0: ArrayLike,
    p1: ArrayLike,
    r0: float | tuple[float, float],
    r1: float | tuple[float, float],
    *,
    sections: int = 16,
    phase: float = 0.0,
) -> Solid:
    """A (possibly elliptic) truncated cone from `p0` to `p1`.

    Parameters
    ----------
    p0, p1 : array_like, shape (3,)
        Centres of the two end caps.
    r0, r1 : float or (float, float)
        Radii at `p0` and `p1`, > 0; a pair gives an ellipse with radii along ``e1`` and ``e2`` (x and y
        for a z-axis frustum, y and z for an x axis, z and x for a y axis).
    sections : int
        Vertices per ring.
    phase : float
        Angle of the first ring vertex, radians.

    Returns
    -------
    Solid
        ``2 * sections + 2`` vertices, ``4 * sections`` triangles.
    """
    a, b = _vec3(p0), _vec3(p1)
    length = float(np.linalg.norm(b - a))
    if length <= 0:
        raise ValueError("frustum needs two distinct end points")
    axis = (b - a) / length
    e1, e2 = _perpendicular_frame(axis)
    angles = phase + 2.0 * np.pi * np.arange(sections) / sections
    cos, sin = np.cos(angles)[:, None], np.sin(angles)[:, None]
    rings = []
    for center, radius in ((a, r0), (b, r1)):
        ra, rb = (radius, radius) if np.isscalar(radius) else radius
        if ra <= 0 or rb <= 0:
            raise ValueError(f"frustum radii must be > 0, got {radius}")
        rings.append(center + ra * cos * e1 + rb * sin * e2)
    vertices = np.concatenate([rings[0], rings[1], a[None], b[None]])
    k = np.arange(sections)
    k1 = (k + 1) % sections
    bottom_c, top_c = 2 * sections, 2 * sections + 1
    faces = np.concatenate(
        [
            np.stack([k, k1, sections + k1], axis=1),
            np.stack([k, sections + k1, sections + k], axis=1),
            np.stack([np.full(sections, top_c), sections + k, sections + k1], axis=1),
            np.stack([np.full(sections, bottom_c), k1, k], axis=1),
        ]
    )
    return vertices, faces.astype(np.int64)


def cylinder(p0: ArrayLike, p1: ArrayLike, radius: float, *, sections: int = 16) -> Solid:
    """A circular cylinder of `radius` from `p0` to `p1`."""
    return frustum(p0, p1, radius, radius, sections=sections)


def ellipsoid(center: ArrayLike, radii: ArrayLike, *, segments: int = 12, rings: int = 6) -> Solid:
    """An axis-aligned ellipsoid (latitude/longitude tessellation).

    Parameters
    ----------
    center, radii : array_like, shape (3,)
        Centre and semi-axes (> 0).
    segments : int
        Vertices per latitude ring (a multiple of 4 reaches the x and y radii exactly).
    rings : int
        Latitude bands (even, so the equator is a ring).
    """
    c, r = _vec3(center), _vec3(radii)
    polar = np.pi * np.arange(1, rings) / rings
    azimuth = 2.0 * np.pi * np.arange(segments) / segments
    ring_pts = np.stack(
        [
            np.outer(np.sin(polar), np.cos(azimuth)),
            np.outer(np.sin(polar), np.sin(azimuth)),
            np.repeat(np.cos(polar)[:, None], segments, axis=1),
        ],
        axis=-1,
    ).reshape(-1, 3)
    unit = np.concatenate([[[0.0, 0.0, 1.0]], ring_pts, [[0.0, 0.0, -1.0]]])
    vertices = c + unit * r
    north, south = 0, len(unit) - 1
    k = np.arange(segments)
    k1 = (k + 1) % segments
    faces = [np.stack([np.full(segments, north), 1 + k, 1 + k1], axis=1)]
    for i in range(rings - 2):
        top, bot = 1 + i * segments, 1 + (i + 1) * segments
        faces.append(np.stack([top + k, bot + k, bot + k1], axis=1))
        faces.append(np.stack([top + k, bot + k1, top + k1], axis=1))
    last = 1 + (rings - 2) * segments
    faces.append(np.stack([np.full(segments, south), last + k1, last + k], axis=1))
    return vertices, np.concatenate(faces).astype(np.int64)


def _to_manifold(solid: Solid) -> manifold3d.Manifold:
    vertices, faces = solid
    mesh = manifold3d.Mesh64(
        vert_properties=np.ascontiguousarray(snap_to_grid(vertices)),
        tri_verts=np.ascontiguousarray(faces, dtype=np.uint32),
    )
    result = manifold3d.Manifold(mesh)
    if result.status() != manifold3d.Error.NoError:
        raise ValueError(f"part is not a closed manifold solid: {result.status()}")
    return result


def _from_manifold(shape: manifold3d.Manifold) -> Solid:
    mesh = shape.to_mesh64()
    vertices = np.array(mesh.vert_properties, dtype=np.float64)[:, :3]
    faces = np.array(mesh.tri_verts, dtype=np.int64).reshape(-1, 3)
    if len(faces) == 0:
        raise ValueError("the operation produced an empty solid")
    return vertices, faces


def _ccw(points: np.ndarray) -> np.ndarray:
    x, y = points[:, 0], points[:, 1]
    area = 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    return points if area > 0 else points[::-1]


def extrude(
    polygon: ArrayLike, z0: float, z1: float, *, scale_top: tuple[float, float] = (1.0, 1.0)
) -> Solid:
    """Extrude a simple polygon in the xy plane from height `z0` to `z1`.

    Parameters
    ----------
    polygon : array_like, shape (K, 2)
        Outline, either orientation.
    z0, z1 : float
        Bottom and top heights, ``z1 > z0``.
    scale_top : (float, float)
        Scale of the top outline about the xy origin (a taper).
    """
    outline = _ccw(np.asarray(polygon, dtype=np.float64).reshape(-1, 2))
    section = manifold3d.CrossSection([outline])
    shape = section.extrude(z1 - z0, scale_top=scale_top).translate((0.0, 0.0, z0))
    return _from_manifold(shape)


def extrude_along(outline: ArrayLike, t0: float, t1: float, *, axis: str) -> Solid:
    """Extrude a simple polygon along the ``"x"``, ``"y"`` or ``"z"`` axis from `t0` to `t1`.

    Parameters
    ----------
    outline : array_like, shape (K, 2)
        Outline in the plane of the other two axes, in the order (y, z) for an x extrusion, (x, z) for
        a y extrusion and (x, y) for a z extrusion; either orientation.
    t0, t1 : float
        Start and end along `axis`, ``t1 > t0``.
    axis : {"x", "y", "z"}
        The direction of the extrusion.
    """
    if axis not in ("x", "y", "z"):
        raise ValueError(f"extrude_along: axis must be 'x', 'y' or 'z', got {axis!r}")
    vertices, faces = extrude(outline, t0, t1)
    if axis == "z":
        return vertices, faces
    if axis == "x":  # (u, v, t) -> (t, u, v): a rotation, winding kept
        return vertices[:, [2, 0, 1]], faces
    # (u, v, t) -> (u, t, v): a mirror, so the winding flips
    return vertices[:, [0, 2, 1]], faces[:, ::-1]


def revolve(profile: ArrayLike, *, sections: int = 16) -> Solid:
    """Revolve a profile about the z axis.

    Parameters
    ----------
    profile : array_like, shape (K, 2)
        Closed outline in ``(radius, z)``, radius >= 0, either orientation.
    sections : int
        Segments around the axis (a multiple of 4).
    """
    outline = _ccw(np.asarray(profile, dtype=np.float64).reshape(-1, 2))
    return _from_manifold(manifold3d.Manifold.revolve(manifold3d.CrossSection([outline]), sections))


def rounded_rectangle(width: float, depth: float, radius: float, *, corner_segments: int = 4) -> np.ndarray:
    """Outline of a ``width`` x ``depth`` rectangle centred at the origin with rounded corners."""
    radius = min(radius, 0.499 * width, 0.499 * depth)
    hx, hy = 0.5 * width - radius, 0.5 * depth - radius
    points = []
    for k, (cx, cy) in enumerate(((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy))):
        for j in range(corner_segments + 1):
            angle = 0.5 * math.pi * (k + j / corner_segments)
            points.append((cx + radius * math.cos(angle), cy + radius * math.sin(angle)))
    return np.array(points)


def rounded_prism(
    center_xy: tuple[float, float], width: float, depth: float, radius: float, z0: float, z1: float
) -> Solid:
    """A box with rounded vertical edges (corner `radius`) from `z0` to `z1`."""
    outline = rounded_rectangle(width, depth, radius) + np.asarray(center_xy, dtype=np.float64)
    return extrude(outline, z0, z1)


def torus(
    center: ArrayLike, major: float, minor: float, *, sections: int = 16, tube: int = 8, axis: str = "z"
) -> Solid:
    """A torus about an axis through `center` (tube radius `minor` < `major`).

    Parameters
    ----------
    center : array_like, shape (3,)
        Centre of the ring.
    major, minor : float
        Radius of the ring's centre line and of its tube.
    sections, tube : int
        Segments around the axis and around the tube.
    axis : {"z", "x", "y"}
        Direction of the ring's axis: ``"z"`` lays the ring flat (a hoop), ``"x"`` and ``"y"`` stand it
        up like a wheel turning about that axis.
    """
    if axis in ("x", "y"):
        # the flat ring turned a quarter about y (its axis becomes x) or about x (its axis becomes y)
        flat = torus((0.0, 0.0, 0.0), major, minor, sections=sections, tube=tube)
        return translate(rotate(flat, "y" if axis == "x" else "x", 0.5 * math.pi), center)
    if axis != "z":
        raise ValueError(f"torus: axis must be 'x', 'y' or 'z', got {axis!r}")
    angles = 2.0 * np.pi * np.arange(tube) / tube
    circle = np.stack([major + minor * np.cos(angles), minor * np.sin(angles)], axis=1)
    vertices, faces = revolve(circle, sections=sections)
    return vertices + _vec3(center), faces


def hull(points: ArrayLike) -> Solid:
    """The convex hull of 3-D points (at least four, not coplanar)."""
    pts = np.ascontiguousarray(snap_to_grid(np.asarray(points, dtype=np.float64).reshape(-1, 3)))
    return _from_manifold(manifold3d.Manifold.hull_points(pts))


def bar(p0: ArrayLike, p1: ArrayLike, thickness: float | ArrayLike) -> Solid:
    """A straight bar between two points: the hull of two boxes of `thickness` centred on them.

    Parameters
    ----------
    p0, p1 : array_like, shape (3,)
        End centres.
    thickness : float or array_like, shape (3,)
        Edge lengths of the end boxes (a scalar gives a cube).
    """
    half = 0.5 * np.broadcast_to(np.asarray(thickness, dtype=np.float64), (3,))
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * half
    return hull(np.concatenate([_vec3(p0) + corners, _vec3(p1) + corners]))


def align(
    solid: Solid,
    *,
    x_min: float | None = None,
    x_max: float | None = None,
    y_min: float | None = None,
    y_max: float | None = None,
    z_min: float | None = None,
    z_max: float | None = None,
) -> Solid:
    """Translate a solid so that its bounding box touches the given planes (at most one per axis)."""
    lo, hi = solid[0].min(axis=0), solid[0].max(axis=0)
    offset = np.zeros(3)
    for axis, (low, high) in enumerate(((x_min, x_max), (y_min, y_max), (z_min, z_max))):
        if low is not None and high is not None:
            raise ValueError("align: give a minimum or a maximum per axis, not both")
        if low is not None:
            offset[axis] = low - lo[axis]
        elif high is not None:
            offset[axis] = high - hi[axis]
    return translate(solid, offset)


def translate(solid: Solid, offset: ArrayLike) -> Solid:
    """Move a solid by `offset`."""
    return solid[0] + _vec3(offset), solid[1]


def rotate(solid: Solid, axis: str, angle: float, *, about: ArrayLike = (0.0, 0.0, 0.0)) -> Solid:
    """Rotate a solid by `angle` radians about a line parallel to the ``"x"``, ``"y"`` or ``"z"`` axis.

    The right-hand rule applies: a positive angle about x turns +y towards +z.
    """
    c, s = math.cos(angle), math.sin(angle)
    matrices = {
        "x": np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]),
        "y": np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]),
        "z": np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]),
    }
    pivot = _vec3(about)
    return apply_linear(solid[0] - pivot, matrices[axis]) + pivot, solid[1]


def difference(base: Solid, *cutters: Solid) -> Solid:
    """``base`` minus every cutter, as one watertight solid (manifold3d)."""
    shape = _to_manifold(base)
    for cutter in cutters:
        shape = shape - _to_manifold(cutter)
    return _from_manifold(shape)


class Assembly:
    """Coloured closed parts of one object, joined into a :class:`MeshData` at the end.

    Parts may touch or overlap; each stays a closed solid of its own, so the joined mesh is closed
    (every edge shared by exactly two triangles) without merging anything.
    """

    def __init__(self) -> None:
        self._parts: list[tuple[Solid, RGB]] = []

    def add(self, solid: Solid, color: RGB) -> None:
        """Add one part of one colour."""
        self._parts.append((solid, color))

    def add_all(self, solids: Iterable[Solid], color: RGB) -> None:
        """Add several parts of the same colour."""
        for solid in solids:
            self.add(solid, color)

    def box(self, lo: Sequence[float], hi: Sequence[float], color: RGB) -> None:
        """Add an axis-aligned box between corners `lo` and `hi`."""
        self.add(box(lo, hi), color)

    def __len__(self) -> int:
        return len(self._parts)

    def mesh(self) -> MeshData:
        """Join the parts; faces keep their part's colour."""
        if not self._parts:
            raise ValueError("an assembly needs at least one part")
        meshes = [
            MeshData(v, f, np.broadcast_to(np.asarray(color, dtype=np.uint8), (len(f), 3)))
            for (v, f), color in self._parts
        ]
        return MeshData.concatenate(meshes)
