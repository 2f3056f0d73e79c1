"""Run an agent online over a dataset split and write the submission ``navverse eval`` scores.

:func:`run_agent` groups the split's episodes by scene, runs them in worker processes (each opens a
:class:`~navverse.env.NavVerseEnv` per scene and drives the agent through it), and writes one record
per episode in the submission format (DESIGN.md §3), in the dataset's order.

PlaceNav episodes are run under one instruction type (``instruction_type``: the agent is given the
episode's ``category``, ``route`` or ``intention`` instruction, :func:`navverse.env.episode_goal`), which
their records name.

Every finished episode is appended at once to ``<out>.partial`` (its first line names the run: agent,
dataset, split, embodiment, seed, limits, instruction type), so a run that is killed resumes where it
stopped when the same command is given again; the submission itself is written atomically at the end
and the partial file removed. An agent gets a seed per episode derived from ``--seed`` and the episode
id, so the output does not depend on how many processes ran it.

The agent's time is limited per call and per episode (:mod:`navverse.eval.agent_workers`): an
episode whose agent runs out of time ends with the label ``agent_timeout`` and the run goes on. What
the agent prints in the worker processes goes to ``<out>.log`` (kept only when not empty).
"""

from __future__ import annotations

import json
import math
import os
import time
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from navverse.dataset import INSTRUCTION_TYPES, Dataset, Episode
from navverse.eval.agent_workers import (
    EPISODE_TIMEOUT,
    STEP_TIMEOUT,
    Chunk,
    Results,
    RunError,
    RunSettings,
    agent_seed,
    run_here,
    run_in_pool,
)
from navverse.sim.recorder import write_submission

__all__ = [
    "EPISODE_TIMEOUT",
    "STEP_TIMEOUT",
    "RunError",
    "RunSettings",
    "RunSummary",
    "agent_seed",
    "pick_episodes",
    "run_agent",
]


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
        How many episodes ended each way (the simulator's label: stop, fall, timeout..., and
        ``agent_timeout`` when the agent ran out of time).
    seconds : float
        Wall time of this run.
    timeouts : list of (str, str)
        The episodes of this run that ended by the agent's time limit, and why.
    log : Path or None
        What the agent printed in the worker processes (None: nothing).
    track : dict
        The run's track (:func:`navverse.eval.protocol.track_of`), recorded on every line.
    """

    out: Path
    episodes: int
    resumed: int
    terminations: dict[str, int]
    seconds: float
    timeouts: list[tuple[str, str]] = field(default_factory=list)
    log: Path | None = None
    track: dict = field(default_factory=dict)


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


def _log_path(out: Path) -> Path:
    return out.with_name(out.name + ".log")


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


def _check_instruction_type(episodes: Sequence[Episode], instruction_type: str) -> None:
    """A RunError if the instruction type is unknown, or if it is not ``category`` and some PlaceNav
    episodes have no instructions to give (a dataset of format 1.0)."""
    if instruction_type not in INSTRUCTION_TYPES:
        raise RunError(
            f"unknown --instruction-type {instruction_type!r}; choose from: {', '.join(INSTRUCTION_TYPES)}"
        )
    if instruction_type == "category":
        return
    bare = [e.episode_id for e in episodes if e.task == "placenav" and not e.instructions]
    if bare:
        raise RunError(
            f"--instruction-type {instruction_type} needs the PlaceNav episodes' instructions, and "
            f"{len(bare)} have none (e.g. {bare[0]}; datasets of format 1.0 have none): rebuild the "
            "dataset, or run under --instruction-type category"
        )


def _chunks(episodes: Sequence[Episode], jobs: int) -> list[list[Episode]]:
    """Per-scene groups of episodes, cut so that every worker gets several."""
    by_scene: dict[str, list[Episode]] = {}
    for episode in episodes:
        by_scene.setdefault(episode.scene_id, []).append(episode)
    size = max(1, math.ceil(len(episodes) / max(1, 3 * jobs)))
    return [group[i : i + size] for group in by_scene.values() for i in range(0, len(group), size)]


# ---------------------------------------------------------------------------------------------- the run


def _run_all(
    settings: RunSettings,
    episodes: list[Episode],
    records: dict[str, dict[str, Any]],
    scene_dirs: dict[str, Path],
    *,
    jobs: int,
    partial: Path,
    log: Path,
    progress: Callable[[int, int], None] | None,
) -> Results:
    """Run the episodes that have no record yet, appending each new record to ``partial``."""
    with partial.open("w") as sink:
        sink.write(json.dumps({"navverse_run": asdict(settings)}) + "\n")
        for record in records.values():
            sink.write(json.dumps(record, separators=(",", ":")) + "\n")
        sink.flush()

        def advance() -> None:
            if progress is not None:
                progress(len(records), len(episodes))

        advance()
        results = Results(records, sink, advance)
        todo = [e for e in episodes if e.episode_id not in records]
        chunks = [
            Chunk(str(scene_dirs[chunk[0].scene_id]), [e.model_dump(mode="json") for e in chunk])
            for chunk in _chunks(todo, max(1, jobs))
        ]
        if jobs == 0:
            run_here(settings, chunks, results)
        elif chunks:
            run_in_pool(settings, chunks, jobs, results, log)
    return results


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
    task: str | None = None,
    seed: int = 0,
    max_steps: int | None = None,
    terrain_friction: float | None = None,
    step_timeout: float = STEP_TIMEOUT,
    episode_timeout: float = EPISODE_TIMEOUT,
    instruction_type: str = "category",
    progress: Callable[[int, int], None] | None = None,
) -> RunSummary:
    """Run an agent on a split and write its submission.

    Parameters
    ----------
    dataset : Dataset
        The dataset version (verified by the caller: :meth:`Dataset.verify`).
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
        Worker processes; 0 runs in this process (time limits by alarm only, in the main thread).
    limit : int, optional
        Run only this many episodes, spread evenly over the split.
    task : str, optional
        Run only this task's episodes (``objnav``, ``placenav`` or ``vln``); `limit` then spreads over them.
    seed : int
        Seed of the agents' per-episode seeds.
    max_steps : int, optional
        Actions per episode before it is cut (label ``max_steps``); the 300 s time limit always holds.
    terrain_friction : float, optional
        Friction of every terrain class instead of the scene's (the friction diagnostic).
    step_timeout : float
        Wall-clock seconds one call to the agent (``reset`` or ``act``) may take.
    episode_timeout : float
        Wall-clock seconds the agent's calls in one episode may take together.
    instruction_type : str
        Which instruction PlaceNav episodes give the agent: ``category`` (the place category),
        ``route`` or ``intention`` (:data:`~navverse.dataset.INSTRUCTION_TYPES`); their records name it.
        Under ``route`` and ``intention`` an agent that is not privileged is not told the category.
    progress : callable, optional
        Called with ``(done, total)`` episodes.

    Returns
    -------
    RunSummary

    Raises
    ------
    RunError
        When the arguments are wrong (an unknown instruction type, or one other than ``category`` for
        PlaceNav episodes without instructions), the agent cannot be loaded, or it raises during an episode
        (the episodes done so far are kept for a resumed run). An agent out of time is not an
        error: its episode ends with the label ``agent_timeout``.
    """
    from navverse.eval.agents import load_agent
    from navverse.eval.protocol import agent_sensors, track_of

    started = time.perf_counter()
    for flag, value in (("--step-timeout", step_timeout), ("--episode-timeout", episode_timeout)):
        if not (math.isfinite(value) and value > 0):
            raise RunError(f"{flag} must be a positive number of seconds, got {value}")
    loaded = load_agent(agent)  # fail here, clearly, rather than in a worker
    privileged = bool(getattr(loaded, "privileged", False))
    track = track_of(agent_sensors(loaded), privileged=privileged)
    if privileged:
        dataset.require_goals(
            split, what=f"the privileged agent {agent!r} (it is given the goals and the reference path)"
        )
    if jobs < 0:
        raise RunError(f"--jobs must be 0 or more, got {jobs}")
    out = Path(out)
    if out.parent and not out.parent.is_dir():
        raise RunError(f"the folder of --out {out} does not exist")
    episodes = pick_episodes(list(dataset.episodes(split=split, task=task)), limit)
    if not episodes:
        which = f"{task} episodes" if task else "episodes"
        raise RunError(f"split {split!r} of {dataset.root} has no {which}")
    _check_instruction_type(episodes, instruction_type)
    tasks = dataset.tasks(split)
    settings = RunSettings(
        agent=agent,
        dataset=f"{dataset.manifest.name} (manifest sha256 {dataset.manifest_sha256})",
        dataset_version=dataset.manifest.version,
        split=split,
        embodiment=embodiment,
        seed=seed,
        max_steps=max_steps,
        terrain_friction=terrain_friction,
        step_timeout=float(step_timeout),
        episode_timeout=float(episode_timeout),
        instruction_type=instruction_type,
        category_ids={t: dict(dataset.file(split, t).category_to_task_category_id) for t in tasks},
    )
    partial, log = _partial_path(out), _log_path(out)
    wanted = {e.episode_id for e in episodes}
    records = {k: v for k, v in _read_partial(partial, settings).items() if k in wanted}
    resumed = len(records)
    log.write_bytes(b"")
    try:
        results = _run_all(settings, episodes, records, scene_dirs, jobs=jobs, partial=partial, log=log,
                           progress=progress)  # fmt: skip
    finally:
        kept_log = log if log.is_file() and log.stat().st_size else None
        if kept_log is None:
            log.unlink(missing_ok=True)
    if results.errors:
        episode_id, message = results.errors[0]
        raise RunError(
            f"agent {agent!r} failed in episode {episode_id} ({len(results.errors)} failures; the rest of "
            f"each failing scene group was not run): {message}. {len(records)} finished episodes are kept "
            f"in {partial}; fix the agent and run the same command again to resume"
            + (f" (its output is in {kept_log})" if kept_log else "")
        )
    ordered = [{**records[e.episode_id], "track": track} for e in episodes]
    write_submission(ordered, out)
    partial.unlink()
    return RunSummary(
        out=out,
        episodes=len(ordered),
        resumed=resumed,
        terminations=dict(Counter(str(r.get("termination")) for r in ordered)),
        seconds=time.perf_counter() - started,
        timeouts=results.timeouts,
        log=kept_log,
        track=track,
    )
