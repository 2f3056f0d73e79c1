"""Small test scenes assembled with :func:`navverse.scene.assemble_scene` (bounds and statistics derived).

Test modules describe their geometry (surfaces and object parts) and let the composition API number
the objects and derive the bounds; these helpers only shorten the common pieces: rectangles, coloured
boxes, closed box rooms, and a scene whose terrain classes follow its surfaces.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from navverse.scene.compose import ObjectPart, SceneType, assemble_scene
from navverse.scene.geometry import MeshData, Scene, Surface
from navverse.scene.terrain import terrain_classes

__all__ = ["box_part", "box_room", "quad", "scene_of"]


def quad(x0: float, y0: float, x1: float, y1: float, z: float) -> MeshData:
    """An upward-facing rectangle at height z."""
    vertices = [[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]]
    return MeshData(np.array(vertices), np.array([[0, 1, 2], [0, 2, 3]]))


def box_part(
    category: str,
    center: Sequence[float],
    size: Sequence[float],
    yaw: float = 0.0,
    *,
    rgb: Sequence[int] | None = None,
) -> ObjectPart:
    """A box-shaped object of `size` (in its own frame) at `center`, all of one colour if `rgb` is given."""
    mesh = MeshData.box(tuple(float(v) for v in size))
    if rgb is not None:
        colors = np.tile(np.array([rgb], dtype=np.uint8), (mesh.num_faces, 1))
        mesh = MeshData(mesh.vertices, mesh.faces, colors)
    return ObjectPart(category, mesh, tuple(float(v) for v in center), yaw)


def box_room(
    x: tuple[float, float], y: tuple[float, float], height: float, wall: float = 0.2
) -> tuple[Surface, ...]:
    """A closed room whose inner faces are at ``x``, ``y`` and ``height``: a 0.1 m floor slab with its
    top at z = 0, four walls as boxes of thickness `wall` outside the faces (the east and west walls
    cover the corners) and a 0.1 m ceiling slab on top."""
    (x0, x1), (y0, y1), h, t = x, y, height, wall
    lx, ly, cx, cy = x1 - x0, y1 - y0, (x0 + x1) / 2, (y0 + y1) / 2
    return (
        Surface("floor", "floor", MeshData.box((lx, ly, 0.1), center=(cx, cy, -0.05))),
        Surface("wall_e", "wall", MeshData.box((t, ly + 2 * t, h), center=(x1 + t / 2, cy, h / 2))),
        Surface("wall_w", "wall", MeshData.box((t, ly + 2 * t, h), center=(x0 - t / 2, cy, h / 2))),
        Surface("wall_n", "wall", MeshData.box((lx, t, h), center=(cx, y1 + t / 2, h / 2))),
        Surface("wall_s", "wall", MeshData.box((lx, t, h), center=(cx, y0 - t / 2, h / 2))),
        Surface("ceiling", "ceiling", MeshData.box((lx, ly, 0.1), center=(cx, cy, h + 0.05))),
    )


def scene_of(
    surfaces: Sequence[Surface],
    objects: Sequence[ObjectPart] = (),
    *,
    scene_id: str,
    scene_type: SceneType = "indoor",
    friction: Mapping[str, float] | None = None,
) -> Scene:
    """Assemble a scene whose terrain classes are the standard ones of its surfaces, in the order the
    surfaces first use them (`friction` overrides some), with objects numbered 1, 2, ... in order."""
    classes = list(dict.fromkeys(s.terrain_class for s in surfaces))
    return assemble_scene(
        scene_id=scene_id,
        scene_type=scene_type,
        surfaces=surfaces,
        objects=objects,
        terrain_classes=terrain_classes(classes, overrides=friction),
    )
