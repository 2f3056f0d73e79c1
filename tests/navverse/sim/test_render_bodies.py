"""Moving bodies in the camera: placed each frame, with their colours, depth and semantic ids."""

from __future__ import annotations

import numpy as np
import pytest

from navverse.scene.geometry import MeshData
from navverse.sim.camera import look_at
from navverse.sim.render import BACKGROUND_ID, SceneRenderer
from tests.navverse.sim.test_render import EYE, FLAT, SMALL, WALL_X, build_scene

PERSON_ID = 50_000_001
BLUE = (20, 60, 220)


def _pillar() -> MeshData:
    """A blue 0.6 m square pillar, 1.8 m tall, standing on its origin."""
    box = MeshData.box((0.6, 0.6, 1.8), center=(0.0, 0.0, 0.9))
    return MeshData(box.vertices, box.faces, np.tile(np.array([BLUE], np.uint8), (box.num_faces, 1)))


def _at(x: float, y: float, yaw: float = 0.0) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0, x], [s, c, 0, y], [0, 0, 1, 0], [0, 0, 0, 1]], dtype=float)


@pytest.mark.parametrize("lit", [False, True], ids=["flat", "lit"])
def test_a_body_shows_where_it_is_placed_and_goes_when_moved(lit: bool) -> None:
    renderer = SceneRenderer(build_scene(), intrinsics=SMALL, **({} if lit else {"shading": FLAT}))
    pose = look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0)))
    before = renderer.render(pose)
    shape = renderer.add_body_shape(_pillar(), max_bodies=4)
    renderer.place_bodies([shape], [_at(2.0, -0.8, 0.3)], [PERSON_ID])
    frame = renderer.render(pose)
    mine = frame.semantic == PERSON_ID
    assert 100 < mine.sum() < 0.3 * mine.size
    assert (frame.terrain[mine] == -1).all()
    assert (np.abs(frame.depth[mine] - 2.0) < 0.45).all()  # 2 m ahead, within its half diagonal
    if not lit:
        assert (frame.rgb[mine] == BLUE).all()
    else:
        assert (frame.rgb[mine][:, 2] > frame.rgb[mine][:, 0]).mean() > 0.95  # blue, lit
    # Elsewhere the frame is the same as without it.
    assert (frame.depth[~mine] == before.depth[~mine]).mean() > 0.98
    renderer.place_bodies([shape], [_at(2.0, 0.0)], [PERSON_ID])  # moved into the middle
    moved = renderer.render(pose)
    assert (moved.semantic == PERSON_ID)[:, SMALL.width // 2].any()
    renderer.place_bodies([], np.zeros((0, 4, 4)), [])
    assert (renderer.render(pose).depth == before.depth).all()


def test_two_bodies_keep_their_own_ids_and_a_body_hides_what_is_behind() -> None:
    renderer = SceneRenderer(build_scene(), intrinsics=SMALL, shading=FLAT)
    pose = look_at(EYE, np.add(EYE, (1.0, 0.0, 0.0)))
    shape = renderer.add_body_shape(_pillar(), max_bodies=2)
    renderer.place_bodies([shape, shape], [_at(1.5, -0.6), _at(3.0, 0.9)], [PERSON_ID, PERSON_ID + 1])
    frame = renderer.render(pose)
    assert (frame.semantic == PERSON_ID).any() and (frame.semantic == PERSON_ID + 1).any()
    assert not (frame.depth[frame.semantic == PERSON_ID + 1] > WALL_X).any()
    assert BACKGROUND_ID in frame.semantic


def test_bodies_beyond_the_room_made_for_them_are_refused() -> None:
    renderer = SceneRenderer(build_scene(), intrinsics=SMALL, shading=FLAT)
    shape = renderer.add_body_shape(_pillar(), max_bodies=1)
    with pytest.raises(ValueError, match="room for 1"):
        renderer.place_bodies([shape, shape], [_at(1.0, 0.0), _at(2.0, 0.0)], [1, 2])
    with pytest.raises(ValueError, match="unknown body shape"):
        renderer.place_bodies([shape + 1], [_at(1.0, 0.0)], [1])
