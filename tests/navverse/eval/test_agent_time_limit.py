"""``run-agent`` limits the agent's wall-clock time: a stuck agent ends its episode as ``agent_timeout``
and the run goes on, in this process (alarm) and in worker processes (alarm, then kill)."""

from __future__ import annotations

import json
import shutil
import time
from pathlib import Path

import pytest

from navverse import cli
from navverse.dataset import Dataset, Episode, EpisodeInfo
from navverse.episodes.packaging import write_dataset
from navverse.eval.runner import RunError, RunSummary, run_agent
from navverse.sim.terminations import AGENT_TIMEOUT
from tests.navverse.test_env import build_room, table_episodes

STUCK = "env_room-objnav-0002"
AGENTS = f'''
import os
import signal
import time

from navverse.eval.agents.ground_truth import OracleAgent


class SleepyAgent(OracleAgent):
    """The oracle, but its act sleeps 1000 s in one episode; it prints on every call."""

    def reset(self, task):
        super().reset(task)
        self._stuck = task.episode_id == "{STUCK}"

    def act(self, observation, info):
        print("thinking...", flush=True)
        if self._stuck:
            time.sleep(1000)
        return super().act(observation, info)


class StubbornAgent(SleepyAgent):
    """Blocks the alarm before it sleeps: only killing its process stops it."""

    def act(self, observation, info):
        if self._stuck:
            signal.pthread_sigmask(signal.SIG_BLOCK, {{signal.SIGALRM}})
        return super().act(observation, info)


class SwallowingAgent(SleepyAgent):
    """Catches the interruption and sleeps on."""

    def act(self, observation, info):
        try:
            return super().act(observation, info)
        except BaseException:
            time.sleep(1000)


class LateAgent(SleepyAgent):
    """Catches the interruption and answers, late."""

    def act(self, observation, info):
        try:
            return super().act(observation, info)
        except BaseException:
            self._stuck = False
            return super().act(observation, info)


class SlowAgent(OracleAgent):
    """Takes 0.3 s per action in one episode: within the step limit, not the episode's."""

    def reset(self, task):
        super().reset(task)
        self._stuck = task.episode_id == "{STUCK}"

    def act(self, observation, info):
        if self._stuck:
            time.sleep(0.3)
        return super().act(observation, info)


class CrashingAgent(SlowAgent):
    """Ends its own process in one episode."""

    def act(self, observation, info):
        if self._stuck:
            os._exit(3)
        return super().act(observation, info)
'''


def _episodes() -> list[Episode]:
    info = EpisodeInfo(
        geodesic_distance=3.0, euclidean_distance=3.0, closest_goal_object_id=1, success_distance=1.6
    )
    return table_episodes(6, first_y=2.0, step=0.6, end=(4.5, 5.0), info=info)


@pytest.fixture(scope="module")
def room(tmp_path_factory: pytest.TempPathFactory) -> tuple[Dataset, Path, Path]:
    """A dataset of six short ObjNav episodes in the test room, the room, and the agents' file."""
    root = tmp_path_factory.mktemp("time_limit")
    (root / "scene").mkdir()
    scene = build_room(root / "scene")
    episodes = _episodes()
    rollouts = {e.episode_id: [[0.0, 2.0, 2.0, 0.55, 0.0, 0.0, 0.0, 1.0]] for e in episodes}
    write_dataset(
        root / "room" / "v1.0",
        episodes,
        rollouts,
        name="room",
        version="1.0",
        splits={"eval": ["env_room"]},
        embodiment="spot",
        recipe="room.yaml",
        recipe_hash="0",
        scene_hashes={"env_room": "0"},
        toolkit_version="0",
    )
    (root / "agents.py").write_text(AGENTS)
    return Dataset(root / "room" / "v1.0"), scene, root / "agents.py"


def _run(room: tuple[Dataset, Path, Path], out: Path, agent: str, **limits) -> RunSummary:
    dataset, scene, agents = room
    name = agent if agent == "oracle" else f"{agents}:{agent}"
    return run_agent(dataset, agent=name, split="eval", embodiment="spot", scene_dirs={"env_room": scene},
                     out=out, **limits)  # fmt: skip


def _records(path: Path) -> dict[str, dict]:
    return {r["episode_id"]: r for r in map(json.loads, path.read_text().splitlines())}


@pytest.fixture(scope="module")
def reference(room, tmp_path_factory: pytest.TempPathFactory) -> dict[str, dict]:
    """The oracle's records, with no agent out of time."""
    out = tmp_path_factory.mktemp("reference") / "oracle.jsonl"
    _run(room, out, "oracle", jobs=0)
    return _records(out)


def _check_timed_out(summary: RunSummary, out: Path, reference: dict[str, dict], reason: str) -> dict:
    """Five episodes as the oracle ran them, the stuck one ended by the time limit; its record."""
    assert summary.terminations == {"stop": 5, AGENT_TIMEOUT: 1}
    assert [episode_id for episode_id, _ in summary.timeouts] == [STUCK] and reason in summary.timeouts[0][1]
    records = _records(out)
    assert list(records) == list(reference)  # every episode, in the dataset's order
    for episode_id, record in records.items():
        if episode_id != STUCK:
            assert record == reference[episode_id]  # the same bytes as without the stuck agent
    stuck = records[STUCK]
    assert stuck["termination"] == AGENT_TIMEOUT and stuck["stop"] is False
    assert stuck["trajectory"][0] == reference[STUCK]["trajectory"][0]  # where the robot started
    return stuck


@pytest.mark.parametrize("jobs", [0, 1])
def test_an_agent_stuck_in_act_is_stopped_and_the_run_goes_on(room, reference, tmp_path: Path, jobs: int):
    out = tmp_path / "sleepy.jsonl"
    started = time.monotonic()
    summary = _run(room, out, "SleepyAgent", jobs=jobs, step_timeout=1.0)
    assert time.monotonic() - started < 120  # not 1000 s
    stuck = _check_timed_out(summary, out, reference, "act took longer than the 1 s step limit")
    assert len(stuck["trajectory"]) == 1  # it never acted
    if jobs:
        assert summary.log == tmp_path / "sleepy.jsonl.log" and "thinking..." in summary.log.read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        {out.name, *([f"{out.name}.log"] if jobs else [])}
    )


@pytest.mark.parametrize("agent", ["StubbornAgent", "SwallowingAgent"])
def test_an_agent_that_ignores_the_alarm_has_its_process_killed(room, reference, tmp_path: Path, agent: str):
    out = tmp_path / "stubborn.jsonl"
    summary = _run(room, out, agent, jobs=1, step_timeout=1.0)
    _check_timed_out(summary, out, reference, "its worker process was killed")


def test_an_answer_after_the_limit_is_a_timeout_too(room, reference, tmp_path: Path):
    out = tmp_path / "late.jsonl"
    summary = _run(room, out, "LateAgent", jobs=0, step_timeout=1.0)
    stuck = _check_timed_out(summary, out, reference, "act took longer than the 1 s step limit")
    assert len(stuck["trajectory"]) == 1  # its late action was not executed


def test_the_episode_limit_counts_the_agents_calls_together(room, reference, tmp_path: Path):
    out = tmp_path / "slow.jsonl"
    summary = _run(room, out, "SlowAgent", jobs=0, step_timeout=30.0, episode_timeout=1.0)
    stuck = _check_timed_out(summary, out, reference, "used up the 1 s episode limit")
    rows = stuck["trajectory"]
    assert 2 <= len(rows) <= 6 and rows == reference[STUCK]["trajectory"][: len(rows)]  # as far as it got


def test_an_agent_that_ends_its_process_fails_the_run_naming_the_episode(room, tmp_path: Path):
    with pytest.raises(RunError, match=rf"failed in episode {STUCK}.*exited unexpectedly \(exit code 3\)"):
        _run(room, tmp_path / "crash.jsonl", "CrashingAgent", jobs=1)


def test_run_agent_reports_timeouts_and_keeps_the_agents_output_off_the_terminal(
    room, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
):
    dataset, scene, agents = room
    workspace = tmp_path / "workspace"
    (workspace / "recipes").mkdir(parents=True)
    artifact = workspace / "data" / "built" / "artifacts" / "navmesh" / "scene-0"
    shutil.copytree(scene, artifact)
    (artifact / "manifest.json").write_text("{}")  # a committed artifact, as the build store has it
    (workspace / "data" / "built" / "targets" / "env_room").mkdir(parents=True)
    (workspace / "data" / "built" / "targets" / "env_room" / "scene").symlink_to(artifact)
    monkeypatch.setenv("NAVVERSE_ROOT", str(workspace))
    out = tmp_path / "sleepy.jsonl"
    base = [
        "run-agent",
        "--dataset",
        str(dataset.root),
        "--agent",
        f"{agents}:SleepyAgent",
        "--out",
        str(out),
    ]
    assert cli.main([*base, "--jobs", "1", "--step-timeout", "1"]) == 0
    captured = capsys.readouterr()
    printed = " ".join(captured.out.split())
    assert f"agent_timeout: {STUCK}: act took longer than the 1 s step limit" in printed
    assert "ended: agent_timeout 1, stop 5" in printed and f"the agent's output is in {out}.log" in printed
    assert "thinking" not in captured.out + captured.err
    for flag, value in (("--step-timeout", "0"), ("--episode-timeout", "nan")):
        assert cli.main([*base, flag, value]) == 1
        error = " ".join(capsys.readouterr().err.split())
        assert f"{flag} must be a positive number of seconds" in error and "Traceback" not in error
