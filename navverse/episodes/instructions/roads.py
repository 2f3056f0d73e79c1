"""Which stretches of a route follow a road: the street as a landmark of outdoor instructions.

A segment of the reference path follows a road when most of it is on the walkway beside one: the
terrain under its sample points is a sidewalk (or curb, crosswalk ramp) and, looking sideways from
them, road surface lies within :data:`ROAD_REACH` meters on one side. Terrain classes are read from
the scene's surfaces by vertical ray casts, so this works on any scene with ``road`` and ``sidewalk``
classes (indoor scenes have none: nothing follows a road there).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from navverse.episodes.instructions.directives import Directive
from navverse.scene.geometry import Scene

__all__ = ["ROAD_REACH", "RoadFollowing"]

ROAD_REACH = 8.0
"""How far sideways (m) the road may be from a walkway that follows it."""
_WALKWAY = frozenset({"sidewalk", "curb", "lowered_curb"})
_ROAD = frozenset({"road"})
_SHARE = 0.7  # of a segment's samples that must be on a walkway beside a road
_STEP = 1.0  # sample spacing along a segment (m)
_MIN_LENGTH = 6.0  # shorter segments are not told as following anything


class RoadFollowing:
    """Answers, for the directives of a route in one scene, which segments follow a road.

    Parameters
    ----------
    scene : Scene
        The scene; its terrain surfaces are ray cast (objects are not).
    """

    def __init__(self, scene: Scene) -> None:
        import open3d as o3d

        labeled = scene.world_mesh(include_objects=False)
        self._o3d = o3d
        self._names = labeled.class_names
        self._class = labeled.class_index.astype(np.int64)
        mesh = labeled.mesh
        self._rays = o3d.t.geometry.RaycastingScene()
        self._useful = bool(set(self._names) & _ROAD) and bool(set(self._names) & _WALKWAY)
        self._origin = mesh.vertices.min(axis=0) if mesh.num_vertices else np.zeros(3)
        self._top = float(mesh.vertices[:, 2].max() - self._origin[2]) + 10.0 if mesh.num_vertices else 10.0
        if self._useful:
            self._rays.add_triangles(
                o3d.core.Tensor((mesh.vertices - self._origin).astype(np.float32)),
                o3d.core.Tensor(mesh.faces.astype(np.uint32)),
            )

    def classes(self, xy: np.ndarray) -> np.ndarray:
        """Terrain class name under each xy point (``""`` where nothing is under it)."""
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        rays = np.zeros((len(xy), 6), dtype=np.float32)
        rays[:, :2], rays[:, 2], rays[:, 5] = xy - self._origin[:2], self._top, -1.0
        ids = self._rays.cast_rays(self._o3d.core.Tensor(rays))["primitive_ids"].numpy().astype(np.int64)
        names = np.array([*self._names, ""], dtype=object)
        hit = ids < len(self._class)
        index = np.full(len(xy), len(self._names), dtype=np.int64)
        index[hit] = self._class[ids[hit]]
        index[index < 0] = len(self._names)  # object faces (not cast, but kept safe)
        return names[index]

    def along_road(self, directives: Sequence[Directive]) -> list[bool]:
        """For each directive, whether the segment walked after it follows a road."""
        found = []
        for k, d in enumerate(directives):
            if not self._useful or d.length < _MIN_LENGTH or k + 1 >= len(directives):
                found.append(False)
                continue
            a = np.asarray(d.position[:2], dtype=np.float64)
            b = np.asarray(directives[k + 1].position[:2], dtype=np.float64)
            found.append(self._follows(a, b))
        return found

    def _follows(self, a: np.ndarray, b: np.ndarray) -> bool:
        length = float(np.hypot(*(b - a)))
        if length < _MIN_LENGTH:
            return False
        along = (b - a) / length
        side = np.array([-along[1], along[0]])
        points = a + np.outer(np.arange(0.5, length, _STEP), along)
        on_walkway = np.isin(self.classes(points), list(_WALKWAY))
        reach = np.arange(1.0, ROAD_REACH + 1e-9, 1.0)
        beside = np.zeros(len(points), dtype=bool)
        for sign in (1.0, -1.0):
            probes = points[:, None, :] + sign * reach[None, :, None] * side
            road = np.isin(self.classes(probes.reshape(-1, 2)), list(_ROAD)).reshape(len(points), len(reach))
            beside |= road.any(axis=1)
        return bool((on_walkway & beside).mean() >= _SHARE)
