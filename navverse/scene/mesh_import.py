"""Reading user meshes (OBJ, glTF/GLB, PLY, USD) into named, coloured nodes in the project's frame.

:func:`read_mesh_nodes` gives one :class:`~.mesh_nodes.MeshNode` per mesh node of the file, with the
node's transform applied, in the file's own units and axes, and a colour on every face (the readers:
:mod:`.mesh_trimesh` for OBJ, glTF/GLB and PLY, :mod:`.mesh_usd` for USD). :func:`to_z_up` converts a
node to meters and the project's z-up frame; :func:`~.mesh_parts.scene_parts` then makes scene
surfaces and objects from the nodes and the roles a recipe gives them.

Hostile files are refused, never waited on: the file and every file it brings in must be a regular
file of at most :data:`~.mesh_files.MAX_MESH_BYTES` (:mod:`.mesh_files`); non-finite vertex
coordinates are an error (trimesh would drop them silently), and :func:`check_extent` refuses
coordinates beyond :data:`MAX_COORDINATE_M` once in meters.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Literal

import numpy as np

from navverse.scene.geometry import MeshData
from navverse.scene.mesh_files import FileCheck, MeshImportError, file_problem
from navverse.scene.mesh_nodes import FileFrame, MeshNode, ProgressFn
from navverse.scene.mesh_trimesh import read_trimesh_nodes
from navverse.scene.mesh_usd import read_usd_nodes

__all__ = [
    "MAX_COORDINATE_M",
    "MESH_SUFFIXES",
    "TRIMESH_SUFFIXES",
    "UNIT_SCALES",
    "USD_SUFFIXES",
    "check_extent",
    "read_mesh_nodes",
    "to_z_up",
]

TRIMESH_SUFFIXES = (".obj", ".glb", ".gltf", ".ply")
USD_SUFFIXES = (".usd", ".usda", ".usdc")
MESH_SUFFIXES = TRIMESH_SUFFIXES + USD_SUFFIXES
"""File suffixes :func:`read_mesh_nodes` reads."""

UNIT_SCALES = {"meters": 1.0, "centimeters": 0.01, "millimeters": 0.001, "inches": 0.0254, "feet": 0.3048}
"""Meters per unit, by unit name."""

MAX_COORDINATE_M = 1e6
"""Largest vertex coordinate, in meters after unit scaling (1000 km: larger means wrong units)."""


def read_mesh_nodes(
    path: Path, *, progress: ProgressFn | None = None, check: FileCheck | None = None
) -> tuple[list[MeshNode], FileFrame]:
    """Read every mesh node of a file.

    Parameters
    ----------
    path : Path
        An ``.obj``, ``.glb``, ``.gltf``, ``.ply``, ``.usd``, ``.usda`` or ``.usdc`` file. OBJ files
        are split by material, and by object and group where they name more than one.
    progress : callable, optional
        Called as ``progress(done, total, description)`` while nodes are converted.
    check : callable, optional
        ``check(resolved_path, name_as_written) -> str | None`` for every file the mesh file brings
        in (USD layers; OBJ material libraries and textures, glTF buffers and images, which must be
        in the mesh's folder or below): why it may not be read, None to read it.

    Returns
    -------
    nodes : list of MeshNode
        Transforms applied, in the file's units and axes; USD prims in stage order, the nodes of
        other formats sorted by path.
    frame : FileFrame
        The up axis and meters per unit the file declares (USD stages; glTF is y-up by its
        specification); None where the format does not say.

    Raises
    ------
    MeshImportError
        If the suffix is not supported; the file, or a file it brings in, is not a regular file,
        is over :data:`~.mesh_files.MAX_MESH_BYTES` or is refused by ``check``; the file cannot be
        parsed, holds no triangles, or has vertices with non-finite coordinates.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise MeshImportError(
            f"cannot import {path}: unsupported format {suffix!r}; use one of {', '.join(MESH_SUFFIXES)}"
        )
    problem = file_problem(path)
    if problem is not None:
        raise MeshImportError(f"cannot import {path}: {problem}")
    if suffix in USD_SUFFIXES:
        nodes, frame = read_usd_nodes(path, progress=progress, check=check)
    else:
        nodes = read_trimesh_nodes(path, progress=progress, check=check)
        frame = FileFrame(up_axis="y", meters_per_unit=1.0) if suffix in (".glb", ".gltf") else FileFrame()
    if not nodes:
        raise MeshImportError(
            f"{path} holds no triangle meshes; check that it is the right file and not empty"
        )
    return nodes, frame


def to_z_up(mesh: MeshData, *, up_axis: Literal["y", "z"], meters_per_unit: float) -> MeshData:
    """Scale a mesh to meters and turn it into the project's z-up frame.

    A y-up mesh is rotated +90 degrees about x (``(x, y, z) -> (x, -z, y)``): a proper rotation,
    so the frame stays right-handed and triangles keep their winding.
    """
    vertices = mesh.vertices * float(meters_per_unit)
    if up_axis == "y":
        vertices = np.stack([vertices[:, 0], -vertices[:, 2], vertices[:, 1]], axis=1)
    return MeshData(vertices, mesh.faces, mesh.face_colors)


def check_extent(
    nodes: Sequence[MeshNode], *, source: Path, meters_per_unit: float, limit: float = MAX_COORDINATE_M
) -> None:
    """Refuse nodes (in meters, see :func:`to_z_up`) with a vertex coordinate beyond ``limit``.

    Raises
    ------
    MeshImportError
        Naming the file, the largest coordinate and the scale used: a file in millimeters read
        as meters lands here.
    """
    largest, where = 0.0, ""
    for node in nodes:
        vertices = node.mesh.vertices
        if len(vertices):
            value = float(np.abs(vertices).max())
            if value > largest:
                largest, where = value, node.path
    if largest > limit:
        raise MeshImportError(
            f"{source}: a vertex of {where} lies {largest:.3g} m from the origin (at {meters_per_unit:g} "
            f"meters per unit), beyond the {limit:.0e} m a scene may span; check meters_per_unit: set the "
            "recipe's 'units' to the file's unit (e.g. 'units: millimeters'), or move the model near "
            "the origin"
        )
