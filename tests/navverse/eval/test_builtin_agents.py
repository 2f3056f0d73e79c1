"""The built-in agents and the agent loader, in the Gymnasium environment on a built room."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from navverse.env import SENSORS, NavVerseEnv
from navverse.eval.agents import BUILTIN_AGENTS, AgentLoadError, agent_factory, load_agent
from navverse.eval.agents.base import AgentTask
from navverse.eval.agents.ground_truth import ARRIVE_DISTANCE, GTGoalAgent, OracleAgent
from navverse.eval.agents.random_actions import RandomAgent
from navverse.eval.runner import agent_seed, pick_episodes
from tests.navverse.test_env import TABLE_CENTER, build_room, episode

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "my_agent.py"


@pytest.fixture(scope="module")
def room(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_room(tmp_path_factory.mktemp("agents_room"))


def _task(room: Path, *, seed: int = 0) -> AgentTask:
    return AgentTask("room-0", "objnav", "table", "table", "indoor", "spot", 0.6, {1: "table"}, seed,
                     str(room))  # fmt: skip


def _run(env: NavVerseEnv, agent, task: AgentTask, ep: dict, *, limit: int = 3000) -> dict:
    agent.reset(task)
    obs, info = env.reset(seed=task.seed, options={"episode": ep})
    for _ in range(limit):
        obs, _, _, _, info = env.step(agent.act(obs, info))
        if "submission" in info:
            return info
    raise AssertionError(f"the episode did not end in {limit} actions")


def _env(scene_dir: Path, agent, cache: Path) -> NavVerseEnv:
    sensors = getattr(agent, "sensors", SENSORS)
    return NavVerseEnv(scene_dir, action_mode=agent.action_mode, privileged=agent.privileged,
                       sensors=sensors, collision_cache=cache)  # fmt: skip


def test_the_oracle_walks_the_reference_path_and_stops_at_its_end(room: Path, tmp_path: Path):
    agent = OracleAgent()
    env = _env(room, agent, tmp_path)
    try:
        path = [[2.0, 4.0, 0.0], [4.0, 2.5, 0.0], [6.0, 4.0, 0.0]]
        info = _run(env, agent, _task(room), episode(reference_path=path))
    finally:
        env.close()
    record = info["submission"]
    rows = np.array(record["trajectory"])
    assert info["termination"] == "stop" and record["stop"] is True
    assert np.hypot(*(rows[-1, 1:3] - [6.0, 4.0])) < ARRIVE_DISTANCE
    # It went by the middle corner, not straight: the closest approach to (4, 2.5) is within 0.3 m.
    assert np.hypot(rows[:, 1] - 4.0, rows[:, 2] - 2.5).min() < 0.3
    # Two 2.5 m legs at up to 1.5 m/s: a few seconds, not the 300 s limit.
    assert 3.0 < rows[-1, 0] < 10.0


def test_gt_goal_plans_to_the_goal_it_is_given(room: Path, tmp_path: Path):
    agent = GTGoalAgent()
    env = _env(room, agent, tmp_path)
    try:
        # The reference path points the other way: gt_goal ignores it and plans to the table.
        info = _run(env, agent, _task(room), episode(reference_path=[[2.0, 4.0, 0.0], [1.0, 1.0, 0.0]]))
    finally:
        env.close()
    end = np.array(info["submission"]["trajectory"][-1][1:4])
    assert info["termination"] == "stop"
    # The table's nearest navigable point: at most the robot's clearance from its edge (1.2 x 0.8 m).
    edge = math.hypot(
        max(abs(end[0] - TABLE_CENTER[0]) - 0.6, 0.0), max(abs(end[1] - TABLE_CENTER[1]) - 0.4, 0.0)
    )
    assert edge < 1.0


def test_gt_goal_without_a_reachable_goal_stops_where_it_is(room: Path, tmp_path: Path):
    agent = GTGoalAgent()
    env = _env(room, agent, tmp_path)
    try:
        goal = {"object_id": 9, "category": "table", "position": [50.0, 50.0, 0.0], "radius": 0.5,
                "size": [1.0, 1.0, 1.0]}  # fmt: skip
        far = episode(goals=[goal])
        info = _run(env, agent, _task(room), far)
    finally:
        env.close()
    assert info["termination"] == "stop" and len(info["submission"]["trajectory"]) <= 2


def test_random_actions_follow_the_episode_seed(room: Path, tmp_path: Path):
    agent = RandomAgent()
    env = _env(room, agent, tmp_path)
    try:
        first = _run(env, agent, _task(room, seed=7), episode())["submission"]
        again = _run(env, agent, _task(room, seed=7), episode())["submission"]
        other = [_run(env, agent, _task(room, seed=s), episode())["submission"] for s in range(8)]
    finally:
        env.close()
    assert first["trajectory"] == again["trajectory"] and first["stop"]
    assert len({len(r["trajectory"]) for r in other}) > 1  # different seeds, different walks


def test_the_example_agent_loads_from_its_file_and_runs(room: Path, tmp_path: Path):
    agent = load_agent(f"{EXAMPLE}:GoalSeekingAgent")
    assert agent.action_mode == "discrete" and agent.privileged is False
    env = _env(room, agent, tmp_path)
    try:
        info = _run(env, agent, _task(room), episode(), limit=200)
    finally:
        env.close()
    # It starts 5 m from the table with the table in view, walks up to it and stops.
    assert info["termination"] == "stop"
    end = np.array(info["submission"]["trajectory"][-1][1:3])
    assert np.hypot(*(end - TABLE_CENTER[:2])) < 2.5


def test_every_builtin_agent_loads_and_bad_names_say_what_to_give():
    for name in BUILTIN_AGENTS:
        agent = load_agent(name)
        assert agent.action_mode in ("discrete", "waypoint")
    assert agent_factory("navverse.eval.agents.random_actions:RandomAgent") is RandomAgent
    with pytest.raises(AgentLoadError, match=r"unknown agent 'nope'.*oracle, gt_goal, random, frontier"):
        load_agent("nope")
    with pytest.raises(AgentLoadError, match="cannot import module 'no_such_module'"):
        load_agent("no_such_module:Agent")
    with pytest.raises(AgentLoadError, match="has no class or function 'Missing'"):
        load_agent("navverse.eval.agents.ground_truth:Missing")
    with pytest.raises(AgentLoadError, match="does not exist"):
        load_agent("nowhere/agent.py:Agent")
    with pytest.raises(AgentLoadError, match="action_mode None"):
        load_agent("collections:OrderedDict")


def test_episode_picking_and_seeds_do_not_depend_on_the_run():
    episodes = list(range(10))
    assert pick_episodes(episodes, 3) == [0, 4, 9] and pick_episodes(episodes, None) == episodes
    assert agent_seed(0, "a") == agent_seed(0, "a") != agent_seed(1, "a") != agent_seed(0, "b")
