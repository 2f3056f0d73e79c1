"""The Gymnasium environment on a built room: API conformance, episodes, terminations, privileged info."""

from __future__ import annotations

import gzip
import json
import math
from pathlib import Path

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from navverse import nav
from navverse.dataset import Episode, EpisodeInfo, Goal
from navverse.env import ACTION_MODES, EnvError, NavVerseEnv
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.scene.directory import SceneFiles, write_scene_dir
from navverse.scene.geometry import Scene
from navverse.sim.actions import DISCRETE_ACTIONS
from navverse.sim.recorder import write_submission
from tests.scenes import box_part, box_room, scene_of

ROOM = (10.0, 8.0, 2.6)
TABLE_CENTER = (7.0, 5.0, 0.375)


def room_scene() -> Scene:
    """A closed 10 m x 8 m room with a ceiling, a table and two chairs (ids 1, 2, 3)."""
    lx, ly, h = ROOM
    objects = [
        box_part("table", TABLE_CENTER, (1.2, 0.8, 0.75)),
        box_part("chair", (3.0, 2.0, 0.45), (0.5, 0.5, 0.9), 0.3),
        box_part("chair", (3.0, 6.0, 0.45), (0.5, 0.5, 0.9), -1.2),
    ]
    return scene_of(box_room((0.0, lx), (0.0, ly), h), objects, scene_id="env_room")


def build_room(root: Path) -> Path:
    """Write the room as a built scene directory (with its navmesh) under ``root``."""
    scene = room_scene()
    write_scene_dir(scene, root, bev=False)
    build_scene_navmesh(scene, nav.INDOOR, jobs=1).save(SceneFiles(root).navmesh)
    return root


def table_episodes(
    count: int,
    *,
    first_y: float,
    step: float,
    end: tuple[float, float],
    info: EpisodeInfo,
) -> list[Episode]:
    """``count`` ObjNav episodes to the room's table, starting at x = 2 m, y = ``first_y + step * i``,
    their reference paths straight to ``end``."""
    goal = Goal(object_id=1, category="table", position=TABLE_CENTER, radius=0.6, size=(1.2, 0.8, 0.75))
    return [
        Episode(
            episode_id=f"env_room-objnav-{i:04d}",
            scene_id="env_room",
            scene_type="indoor",
            task="objnav",
            start_position=(2.0, first_y + step * i, 0.0),
            start_rotation=(0.0, 0.0, 0.0, 1.0),
            object_category="table",
            goals=[goal],
            reference_path=[(2.0, first_y + step * i, 0.0), (*end, 0.0)],
            info=info,
        )
        for i in range(count)
    ]


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_room(tmp_path_factory.mktemp("env_room"))


@pytest.fixture(scope="module")
def env(scene_dir: Path, tmp_path_factory: pytest.TempPathFactory):
    e = NavVerseEnv(scene_dir, privileged=True, collision_cache=tmp_path_factory.mktemp("coacd"))
    yield e
    e.close()


def episode(**overrides) -> dict:
    ep = {
        "episode_id": "room-0",
        "scene_id": "env_room",
        "task": "objnav",
        "start_position": [2.0, 4.0, 0.0],
        "start_rotation": [0.0, 0.0, 0.0, 1.0],  # facing +x
        "object_category": "table",
        "goals": [{"object_id": 1, "category": "table", "position": list(TABLE_CENTER), "radius": 0.6,
                   "size": [1.2, 0.8, 0.75]}],
        "reference_path": [[2.0, 4.0, 0.0], [6.0, 4.0, 0.0]],
    }  # fmt: skip
    ep.update(overrides)
    return ep


@pytest.mark.parametrize("mode", ACTION_MODES)
@pytest.mark.filterwarnings("ignore:.*symmetric and normalized space")  # actions are in meters and radians
def test_gymnasium_env_checker_passes(scene_dir: Path, mode: str, tmp_path: Path):
    env = gymnasium.make(f"NavVerse-{mode.capitalize()}-v0", scene=str(scene_dir), collision_cache=tmp_path)
    try:
        check_env(env.unwrapped, skip_render_check=True)
    finally:
        env.close()


def test_observations_are_the_camera_and_the_pose(env: NavVerseEnv):
    obs, info = env.reset(seed=1, options={"episode": episode()})
    assert env.observation_space.contains(obs)
    assert obs["rgb"].shape == (480, 640, 3) and obs["depth"].shape == (480, 640, 1)
    assert obs["goal"] == "table"
    # Facing +x from x = 2: the east wall's inside face is 8 m ahead of the base, 7.5 m from the camera.
    camera_x = info["camera_to_base"][0, 3]
    centre = float(obs["depth"][240, 320, 0])
    assert centre == pytest.approx(ROOM[0] - 2.0 - camera_x, abs=0.05)
    # The table (instance 1, 5 m ahead and 1 m to the left) is in view, left of the image centre.
    columns = np.nonzero((obs["semantic"] == 1).any(axis=0))[0]
    assert len(columns) and columns.max() < 320
    assert obs["pose"][:2] == pytest.approx([2.0, 4.0], abs=0.01)
    assert info["surface"] == "floor" and info["collisions"] == 0 and info["termination"] is None
    assert info["robot_radius"] == 0.6
    assert info["camera_intrinsics"][0, 0] == pytest.approx(320.0)  # 90 degrees over 640 pixels


def test_privileged_signals_follow_the_robot(env: NavVerseEnv):
    _, info = env.reset(seed=1, options={"episode": episode()})
    assert info["goal_positions"].tolist() == [list(TABLE_CENTER)]
    assert info["reference_path"].shape == (2, 3)
    before = info["distance_to_goal"]
    forward = DISCRETE_ACTIONS.index("forward")
    for _ in range(4):
        _, reward, terminated, truncated, info = env.step(forward)
        assert reward == 0.0 and not terminated and not truncated
    assert info["distance_to_goal"] == pytest.approx(before - 1.0, abs=0.1)


def test_stop_ends_the_episode_with_a_submission_record(env: NavVerseEnv, tmp_path: Path):
    env.reset(seed=2, options={"episode": episode()})
    for name in ("forward", "rotate_left", "forward", "stop"):
        _, _, terminated, truncated, info = env.step(DISCRETE_ACTIONS.index(name))
    assert terminated and not truncated and info["termination"] == "stop"
    record = info["submission"]
    assert record["episode_id"] == "room-0" and record["stop"] is True
    rows = np.array(record["trajectory"])
    assert rows.shape[1] == 8 and rows[0, 0] == 0.0 and np.all(np.diff(rows[:, 0]) > 0)
    assert rows[-1, 0] == pytest.approx(info["time"])
    assert np.linalg.norm(rows[:, 4:], axis=1) == pytest.approx(1.0)
    # 0.25 m forward, a 30 degree turn to the left, 0.25 m forward.
    expected = (2.25 + 0.25 * math.cos(math.radians(30)), 4.0 + 0.25 * math.sin(math.radians(30)))
    assert rows[-1, 1:3] == pytest.approx(expected, abs=0.03)
    path = write_submission([record], tmp_path / "run.jsonl.gz")
    assert json.loads(gzip.decompress(path.read_bytes()))["trajectory"] == record["trajectory"]
    with pytest.raises(EnvError, match="call reset"):
        env.step(0)


def test_waypoints_stream_and_time_runs_out(scene_dir: Path, tmp_path: Path):
    env = NavVerseEnv(scene_dir, action_mode="waypoint", max_time=3.0, collision_cache=tmp_path)
    try:
        env.reset(seed=0, options={"episode": episode()})
        truncated = False
        steps = 0
        while not truncated:
            _, _, terminated, truncated, info = env.step(np.array([6.0, 4.0, 0.0, 0.0], dtype=np.float32))
            assert not terminated
            steps += 1
        assert info["termination"] == "timeout" and info["submission"]["stop"] is False
        assert not {"goal_positions", "distance_to_goal", "reference_path"} & set(info)  # not privileged
        assert steps == pytest.approx(30, abs=1)  # 0.1 s per decision
        # Three seconds towards x = 6 at up to 1.5 m/s (with acceleration and braking): well on the way.
        assert 4.0 < info["submission"]["trajectory"][-1][1] < 6.1
    finally:
        env.close()


def test_driving_into_a_wall_is_a_collision(scene_dir: Path, tmp_path: Path):
    env = NavVerseEnv(scene_dir, action_mode="velocity", collision_cache=tmp_path)
    try:
        env.reset(seed=0, options={"episode": episode(start_position=[8.5, 4.0, 0.0])})
        for _ in range(20):
            _, _, _, _, info = env.step(np.array([1.0, 0.0, 0.0, 0.0], dtype=np.float32))
        assert info["collisions"] > 0
        assert env.sim.collisions[-1].body.terrain_class == "wall"
    finally:
        env.close()


def test_default_episodes_are_seeded(env: NavVerseEnv):
    first = env.reset(seed=5)[0]["pose"]
    again = env.reset(seed=5)[0]["pose"]
    other = env.reset(seed=6)[0]["pose"]
    assert np.array_equal(first, again) and not np.array_equal(first, other)
    assert env.reset(seed=5)[0]["goal"] in {"table", "chair"}


def test_appearance_is_fixed_for_eval_and_drawn_from_the_seed_for_training(env: NavVerseEnv):
    start = {"episode": episode()}
    evaluation = env.reset(seed=1, options=start)[0]["rgb"]
    drawn = env.reset(seed=3, options={**start, "appearance": "random"})[0]["rgb"]
    again = env.reset(seed=3, options={**start, "appearance": "random"})[0]["rgb"]
    other = env.reset(seed=4, options={**start, "appearance": "random"})[0]["rgb"]
    assert np.array_equal(drawn, again) and not np.array_equal(drawn, other)
    assert not np.array_equal(drawn, evaluation)
    dusk = env.reset(seed=1, options={**start, "appearance": {"time_of_day": 18.5}})[0]["rgb"]
    assert not np.array_equal(dusk, evaluation)
    kept = env.reset(seed=2, options=start)[0]["rgb"]  # no appearance option: the last look stays
    assert np.array_equal(kept, dusk)
    assert np.array_equal(env.reset(seed=1, options={**start, "appearance": "eval"})[0]["rgb"], evaluation)
    with pytest.raises(EnvError, match="time_of_day"):
        env.reset(options={**start, "appearance": {"time_of_day": 30}})
    with pytest.raises(EnvError, match='"eval", "random"'):
        env.reset(options={**start, "appearance": "sunny"})


def test_bad_input_says_what_to_change(scene_dir: Path, env: NavVerseEnv, tmp_path: Path):
    with pytest.raises(EnvError, match="not a built scene directory"):
        NavVerseEnv(tmp_path)
    with pytest.raises(EnvError, match="unknown action mode 'joystick'"):
        NavVerseEnv(scene_dir, action_mode="joystick")
    with pytest.raises(EnvError, match="start_position"):
        env.reset(options={"episode": {"episode_id": "x"}})
    env.reset(seed=0, options={"episode": episode()})
    with pytest.raises(EnvError, match="out of range"):
        env.step(11)
    waypoint = NavVerseEnv(scene_dir, action_mode="waypoint", collision_cache=tmp_path)
    try:
        waypoint.reset(seed=0, options={"episode": episode()})
        with pytest.raises(EnvError, match="4 finite numbers"):
            waypoint.step([1.0, math.nan, 0.0, 0.0])
    finally:
        waypoint.close()


def test_sensors_choose_what_is_rendered_and_max_steps_cuts_the_episode(scene_dir: Path, tmp_path: Path):
    env = NavVerseEnv(scene_dir, sensors=("depth",), max_steps=3, collision_cache=tmp_path)
    try:
        obs, _ = env.reset(seed=0, options={"episode": episode()})
        assert set(obs) == {"depth", "pose", "goal", "goal_id"} and env.observation_space.contains(obs)
        labels = []
        for _ in range(3):
            obs, _, terminated, truncated, info = env.step(DISCRETE_ACTIONS.index("rotate_left"))
            labels.append((terminated, truncated, info["termination"], info["steps"]))
        assert labels == [(False, False, None, 1), (False, False, None, 2), (False, True, "max_steps", 3)]
        assert info["submission"]["termination"] == "max_steps" and info["submission"]["stop"] is False
    finally:
        env.close()
    blind = NavVerseEnv(scene_dir, action_mode="waypoint", sensors=(), collision_cache=tmp_path)
    try:
        obs, _ = blind.reset(seed=0, options={"episode": episode()})
        assert set(obs) == {"pose", "goal", "goal_id"}
    finally:
        blind.close()
    with pytest.raises(EnvError, match="unknown sensors"):
        NavVerseEnv(scene_dir, sensors=("lidar",))


def test_terrain_friction_replaces_every_class_friction(scene_dir: Path, tmp_path: Path):
    env = NavVerseEnv(scene_dir, terrain_friction=0.25, collision_cache=tmp_path)
    try:
        frictions = {b.terrain_class: b.friction for b in env.world.bodies.values() if b.kind == "terrain"}
        assert frictions and set(frictions.values()) == {0.25}
    finally:
        env.close()
    with pytest.raises(EnvError, match="terrain_friction"):
        NavVerseEnv(scene_dir, terrain_friction=-1.0)
