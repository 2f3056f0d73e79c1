"""Watertight primitive solids (box, ramp, cylinder) as triangle meshes, via trimesh and numpy."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

HEXAHEDRON_FACES = np.array(
    [
        [4, 5, 6], [4, 6, 7],  # top
        [0, 2, 1], [0, 3, 2],  # bottom
        [0, 1, 5], [0, 5, 4],  # -y
        [3, 7, 6], [3, 6, 2],  # +y
        [0, 4, 7], [0, 7, 3],  # -x
        [1, 2, 6], [1, 6, 5],  # +x
    ],
    dtype=np.int64,
)  # fmt: skip
"""Triangles of a hexahedron over corners 0..3 (bottom, counter-clockwise seen from above) and 4..7
(top, each above its bottom corner), wound counter-clockwise seen from outside (normals out)."""

_BOX_CORNERS = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=bool
)


def boxes(lo: ArrayLike, hi: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Many axis-aligned boxes at once, 8 vertices and 12 outward-facing triangles each.

    Parameters
    ----------
    lo, hi : array_like, shape (K, 3) or (3,)
        Minimum and maximum corners; ``hi > lo`` on every axis.

    Returns
    -------
    tuple of ndarray
        ``(vertices (8K, 3), faces (12K, 3))``; box ``k`` owns vertices ``8k .. 8k + 7``.

    Raises
    ------
    ValueError
        If the shapes differ or a box has no volume.
    """
    lo = np.atleast_2d(np.asarray(lo, dtype=np.float64))
    hi = np.atleast_2d(np.asarray(hi, dtype=np.float64))
    if lo.shape != hi.shape or lo.shape[1] != 3 or not (hi > lo).all():
        raise ValueError("boxes need lo < hi on every axis, both of shape (K, 3)")
    corners = np.where(_BOX_CORNERS[None], hi[:, None, :], lo[:, None, :])
    faces = HEXAHEDRON_FACES[None] + 8 * np.arange(len(lo))[:, None, None]
    return corners.reshape(-1, 3), faces.reshape(-1, 3)


def box(size: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """An axis-aligned box of ``size`` centred at the origin.

    Returns
    -------
    tuple of ndarray
        ``(vertices (N, 3), faces (M, 3))``, outward-facing triangles.
    """
    import trimesh

    mesh = trimesh.creation.box(extents=np.asarray(size, dtype=float))
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def cylinder(radius: float, height: float, *, sections: int = 24) -> tuple[np.ndarray, np.ndarray]:
    """An upright cylinder centred at the origin."""
    import trimesh

    mesh = trimesh.creation.cylinder(radius=radius, height=height, sections=sections)
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def ramp(length: float, width: float, height: float) -> tuple[np.ndarray, np.ndarray]:
    """A wedge rising along +x from 0 to ``height`` over ``length``, centred on its bounding box.

    The sloped top makes an angle ``atan(height / length)`` with the ground.
    """
    import trimesh

    hl, hw, hh = length / 2.0, width / 2.0, height / 2.0
    points = np.array(
        [
            [-hl, -hw, -hh],
            [hl, -hw, -hh],
            [hl, hw, -hh],
            [-hl, hw, -hh],  # base
            [hl, -hw, hh],
            [hl, hw, hh],  # high edge
        ]
    )
    mesh = trimesh.convex.convex_hull(points)
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def ramp_for_slope(slope_deg: float, height: float, width: float) -> tuple[float, float, float]:
    """``(length, width, height)`` of a ramp climbing ``height`` at ``slope_deg`` degrees."""
    return height / math.tan(math.radians(slope_deg)), width, height
