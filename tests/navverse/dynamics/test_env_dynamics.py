"""The environment with people: out of sight at the start, the same crowd for the same episode, drawn
by the camera with their own ids, off by default."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from navverse import nav
from navverse.dynamics.pedestrians import PedestrianSettings
from navverse.dynamics.runtime import PERSON_ID_BASE
from navverse.dynamics.scene_dynamics import DynamicsSettings
from navverse.env import EnvError, NavVerseEnv
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.scene.directory import SceneFiles, write_scene_dir
from navverse.scene.geometry import MeshData, Surface
from tests.scenes import box_room, scene_of

PEOPLE = DynamicsSettings(mode="pedestrians", people=PedestrianSettings(density=80.0, areas=("floor",),
                                                                        trip_length=(2.0, 10.0)))  # fmt: skip
EPISODE = {"episode_id": "split-room-0", "start_position": [2.0, 2.0, 0.0], "start_rotation": [0, 0, 0, 1],
           "task": "objnav", "object_category": "chair", "goals": []}  # fmt: skip


@pytest.fixture(scope="module")
def split_room(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A 16 m x 8 m room cut by a wall at x = 6 from y = 0 to 6 (a 2 m gap at the north end)."""
    partition = Surface("wall_mid", "wall", MeshData.box((0.2, 6.0, 2.6), center=(6.0, 3.0, 1.3)))
    scene = scene_of((*box_room((0.0, 16.0), (0.0, 8.0), 2.6), partition), scene_id="split_room")
    root = tmp_path_factory.mktemp("split_room")
    write_scene_dir(scene, root, bev=False)
    build_scene_navmesh(scene, nav.INDOOR, jobs=1).save(SceneFiles(root).navmesh)
    return root


def _env(root: Path, dynamics) -> NavVerseEnv:
    return NavVerseEnv(root, dynamics=dynamics, collision_cache=None, sensors=("rgb", "depth", "semantic"))


def test_people_start_out_of_sight_and_walk_into_view(split_room: Path) -> None:
    env = _env(split_room, PEOPLE)
    obs, info = env.reset(options={"episode": EPISODE})
    people = env._dynamics.bodies.state.people
    assert info["dynamics"] == "pedestrians" and len(people) >= 3
    assert (people[:, 0] > 6.0).all()  # behind the wall, as seen from (2, 2)
    assert not (obs["semantic"] >= PERSON_ID_BASE).any()
    seen = 0
    for _ in range(80):  # turning on the spot: people come through the gap into view
        obs, *_ = env.step(5)  # rotate left
        seen += int((obs["semantic"] >= PERSON_ID_BASE).any())
    assert seen > 0
    env.close()


def test_an_episode_run_twice_meets_the_same_people(split_room: Path) -> None:
    tracks = []
    for _ in range(2):
        env = _env(split_room, PEOPLE)
        env.reset(options={"episode": EPISODE})
        for _ in range(10):
            env.step(1)
        tracks.append(env._dynamics.bodies.state.people.tobytes())
        env.close()
    assert tracks[0] == tracks[1]


def test_dynamics_are_off_unless_asked(split_room: Path) -> None:
    env = _env(split_room, "off")
    _, info = env.reset(options={"episode": EPISODE})
    assert info["dynamics"] == "off" and env._dynamics is None
    env.close()
    with pytest.raises(EnvError, match="unknown dynamics 'crowd'"):
        NavVerseEnv(split_room, dynamics="crowd", collision_cache=None)


def test_a_new_episode_replaces_the_last_ones_people(split_room: Path) -> None:
    env = _env(split_room, PEOPLE)
    env.reset(options={"episode": EPISODE})
    first = list(env._dynamics.bodies.people)
    env.reset(options={"episode": {**EPISODE, "episode_id": "split-room-1"}})
    bodies = env.world.bodies
    assert not any(b in bodies for b in first if b not in env._dynamics.bodies.people)
    assert np.isfinite(env._dynamics.bodies.state.people).all()
    env.close()
