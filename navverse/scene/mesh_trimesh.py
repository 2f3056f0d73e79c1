"""Reading OBJ, glTF/GLB and PLY files with trimesh: one :class:`~.mesh_nodes.MeshNode` per mesh
node of the file (trimesh scene nodes; for OBJ files the objects, groups and materials), with the
node's transform applied and a colour on every face: the file's vertex or face colours, else its
material's diffuse colour (or the mean colour of its texture), else a colour derived from the
node's name. The files a mesh names are served by :class:`~.mesh_files.ConfinedResolver`.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from navverse.scene.colors import default_color
from navverse.scene.geometry import MeshData
from navverse.scene.mesh_files import ConfinedResolver, FileCheck, MeshImportError
from navverse.scene.mesh_nodes import MeshNode, ProgressFn, apply_transform, raise_non_finite, uniform_colors

__all__ = ["read_trimesh_nodes"]


def _rgb(values: np.ndarray) -> np.ndarray:
    """uint8 RGB from 0..255 or 0..1 colour arrays (alpha dropped)."""
    array = np.asarray(values)
    if np.issubdtype(array.dtype, np.floating) and array.size and array.max() <= 1.0:
        array = array * 255.0
    return np.clip(np.rint(np.asarray(array, dtype=np.float64)[..., :3]), 0, 255).astype(np.uint8)


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
    return uniform_colors(color if color is not None else default_color(name), count)


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
        raise_non_finite(path, bad)


def _node_path(parents: dict[str, str], node: str, base: str) -> str:
    chain = [node]
    while parents.get(chain[-1]) not in (None, base) and len(chain) < 1000:
        chain.append(parents[chain[-1]])
    return "/" + "/".join(reversed(chain))


def read_trimesh_nodes(
    path: Path, *, progress: ProgressFn | None = None, check: FileCheck | None = None
) -> list[MeshNode]:
    """Read every mesh node of an ``.obj``, ``.glb``, ``.gltf`` or ``.ply`` file with trimesh.

    Parameters
    ----------
    path : Path
        The file, already checked as a regular file within the size cap. OBJ files are split by
        material, and by object and group where they name more than one.
    progress : callable, optional
        Called as ``progress(done, total, description)`` while nodes are converted.
    check : callable, optional
        ``check(resolved_path, name_as_written) -> str | None`` for every file the mesh names
        (material libraries, textures, buffers, images; in the mesh's folder or below).

    Returns
    -------
    list of MeshNode
        Transforms applied, in the file's units and axes, sorted by node path; point clouds,
        curves and empty meshes left out.

    Raises
    ------
    MeshImportError
        If trimesh cannot parse the file, a file it names is refused, or vertices are not finite.
    """
    import trimesh

    suffix = path.suffix.lower()
    options = _obj_split_options(path) if suffix == ".obj" else {}
    resolver = ConfinedResolver(path, check=check)
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
        vertices, faces = apply_transform(
            np.asarray(geometry.vertices, dtype=np.float64),
            np.asarray(geometry.faces, dtype=np.int64),
            matrix,
        )
        mesh = MeshData(vertices, faces, colors)
        nodes.append(MeshNode(str(node), _node_path(parents, node, base), mesh))
        if progress is not None:
            progress(index + 1, len(names), "mesh nodes")
    return nodes
