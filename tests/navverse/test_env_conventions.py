"""Conventions habitat-lab users expect of the environment: a habitat reward, an integer goal, action names
and aliases, blocked discrete actions that end early, and collision events rather than contact steps."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import gymnasium
import numpy as np
import pytest

from navverse.assets.facade.storefronts import PLACE_CATEGORIES
from navverse.assets.library import categories
from navverse.env import REWARD_SLACK, REWARD_SUCCESS, EnvError, NavVerseEnv, episode_goal_id
from navverse.scene.geometry import MeshData, Surface
from navverse.sim import actions
from navverse.sim.actions import DISCRETE_ACTIONS, DISCRETE_TIMEOUT, ActionRunner, action_index
from navverse.sim.controller import wrap_angle
from navverse.sim.embodiments import make_embodiment
from navverse.sim.simulator import Simulator
from navverse.sim.world import World
from tests.navverse.test_env import build_room, episode
from tests.navverse.test_env_instruction_type import placenav
from tests.scenes import scene_of

STEP = 0.25  # the room is an indoor scene
TABLE_IDS = {"chair": 4, "table": 17}


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_room(tmp_path_factory.mktemp("env_room_conv"))


@pytest.fixture(scope="module")
def cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("coacd_conv")


@pytest.fixture(scope="module")
def env(scene_dir: Path, cache: Path) -> Iterator[NavVerseEnv]:
    e = NavVerseEnv(
        scene_dir,
        sensors=(),
        privileged=True,
        reward="habitat",
        category_ids=TABLE_IDS,
        collision_cache=cache,
    )
    yield e
    e.close()


def _yaw(obs: dict) -> float:
    x, y, z, w = obs["pose"][3:]
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


# ---------------------------------------------------------------------------------------------- reward


def test_the_habitat_reward_sums_to_progress_slack_and_success(env: NavVerseEnv):
    _, info = env.reset(seed=0, options={"episode": episode()})
    d0 = previous = info["distance_to_goal"]
    rewards = []
    for _ in range(15):  # 3.75 m towards the table, to x = 5.75: 1.6 m from its centre, 1.0 m from its edge
        _, reward, terminated, _, info = env.step("move_forward")
        rewards.append(reward)
        assert not terminated and "success" not in info
        # Every step: the drop of the geodesic distance (at most a step), less 0.01.
        assert reward == pytest.approx(previous - info["distance_to_goal"] + REWARD_SLACK, abs=1e-9)
        assert -0.05 < reward < STEP + REWARD_SLACK + 0.02
        previous = info["distance_to_goal"]
    _, reward, terminated, _, info = env.step("stop")
    rewards.append(reward)
    assert terminated and info["success"] is True
    d_end = info["distance_to_goal"]
    assert d0 - d_end > 2.0  # the geodesic path to the table bends: less than 3.75 m of progress
    assert sum(rewards) == pytest.approx(d0 - d_end + REWARD_SLACK * 16 + REWARD_SUCCESS, abs=1e-6)
    assert reward == pytest.approx(REWARD_SLACK + REWARD_SUCCESS, abs=1e-3)  # stop: one still tick


def test_a_stop_far_from_the_goal_earns_no_bonus_and_an_unreachable_goal_no_progress(env: NavVerseEnv):
    _, info = env.reset(seed=0, options={"episode": episode()})
    d0 = info["distance_to_goal"]
    rewards = [env.step(name)[1] for name in ("forward", "forward")]
    _, reward, terminated, _, info = env.step("stop")
    assert terminated and info["success"] is False
    assert sum(rewards) + reward == pytest.approx(d0 - info["distance_to_goal"] + 3 * REWARD_SLACK, abs=1e-6)
    # A goal off the navmesh: the geodesic distance is inf, every step earns the slack alone.
    far = {"object_id": 9, "category": "table", "position": [50.0, 50.0, 0.0], "radius": 0.5}
    _, info = env.reset(seed=0, options={"episode": episode(goals=[far])})
    assert info["distance_to_goal"] == math.inf
    rewards = [env.step(name)[1] for name in ("forward", "turn_left", "stop")]
    assert rewards == [pytest.approx(REWARD_SLACK, abs=1e-12)] * 3


def test_the_reward_is_zero_by_default_and_made_with_gymnasium_kwargs(scene_dir: Path, cache: Path):
    plain = NavVerseEnv(scene_dir, sensors=(), collision_cache=cache)
    made = gymnasium.make(
        "NavVerse-Discrete-v0",
        scene=str(scene_dir),
        sensors=(),
        collision_cache=cache,
        reward="habitat",
        reward_slack=-0.5,
        reward_success=10.0,
    )
    try:
        plain.reset(seed=0, options={"episode": episode()})
        assert [plain.step("forward")[1] for _ in range(2)] == [0.0, 0.0]
        made.reset(seed=0, options={"episode": episode()})
        _, reward, *_ = made.step("turn_left")  # a turn in place: no progress, the slack alone
        assert reward == pytest.approx(-0.5, abs=0.02)
        assert made.unwrapped.reward_kind == "habitat" and made.unwrapped.reward_success == 10.0
    finally:
        plain.close()
        made.close()
    with pytest.raises(EnvError, match="unknown reward 'sparse'; choose from: none, habitat"):
        NavVerseEnv(scene_dir, reward="sparse", collision_cache=cache)


# ---------------------------------------------------------------------------------------------- goal id


def test_goal_id_is_the_datasets_id_or_the_library_index(scene_dir: Path, cache: Path, env: NavVerseEnv):
    obs, _ = env.reset(seed=0, options={"episode": episode()})
    assert obs["goal_id"].dtype == np.int64 and obs["goal_id"].shape == () and int(obs["goal_id"]) == 17
    assert env.observation_space.contains(obs)
    obs, _ = env.reset(seed=0, options={"episode": episode(), "category_ids": {"table": 3}})
    assert int(obs["goal_id"]) == 3  # the reset's map wins for that episode
    obs, _ = env.reset(seed=0, options={"episode": episode(object_category="sofa")})
    assert int(obs["goal_id"]) == -1  # a category the map lacks
    with pytest.raises(EnvError, match=r"integers in -1\.\.1000000"):
        env.reset(seed=0, options={"episode": episode(), "category_ids": {"table": 10**7}})
    # Without a map: the library's sorted object categories, then the place categories.
    bare = NavVerseEnv(scene_dir, sensors=(), collision_cache=cache)
    try:
        obs, _ = bare.reset(seed=0, options={"episode": episode(object_category="chair")})
        assert int(obs["goal_id"]) == categories().index("chair")
        obs, _ = bare.reset(seed=0, options={"episode": placenav()})
        assert int(obs["goal_id"]) == len(categories()) + PLACE_CATEGORIES.index("bank")
        obs, _ = bare.reset(seed=0, options={"episode": episode()})
        assert int(obs["goal_id"]) == -1  # "table" is not a library category
    finally:
        bare.close()


def test_goal_id_is_minus_one_when_the_agent_is_not_told_the_category():
    vln = episode(task="vln", instruction={"instruction_text": "Go to the table.", "template_text": "",
                                           "instruction_type": "refined"})  # fmt: skip
    assert episode_goal_id(vln, category_ids=TABLE_IDS) == -1
    assert episode_goal_id(placenav(), category_ids={"bank": 5}, instruction_type="route") == -1
    assert episode_goal_id(placenav(), category_ids={"bank": 5}, instruction_type="category") == 5
    assert episode_goal_id(episode(object_category=None), category_ids=TABLE_IDS) == -1


# ---------------------------------------------------------------------------------------------- names


def test_action_indices_are_unchanged_and_names_and_aliases_are_accepted(env: NavVerseEnv):
    names = ("stop", "forward", "left", "right", "rotate_left", "rotate_right", "small_rotate_left",
             "small_rotate_right")  # fmt: skip
    assert names == DISCRETE_ACTIONS and env.action_names == names
    assert [env.action_index(a) for a in ("move_forward", "strafe_left", "strafe_right", "turn_left",
                                          "turn_right", "stop")] == [1, 2, 3, 4, 5, 0]  # fmt: skip
    assert action_index("small_rotate_right") == 7
    with pytest.raises(
        EnvError, match=r"unknown discrete action 'look_up'; choose from: stop, forward.*turn_left"
    ):
        env.action_index("look_up")
    env.reset(seed=0, options={"episode": episode()})
    with pytest.raises(EnvError, match="unknown discrete action 'jump'"):
        env.step("jump")


def test_turns_by_name_rotate_and_left_is_a_sidestep(env: NavVerseEnv):
    obs, _ = env.reset(seed=0, options={"episode": episode()})  # facing +x at (2, 4)
    yaw0 = _yaw(obs)
    obs, *_ = env.step("turn_left")
    assert math.degrees(wrap_angle(_yaw(obs) - yaw0)) == pytest.approx(30.0, abs=1.0)
    obs, *_ = env.step("turn_right")
    assert math.degrees(wrap_angle(_yaw(obs) - yaw0)) == pytest.approx(0.0, abs=1.0)
    before = obs["pose"][:2].copy()
    obs, *_ = env.step("left")  # a sidestep: +y, heading kept
    assert obs["pose"][:2] - before == pytest.approx([0.0, STEP], abs=0.03)
    assert math.degrees(wrap_angle(_yaw(obs) - yaw0)) == pytest.approx(0.0, abs=2.0)


# ---------------------------------------------------------------------------------------------- blocked


def test_a_forward_into_a_wall_is_blocked_and_ends_early(env: NavVerseEnv):
    # Spot's front is 0.55 m ahead of its base: at x = 9.3 it is 0.15 m from the east wall (x = 10).
    _, info = env.reset(seed=0, options={"episode": episode(start_position=[9.3, 4.0, 0.0])})
    assert info["blocked"] is False and info["blocked_actions"] == 0
    for k in range(3):
        start = info["time"]
        obs, _, _, _, info = env.step("forward")
        assert info["blocked"] is True and info["blocked_actions"] == k + 1
        assert info["time"] - start < 2.5 < DISCRETE_TIMEOUT
    assert obs["pose"][0] < 9.3 + STEP - 0.05  # did not reach its target
    # In open space the same action is not blocked and moves a step.
    _, info = env.reset(seed=0, options={"episode": episode()})
    obs, _, _, _, info = env.step("forward")
    assert info["blocked"] is False and info["blocked_actions"] == 0
    assert obs["pose"][:2] == pytest.approx([2.0 + STEP, 4.0], abs=0.02)


@pytest.mark.parametrize("embodiment", ["spot", "turtlebot"])
def test_the_blocked_rule_leaves_unblocked_primitives_unchanged(embodiment: str, monkeypatch):
    """The same primitives with the rule and without it (an endless window) give the same bytes."""
    sequence = [a for a in DISCRETE_ACTIONS if a != "stop"] * 2

    def poses() -> bytes:
        floor = Surface("floor", "floor", MeshData.box((40, 40, 1), center=(0, 0, -0.5)))
        with World(scene_of([floor], scene_id="flat"), collision_cache=None) as world:
            sim = Simulator(world, make_embodiment(embodiment))
            sim.spawn((0.0, 0.0, 0.0), 0.4)
            rows: list[np.ndarray] = []
            sim.observers.append(
                lambda s: rows.append(np.concatenate([s.pose().position, s.pose().quaternion]))
            )
            runner = ActionRunner(sim, step=STEP)
            blocked = []
            for action in sequence:
                runner.discrete(action)
                blocked.append(runner.blocked)
            assert not any(blocked)
            return np.asarray(rows).tobytes()

    with_rule = poses()
    monkeypatch.setattr(actions, "BLOCKED_WINDOW", math.inf)
    assert poses() == with_rule and len(with_rule) > 200 * 7 * 8  # over 200 ticks of poses


# ---------------------------------------------------------------------------------------------- collisions


def test_collisions_count_events_and_contact_steps_the_old_figure(env: NavVerseEnv):
    _, info = env.reset(seed=0, options={"episode": episode(start_position=[9.3, 4.0, 0.0])})
    assert info["collisions"] == 0 and info["contact_steps"] == 0
    for _ in range(5):
        _, _, _, _, info = env.step("forward")
    assert info["collisions"] >= 1  # pushing against the wall is a contact event
    assert info["collisions"] <= 5  # at most one per blocked action, not one per physics step
    assert info["contact_steps"] > 50 * info["collisions"]
    assert info["contact_steps"] == len(env.sim.collisions)
    _, _, _, _, info = env.step("stop")
    # The submission's collision times still come from every logged contact (the evaluator's CR).
    times = {c.time for c in env.sim.collisions}
    assert len(info["submission"]["collisions"]) == len(times) > info["collisions"]
