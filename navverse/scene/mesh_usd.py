"""Reading USD files (``.usd``, ``.usda``, ``.usdc``): one :class:`~.mesh_nodes.MeshNode` per
visible, renderable ``UsdGeom.Mesh`` prim, in stage order, with its world transform applied and a
colour on every face (``displayColor``, else its bound preview material's diffuse colour, else a
colour derived from the prim's name), and the up axis and meters per unit the stage declares. The
layers the file brings in are checked by :func:`~.mesh_files.usd_layer_files` before the stage is
opened.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from navverse.scene.colors import default_color
from navverse.scene.geometry import MeshData
from navverse.scene.mesh_files import FileCheck, MeshImportError, usd_layer_files
from navverse.scene.mesh_nodes import (
    FileFrame,
    MeshNode,
    ProgressFn,
    apply_transform,
    raise_non_finite,
    uniform_colors,
)

__all__ = ["read_usd_nodes"]


def _linear_to_srgb(linear: np.ndarray) -> np.ndarray:
    c = np.clip(np.asarray(linear, dtype=np.float64), 0.0, 1.0)
    return np.rint(255.0 * np.where(c <= 0.0031308, c * 12.92, 1.055 * c ** (1.0 / 2.4) - 0.055)).astype(
        np.uint8
    )


def _usd_colors(
    prim: object, *, counts: np.ndarray, corners: np.ndarray, faces: np.ndarray, name: str
) -> np.ndarray:
    """Per-triangle sRGB colours of a USD mesh: displayColor, else its bound preview material's
    diffuse colour, else a colour from the prim's name.

    `corners` are the face-vertex (corner) indices of the triangles, `faces` their point indices.
    """
    from pxr import UsdGeom, UsdShade

    triangles = len(faces)
    primvar = UsdGeom.PrimvarsAPI(prim).GetPrimvar("displayColor")
    values = primvar.ComputeFlattened() if primvar and primvar.HasAuthoredValue() else None
    if values is not None and len(values):
        linear = np.asarray(values, dtype=np.float64).reshape(-1, 3)
        interpolation = primvar.GetInterpolation()
        if interpolation == UsdGeom.Tokens.constant:
            return uniform_colors(_linear_to_srgb(linear[0]), triangles)
        if interpolation == UsdGeom.Tokens.uniform and len(linear) >= len(counts):
            polygon = np.repeat(np.arange(len(counts)), np.maximum(counts - 2, 0))
            return _linear_to_srgb(linear[polygon])
        if interpolation == UsdGeom.Tokens.faceVarying and len(linear) > corners.max(initial=0):
            return _linear_to_srgb(linear[corners].mean(axis=1))
        if len(linear) > faces.max(initial=0):  # vertex / varying: indexed like the points
            return _linear_to_srgb(linear[faces].mean(axis=1))
    material, _ = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()
    if material:
        shader = material.ComputeSurfaceSource()[0]
        diffuse = shader.GetInput("diffuseColor") if shader else None
        value = diffuse.Get() if diffuse and not diffuse.HasConnectedSource() else None
        if value is not None:
            return uniform_colors(_linear_to_srgb(np.asarray(value, dtype=np.float64)), triangles)
    return uniform_colors(default_color(name), triangles)


def read_usd_nodes(
    path: Path, *, progress: ProgressFn | None = None, check: FileCheck | None = None
) -> tuple[list[MeshNode], FileFrame]:
    """Read every visible, renderable mesh prim of a USD file.

    Parameters
    ----------
    path : Path
        A ``.usd``, ``.usda`` or ``.usdc`` file, already checked as a regular file within the size cap.
    progress : callable, optional
        Called as ``progress(done, total, description)`` while prims are converted.
    check : callable, optional
        ``check(resolved_path, asset_path) -> str | None`` for every layer the file brings in
        (see :func:`~.mesh_files.usd_layer_files`).

    Returns
    -------
    nodes : list of MeshNode
        In stage order, world transforms applied, in the stage's units and axes.
    frame : FileFrame
        The stage's up axis and meters per unit.

    Raises
    ------
    MeshImportError
        If a layer is refused or cannot be parsed, the stage cannot be opened, or a mesh has
        non-finite points or face indices that do not match them.
    """
    from pxr import Tf, Usd, UsdGeom

    usd_layer_files(path, check=check)
    try:
        stage = Usd.Stage.Open(str(path), Usd.Stage.LoadAll)
    except Tf.ErrorException as exc:
        message = " ".join(str(exc).split())
        raise MeshImportError(f"cannot read {path} as USD ({message}); check the file in usdview") from None
    if stage is None:
        raise MeshImportError(f"cannot read {path} as USD; check the file in usdview")
    up = str(UsdGeom.GetStageUpAxis(stage)).lower()
    frame = FileFrame(
        up_axis="y" if up == "y" else "z", meters_per_unit=float(UsdGeom.GetStageMetersPerUnit(stage))
    )
    time = Usd.TimeCode.Default()
    prims = [p for p in stage.Traverse(Usd.TraverseInstanceProxies()) if p.IsA(UsdGeom.Mesh)]
    nodes: list[MeshNode] = []
    for index, prim in enumerate(prims):
        imageable = UsdGeom.Imageable(prim)
        if imageable.ComputeVisibility(time) == UsdGeom.Tokens.invisible or imageable.ComputePurpose() in (
            UsdGeom.Tokens.guide,
            UsdGeom.Tokens.proxy,
        ):
            continue
        node = _usd_node(path, prim, time)
        if node is not None:
            nodes.append(node)
        if progress is not None:
            progress(index + 1, len(prims), "mesh prims")
    return nodes, frame


def _usd_node(path: Path, prim: object, time: object) -> MeshNode | None:
    from pxr import UsdGeom

    mesh = UsdGeom.Mesh(prim)
    points = mesh.GetPointsAttr().Get(time)
    counts_value = mesh.GetFaceVertexCountsAttr().Get(time)
    indices_value = mesh.GetFaceVertexIndicesAttr().Get(time)
    if points is None or counts_value is None or indices_value is None or len(points) == 0:
        return None
    vertices = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    non_finite = int((~np.isfinite(vertices).all(axis=1)).sum())
    if non_finite:
        raise_non_finite(path, {str(prim.GetPath()): non_finite})  # type: ignore[attr-defined]
    counts = np.asarray(counts_value, dtype=np.int64)
    indices = np.asarray(indices_value, dtype=np.int64)
    if counts.sum() != len(indices) or (
        len(indices) and (indices.min() < 0 or indices.max() >= len(vertices))
    ):
        raise MeshImportError(
            f"{path}: mesh {prim.GetPath()} has face vertex counts or indices that do not match its "  # type: ignore[attr-defined]
            "points; fix or re-export the file"
        )
    # Fan triangulation in corner (face-vertex) space: polygon p with n corners from s gives
    # corners (s, s+k+1, s+k+2) for k in 0..n-3; polygons with fewer than 3 corners are skipped.
    fan = np.maximum(counts - 2, 0)
    polygon = np.repeat(np.arange(len(counts)), fan)
    start = (np.cumsum(counts) - counts)[polygon]
    k = np.arange(len(polygon)) - np.repeat(np.cumsum(fan) - fan, fan)
    corners = np.stack([start, start + k + 1, start + k + 2], axis=1)
    if len(corners) == 0:
        return None
    faces = indices[corners]
    name = str(prim.GetName())  # type: ignore[attr-defined]
    colors = _usd_colors(prim, counts=counts, corners=corners, faces=faces, name=name)
    if mesh.GetOrientationAttr().Get(time) == UsdGeom.Tokens.leftHanded:
        faces = faces[:, ::-1]
    # USD matrices act on row vectors; transpose into the column-vector form.
    matrix = np.asarray(UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(time), dtype=np.float64).T
    vertices, faces = apply_transform(vertices, faces, matrix)
    return MeshNode(name, str(prim.GetPath()), MeshData(vertices, faces, colors))  # type: ignore[attr-defined]
