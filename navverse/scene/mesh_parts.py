"""Scene parts from mesh nodes: :func:`scene_parts` makes :class:`~navverse.scene.geometry.Surface`
and :class:`~navverse.scene.compose.ObjectPart` values from z-up, metric nodes and the roles
(:class:`NodeRole`) a recipe gives them, split into connected components (:func:`split_components`)
and subdivided (:func:`subdivide`) on request."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from navverse.scene.compose import ObjectPart
from navverse.scene.geometry import MeshData, Surface
from navverse.scene.mesh_nodes import MeshNode, ProgressFn
from navverse.scene.naming import sanitize_identifier, unique_name
from navverse.scene.simplify import clean_mesh

__all__ = ["MIN_OBJECT_SIZE", "NodeRole", "scene_parts", "split_components", "subdivide"]

MIN_OBJECT_SIZE = 1e-3
"""Smallest annotated object extent (m); flat objects get this thickness in their annotation."""


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
