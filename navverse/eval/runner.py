"""Run an agent online over a dataset split and write the submission ``navverse eval`` scores.

:func:`run_agent` groups the split's episodes by scene, runs them in worker processes (each opens a
:class:`~navverse.env.NavVerseEnv` per scene and drives the agent through it), and writes one record
per episode in the submission format (DESIGN.md §3), in the dataset's order.

Every finished episode is appended at once to ``<out>.partial`` (its first line names the run: agent,
dataset, split, embodiment, seed, limits), so a run that is killed resumes where it stopped when the
same command is given again; the submission itself is written atomically at the end and the partial
file removed. An agent gets a seed per episode derived from ``--seed`` and the episode id, so the
output does not depend on how many processes ran it.
"""

from __future__ import annotations

import hashlib
import json
import math
import multiprocessing
import os
import queue
import time
import traceback
from collections import Counter
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from navverse.dataset import Dataset, Episode
from navverse.errors import NavverseError
from navverse.sim.recorder import write_submission

__all__ = ["RunError", "RunSettings", "RunSummary", "agent_seed", "pick_episodes", "run_agent"]


class RunError(NavverseError):
    """An agent run that cannot start (bad arguments) or whose agent failed."""


@dataclass(frozen=True)
class RunSettings:
    """What a run is: its results can be resumed only under the same settings."""

    agent: str
    dataset: str
    dataset_version: str
    split: str
    embodiment: str
    seed: int = 0
    max_steps: int | None = None
    terrain_friction: float | None = None


@dataclass(frozen=True)
class RunSummary:
    """The outcome of :func:`run_agent`.

    Attributes
    ----------
    out : Path
        The submission written.
    episodes : int
        Episodes in it.
    resumed : int
        Episodes taken from an earlier, interrupted run.
    terminations : dict
        How many episodes ended each way (the simulator's label: stop, fall, timeout...).
    seconds : float
        Wall time of this run.
    """

    out: Path
    episodes: int
    resumed: int
    terminations: dict[str, int]
    seconds: float


def agent_seed(seed: int, episode_id: str) -> int:
    """The seed an agent gets for an episode: a hash of the run's seed and the episode id."""
    digest = hashlib.sha256(f"{seed}:{episode_id}".encode()).digest()
    return int.from_bytes(digest[:4], "little")


def pick_episodes(episodes: Sequence[Episode], limit: int | None) -> list[Episode]:
    """``limit`` episodes spread evenly over the list (all when None)."""
    if limit is None or limit >= len(episodes):
        return list(episodes)
    if limit < 1:
        raise RunError(f"--limit must be at least 1, got {limit}")
    indices = np.unique(np.linspace(0, len(episodes) - 1, limit).round().astype(int))
    return [episodes[i] for i in indices]


def _partial_path(out: Path) -> Path:
    return out.with_name(out.name + ".partial")


def _read_partial(path: Path, settings: RunSettings) -> dict[str, dict[str, Any]]:
    """Records of an interrupted run with the same settings (a torn last line is dropped)."""
    if not path.is_file():
        return {}
    lines = path.read_text().splitlines()
    try:
        header = json.loads(lines[0]) if lines else {}
    except json.JSONDecodeError:
        header = {}
    if header.get("navverse_run") != asdict(settings):
        return {}
    records: dict[str, dict[str, Any]] = {}
    for line in lines[1:]:
        try:
            record = json.loads(line)
        except json.JSONDecodeError:
            break
        records[record["episode_id"]] = record
    return records


def _chunks(episodes: Sequence[Episode], jobs: int) -> list[list[Episode]]:
    """Per-scene groups of episodes, cut so that every worker gets several."""
    by_scene: dict[str, list[Episode]] = {}
    for episode in episodes:
        by_scene.setdefault(episode.scene_id, []).append(episode)
    size = max(1, math.ceil(len(episodes) / max(1, 3 * jobs)))
    return [group[i : i + size] for group in by_scene.values() for i in range(0, len(group), size)]


def _task_for(episode: Episode, *, embodiment: str, radius: float, categories: dict[int, str],
              seed: int, scene_dir: Path):  # fmt: skip
    from navverse.eval.agents.base import AgentTask

    instruction = episode.instruction
    goal = instruction.instruction_text if instruction is not None else episode.goal_category
    return AgentTask(
        episode_id=episode.episode_id,
        task=episode.task,
        goal=goal,
        goal_category=episode.goal_category,
        scene_type=episode.scene_type,
        embodiment=embodiment,
        robot_radius=radius,
        semantic_categories=categories,
        seed=agent_seed(seed, episode.episode_id),
        scene_dir=str(scene_dir),
    )


def _run_chunk(
    settings: RunSettings,
    scene_dir: str,
    episodes: list[dict[str, Any]],
    sink: Any,
) -> None:
    """Worker: run ``episodes`` of one scene and put ``(episode_id, record)`` on ``sink`` as each ends."""
    from navverse.env import SENSORS, NavVerseEnv
    from navverse.eval.agents import load_agent

    agent = load_agent(settings.agent)
    env = NavVerseEnv(
        scene_dir,
        embodiment=settings.embodiment,
        action_mode=agent.action_mode,
        privileged=bool(getattr(agent, "privileged", False)),
        sensors=tuple(getattr(agent, "sensors", SENSORS)),
        max_steps=settings.max_steps,
        terrain_friction=settings.terrain_friction,
    )
    try:
        categories = {o.id: o.category for o in env.scene.annotations.objects if o.category}
        radius = float(env.sim.robot.radius)
        for data in episodes:
            episode = Episode.model_validate(data)
            task = _task_for(episode, embodiment=settings.embodiment, radius=radius, categories=categories,
                             seed=settings.seed, scene_dir=Path(scene_dir))  # fmt: skip
            try:
                agent.reset(task)
                observation, info = env.reset(seed=task.seed, options={"episode": data})
                while "submission" not in info:
                    action = agent.act(observation, info)
                    observation, _, _, _, info = env.step(action)
            except Exception as exc:  # the agent's (or its action's) failure, reported with its place
                frame = traceback.extract_tb(exc.__traceback__)[-1]
                where = f"{Path(frame.filename).name}:{frame.lineno} in {frame.name}"
                sink.put(("error", episode.episode_id, f"{type(exc).__name__}: {exc} (at {where})"))
                return
            sink.put(("record", episode.episode_id, info["submission"]))
    finally:
        env.close()


def run_agent(
    dataset: Dataset,
    *,
    agent: str,
    split: str,
    embodiment: str,
    scene_dirs: dict[str, Path],
    out: str | os.PathLike[str],
    jobs: int = 1,
    limit: int | None = None,
    seed: int = 0,
    max_steps: int | None = None,
    terrain_friction: float | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> RunSummary:
    """Run an agent on a split and write its submission.

    Parameters
    ----------
    dataset : Dataset
        The dataset version.
    agent : str
        A built-in agent name, ``module:Class`` or ``file.py:Class`` (see
        :func:`navverse.eval.agents.load_agent`).
    split, embodiment : str
        The split run and the robot.
    scene_dirs : dict
        Built scene directory of every scene of the split.
    out : path
        The submission (``.jsonl`` or ``.jsonl.gz``).
    jobs : int
        Worker processes; 0 runs in this process.
    limit : int, optional
        Run only this many episodes, spread evenly over the split.
    seed : int
        Seed of the agents' per-episode seeds.
    max_steps : int, optional
        Actions per episode before it is cut (label ``max_steps``); the 300 s time limit always holds.
    terrain_friction : float, optional
        Friction of every terrain class instead of the scene's (the friction diagnostic).
    progress : callable, optional
        Called with ``(done, total)`` episodes.

    Returns
    -------
    RunSummary

    Raises
    ------
    RunError
        When the agent cannot be loaded, or raises during an episode (the episodes done so far are
        kept for a resumed run).
    """
    from navverse.eval.agents import load_agent

    started = time.perf_counter()
    load_agent(agent)  # fail here, clearly, rather than in a worker
    if jobs < 0:
        raise RunError(f"--jobs must be 0 or more, got {jobs}")
    out = Path(out)
    if out.parent and not out.parent.is_dir():
        raise RunError(f"the folder of --out {out} does not exist")
    episodes = pick_episodes(list(dataset.episodes(split=split)), limit)
    if not episodes:
        raise RunError(f"split {split!r} of {dataset.root} has no episodes")
    settings = RunSettings(
        agent=agent,
        dataset=str(Path(dataset.root).resolve()),
        dataset_version=dataset.manifest.version,
        split=split,
        embodiment=embodiment,
        seed=seed,
        max_steps=max_steps,
        terrain_friction=terrain_friction,
    )
    partial = _partial_path(out)
    wanted = {e.episode_id for e in episodes}
    records = {k: v for k, v in _read_partial(partial, settings).items() if k in wanted}
    resumed = len(records)
    with partial.open("w") as sink_file:
        sink_file.write(json.dumps({"navverse_run": asdict(settings)}) + "\n")
        for record in records.values():
            sink_file.write(json.dumps(record, separators=(",", ":")) + "\n")
        sink_file.flush()
        todo = [e for e in episodes if e.episode_id not in records]
        if progress is not None:
            progress(len(records), len(episodes))

        errors: list[tuple[str, str]] = []

        def collect(item: tuple[str, str, Any]) -> None:
            kind, episode_id, payload = item
            if kind == "error":
                errors.append((episode_id, payload))
                return
            records[episode_id] = payload
            sink_file.write(json.dumps(payload, separators=(",", ":")) + "\n")
            sink_file.flush()
            if progress is not None:
                progress(len(records), len(episodes))

        chunks = _chunks(todo, max(1, jobs))
        work = [
            (str(scene_dirs[chunk[0].scene_id]), [e.model_dump(mode="json") for e in chunk])
            for chunk in chunks
        ]
        if jobs == 0:
            local: queue.SimpleQueue = queue.SimpleQueue()
            for scene_dir, batch in work:
                _run_chunk(settings, scene_dir, batch, local)
                while not local.empty():
                    collect(local.get())
        elif work:
            _run_in_pool(settings, work, jobs, collect, expected=len(todo))
    if errors:
        episode_id, message = errors[0]
        raise RunError(
            f"agent {agent!r} failed in episode {episode_id} ({len(errors)} failures; the rest of each "
            f"failing scene group was not run): {message}. {len(records)} finished episodes are kept in "
            f"{partial}; fix the agent and run the same command again to resume"
        )
    ordered = [records[e.episode_id] for e in episodes]
    write_submission(ordered, out)
    partial.unlink()
    return RunSummary(
        out=out,
        episodes=len(ordered),
        resumed=resumed,
        terminations=dict(Counter(str(r.get("termination")) for r in ordered)),
        seconds=time.perf_counter() - started,
    )


def _run_in_pool(
    settings: RunSettings,
    work: list[tuple[str, list[dict[str, Any]]]],
    jobs: int,
    collect: Callable[[tuple[str, str, Any]], None],
    *,
    expected: int,
) -> None:
    """Run the chunks in ``jobs`` spawned processes, collecting results as episodes finish."""
    context = multiprocessing.get_context("spawn")
    with context.Manager() as manager:
        sink = manager.Queue()
        with ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
            futures: list[Future] = [pool.submit(_run_chunk, settings, d, batch, sink) for d, batch in work]
            received = 0
            try:
                while received < expected:
                    try:
                        item = sink.get(timeout=0.5)
                    except queue.Empty:
                        failed = next((f for f in futures if f.done() and f.exception() is not None), None)
                        if failed is not None:
                            raise RunError(f"a worker failed: {failed.exception()}") from None
                        if all(f.done() for f in futures) and sink.empty():
                            break
                        continue
                    received += 1
                    collect(item)
            except BaseException:
                for future in futures:
                    future.cancel()
                raise
