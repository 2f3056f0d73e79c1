"""Reading user meshes (OBJ, glTF/GLB, PLY, USD) into named, coloured nodes, and turning nodes into
scene surfaces and objects.

:func:`read_mesh_nodes` gives one :class:`MeshNode` per mesh node of the file (trimesh scene nodes;
for OBJ files the objects, groups and materials; for USD files the ``UsdGeom.Mesh`` prims) with the
node's transform applied, in the file's own units and axes, and a colour on every face: the file's
vertex or face colours, else its material's diffuse colour (or the mean colour of its texture),
else a colour derived from the node's name. :func:`to_z_up` converts a node to meters and the
project's z-up frame; :func:`scene_parts` makes :class:`Surface` and :class:`ObjectPart` values from
nodes and the roles a recipe gives them.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from navverse.errors import NavverseError
from navverse.scene.colors import default_color
from navverse.scene.compose import ObjectPart
from navverse.scene.geometry import MeshData, Surface
from navverse.scene.naming import sanitize_identifier, unique_name
from navverse.scene.simplify import clean_mesh

__all__ = [
    "MESH_SUFFIXES",
    "MIN_OBJECT_SIZE",
    "UNIT_SCALES",
    "FileFrame",
    "MeshImportError",
    "MeshNode",
    "NodeRole",
    "read_mesh_nodes",
    "scene_parts",
    "split_components",
    "subdivide",
    "to_z_up",
]

TRIMESH_SUFFIXES = (".obj", ".glb", ".gltf", ".ply")
USD_SUFFIXES = (".usd", ".usda", ".usdc")
MESH_SUFFIXES = TRIMESH_SUFFIXES + USD_SUFFIXES
"""File suffixes :func:`read_mesh_nodes` reads."""

UNIT_SCALES = {"meters": 1.0, "centimeters": 0.01, "millimeters": 0.001, "inches": 0.0254, "feet": 0.3048}
"""Meters per unit, by unit name."""

MIN_OBJECT_SIZE = 1e-3
"""Smallest annotated object extent (m); flat objects get this thickness in their annotation."""

ProgressFn = Callable[[int, int, str], None]


class MeshImportError(NavverseError):
    """A mesh file cannot be read or holds nothing to import."""


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


@dataclass(frozen=True)
class NodeRole:
    """What a node becomes in a scene.

    Parameters
    ----------
    kind : {"object", "surface"}
        An annotated object or static terrain geometry.
    label : str
        The object category or the terrain class.
    split : bool
        One item per connected component (components whose bounding boxes come within
        `join_gap` of each other form one item) instead of one item for the node.
    join_gap : float
        See `split`, in meters.
    """

    kind: Literal["object", "surface"]
    label: str
    split: bool = False
    join_gap: float = 0.05


# ------------------------------------------------------------------------------------------ colours


def _rgb(values: np.ndarray) -> np.ndarray:
    """uint8 RGB from 0..255 or 0..1 colour arrays (alpha dropped)."""
    array = np.asarray(values)
    if np.issubdtype(array.dtype, np.floating) and array.size and array.max() <= 1.0:
        array = array * 255.0
    return np.clip(np.rint(np.asarray(array, dtype=np.float64)[..., :3]), 0, 255).astype(np.uint8)


def _linear_to_srgb(linear: np.ndarray) -> np.ndarray:
    c = np.clip(np.asarray(linear, dtype=np.float64), 0.0, 1.0)
    return np.rint(255.0 * np.where(c <= 0.0031308, c * 12.92, 1.055 * c ** (1.0 / 2.4) - 0.055)).astype(
        np.uint8
    )


def _uniform(color: np.ndarray | tuple[int, int, int], count: int) -> np.ndarray:
    return np.broadcast_to(np.asarray(color, dtype=np.uint8).reshape(1, 3), (count, 3)).copy()


def _material_color(material: object) -> np.ndarray | None:
    """Diffuse colour of a trimesh material (OBJ ``Kd``, glTF ``baseColorFactor``), times the mean
    colour of its texture if it has one."""
    if material is None:
        return None
    if hasattr(material, "baseColorFactor"):  # glTF: the factor defaults to white
        factor, image = (
            getattr(material, "baseColorFactor", None),
            getattr(material, "baseColorTexture", None),
        )
        color = _rgb(np.asarray(factor)).astype(np.float64) if factor is not None else np.full(3, 255.0)
    else:
        image = getattr(material, "image", None)
        color = _rgb(np.asarray(material.main_color)).astype(np.float64)  # type: ignore[attr-defined]
    if image is not None:
        pixels = np.asarray(image.convert("RGB"), dtype=np.float64).reshape(-1, 3)
        if len(pixels):
            color = color * pixels.mean(axis=0) / 255.0
    return np.clip(np.rint(color), 0, 255).astype(np.uint8)


def _trimesh_face_colors(geometry: object, name: str) -> np.ndarray:
    count = len(geometry.faces)  # type: ignore[attr-defined]
    visual = geometry.visual  # type: ignore[attr-defined]
    kind = getattr(visual, "kind", None)
    if kind == "face":
        return _rgb(visual.face_colors)
    if kind == "vertex":
        corners = _rgb(visual.vertex_colors)[geometry.faces]  # type: ignore[attr-defined]
        return np.rint(corners.astype(np.float64).mean(axis=1)).astype(np.uint8)
    color = _material_color(getattr(visual, "material", None))
    return _uniform(color if color is not None else default_color(name), count)


# ------------------------------------------------------------------------------------------ trimesh


def _obj_split_options(path: Path) -> dict[str, bool]:
    """Split an OBJ file by objects / groups only where it names more than one."""
    text = path.read_text(encoding="utf-8", errors="replace")
    objects = set(re.findall(r"^o[ \t]+(.*?)\s*$", text, flags=re.MULTILINE))
    groups = set(re.findall(r"^g[ \t]+(.*?)\s*$", text, flags=re.MULTILINE))
    return {"split_objects": len(objects) > 1, "split_groups": len(groups) > 1}


def _node_path(parents: dict[str, str], node: str, base: str) -> str:
    chain = [node]
    while parents.get(chain[-1]) not in (None, base) and len(chain) < 1000:
        chain.append(parents[chain[-1]])
    return "/" + "/".join(reversed(chain))


def _apply_transform(
    vertices: np.ndarray, faces: np.ndarray, matrix: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Apply a 4x4 column-vector transform; mirroring transforms get their winding reversed."""
    linear = matrix[:3, :3]
    placed = vertices @ linear.T + matrix[:3, 3]
    if np.linalg.det(linear) < 0:
        faces = faces[:, ::-1]
    return placed, faces


def _read_trimesh(path: Path, progress: ProgressFn | None) -> list[MeshNode]:
    import trimesh

    options = _obj_split_options(path) if path.suffix.lower() == ".obj" else {}
    try:
        scene = trimesh.load(str(path), force="scene", **options)
    except Exception as exc:  # any parser failure is the file's fault
        raise MeshImportError(
            f"cannot read {path} as a {path.suffix} mesh ({type(exc).__name__}: {exc}); "
            "check the file (export it again, or convert it to .glb or .obj)"
        ) from None
    parents = dict(scene.graph.transforms.parents)
    base = scene.graph.base_frame
    # trimesh does not keep the file's order (its OBJ reader reverses it): go by node path.
    names = sorted(scene.graph.nodes_geometry, key=lambda node: (_node_path(parents, node, base), str(node)))
    nodes: list[MeshNode] = []
    for index, node in enumerate(names):
        matrix, geometry_name = scene.graph[node]
        geometry = scene.geometry.get(geometry_name)
        if not isinstance(geometry, trimesh.Trimesh) or len(geometry.faces) == 0:
            continue  # point clouds, curves and empty meshes carry no surface
        colors = _trimesh_face_colors(geometry, str(node))
        vertices, faces = _apply_transform(
            np.asarray(geometry.vertices, dtype=np.float64),
            np.asarray(geometry.faces, dtype=np.int64),
            matrix,
        )
        mesh = MeshData(vertices, faces, colors)
        nodes.append(MeshNode(str(node), _node_path(parents, node, base), mesh))
        if progress is not None:
            progress(index + 1, len(names), "mesh nodes")
    return nodes


# ---------------------------------------------------------------------------------------------- USD


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
            return _uniform(_linear_to_srgb(linear[0]), triangles)
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
            return _uniform(_linear_to_srgb(np.asarray(value, dtype=np.float64)), triangles)
    return _uniform(default_color(name), triangles)


def _read_usd(path: Path, progress: ProgressFn | None) -> tuple[list[MeshNode], FileFrame]:
    from pxr import Tf, Usd, UsdGeom

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
    vertices, faces = _apply_transform(vertices, faces, matrix)
    return MeshNode(name, str(prim.GetPath()), MeshData(vertices, faces, colors))  # type: ignore[attr-defined]


# --------------------------------------------------------------------------------------- read, frame


def read_mesh_nodes(path: Path, *, progress: ProgressFn | None = None) -> tuple[list[MeshNode], FileFrame]:
    """Read every mesh node of a file.

    Parameters
    ----------
    path : Path
        An ``.obj``, ``.glb``, ``.gltf``, ``.ply``, ``.usd``, ``.usda`` or ``.usdc`` file. OBJ files
        are split by material, and by object and group where they name more than one.
    progress : callable, optional
        Called as ``progress(done, total, description)`` while nodes are converted.

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
        If the suffix is not supported, the file cannot be parsed, or it holds no triangles.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise MeshImportError(
            f"cannot import {path}: unsupported format {suffix!r}; use one of {', '.join(MESH_SUFFIXES)}"
        )
    if not path.is_file():
        raise MeshImportError(f"mesh file not found: {path}")
    if suffix in USD_SUFFIXES:
        nodes, frame = _read_usd(path, progress)
    else:
        nodes = _read_trimesh(path, progress)
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


# ---------------------------------------------------------------------------------------- mesh ops


def subdivide(mesh: MeshData, iterations: int) -> MeshData:
    """Split every triangle into four at its edge midpoints, `iterations` times (shape unchanged).

    Midpoints are shared by the triangles of an edge, so a closed mesh stays closed; colours are
    copied to the four children.
    """
    import trimesh.remesh

    vertices, faces, colors = mesh.vertices, mesh.faces, mesh.face_colors
    for _ in range(iterations):
        # trimesh puts the four children of face i at rows 4i .. 4i+3.
        vertices, faces = trimesh.remesh.subdivide(vertices, faces)
        if colors is not None:
            colors = np.repeat(colors, 4, axis=0)
    return MeshData(vertices, faces, colors)


def split_components(mesh: MeshData, *, join_gap: float) -> list[MeshData]:
    """Split a mesh into connected pieces, joining pieces whose bounding boxes come within `join_gap`.

    Vertices at the same position are connected. The result is ordered by each piece's first face,
    so the same mesh always splits the same way.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    welded = clean_mesh(mesh)
    if welded.num_faces == 0:
        return []
    faces, n = welded.faces, welded.num_vertices
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]]])
    graph = coo_matrix((np.ones(len(edges), dtype=np.int8), (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, vertex_label = connected_components(graph, directed=False)
    face_label = vertex_label[faces[:, 0]]
    count = int(face_label.max()) + 1
    lo = np.full((count, 3), np.inf)
    hi = np.full((count, 3), -np.inf)
    corners = welded.vertices[faces]
    np.minimum.at(lo, face_label, corners.min(axis=1))
    np.maximum.at(hi, face_label, corners.max(axis=1))
    group = _join_boxes(lo - 0.5 * join_gap, hi + 0.5 * join_gap)
    face_group = group[face_label]
    _, first_face = np.unique(face_group, return_index=True)
    pieces = []
    for label in face_group[np.sort(first_face)]:
        face_ids = np.flatnonzero(face_group == label)
        used, local = np.unique(faces[face_ids], return_inverse=True)
        colors = welded.face_colors[face_ids] if welded.face_colors is not None else None
        pieces.append(MeshData(welded.vertices[used], local.reshape(-1, 3), colors))
    return pieces


def _join_boxes(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Label of the group of overlapping boxes each box belongs to (sweep along x)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    count = len(lo)
    order = np.argsort(lo[:, 0], kind="stable")
    sorted_lo = lo[order, 0]
    rows: list[np.ndarray] = []
    cols: list[np.ndarray] = []
    for position, box in enumerate(order):
        end = int(np.searchsorted(sorted_lo, hi[box, 0], side="right"))
        others = order[position + 1 : end]
        if len(others):
            touching = others[
                np.all((lo[others, 1:] <= hi[box, 1:]) & (lo[box, 1:] <= hi[others, 1:]), axis=1)
            ]
            rows.append(np.full(len(touching), box))
            cols.append(touching)
    if not rows:
        return np.arange(count)
    r, c = np.concatenate(rows), np.concatenate(cols)
    graph = coo_matrix((np.ones(len(r), dtype=np.int8), (r, c)), shape=(count, count))
    return connected_components(graph, directed=False)[1]


# ------------------------------------------------------------------------------------ scene parts


def scene_parts(
    nodes: Sequence[MeshNode],
    roles: Sequence[NodeRole | None],
    *,
    subdivisions: int = 0,
    progress: ProgressFn | None = None,
) -> tuple[list[Surface], list[ObjectPart]]:
    """Turn z-up, metric nodes into terrain surfaces and objects.

    Parameters
    ----------
    nodes : sequence of MeshNode
        Nodes in meters, z up (see :func:`to_z_up`).
    roles : sequence of NodeRole or None
        What each node becomes; None drops it.
    subdivisions : int
        :func:`subdivide` iterations applied to every surface and object mesh.
    progress : callable, optional
        Called as ``progress(done, total, description)`` per node.

    Returns
    -------
    surfaces : list of Surface
        One per node (or component), named after the node (made a unique USD identifier).
    objects : list of ObjectPart
        One per node (or component), in node order, meshes in a frame centred on their bounding box
        (yaw 0); :func:`~navverse.scene.compose.assemble_scene` numbers them.
    """
    surfaces: list[Surface] = []
    objects: list[ObjectPart] = []
    taken: set[str] = set()
    for index, (node, role) in enumerate(zip(nodes, roles, strict=True)):
        if role is not None:
            pieces = (
                split_components(node.mesh, join_gap=role.join_gap) if role.split else [clean_mesh(node.mesh)]
            )
            base = sanitize_identifier(node.name)
            for number, piece in enumerate(p for p in pieces if p.num_faces):
                if subdivisions:
                    piece = subdivide(piece, subdivisions)
                if role.kind == "surface":
                    name = unique_name(f"{base}_{number + 1:03d}" if role.split else base, taken)
                    surfaces.append(Surface(name=name, terrain_class=role.label, mesh=piece))
                else:
                    objects.append(_object_part(piece, role.label))
        if progress is not None:
            progress(index + 1, len(nodes), "scene parts")
    return surfaces, objects


def _object_part(mesh: MeshData, category: str) -> ObjectPart:
    lo, hi = mesh.bounds()
    center = 0.5 * (lo + hi)
    size = np.maximum(hi - lo, MIN_OBJECT_SIZE)
    return ObjectPart(
        category=category,
        mesh=MeshData(mesh.vertices - center, mesh.faces, mesh.face_colors),
        center=(float(center[0]), float(center[1]), float(center[2])),
        yaw=0.0,
        size=(float(size[0]), float(size[1]), float(size[2])),
    )
