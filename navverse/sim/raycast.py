"""Ray casting against a triangle mesh for the robot camera: Embree's 8-wide ray packets.

The camera casts 307,200 primary rays per 640 x 480 frame and up to as many shadow rays, each group
coherent (neighbouring pixels' rays leave one eye, or neighbouring surface points, in nearly one
direction). :class:`TriangleCaster` hands them to Embree eight at a time (``rtcIntersect8`` /
``rtcOccluded8``, the C++ extension ``navverse.sim._raycast`` over the system Embree 3), so the
acceleration structure is traversed once per packet instead of once per ray: on a populated square
kilometre of city about 3x the rays per second of a per-ray cast (``bench/look.py``). A ray's packet is
fixed by its index, so results do not depend on the thread count.

Rays are ``(..., 6)`` float32 arrays: origin then direction (not necessarily unit length); a ray's hit
parameter ``t`` is in units of its direction's length, as in Open3D's ``RaycastingScene``.

Besides its static mesh, a caster can show moving bodies (people, cars): shapes added once
(:meth:`TriangleCaster.add_shape`) and instances of them placed anew each frame
(:meth:`TriangleCaster.set_instances`). Each shape keeps its own acceleration structure; a frame only
rebuilds the small one over the instances, never the static mesh's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from navverse.extensions import missing_extension

try:
    from navverse.sim import _raycast
except ImportError as exc:  # pragma: no cover - depends on the installation
    raise missing_extension("navverse.sim._raycast", library="Embree", package="libembree-dev") from exc

__all__ = ["NO_FACE", "RayHits", "TriangleCaster"]

NO_FACE = np.uint32(0xFFFFFFFF)
"""The face index of a ray that hits nothing."""


@dataclass(frozen=True)
class RayHits:
    """The first hit of each ray of a cast, shaped as the rays without their last axis.

    Attributes
    ----------
    t_hit : ndarray of float32
        Ray parameter of the hit (``inf``: none).
    face : ndarray of uint32
        Index of the triangle hit (:data:`NO_FACE`: none).
    barycentric : ndarray of float32, shape (..., 2)
        ``(u, v)`` of the hit in its triangle: hit = ``(1-u-v) p0 + u p1 + v p2`` (0 where none).
    instance : ndarray of int32
        The instance hit (:meth:`TriangleCaster.set_instances` order; ``face`` is then a face of its
        shape), -1 for the static mesh or no hit.
    """

    t_hit: np.ndarray
    face: np.ndarray
    barycentric: np.ndarray
    instance: np.ndarray


class TriangleCaster:
    """A triangle mesh prepared for casting rays (an Embree scene built at high quality).

    Parameters
    ----------
    vertices : array_like, shape (N, 3)
        Vertex positions (cast to float32; keep them near the origin for precision).
    faces : array_like of int, shape (M, 3)
        Vertex indices of each triangle; ``M`` may be 0 (every ray misses).
    threads : int, keyword-only
        Threads per cast; 0 uses every core.

    Raises
    ------
    ValueError
        If the arrays are not ``(N, 3)`` and ``(M, 3)`` or a face names a vertex that does not exist.
    """

    def __init__(self, vertices: ArrayLike, faces: ArrayLike, *, threads: int = 0) -> None:
        points = np.ascontiguousarray(vertices, dtype=np.float32)
        triangles = np.asarray(faces)
        if triangles.size and triangles.min() < 0:
            raise ValueError("faces name negative vertex indices")
        self._threads = int(threads)
        self._caster = _raycast.TriangleCaster(points, np.ascontiguousarray(triangles, dtype=np.uint32))

    @property
    def num_faces(self) -> int:
        """How many triangles the static mesh has."""
        return int(self._caster.num_faces)

    @property
    def num_instances(self) -> int:
        """How many instances the last :meth:`set_instances` placed."""
        return int(self._caster.num_instances)

    def add_shape(self, vertices: ArrayLike, faces: ArrayLike) -> int:
        """Add a mesh that instances can show, in its own frame; returns its index.

        Raises
        ------
        ValueError
            If the arrays are not ``(N, 3)`` and ``(M, 3)`` or a face names a vertex that does not exist.
        """
        triangles = np.asarray(faces)
        if triangles.size and triangles.min() < 0:
            raise ValueError("faces name negative vertex indices")
        points = np.ascontiguousarray(vertices, dtype=np.float32)
        return int(self._caster.add_shape(points, np.ascontiguousarray(triangles, dtype=np.uint32)))

    def set_instances(self, shapes: ArrayLike, transforms: ArrayLike) -> None:
        """Show these instances from now on (replacing the last ones): shape ``shapes[i]`` placed by the
        rigid transform ``transforms[i]`` (4 x 4, shape frame to the caster's frame).

        Raises
        ------
        ValueError
            If a shape index is unknown or the transforms are not one 4 x 4 per shape.
        """
        ids = np.ascontiguousarray(shapes, dtype=np.int32).reshape(-1)
        matrices = np.ascontiguousarray(transforms, dtype=np.float32).reshape(-1)
        self._caster.set_instances(ids, matrices)

    def cast(self, rays: np.ndarray) -> RayHits:
        """The first hit of every ray.

        Parameters
        ----------
        rays : ndarray of float32, shape (..., 6)
            Origins and directions; neighbouring rays (in C order) should be coherent for speed.

        Returns
        -------
        RayHits
            Arrays shaped ``rays.shape[:-1]``.
        """
        rays = _ray_array(rays)
        shape = rays.shape[:-1]
        t_hit = np.empty(shape, dtype=np.float32)
        face = np.empty(shape, dtype=np.uint32)
        barycentric = np.empty((*shape, 2), dtype=np.float32)
        instance = np.empty(shape, dtype=np.int32)
        self._caster.cast(rays, t_hit, face, barycentric, instance, self._threads)
        return RayHits(t_hit, face, barycentric, instance)

    def occluded(self, rays: np.ndarray, *, tfar: float = np.inf) -> np.ndarray:
        """Whether each ray meets a triangle (of the mesh or an instance) at a parameter in ``[0, tfar]``.

        Parameters
        ----------
        rays : ndarray of float32, shape (..., 6)
            Origins and directions.
        tfar : float, keyword-only
            The farthest parameter that counts (``inf``: any).

        Returns
        -------
        ndarray of bool, shape ``rays.shape[:-1]``
        """
        rays = _ray_array(rays)
        blocked = np.empty(rays.shape[:-1], dtype=np.uint8)
        self._caster.occluded(rays, float(tfar), blocked, self._threads)
        return blocked.view(bool)


def _ray_array(rays: np.ndarray) -> np.ndarray:
    """`rays` as a C-contiguous float32 ``(..., 6)`` array, or a ValueError."""
    array = np.ascontiguousarray(rays, dtype=np.float32)
    if array.ndim < 1 or array.shape[-1] != 6:
        raise ValueError(f"rays must be an array of shape (..., 6), got {array.shape}")
    return array
