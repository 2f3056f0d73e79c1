"""Watertight primitive solids (box, ramp, cylinder) as triangle meshes, via trimesh."""

from __future__ import annotations

import math

import numpy as np


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
