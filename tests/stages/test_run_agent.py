"""``navverse run-agent`` on the tiny dataset: submissions eval scores, determinism, resume, errors."""

from __future__ import annotations

import gzip
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from navverse.dataset import Dataset
from navverse.eval.runner import _chunks, run_agent
from tests.stages.conftest import Built, navverse_command, scene_dirs

FLAKY_AGENT = '''
from pathlib import Path

import numpy as np
import pytest

from navverse.eval.agents.random_actions import RandomAgent


class FlakyAgent(RandomAgent):
    """Random actions, but it raises in one episode while a marker file exists."""

    def reset(self, task):
        super().reset(task)
        self._broken = task.episode_id == "{episode}" and Path("{marker}").exists()

    def act(self, observation, info):
        if self._broken:
            raise ValueError("the model is not loaded")
        return super().act(observation, info)
'''


def _records(path: Path) -> list[dict]:
    text = gzip.decompress(path.read_bytes()).decode() if path.suffix == ".gz" else path.read_text()
    return [json.loads(line) for line in text.splitlines()]


@pytest.mark.slow(seconds=25)
def test_the_oracle_run_is_scored_as_all_successes_whatever_the_process_count(
    built: Built, dataset: Dataset, tmp_path: Path
):
    root = built.workspace.root
    out = tmp_path / "oracle.jsonl.gz"
    ran = navverse_command(root, "run-agent", "--dataset", str(dataset.root), "--agent", "oracle",
                           "--out", str(out), "--jobs", "2")  # fmt: skip
    assert ran.returncode == 0, ran.stderr
    ids = [e.episode_id for e in dataset.episodes(split="eval")]
    assert [r["episode_id"] for r in _records(out)] == ids  # every episode, in the dataset's order
    assert f"{len(ids)} episodes" in ran.stdout and "navverse eval" in ran.stdout
    scored = navverse_command(root, "eval", "--dataset", str(dataset.root), "--submission", str(out),
                              "--out", str(tmp_path / "eval"))  # fmt: skip
    assert scored.returncode == 0, scored.stderr
    metrics = json.loads((tmp_path / "eval" / "metrics.json").read_text())
    assert metrics["overall"]["success"] == 1.0
    in_process = tmp_path / "in_process.jsonl.gz"
    run_agent(dataset, agent="oracle", split="eval", embodiment="spot", scene_dirs=scene_dirs(built),
              out=in_process, jobs=0)  # fmt: skip
    assert in_process.read_bytes() == out.read_bytes()


@pytest.mark.slow(seconds=12)
def test_a_failing_agent_is_reported_and_the_run_resumes_once_it_is_fixed(
    built: Built, dataset: Dataset, tmp_path: Path
):
    root = built.workspace.root
    ids = [e.episode_id for e in dataset.episodes(split="eval")]
    marker = tmp_path / "broken"
    marker.touch()
    agent_file = tmp_path / "flaky.py"
    agent_file.write_text(FLAKY_AGENT.format(episode=ids[1], marker=marker))
    out = tmp_path / "flaky.jsonl"
    args = ("run-agent", "--dataset", str(dataset.root), "--agent", f"{agent_file}:FlakyAgent",
            "--out", str(out), "--jobs", "0")  # fmt: skip
    failed = navverse_command(root, *args)
    assert failed.returncode == 1 and "Traceback" not in failed.stderr
    message = " ".join(failed.stderr.split())
    assert f"failed in episode {ids[1]}" in message and "ValueError: the model is not loaded" in message
    assert "flaky.py" in message and "run the same command again to resume" in message
    partial = out.with_name(out.name + ".partial")
    assert not out.exists() and partial.is_file()
    kept_ids = [json.loads(line)["episode_id"] for line in partial.read_text().splitlines()[1:]]
    # The failing episode's group stops at it: the one before it is kept, it and the rest of its group
    # are not; the other groups run to the end.
    chunk = next(
        c for c in _chunks(list(dataset.episodes(split="eval")), 1) if ids[1] in {e.episode_id for e in c}
    )
    after = {e.episode_id for e in chunk[[e.episode_id for e in chunk].index(ids[1]) :]}
    assert sorted(kept_ids) == sorted(set(ids) - after) and ids[0] in kept_ids
    kept = len(kept_ids)
    marker.unlink()
    # The run resumes from the same version read from elsewhere (a run is of a dataset, not of a path).
    elsewhere = tmp_path / "copy" / Path(dataset.root).name
    shutil.copytree(dataset.root, elsewhere)
    args = tuple(str(elsewhere) if a == str(dataset.root) else a for a in args)
    resumed = navverse_command(root, *args)
    assert resumed.returncode == 0, resumed.stderr
    assert f"({kept} resumed from an interrupted run)" in " ".join(resumed.stdout.split())
    assert [r["episode_id"] for r in _records(out)] == ids and not partial.exists()


def test_run_agent_refuses_bad_arguments_with_what_to_change(built: Built, dataset: Dataset, tmp_path: Path):
    root = built.workspace.root
    cases = {
        ("--agent", "nope"): "unknown agent 'nope'",
        ("--agent", "oracle", "--split", "val"): "has no split 'val'",
        ("--agent", "oracle", "--limit", "0"): "--limit must be at least 1",
        ("--agent", "oracle", "--task", "placenav"): "has no placenav episodes",
    }
    for extra, expected in cases.items():
        result = navverse_command(root, "run-agent", "--dataset", str(dataset.root), "--out",
                                  str(tmp_path / "x.jsonl"), *extra)  # fmt: skip
        assert result.returncode == 1, (extra, result.stdout)
        assert expected in " ".join(result.stderr.split()) and "Traceback" not in result.stderr
    assert not list(tmp_path.iterdir())  # nothing half-written


def test_run_agent_runs_only_the_task_asked(built: Built, dataset: Dataset, tmp_path: Path):
    out = tmp_path / "vln.jsonl"
    run_agent(dataset, agent="oracle", split="eval", embodiment="spot", scene_dirs=scene_dirs(built),
              out=out, jobs=0, task="vln", limit=2)  # fmt: skip
    vln = {e.episode_id for e in dataset.episodes(split="eval", task="vln")}
    ran = [record["episode_id"] for record in _records(out)]
    assert len(ran) == 2 and set(ran) <= vln
    assert len(vln) < len(list(dataset.episodes(split="eval")))  # other tasks were there to leave out


SPY_AGENT = '''
import json

import numpy as np


class Spy:
    """Writes down everything it is told and sees, then stops."""

    action_mode = "discrete"
    privileged = False
    {sensors}

    def reset(self, task):
        self.task = task

    def act(self, observation, info):
        seen = {{
            "task": {{k: getattr(self.task, k) for k in self.task.__dataclass_fields__}},
            "observation_keys": sorted(observation),
            "goal": observation["goal"],
            "goal_id": int(observation["goal_id"]),
            "info": {{k: repr(v) for k, v in info.items()}},
        }}
        categories = seen["task"]["semantic_categories"]
        seen["task"]["semantic_categories"] = {{str(k): v for k, v in categories.items()}}
        with open("{log}", "a") as handle:
            handle.write(json.dumps(seen) + "\\n")
        return 0
'''


def _spy(tmp_path: Path, name: str, sensors: str) -> tuple[str, Path]:
    log = tmp_path / f"{name}.log"
    agent_file = tmp_path / f"{name}.py"
    agent_file.write_text(SPY_AGENT.format(sensors=sensors, log=log))
    return f"{agent_file}:Spy", log


def test_a_vln_agent_is_told_the_instruction_only_and_its_track_is_scored(
    built: Built, dataset: Dataset, tmp_path: Path
):
    episodes = {e.episode_id: e for e in dataset.episodes(split="eval")}
    vln = {i: e.goal_category for i, e in episodes.items() if e.task == "vln"}
    assert vln and all(vln.values())  # every VLN episode has a destination category the agent must not get
    agent, log = _spy(tmp_path, "standard", "")
    out = tmp_path / "spy.jsonl"
    summary = run_agent(dataset, agent=agent, split="eval", embodiment="spot", scene_dirs=scene_dirs(built),
                        out=out, jobs=0)  # fmt: skip
    assert summary.track == {"name": "standard", "sensors": ["depth", "rgb"], "privileged": False}
    seen = {s["task"]["episode_id"]: s for s in map(json.loads, log.read_text().splitlines())}
    assert set(vln) <= set(seen)
    for episode_id, category in vln.items():
        told = seen[episode_id]
        assert told["goal"] == episodes[episode_id].instruction.instruction_text  # the instruction itself
        assert told["task"]["goal_category"] == "" and told["goal_id"] == -1
        assert told["task"]["semantic_categories"] == {} and "semantic" not in told["observation_keys"]
        rest = json.dumps({**told, "goal": "", "task": {**told["task"], "goal": ""}})
        assert category not in rest, rest  # nothing but the instruction can name the destination
        assert "goal_positions" not in told["info"] and "reference_path" not in told["info"]
    objnav = [s for i, s in seen.items() if episodes[i].task == "objnav"]
    assert objnav and all(
        s["task"]["goal_category"] == s["goal"] for s in objnav
    )  # ObjNav is told its category
    assert all(r["track"] == summary.track for r in _records(out))
    scored = navverse_command(built.workspace.root, "eval", "--dataset", str(dataset.root), "--submission",
                              str(out), "--out", str(tmp_path / "eval"))  # fmt: skip
    assert scored.returncode == 0, scored.stderr
    metrics = json.loads((tmp_path / "eval" / "metrics.json").read_text())
    assert metrics["track"] == summary.track
    assert "Track: standard (depth, rgb)." in (tmp_path / "eval" / "tables.md").read_text()

    agent, log = _spy(tmp_path, "semantic", 'sensors = ("semantic",)')  # the ground-truth sensor, opted in
    summary = run_agent(dataset, agent=agent, split="eval", embodiment="spot", scene_dirs=scene_dirs(built),
                        out=tmp_path / "semantic.jsonl", jobs=0, limit=2)  # fmt: skip
    assert summary.track["name"] == "gt-semantic"
    told = [json.loads(line) for line in log.read_text().splitlines()]
    assert all(t["task"]["semantic_categories"] and "semantic" in t["observation_keys"] for t in told)


def test_a_partial_run_is_scored_over_its_episodes_only_when_asked_and_every_metric_states_its_n(
    built: Built, dataset: Dataset, tmp_path: Path
):
    root = built.workspace.root
    total = len(list(dataset.episodes(split="eval")))
    out = tmp_path / "three.jsonl"
    run_agent(dataset, agent="oracle", split="eval", embodiment="spot", scene_dirs=scene_dirs(built),
              out=out, jobs=0, limit=3)  # fmt: skip
    args = ("eval", "--dataset", str(dataset.root), "--submission", str(out))
    submitted = navverse_command(root, *args, "--episodes", "submitted", "--out", str(tmp_path / "sub"))
    assert submitted.returncode == 0, submitted.stderr
    metrics = json.loads((tmp_path / "sub" / "metrics.json").read_text())
    overall = metrics["overall"]
    assert overall["success"] == 1.0 and overall["episodes"] == overall["success_n"] == overall["ne_n"] == 3
    assert metrics["scope"] == {"episodes": "submitted", "split": "eval", "split_episodes": total,
                                "submitted": 3, "scored": 3, "missing": 0}  # fmt: skip
    assert "PARTIAL" in (tmp_path / "sub" / "tables.md").read_text() and "PARTIAL" in submitted.stdout
    assert "PARTIAL" in (tmp_path / "sub" / "report.html").read_text()

    full = navverse_command(root, *args, "--out", str(tmp_path / "all"))
    assert full.returncode == 0, full.stderr
    metrics = json.loads((tmp_path / "all" / "metrics.json").read_text())
    overall = metrics["overall"]
    assert overall["episodes"] == overall["success_n"] == total and overall["success"] == round(3 / total, 6)
    assert overall["ne_n"] == 3  # the final distance needs a trajectory: its own N
    names = [n for n in metrics["definitions"] if overall.get(n) is not None]
    assert names and all(isinstance(overall[f"{n}_n"], int) for n in names)
    tables = (tmp_path / "all" / "tables.md").read_text()
    assert f"Scored over all {total} episodes of split eval; {total - 3} without a valid record" in tables
    assert "(n=" in tables


def test_a_dataset_exports_for_habitat_lab_from_the_command_line(
    built: Built, dataset: Dataset, tmp_path: Path
):
    out = tmp_path / "habitat"
    done = navverse_command(built.workspace.root, "export", "habitat", str(dataset.root), str(out))
    assert done.returncode == 0, done.stderr
    assert "R2R-VLN episodes" in done.stdout
    splits = {p.name for p in (out / "objectnav_v1").iterdir()}
    assert splits == set(dataset.splits) and (out / "vln_r2r" / "eval" / "eval.json.gz").is_file()
    again = navverse_command(built.workspace.root, "export", "habitat", str(dataset.root), str(out))
    assert again.returncode == 1 and "not empty" in again.stderr and "Traceback" not in again.stderr


def test_the_python_api_builds_a_dict_recipe_loads_it_and_makes_an_env_on_a_dataset_episode(
    built: Built, dataset: Dataset
):
    import navverse.api as navverse

    recipe = {
        "extends": "indoor-building",
        "stages": {"indoor_layout": {"building_type": "cafe", "length": 12}},
    }
    made = navverse.build(recipe, name="api-cafe", root=built.workspace.root)
    scene_dir = made.output("api-cafe")
    assert made.built > 0 and (scene_dir / "navmesh.bin").is_file()
    again = navverse.build(recipe, name="api-cafe", root=built.workspace.root)
    assert again.built == 0 and again.output("api-cafe") == scene_dir  # the engine's cache
    loaded = navverse.load_scene("api-cafe", scenes=[built.workspace.built_dir])
    assert loaded.directory == scene_dir and loaded.annotations.scene_type == "indoor"
    assert loaded.pathfinder is not None and loaded.pathfinder.navigable_area > 20.0
    with pytest.raises(navverse.ApiError, match=r"nope"):
        navverse.build("nope", root=built.workspace.root)

    episode = next(e for e in dataset.episodes(split="eval") if e.task == "objnav")
    env = navverse.make_env(dataset.root, episode.episode_id, scenes=[built.workspace.built_dir],
                            sensors=("depth",))  # fmt: skip
    try:
        observation, _ = env.reset()
        assert np.allclose(observation["pose"][:2], episode.start_position[:2], atol=0.05)
        assert observation["goal"] == episode.object_category
        ids = dataset.file("eval", "objnav").category_to_task_category_id
        assert int(observation["goal_id"]) == ids[episode.object_category]
        observation, *_ = env.step("turn_left")
        assert observation["depth"].shape[:2] == (480, 640)
    finally:
        env.close()
