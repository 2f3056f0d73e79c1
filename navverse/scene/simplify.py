"""Mesh cleanup and quadric decimation that keep per-face colours.

:func:`clean_mesh` merges duplicate and near vertices, drops degenerate and repeated triangles and
unused vertices (no change of shape). :func:`decimate_mesh` cleans, then simplifies each colour
group of a mesh with quadric edge collapses (Open3D, or fast-simplification) to a fraction of its
faces, so colours stay exactly where they were; :func:`decimate_scene` does that for every mesh of
a scene. All are deterministic: the same mesh gives the same arrays.

>>> mesh = MeshData.box((1.0, 1.0, 1.0))
>>> decimate_mesh(mesh, 0.5, min_faces=100, method="open3d").num_faces  # too small: only cleaned
12
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_validator
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from navverse.errors import NavverseError
from navverse.scene.compose import object_parts, replace_parts
from navverse.scene.geometry import MeshData, Scene, Surface
from navverse.settings import Settings

__all__ = [
    "MIN_TRIANGLE_AREA",
    "DecimateSettings",
    "SimplifyError",
    "SimplifyReport",
    "budget_ratio",
    "clean_mesh",
    "decimate_mesh",
    "decimate_scene",
    "merge_vertices",
    "triangle_areas",
]

MIN_TRIANGLE_AREA = 1e-12
"""Triangles with a smaller area (m^2) are degenerate and dropped by :func:`clean_mesh`."""


def triangle_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area of every triangle.

    Parameters
    ----------
    vertices : ndarray, shape (N, 3)
        Vertex positions.
    faces : ndarray, shape (M, 3)
        Vertex indices per triangle.

    Returns
    -------
    ndarray, shape (M,)
        Areas in squared units of `vertices`.
    """
    if len(faces) == 0:
        return np.zeros(0)
    corners = vertices[faces]
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    return 0.5 * np.linalg.norm(cross, axis=1)


def merge_vertices(vertices: np.ndarray, *, tolerance: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Merge equal vertices, and vertices closer than `tolerance`.

    Parameters
    ----------
    vertices : ndarray, shape (N, 3)
        Vertex positions.
    tolerance : float
        Vertices within this distance of each other become one (chains merge transitively); 0 merges
        only exact duplicates. A merged vertex keeps the position of its lowest-index member.

    Returns
    -------
    merged : ndarray, shape (K, 3)
        The kept vertices, in order of first appearance.
    index : ndarray of int64, shape (N,)
        Index into `merged` of every input vertex.
    """
    vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    if len(vertices) == 0:
        return vertices.copy(), np.zeros(0, dtype=np.int64)
    _, first, inverse = np.unique(vertices, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    # Relabel the unique rows in order of first appearance, so the result follows the input order.
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    unique_points = vertices[first[order]]
    label = rank[inverse]
    if tolerance > 0.0 and len(unique_points) > 1:
        pairs = cKDTree(unique_points).query_pairs(r=tolerance, output_type="ndarray")
        if len(pairs):
            n = len(unique_points)
            graph = coo_matrix((np.ones(len(pairs), dtype=np.int8), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
            _, component = connected_components(graph, directed=False)
            # Representative of each component: its lowest index (unique_points are in input order).
            lowest = np.full(component.max() + 1, n, dtype=np.int64)
            np.minimum.at(lowest, component, np.arange(n))
            keep = np.unique(lowest)
            new_index = np.empty(n, dtype=np.int64)
            new_index[keep] = np.arange(len(keep))
            label = new_index[lowest[component]][label]
            unique_points = unique_points[keep]
    return unique_points, label.astype(np.int64)


def _canonical_rotation(faces: np.ndarray) -> np.ndarray:
    """Each triangle rotated so its smallest index comes first (winding kept)."""
    shift = np.argmin(faces, axis=1)
    rows = np.arange(len(faces))[:, None]
    return faces[rows, (shift[:, None] + np.arange(3)) % 3]


def clean_mesh(mesh: MeshData, *, tolerance: float = 0.0) -> MeshData:
    """Merge duplicate and near vertices, drop degenerate and repeated triangles and unused vertices.

    Parameters
    ----------
    mesh : MeshData
        Any triangle mesh.
    tolerance : float
        Vertex merge distance (see :func:`merge_vertices`).

    Returns
    -------
    MeshData
        The same surface: triangles whose corners merged into fewer than three vertices, triangles of
        (nearly) zero area and second copies of a triangle with the same corners and winding are gone
        (a triangle and its reverse both stay: two-sided sheets are kept). Colours follow their faces.
    """
    if mesh.num_faces == 0:
        return mesh
    vertices, index = merge_vertices(mesh.vertices, tolerance=tolerance)
    faces = index[mesh.faces]
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    keep &= triangle_areas(vertices, faces) > MIN_TRIANGLE_AREA
    kept = np.flatnonzero(keep)
    _, first = np.unique(_canonical_rotation(faces[kept]), axis=0, return_index=True)
    kept = kept[np.sort(first)]
    faces = faces[kept]
    colors = mesh.face_colors[kept] if mesh.face_colors is not None else None
    used = np.unique(faces)
    remap = np.full(len(vertices), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return MeshData(vertices[used], remap[faces].reshape(-1, 3), colors)


def _simplify_open3d(vertices: np.ndarray, faces: np.ndarray, target: int) -> tuple[np.ndarray, np.ndarray]:
    import open3d as o3d

    mesh = o3d.geometry.TriangleMesh(
        o3d.utility.Vector3dVector(vertices), o3d.utility.Vector3iVector(faces.astype(np.int32))
    )
    # Boundary quadrics (weight 1) let open borders such as floor outlines slide along themselves
    # but not shrink.
    out = mesh.simplify_quadric_decimation(target_number_of_triangles=int(target), boundary_weight=1.0)
    return np.asarray(out.vertices, dtype=np.float64), np.asarray(out.triangles, dtype=np.int64)


def _simplify_fast(vertices: np.ndarray, faces: np.ndarray, target: int) -> tuple[np.ndarray, np.ndarray]:
    import fast_simplification

    # Its quadrics have no border terms, so border vertices are pinned instead (outlines stay exact).
    points, triangles = fast_simplification.simplify(
        vertices, faces.astype(np.int64), target_count=int(target), preserve_border=True
    )
    return np.asarray(points, dtype=np.float64), np.asarray(triangles, dtype=np.int64).reshape(-1, 3)


Method = Literal["open3d", "fast"]
_METHODS: dict[str, Callable[[np.ndarray, np.ndarray, int], tuple[np.ndarray, np.ndarray]]] = {
    "open3d": _simplify_open3d,
    "fast": _simplify_fast,
}


def _submesh(mesh: MeshData, face_ids: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    faces = mesh.faces[face_ids]
    used, local = np.unique(faces, return_inverse=True)
    return mesh.vertices[used], local.reshape(-1, 3).astype(np.int64)


def decimate_mesh(
    mesh: MeshData,
    ratio: float,
    *,
    min_faces: int,
    method: Method,
    tolerance: float = 0.0,
) -> MeshData:
    """Clean a mesh, then simplify it to about ``ratio`` of its faces, colour group by colour group.

    Parameters
    ----------
    mesh : MeshData
        Any triangle mesh, with or without face colours.
    ratio : float
        Fraction of the (cleaned) faces to keep, in (0, 1]; 1 only cleans.
    min_faces : int
        Colour groups (and meshes) with fewer faces are left as they are
        (:attr:`DecimateSettings.min_faces`).
    method : {"open3d", "fast"}
        The simplification (:attr:`DecimateSettings.method`).
    tolerance : float
        Vertex merge distance of the cleanup (see :func:`clean_mesh`).

    Returns
    -------
    MeshData
        The simplified mesh; faces of each colour keep that colour.

    Raises
    ------
    ValueError
        If `ratio` is not in (0, 1] (a programming error: stages validate their params).
    """
    if not 0.0 < ratio <= 1.0:
        raise ValueError(f"ratio must be in (0, 1], got {ratio}")
    cleaned = clean_mesh(mesh, tolerance=tolerance)
    if ratio >= 1.0 or cleaned.num_faces < max(min_faces, 4):
        return cleaned
    if cleaned.face_colors is None:
        groups = np.zeros(cleaned.num_faces, dtype=np.int64)
        palette = None
    else:
        palette, groups = np.unique(cleaned.face_colors, axis=0, return_inverse=True)
        groups = groups.reshape(-1)
    parts: list[MeshData] = []
    for group in range(int(groups.max()) + 1):
        face_ids = np.flatnonzero(groups == group)
        vertices, faces = _submesh(cleaned, face_ids)
        if len(face_ids) < max(min_faces, 4):
            part = MeshData(vertices, faces)
        else:
            target = max(1, round(ratio * len(face_ids)))
            part = clean_mesh(MeshData(*_METHODS[method](vertices, faces, target)))
        if palette is not None:
            colors = np.broadcast_to(palette[group], (part.num_faces, 3))
            part = MeshData(part.vertices, part.faces, colors)
        parts.append(part)
    return clean_mesh(MeshData.concatenate(parts))


# ------------------------------------------------------------------------------------------- scenes


class SimplifyError(NavverseError):
    """A decimation budget that cannot be met."""


class DecimateSettings(Settings):
    """How a scene's meshes are cleaned and simplified (:func:`decimate_scene`).

    Give ``ratio`` (the fraction of faces to keep in every mesh) or ``target_faces`` (a budget for
    the whole scene, shared in proportion to the meshes' faces), or neither: then the meshes are
    only cleaned (vertices within ``merge_tolerance`` meters merged, degenerate and repeated
    triangles dropped), which is cheap for light procedural scenes. Meshes (and colour groups of a
    mesh) under ``min_faces`` faces are never simplified; each colour group is simplified alone, so
    colours stay where they were.
    """

    ratio: (
        Annotated[float, Field(gt=0.0, le=1.0, description="Fraction kept, more than 0, at most 1.")] | None
    ) = None
    """Fraction of faces to keep in every mesh; None: ``target_faces``, or only cleaning."""
    target_faces: Annotated[int, Field(ge=1, le=100_000_000, description="Faces, 1 to 1e8.")] | None = None
    """Total faces wanted, turned into one ratio for all meshes (:func:`budget_ratio`); None:
    ``ratio``, or only cleaning."""
    min_faces: Annotated[int, Field(ge=4, le=10_000_000, description="Faces, 4 to 1e7.")] = 64
    """Meshes and colour groups with fewer faces are left as they are."""
    merge_tolerance: Annotated[float, Field(ge=0.0, le=0.1, description="Meters, 0 to 0.1.")] = 1e-4
    """Vertex merge distance of the cleanup (m, see :func:`clean_mesh`)."""
    method: Method = "open3d"
    """``open3d``: Open3D's quadric decimation with boundary quadrics (open outlines such as floor
    edges are simplified along themselves, not shrunk: floor outlines keep their place). ``fast``:
    fast-simplification with border vertices pinned (about twice as fast, fewer faces removed on
    meshes with long open borders)."""

    @model_validator(mode="after")
    def _one_budget(self) -> DecimateSettings:
        if self.ratio is not None and self.target_faces is not None:
            raise ValueError("give either 'ratio' or 'target_faces', not both")
        return self


@dataclass(frozen=True)
class SimplifyReport:
    """Counts of a scene decimation: faces and vertices before, after cleanup and after, and the
    fraction of faces kept in meshes large enough to simplify."""

    faces_before: int
    faces_cleaned: int
    faces_after: int
    vertices_before: int
    vertices_after: int
    ratio: float


def _group_sizes(mesh: MeshData) -> np.ndarray:
    """Face count of every colour group of a mesh (one group without colours)."""
    if mesh.face_colors is None:
        return np.array([mesh.num_faces])
    return np.unique(mesh.face_colors, axis=0, return_counts=True)[1]


def budget_ratio(meshes: Sequence[MeshData], target_faces: int, *, min_faces: int) -> float:
    """The fraction of faces to keep in every large enough colour group so the meshes total about
    `target_faces` faces (groups under `min_faces` are kept whole).

    Raises
    ------
    SimplifyError
        If the groups too small to simplify alone exceed the budget.
    """
    sizes = np.concatenate([_group_sizes(m) for m in meshes]) if meshes else np.zeros(0, dtype=np.int64)
    fixed = int(sizes[sizes < max(min_faces, 4)].sum())
    free = int(sizes.sum()) - fixed
    if target_faces >= fixed + free:
        return 1.0
    if target_faces <= fixed:
        raise SimplifyError(
            f"target_faces {target_faces} cannot be met: {fixed} faces are in meshes (or colour groups) "
            f"under min_faces ({min_faces}), which are not simplified; raise target_faces or lower min_faces"
        )
    return (target_faces - fixed) / free


def decimate_scene(
    scene: Scene,
    *,
    settings: DecimateSettings | None = None,
    progress: Callable[[int, int, str], None] | None = None,
) -> tuple[Scene, SimplifyReport]:
    """Clean and decimate every surface and object mesh of a scene.

    Parameters
    ----------
    scene : Scene
        The scene; objects are simplified in their own frames and keep their annotations.
    settings : DecimateSettings, optional
        The budget (a ratio, a face count or none: only cleaning), the smallest meshes simplified,
        the merge tolerance and the method.
    progress : callable, optional
        Called as ``progress(done, total, description)`` per mesh.

    Returns
    -------
    Scene
        Same annotations but for ``statistics.faces`` and the bounds, derived again.
    SimplifyReport
        Face and vertex counts.

    Raises
    ------
    SimplifyError
        If `target_faces` cannot be met.
    """
    settings = settings or DecimateSettings()
    meshes = [s.mesh for s in scene.surfaces] + [o.mesh for o in scene.objects]
    cleaned = [clean_mesh(m, tolerance=settings.merge_tolerance) for m in meshes]
    ratio = settings.ratio
    if settings.target_faces is not None:
        ratio = budget_ratio(cleaned, settings.target_faces, min_faces=settings.min_faces)
    keep = 1.0 if ratio is None else float(ratio)
    simplified = []
    for index, mesh in enumerate(cleaned):
        simplified.append(
            decimate_mesh(mesh, keep, min_faces=settings.min_faces, method=settings.method)
            if keep < 1
            else mesh
        )
        if progress is not None:
            progress(index + 1, len(cleaned), "decimate")
    surfaces = [
        Surface(s.name, s.terrain_class, m)
        for s, m in zip(scene.surfaces, simplified[: len(scene.surfaces)], strict=True)
    ]
    objects = [
        replace(part, mesh=m)
        for part, m in zip(object_parts(scene), simplified[len(scene.surfaces) :], strict=True)
    ]
    faces_after = sum(m.num_faces for m in simplified)
    report = SimplifyReport(
        faces_before=sum(m.num_faces for m in meshes),
        faces_cleaned=sum(m.num_faces for m in cleaned),
        faces_after=faces_after,
        vertices_before=sum(m.num_vertices for m in meshes),
        vertices_after=sum(m.num_vertices for m in simplified),
        ratio=keep,
    )
    return replace_parts(scene, surfaces=surfaces, objects=objects), report
