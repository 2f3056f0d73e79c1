"""Reading user meshes (OBJ, glTF/GLB, PLY, USD) into named, coloured nodes, and turning nodes into
scene surfaces and objects.

:func:`read_mesh_nodes` gives one :class:`MeshNode` per mesh node of the file (trimesh scene nodes;
for OBJ files the objects, groups and materials; for USD files the ``UsdGeom.Mesh`` prims) with the
node's transform applied, in the file's own units and axes, and a colour on every face: the file's
vertex or face colours, else its material's diffuse colour (or the mean colour of its texture),
else a colour derived from the node's name. :func:`to_z_up` converts a node to meters and the
project's z-up frame; :func:`scene_parts` makes :class:`Surface` and :class:`ObjectPart` values from
nodes and the roles a recipe gives them.

Hostile files are refused, never waited on: the file and every file it brings in (OBJ material
libraries and textures, glTF buffers and images, USD sublayers, references, payloads and value
clips, see :func:`usd_layer_files`) must be a regular file (``os.stat`` before any open: no named
pipes, devices or directories) of at most :data:`MAX_MESH_BYTES`; non-finite vertex coordinates
are an error (trimesh would drop them silently), and :func:`check_extent` refuses coordinates
beyond :data:`MAX_COORDINATE_M` once in meters.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from navverse.errors import NavverseError
from navverse.files import regular_file_problem
from navverse.scene.colors import default_color
from navverse.scene.compose import ObjectPart
from navverse.scene.geometry import MeshData, Surface
from navverse.scene.naming import sanitize_identifier, unique_name
from navverse.scene.simplify import clean_mesh

__all__ = [
    "MAX_COORDINATE_M",
    "MAX_MESH_BYTES",
    "MESH_SUFFIXES",
    "MIN_OBJECT_SIZE",
    "UNIT_SCALES",
    "USD_SUFFIXES",
    "FileCheck",
    "FileFrame",
    "MeshImportError",
    "MeshNode",
    "NodeRole",
    "UsdDependencyError",
    "check_extent",
    "file_problem",
    "read_mesh_nodes",
    "scene_parts",
    "split_components",
    "subdivide",
    "to_z_up",
    "usd_layer_files",
]

TRIMESH_SUFFIXES = (".obj", ".glb", ".gltf", ".ply")
USD_SUFFIXES = (".usd", ".usda", ".usdc")
MESH_SUFFIXES = TRIMESH_SUFFIXES + USD_SUFFIXES
"""File suffixes :func:`read_mesh_nodes` reads."""

UNIT_SCALES = {"meters": 1.0, "centimeters": 0.01, "millimeters": 0.001, "inches": 0.0254, "feet": 0.3048}
"""Meters per unit, by unit name."""

MIN_OBJECT_SIZE = 1e-3
"""Smallest annotated object extent (m); flat objects get this thickness in their annotation."""

MAX_MESH_BYTES = 2 * 1024**3
"""Largest mesh file, and largest file it brings in (2 GiB): files are parsed whole, in memory."""

MAX_COORDINATE_M = 1e6
"""Largest vertex coordinate, in meters after unit scaling (1000 km: larger means wrong units)."""

ProgressFn = Callable[[int, int, str], None]

FileCheck = Callable[[Path, str], str | None]
"""``check(resolved_path, written)``: why a file a mesh brings in may not be read (None: it may)."""


class MeshImportError(NavverseError):
    """A mesh file cannot be read or holds nothing to import."""


class UsdDependencyError(MeshImportError):
    """A file a USD file brings in (sublayer, reference, payload, value clip) may not be read."""


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


# -------------------------------------------------------------------------------------------- files


def file_problem(path: Path, *, max_bytes: int = MAX_MESH_BYTES) -> str | None:
    """Why ``path`` cannot be read as a mesh file (None: it can), found with ``os.stat``, never opening it."""
    problem = regular_file_problem(path, max_bytes=max_bytes, what="mesh file")
    if problem is not None and "limit" in problem:
        problem += "; decimate or split it first (e.g. in Blender)"
    return problem


class _ConfinedResolver:
    """Serves the files a mesh names (OBJ material libraries and textures, glTF buffers and images)
    from the mesh's folder and below, each a regular file within the size cap and passing ``check``.

    trimesh swallows a resolver's errors (a material is then just missing), so the refusals are
    also kept in :attr:`refused`, for the reader to report after loading.
    """

    def __init__(self, source: Path, *, check: FileCheck | None, base: Path | None = None) -> None:
        self.root = source.parent.resolve()
        self.base = base or self.root
        self.file_name = source.name  # trimesh names an OBJ's unnamed mesh after it
        self.source = source
        self.check = check
        self.refused: list[str] = []

    def _candidates(self, name: str) -> Iterator[Path]:
        stripped = name.strip()
        for candidate in (stripped, stripped.lstrip("/"), os.path.basename(stripped)):
            path = (self.base / candidate).resolve()
            if candidate and path.is_relative_to(self.root) and os.path.lexists(path):
                yield path

    def get(self, name: str) -> bytes:
        """The bytes of the file ``name`` (relative to the mesh's folder)."""
        path = next(self._candidates(name), None)
        if path is None:
            raise FileNotFoundError(f"{name!r} is not a file in {self.root}")
        problem = file_problem(path)
        if problem is None and self.check is not None:
            problem = self.check(path, name)
        if problem is not None:
            self.refused.append(f"{name!r}: {problem}")
            raise OSError(problem)
        return path.read_bytes()

    def __getitem__(self, name: str) -> bytes:
        return self.get(name)

    def write(self, name: str, data: object) -> None:
        """Never used: reading writes nothing."""
        raise OSError(f"cannot write {name!r}: mesh import reads only")

    def namespaced(self, namespace: str) -> _ConfinedResolver:
        """The same confinement, with names relative to the subfolder ``namespace``."""
        resolver = _ConfinedResolver(self.source, check=self.check, base=(self.base / namespace).resolve())
        resolver.refused = self.refused
        return resolver

    def keys(self) -> Iterator[str]:
        """No listing (trimesh asks only for archives)."""
        return iter(())


# ------------------------------------------------------------------------------------------ trimesh


def _obj_split_options(path: Path) -> dict[str, bool]:
    """Split an OBJ file by objects / groups only where it names more than one (read line by line)."""
    objects: set[str] = set()
    groups: set[str] = set()
    pattern = re.compile(r"^([og])[ \t]+(.*?)\s*$")
    with path.open(encoding="utf-8", errors="replace") as lines:
        for line in lines:
            if line[:1] in ("o", "g"):
                match = pattern.match(line)
                if match is not None:
                    (objects if match[1] == "o" else groups).add(match[2])
    return {"split_objects": len(objects) > 1, "split_groups": len(groups) > 1}


_PROCESSED_BY_TRIMESH = (".obj", ".ply")
"""Formats whose meshes trimesh processes when loading (NaN vertices dropped, vertices merged): they
are loaded unprocessed, checked, then processed the same way."""


def _check_finite(path: Path, geometries: dict[str, object]) -> None:
    """Refuse a file whose meshes have non-finite vertex coordinates (before trimesh drops them)."""
    bad = {
        name: int((~np.isfinite(np.asarray(g.vertices, dtype=np.float64)).all(axis=1)).sum())  # type: ignore[attr-defined]
        for name, g in geometries.items()
        if hasattr(g, "vertices")
    }
    bad = {name: count for name, count in bad.items() if count}
    if bad:
        _raise_non_finite(path, bad)


def _raise_non_finite(path: Path, bad: dict[str, int]) -> None:
    total = sum(bad.values())
    where = ", ".join(f"{name!r}: {count}" for name, count in sorted(bad.items())[:5])
    more = f" and {len(bad) - 5} more meshes" if len(bad) > 5 else ""
    count = f"{total} vertex has" if total == 1 else f"{total} vertices have"
    raise MeshImportError(
        f"{path}: {count} non-finite coordinates (NaN or infinity) ({where}{more}); fix or re-export the file"
    )


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


def _read_trimesh(path: Path, progress: ProgressFn | None, check: FileCheck | None) -> list[MeshNode]:
    import trimesh

    suffix = path.suffix.lower()
    options = _obj_split_options(path) if suffix == ".obj" else {}
    resolver = _ConfinedResolver(path, check=check)
    try:
        scene = trimesh.load(str(path), force="scene", resolver=resolver, process=False, **options)
    except Exception as exc:  # any parser failure is the file's fault
        raise MeshImportError(
            f"cannot read {path} as a {path.suffix} mesh ({type(exc).__name__}: {exc}); "
            "check the file (export it again, or convert it to .glb or .obj)"
        ) from None
    if resolver.refused:
        raise MeshImportError(
            f"{path} names files that cannot be read: {'; '.join(resolver.refused)}; "
            "fix the references (material libraries, textures, buffers) or the files"
        )
    _check_finite(path, scene.geometry)
    if suffix in _PROCESSED_BY_TRIMESH:
        for geometry in scene.geometry.values():
            if isinstance(geometry, trimesh.Trimesh):
                geometry.process()
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


def _open_layer(identifier: str) -> object:
    from pxr import Sdf, Tf

    try:
        layer = Sdf.Layer.FindOrOpen(identifier)
    except Tf.ErrorException as exc:
        message = " ".join(str(exc).split())
        raise MeshImportError(
            f"cannot read {identifier} as USD ({message}); check the file in usdview"
        ) from None
    if layer is None:
        raise MeshImportError(f"cannot read {identifier} as USD; check the file in usdview")
    return layer


def _layer_assets(layer: object) -> Iterator[tuple[str, str]]:
    """``(kind, asset path as written)`` of every file a layer names, without composing anything."""
    from pxr import UsdUtils

    sublayers, references, payloads = UsdUtils.ExtractExternalReferences(layer.identifier)  # type: ignore[attr-defined]
    for kind, assets in (("sublayer", sublayers), ("reference", references), ("payload", payloads)):
        for asset in assets:
            yield kind, str(asset)


def usd_layer_files(path: Path, *, check: FileCheck | None = None) -> list[Path]:
    """Every file a USD file brings in when opened, found layer by layer without composing a stage.

    Sublayers, references, payloads and value clips (and any asset path naming a USD layer) are
    followed recursively; each must be a regular file within :data:`MAX_MESH_BYTES` and pass
    ``check`` before it is opened. Asset paths of other files (textures) are not followed: the
    import never opens them. An asset path that resolves to nothing is skipped, as USD skips it.

    Parameters
    ----------
    path : Path
        A ``.usd``, ``.usda`` or ``.usdc`` file.
    check : callable, optional
        ``check(resolved_path, asset_path) -> str | None``: why a file may not be read (e.g.
        outside the allowed folders); None lets it be read.

    Returns
    -------
    list of Path
        The resolved files, ``path`` first, each once (the package file for a layer inside a
        ``.usdz``).

    Raises
    ------
    UsdDependencyError
        If a file brought in is not a regular file, is too big, or ``check`` refuses it; the
        message names the layer that names it and the asset path as written.
    MeshImportError
        If a layer cannot be parsed.
    """
    from pxr import Ar, Sdf

    root = Path(path).resolve()
    problem = file_problem(root)
    if problem is not None:
        raise MeshImportError(f"cannot read {path}: {problem}")
    resolver = Ar.GetResolver()
    files, queue, layers = [root], [str(root)], []
    seen = {str(root)}
    while queue:
        layer = _open_layer(queue.pop(0))
        layers.append(layer)  # keep each layer open until the walk is done (no re-reading)
        for kind, asset in _layer_assets(layer):
            identifier = resolver.CreateIdentifier(asset, layer.resolvedPath)  # type: ignore[attr-defined]
            if kind == "reference" and not Sdf.FileFormat.FindByExtension(
                Sdf.FileFormat.GetFileExtension(identifier)
            ):
                continue  # a texture or another non-layer asset: never opened
            resolved = str(resolver.Resolve(identifier))
            if not resolved or resolved in seen:
                continue
            seen.add(resolved)
            outer = (
                Ar.SplitPackageRelativePathOuter(resolved)[0]
                if Ar.IsPackageRelativePath(resolved)
                else resolved
            )
            file = Path(outer).resolve()
            problem = file_problem(file) or (check(file, asset) if check is not None else None)
            if problem is not None:
                raise UsdDependencyError(
                    f"{layer.realPath or layer.identifier}: {kind} @{asset}@ cannot be read: {problem}"  # type: ignore[attr-defined]
                )
            if file not in files:
                files.append(file)
            queue.append(resolved)
    return files


def _read_usd(
    path: Path, progress: ProgressFn | None, check: FileCheck | None
) -> tuple[list[MeshNode], FileFrame]:
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
        _raise_non_finite(path, {str(prim.GetPath()): non_finite})  # type: ignore[attr-defined]
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
        is over :data:`MAX_MESH_BYTES` or is refused by ``check``; the file cannot be parsed, holds
        no triangles, or has vertices with non-finite coordinates.
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
        nodes, frame = _read_usd(path, progress, check)
    else:
        nodes = _read_trimesh(path, progress, check)
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
