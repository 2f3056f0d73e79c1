"""What people and moving cars look like to the camera: meshes in their own frames, made once.

A person is a figure of simple solids (legs, torso, arms, head) 1.7 m tall, standing on its origin and
facing +x, in one of :data:`PERSON_OUTFITS`; a car is a sedan of the asset library, its length along +x,
its wheels on its origin. The renderer instances them (``SceneRenderer.add_body_shape``); the physics
sees the capsules and boxes of :mod:`navverse.dynamics.bodies`.
"""

from __future__ import annotations

import math

import numpy as np
import trimesh

from navverse.assets.library import make_object
from navverse.scene.geometry import MeshData

__all__ = ["PERSON_OUTFITS", "car_mesh", "person_mesh"]

SKIN = (205, 160, 130)
PERSON_OUTFITS: tuple[tuple[tuple[int, int, int], tuple[int, int, int]], ...] = (
    ((40, 70, 140), (45, 45, 50)),  # blue top, dark trousers
    ((170, 40, 40), (60, 60, 90)),  # red top, jeans
    ((230, 230, 225), (110, 90, 70)),  # white top, brown trousers
    ((60, 120, 70), (35, 35, 35)),  # green top, black trousers
)
"""(top, trousers) sRGB colours of the person variants."""


def _part(mesh: trimesh.Trimesh, color: tuple[int, int, int]) -> MeshData:
    colors = np.tile(np.asarray(color, dtype=np.uint8), (len(mesh.faces), 1))
    return MeshData(np.asarray(mesh.vertices, float), np.asarray(mesh.faces, np.int64), colors)


def _capsule(radius: float, length: float, center: tuple[float, float, float], tilt: float = 0.0):
    mesh = trimesh.creation.capsule(height=length, radius=radius, count=[8, 8])
    if tilt:
        mesh.apply_transform(trimesh.transformations.rotation_matrix(tilt, (1.0, 0.0, 0.0)))
    mesh.apply_translation(center)
    return mesh


def person_mesh(outfit: int) -> MeshData:
    """A standing person 1.7 m tall in outfit `outfit` (an index of :data:`PERSON_OUTFITS`)."""
    top, trousers = PERSON_OUTFITS[outfit % len(PERSON_OUTFITS)]
    parts = [
        _part(_capsule(0.075, 0.7, (0.0, 0.1, 0.45)), trousers),
        _part(_capsule(0.075, 0.7, (0.0, -0.1, 0.45)), trousers),
        _part(_capsule(0.17, 0.35, (0.0, 0.0, 1.15)), top),
        _part(_capsule(0.05, 0.5, (0.0, 0.24, 1.12), tilt=0.08), top),
        _part(_capsule(0.05, 0.5, (0.0, -0.24, 1.12), tilt=-0.08), top),
    ]
    head = trimesh.creation.icosphere(subdivisions=2, radius=0.11)
    head.apply_translation((0.0, 0.0, 1.59))
    parts.append(_part(head, SKIN))
    return MeshData.concatenate(parts)


def car_mesh(seed: int = 0) -> MeshData:
    """A sedan of the asset library (its colours from `seed`), length along +x, wheels on the origin."""
    mesh, _ = make_object("sedan", np.random.default_rng(seed))
    lo, _ = mesh.bounds()
    return mesh.transformed((0.0, 0.0, -float(lo[2])), yaw=-math.pi / 2.0)
