"""Heights of a scene's surfaces under ground points, by vertical ray casts."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from navverse.scene.geometry import Scene

__all__ = ["SurfaceHeights"]


class SurfaceHeights:
    """The height of the highest surface of a scene (its objects left out) under xy points.

    Rays are cast in a frame at the scene's lower corner, so float32 keeps millimetres far from the
    world origin.

    Parameters
    ----------
    scene : Scene
        The scene; its terrain surfaces and buildings are hit, its objects are not.
    """

    def __init__(self, scene: Scene) -> None:
        import open3d as o3d

        mesh = scene.world_mesh(include_objects=False).mesh
        self._o3d = o3d
        self._rays = o3d.t.geometry.RaycastingScene()
        if mesh.num_faces == 0:
            self._origin, self._top = np.zeros(2), 0.0
            return
        self._origin = mesh.vertices[:, :2].min(axis=0)
        self._top = float(mesh.vertices[:, 2].max()) + 10.0
        local = mesh.vertices - np.array([*self._origin, 0.0])
        self._rays.add_triangles(
            o3d.core.Tensor(local.astype(np.float32)), o3d.core.Tensor(mesh.faces.astype(np.uint32))
        )

    def __call__(self, xy: ArrayLike) -> np.ndarray:
        """Heights under each point, shape (N,); NaN where nothing is under it."""
        xy = np.atleast_2d(np.asarray(xy, dtype=np.float64)).reshape(-1, 2)
        rays = np.zeros((len(xy), 6), dtype=np.float32)
        rays[:, :2], rays[:, 2], rays[:, 5] = xy - self._origin, self._top, -1.0
        hit = self._rays.cast_rays(self._o3d.core.Tensor(rays))["t_hit"].numpy().astype(np.float64)
        return np.where(np.isfinite(hit), self._top - hit, np.nan)
