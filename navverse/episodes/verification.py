"""Physics verification of episode candidates (paper Appendix D.2).

Each candidate is executed in PyBullet: the robot is spawned at the start, facing the start yaw, and
follows the reference path's corners with the shared waypoint follower under full physics
(:func:`navverse.sim.rollout.follow_path`). It is accepted only if

* the robot came within the success distance of at least one goal instance at some time (oracle
  success; :func:`navverse.dataset.goal_distance` of the robot base, in 3-D);
* the rollout lasted more than 5 s and at most 100 s (the timeout of generation);
* the robot traveled more than 5 m and less than 50 m;
* no termination ended it (fall, stuck, out of bounds, timeout).

The first unmet condition is the rejection reason. Scenes are verified in parallel processes, each
scene's candidates in order in one world, so results do not depend on the number of processes. A
scene's world gives collision geometry only to the objects within ``object_margin_m`` of one of its
candidates' reference paths (:func:`navverse.sim.world.objects_near`).

Verification renders nothing: how a scene looks (its ``look`` layer and the renderer) is outside
this module's code closure, so changing the look never re-verifies an episode. Pictures along a
rollout are drawn where they are looked at (``navverse review``, ``navverse eval --report``).
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import numpy as np
from pydantic import Field, model_validator

from navverse.processes import end_with_parent
from navverse.records.schema import Episode, Verification, goal_distance
from navverse.settings import Settings

__all__ = ["REASONS", "VerificationResult", "VerificationSettings", "verify_episodes", "verify_scene"]

REASONS = (
    "fall",
    "stuck",
    "out_of_bounds",
    "timeout",
    "no_oracle_success",
    "too_short_duration",
    "too_long_duration",
    "too_short_distance",
    "too_long_distance",
)
"""Rejection reasons, in the order they are checked."""


class VerificationSettings(Settings):
    """Acceptance bounds of a rollout (Appendix D.2) and what to keep of it.

    A rollout must reach a goal instance (oracle success), last more than ``duration_s[0]`` and at
    most ``duration_s[1]`` seconds, travel more than ``traveled_m[0]`` and less than
    ``traveled_m[1]`` meters, and end without a fall, getting stuck or leaving the scene.
    """

    duration_s: tuple[
        Annotated[float, Field(ge=0.0, le=3600.0, description="Seconds, 0 to 3600.")],
        Annotated[float, Field(gt=0.0, le=3600.0, description="Seconds, more than 0, at most 3600.")],
    ] = (5.0, 100.0)
    """A rollout must last longer than the first and at most the second (s of simulated time); the
    second is the timeout: longer rollouts end as ``timeout``."""
    traveled_m: tuple[
        Annotated[float, Field(ge=0.0, le=1000.0, description="Meters, 0 to 1000.")],
        Annotated[float, Field(gt=0.0, le=1000.0, description="Meters, more than 0, at most 1000.")],
    ] = (5.0, 50.0)
    """The executed path must be longer than the first and shorter than the second (m)."""
    object_margin_m: Annotated[float, Field(ge=1.0, le=1000.0)] | None = 10.0
    """Objects whose box is farther than this (m, horizontally) from every reference path of the
    scene's candidates get no collision geometry: the follower keeps the robot within centimetres
    of its path, and one that strays this far has failed already. None (null) loads every object."""

    @model_validator(mode="after")
    def _ordered_bounds(self) -> VerificationSettings:
        for name in ("duration_s", "traveled_m"):
            low, high = getattr(self, name)
            if low >= high:
                raise ValueError(f"{name} must be [lowest, highest], got {[low, high]}")
        return self


@dataclass(frozen=True, eq=False)
class VerificationResult:
    """The outcome of one candidate's rollout."""

    episode_id: str
    reason: str | None  # None: accepted
    verification: Verification
    trajectory: np.ndarray  # (K, 8) rows [t, x, y, z, qx, qy, qz, qw] at 10 Hz

    @property
    def accepted(self) -> bool:
        """Whether the episode passed every check."""
        return self.reason is None


def _oracle_success_time(episode: Episode, trajectory: np.ndarray) -> float | None:
    """First time (s) the base is within the success distance of any goal, None if never."""
    tolerance = episode.info.success_distance
    for row in trajectory:
        if any(goal_distance(row[1:4], goal) <= tolerance for goal in episode.goals):
            return float(row[0])
    return None


def _judge(episode: Episode, termination: str | None, duration: float, traveled: float,
           success_time: float | None, settings: VerificationSettings) -> str | None:  # fmt: skip
    if termination is not None:
        return termination
    if success_time is None:
        return "no_oracle_success"
    shortest, longest = settings.duration_s
    if duration <= shortest:
        return "too_short_duration"
    if duration > longest:
        return "too_long_duration"
    least, most = settings.traveled_m
    if traveled <= least:
        return "too_short_distance"
    if traveled >= most:
        return "too_long_distance"
    return None


def verify_scene(
    scene_dir: str | os.PathLike[str],
    episodes: Sequence[Episode],
    *,
    embodiment: str,
    settings: VerificationSettings | None = None,
    collision_cache: str | Path | None = "default",
    progress: Callable[[int], None] | None = None,
) -> list[VerificationResult]:
    """Roll out the episodes of one scene, in order, in one world.

    Parameters
    ----------
    scene_dir : path
        The built scene directory.
    episodes : sequence of Episode
        Candidates of this scene.
    embodiment : str
        The robot (``spot``, ``turtlebot``...).
    settings : VerificationSettings, optional
        Acceptance bounds (default: the defaults).
    collision_cache : path, "default" or None
        Where convex decompositions are cached (see :class:`~navverse.sim.world.World`).
    progress : callable, optional
        Called with 1 after each episode.
    """
    from navverse.scene.directory import read_scene
    from navverse.sim.embodiments import make_embodiment
    from navverse.sim.rollout import follow_path
    from navverse.sim.simulator import Simulator
    from navverse.sim.terminations import TerminationMonitor
    from navverse.sim.world import World, objects_near

    settings = settings or VerificationSettings()
    results = []
    scene = read_scene(Path(scene_dir))
    object_ids = None
    if settings.object_margin_m is not None:
        paths = [np.asarray(episode.reference_path, dtype=float) for episode in episodes]
        object_ids = objects_near(scene, paths, margin=settings.object_margin_m)
    with World(scene, collision_cache=collision_cache, object_ids=object_ids) as world:
        sim = Simulator(world, make_embodiment(embodiment))
        for episode in episodes:
            sim.spawn(episode.start_position, episode.start_yaw)
            monitor = TerminationMonitor(timeout=settings.duration_s[1], detect_stuck=True)
            rollout = follow_path(sim, np.asarray(episode.reference_path), monitor=monitor)
            trajectory = rollout.trajectory
            success_time = _oracle_success_time(episode, trajectory)
            reason = _judge(
                episode, rollout.termination, rollout.duration, rollout.traveled, success_time, settings
            )
            results.append(
                VerificationResult(
                    episode_id=episode.episode_id,
                    reason=reason,
                    verification=Verification(
                        embodiment=embodiment,
                        duration_s=round(rollout.duration, 3),
                        traveled_m=round(rollout.traveled, 3),
                        oracle_success_time_s=round(success_time, 3) if success_time is not None else -1.0,
                    ),
                    trajectory=trajectory,
                )
            )
            if progress is not None:
                progress(1)
        sim.robot.remove()
    return results


def _verify_task(args: tuple) -> list[VerificationResult]:
    scene_dir, episodes, embodiment, settings = args
    return verify_scene(scene_dir, episodes, embodiment=embodiment, settings=settings)


def verify_episodes(
    episodes: Sequence[Episode],
    scene_dirs: dict[str, Path],
    *,
    embodiment: str,
    settings: VerificationSettings | None = None,
    jobs: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    mapper: Callable[[Callable, list], list] | None = None,
) -> list[VerificationResult]:
    """Verify candidates of many scenes, a process per scene at a time; results in the candidates' order.

    Parameters
    ----------
    episodes : sequence of Episode
        Candidates.
    scene_dirs : dict
        Built scene directory by scene id; every candidate's scene must be there.
    embodiment : str
        The robot.
    settings : VerificationSettings, optional
        Acceptance bounds (default: the defaults).
    jobs : int, optional
        Processes (default: the number of CPUs; 0 or 1 verifies in this process).
    progress : callable, optional
        Called with (scenes done, scenes) as scenes finish.
    mapper : callable, optional
        ``mapper(fn, items) -> [fn(item) for item in items]`` run elsewhere: a build stage's
        ``ctx.map`` (local processes or Ray tasks, as the build runs); then ``jobs`` and ``progress``
        are the mapper's business.
    """
    settings = settings or VerificationSettings()
    by_scene: dict[str, list[Episode]] = {}
    for episode in episodes:
        by_scene.setdefault(episode.scene_id, []).append(episode)
    tasks = [(scene_dirs[scene], eps, embodiment, settings) for scene, eps in sorted(by_scene.items())]
    results: dict[str, VerificationResult] = {}
    if mapper is not None:
        for scene_results in mapper(_verify_task, tasks):
            results.update((r.episode_id, r) for r in scene_results)
        return [results[e.episode_id] for e in episodes]
    jobs = min(len(tasks), os.cpu_count() or 1) if jobs is None else jobs
    done = 0
    if jobs <= 1:
        for task in tasks:
            results.update((r.episode_id, r) for r in _verify_task(task))
            done += 1
            if progress is not None:
                progress(done, len(tasks))
    else:
        context = multiprocessing.get_context("spawn")
        pool = cf.ProcessPoolExecutor(max_workers=jobs, mp_context=context, initializer=end_with_parent)
        with pool:
            futures = [pool.submit(_verify_task, task) for task in tasks]
            for future in cf.as_completed(futures):
                results.update((r.episode_id, r) for r in future.result())
                done += 1
                if progress is not None:
                    progress(done, len(tasks))
    return [results[e.episode_id] for e in episodes]
