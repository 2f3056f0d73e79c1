"""What a mesh file reader gives: :class:`MeshNode` values (one mesh of the file, placed by its
transform, in the file's units and axes, a colour on every face) and the :class:`FileFrame` the file
declares; and what every reader does alike: place a mesh by a transform, colour a mesh in one
colour, refuse non-finite vertex coordinates (trimesh would drop them silently)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from navverse.scene.geometry import MeshData
from navverse.scene.mesh_files import MeshImportError

__all__ = ["FileFrame", "MeshNode", "ProgressFn", "apply_transform", "raise_non_finite", "uniform_colors"]

ProgressFn = Callable[[int, int, str], None]
"""``progress(done, total, description)``, called as a reader converts nodes."""


@dataclass(frozen=True, eq=False)
class MeshNode:
    """One mesh of a file, placed by its transform, in the file's units and axes.

    Parameters
    ----------
    name : str
        Node name (trimesh node name; OBJ object/group/material name; USD prim name).
    path : str
        Node path: ``/parent/.../name`` in the file's hierarchy (the USD prim path).
    mesh : MeshData
        Triangles with a colour on every face.
    """

    name: str
    path: str
    mesh: MeshData


@dataclass(frozen=True)
class FileFrame:
    """What a file says about its frame: up axis and meters per unit (None where it says nothing)."""

    up_axis: Literal["y", "z"] | None = None
    meters_per_unit: float | None = None


def uniform_colors(color: np.ndarray | tuple[int, int, int], count: int) -> np.ndarray:
    """``count`` rows of one uint8 RGB colour (a face colour array)."""
    return np.broadcast_to(np.asarray(color, dtype=np.uint8).reshape(1, 3), (count, 3)).copy()


def raise_non_finite(path: Path, bad: dict[str, int]) -> None:
    """Refuse ``path``, whose meshes have non-finite vertex coordinates (``bad``: mesh name -> count).

    Raises
    ------
    MeshImportError
        Always, naming up to five meshes and the number of vertices.
    """
    total = sum(bad.values())
    where = ", ".join(f"{name!r}: {count}" for name, count in sorted(bad.items())[:5])
    more = f" and {len(bad) - 5} more meshes" if len(bad) > 5 else ""
    count = f"{total} vertex has" if total == 1 else f"{total} vertices have"
    raise MeshImportError(
        f"{path}: {count} non-finite coordinates (NaN or infinity) ({where}{more}); fix or re-export the file"
    )


def apply_transform(
    vertices: np.ndarray, faces: np.ndarray, matrix: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Apply a 4x4 column-vector transform; mirroring transforms get their winding reversed."""
    linear = matrix[:3, :3]
    placed = vertices @ linear.T + matrix[:3, 3]
    if np.linalg.det(linear) < 0:
        faces = faces[:, ::-1]
    return placed, faces
