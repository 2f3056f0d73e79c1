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
import trimesh

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


def _decompose(part: trimesh.Trimesh, cache_dir: Path | None) -> list[np.ndarray]:
    key = _digest(part.vertices, part.faces)
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
            coacd.Mesh(np.asarray(part.vertices, dtype=np.float64), np.asarray(part.faces, dtype=np.int64)),
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


def convex_parts(mesh: MeshData, *, cache_dir: Path | None = None) -> ConvexParts:
    """Convex pieces covering a closed mesh (each connected part: its hull, or CoACD's pieces).

    Parameters
    ----------
    mesh : MeshData
        An object's mesh (closed parts).
    cache_dir : Path, optional
        Where decompositions are kept between runs (``<digest>.npz``); memory only when None.

    Returns
    -------
    ConvexParts
        Vertex arrays of convex pieces.
    """
    whole = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    parts = ConvexParts()
    for part in whole.split(only_watertight=False):
        if len(part.vertices) < 4:
            continue
        # A flat part (or its hull) has no volume: trimesh's centre of mass divides by zero, harmlessly.
        with np.errstate(invalid="ignore", divide="ignore"):
            try:
                hull = part.convex_hull
            except Exception:  # degenerate: nothing solid to collide with
                continue
            volume = abs(float(part.volume)) if part.is_watertight else 0.0
            hull_volume = float(hull.volume)
        small = float(np.ptp(part.vertices, axis=0).max()) < _MIN_EXTENT
        if small or volume < _MIN_VOLUME or hull_volume <= _CONCAVE * volume:
            parts.append(np.asarray(hull.vertices, dtype=np.float64))
        else:
            parts.extend(_decompose(part, cache_dir))
    return parts


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
        lines.append(f"o hull{k}")
        lines.extend(f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in v)
        lines.extend(f"f {a} {b} {c}" for a, b, c in faces)
        offset += len(v)
    directory.mkdir(parents=True, exist_ok=True)
    with atomic_write(path, mode="w") as handle:
        handle.write("\n".join(lines) + "\n")
    return path
