"""Convex collision parts of object meshes: convex pieces as hulls, concave ones decomposed with CoACD.

Objects of the library are unions of closed parts (legs, seats, shells); most parts are convex and
keep their own convex hull. A part whose hull is clearly larger than the part (a bathtub shell, a
basin, a shelf carcass) is decomposed with CoACD. Decompositions are cached by the part's bytes, in
memory and optionally on disk, so every identical part is decomposed once.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from navverse.cache import cache_root
from navverse.files import atomic_path, atomic_write
from navverse.scene.geometry import MeshData

__all__ = ["ConvexParts", "convex_parts", "default_cache_dir", "hulls_file"]

_CONCAVE = 1.5  # hull volume / part volume above which a part is decomposed
_MIN_EXTENT = 0.25  # m: smaller parts keep their hull (a lamp shade, leaves): a robot never feels the gap
_MIN_VOLUME = 1e-7  # m^3: parts thinner than this keep their hull (sheets, wires)
_MEMORY: dict[str, list[np.ndarray]] = {}


class ConvexParts(list):
    """Vertex arrays (K_i, 3) of convex pieces, in the mesh's frame."""


def _digest(vertices: np.ndarray, faces: np.ndarray) -> str:
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(vertices, dtype=np.float64).tobytes())
    h.update(np.ascontiguousarray(faces, dtype=np.int64).tobytes())
    return h.hexdigest()[:32]


def _decompose(vertices: np.ndarray, faces: np.ndarray, cache_dir: Path | None) -> list[np.ndarray]:
    """CoACD's convex pieces of one concave closed part, cached by the part's bytes."""
    key = _digest(vertices, faces)
    if key in _MEMORY:
        return _MEMORY[key]
    cached = cache_dir / f"{key}.npz" if cache_dir is not None else None
    if cached is not None and cached.is_file():
        with np.load(cached) as data:
            hulls = [data[name] for name in sorted(data.files, key=lambda n: int(n.split("_")[1]))]
    else:
        import coacd

        coacd.set_log_level("error")
        result = coacd.run_coacd(
            coacd.Mesh(np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int64)),
            threshold=0.08,
            max_convex_hull=12,
            preprocess_mode="off",  # library parts are closed manifolds already
            resolution=1000,
            mcts_iterations=30,
            mcts_nodes=10,
            mcts_max_depth=2,
            seed=0,
        )
        hulls = [np.asarray(v, dtype=np.float64) for v, _ in result]
        if cached is not None:
            cached.parent.mkdir(parents=True, exist_ok=True)
            with atomic_path(cached) as tmp:
                np.savez(tmp, **{f"hull_{i}": v for i, v in enumerate(hulls)})
    _MEMORY[key] = hulls
    return hulls


def default_cache_dir() -> Path:
    """Where decompositions are cached: ``$NAVVERSE_CACHE_DIR/coacd`` (default ``~/.cache/navverse``)."""
    return cache_root() / "coacd"


def _face_components(faces: np.ndarray, vertex_count: int) -> tuple[int, np.ndarray, np.ndarray]:
    """Connected parts of a mesh: faces joined by an edge that exactly two faces share.

    Returns
    -------
    count : int
        Number of parts, numbered in the order of their first face.
    label : ndarray of int, shape (F,)
        Each face's part.
    edge_key : ndarray of int64, shape (3F,)
        Each face edge ``(a, b)``, ``a < b``, as ``a * V + b``: face ``f``'s edges are rows
        ``3f .. 3f + 2``.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    edges = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1).astype(np.int64)
    edge_key = edges[:, 0] * vertex_count + edges[:, 1]
    order = np.argsort(edge_key, kind="stable")
    sorted_key = edge_key[order]
    starts = np.flatnonzero(np.r_[True, sorted_key[1:] != sorted_key[:-1]])
    lengths = np.diff(np.r_[starts, len(sorted_key)])
    shared = starts[lengths == 2]  # an edge of exactly two faces joins them
    a, b = order[shared] // 3, order[shared + 1] // 3
    count = len(faces)
    graph = coo_matrix((np.ones(len(a), dtype=np.int8), (a, b)), shape=(count, count))
    parts, label = connected_components(graph, directed=False)
    return int(parts), label, edge_key


def _closed_parts(label: np.ndarray, edge_key: np.ndarray, parts: int) -> np.ndarray:
    """Which parts are closed: each of their edges is shared by exactly two of their faces."""
    edge_part = np.repeat(label, 3).astype(np.int64)
    key = np.stack([edge_part, edge_key], axis=1)
    _, index, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    closed = np.ones(parts, dtype=bool)
    closed[edge_part[index[counts != 2]]] = False
    return closed


def _signed_volume(corners: np.ndarray) -> np.ndarray:
    """Six times the signed volume of each tetrahedron (origin, a, b, c) of ``corners`` (N, 3, 3)."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    return (
        a[:, 0] * (b[:, 1] * c[:, 2] - b[:, 2] * c[:, 1])
        + a[:, 1] * (b[:, 2] * c[:, 0] - b[:, 0] * c[:, 2])
        + a[:, 2] * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    )


def _hull(points: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The convex hull's vertices (in the points' order) and its triangles; None when degenerate."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        try:
            hull = ConvexHull(points, qhull_options="QbB Pp Qt")
        except QhullError:  # nearly flat or repeated points: joggle them
            hull = ConvexHull(points, qhull_options="QJ")
    except (QhullError, ValueError):
        return None
    return points[np.sort(hull.vertices)], hull.simplices


def _hull_volume(points: np.ndarray, triangles: np.ndarray) -> float:
    """Volume of a convex hull: its triangles' tetrahedra about its centroid (Qhull's own volume is of
    the points scaled to a unit box)."""
    corners = points[triangles] - points[np.unique(triangles)].mean(axis=0)
    return float(np.abs(_signed_volume(corners)).sum() / 6.0)


def convex_parts(mesh: MeshData, *, cache_dir: Path | None = None) -> ConvexParts:
    """Convex pieces covering a closed mesh (each connected part: its hull, or CoACD's pieces).

    A part is a set of faces joined by edges that exactly two faces share. A part keeps its convex
    hull when it is small (under 0.25 m), thin or open (no volume), or nearly convex (its hull at most
    1.5 times its volume); otherwise it is decomposed with CoACD.

    Parameters
    ----------
    mesh : MeshData
        An object's mesh (closed parts).
    cache_dir : Path, optional
        Where decompositions are kept between runs (``<digest>.npz``); memory only when None.

    Returns
    -------
    ConvexParts
        Vertex arrays of convex pieces, part by part in the order of their first face.
    """
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(mesh.faces, dtype=np.int64).reshape(-1, 3)
    result = ConvexParts()
    if len(faces) == 0:
        return result
    parts, label, edge_key = _face_components(faces, len(vertices))
    closed = _closed_parts(label, edge_key, parts)
    volumes = np.abs(np.bincount(label, weights=_signed_volume(vertices[faces]) / 6.0, minlength=parts))
    order = np.argsort(label)  # a part's faces in the order its cached decomposition was keyed by
    bounds = np.r_[0, np.cumsum(np.bincount(label, minlength=parts))]
    for part in range(parts):
        part_faces = faces[order[bounds[part] : bounds[part + 1]]]
        used = np.unique(part_faces)
        if len(used) < 4:
            continue
        points = vertices[used]
        hull = _hull(points)
        if hull is None:  # nothing solid to collide with
            continue
        hull_points, triangles = hull
        volume = volumes[part] if closed[part] else 0.0
        small = float(np.ptp(points, axis=0).max()) < _MIN_EXTENT
        if small or volume < _MIN_VOLUME or _hull_volume(points, triangles) <= _CONCAVE * volume:
            result.append(hull_points)
        else:
            remap = np.zeros(len(vertices), dtype=np.int64)
            remap[used] = np.arange(len(used))
            result.extend(_decompose(points, remap[part_faces], cache_dir))
    return result


def hulls_file(hulls: list[np.ndarray], directory: Path) -> Path:
    """A Wavefront OBJ with one object per convex hull of ``hulls``, in ``directory``, named by content.

    PyBullet loads such a file as one compound collision shape of convex hulls, one per object of the
    file, without the 16-shape limit of ``createCollisionShapeArray``. Files are written once
    (atomically) and reused.
    """
    from scipy.spatial import ConvexHull, QhullError

    points = [np.ascontiguousarray(v, dtype=np.float64) for v in hulls]
    digest = hashlib.sha256()
    for v in points:
        digest.update(np.int64(len(v)).tobytes())
        digest.update(v.tobytes())
    path = directory / f"hulls-{digest.hexdigest()[:32]}.obj"
    if path.is_file():
        return path
    lines: list[str] = []
    offset = 1
    for k, v in enumerate(points):
        try:
            faces = ConvexHull(v).simplices + offset
        except QhullError:  # nearly flat or repeated points (a thin pole): joggle them by ~1e-11
            faces = ConvexHull(v, qhull_options="QJ").simplices + offset
        lines.append(f"o hull{k}\n")
        lines.append(("v %.9g %.9g %.9g\n" * len(v)) % tuple(v.ravel().tolist()))
        lines.append(("f %d %d %d\n" * len(faces)) % tuple(faces.ravel().tolist()))
        offset += len(v)
    directory.mkdir(parents=True, exist_ok=True)
    with atomic_write(path, mode="w") as handle:
        handle.write("".join(lines))
    return path
