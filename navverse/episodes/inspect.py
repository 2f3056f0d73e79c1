"""Looking at a dataset: its count tables, one episode drawn on its scene, and replaying its rollouts."""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from rich.table import Table

from navverse.dataset import Dataset, Episode
from navverse.scene_types import SCENE_TYPES

if TYPE_CHECKING:
    from navverse.episodes.sampling import SamplingSettings
    from navverse.episodes.verification import VerificationSettings

__all__ = [
    "ReplayReport",
    "category_table",
    "check_bounds",
    "counts_table",
    "draw_episode",
    "replay",
    "scenes_table",
]


def counts_table(dataset: Dataset) -> Table:
    """Episodes per split and task, by scene type (the paper's episode-count table)."""
    manifest = dataset.manifest
    scene_types = SCENE_TYPES
    table = Table(title=f"{manifest.name} v{manifest.version}: episodes ({manifest.embodiment})")
    for column in ("split", "task", *scene_types, "total"):
        table.add_column(column, justify="right" if column in (*scene_types, "total") else "left")
    totals = Counter()
    for split, tasks in manifest.counts.items():
        for task, by_type in tasks.items():
            row = [by_type.get(t, 0) for t in scene_types]
            totals.update(dict(zip(scene_types, row, strict=True)))
            table.add_row(split, task, *map(str, row), str(sum(row)))
    table.add_row("all", "", *(str(totals[t]) for t in scene_types), str(sum(totals.values())), style="bold")
    return table


def scenes_table(dataset: Dataset) -> Table:
    """Scenes per split, by scene type (each scene's type is that of its episodes)."""
    types = {e.scene_id: e.scene_type for e in dataset.episodes()}
    table = Table(title="scenes")
    for column in ("split", *SCENE_TYPES, "total"):
        table.add_column(column, justify="left" if column == "split" else "right")
    totals: Counter[str] = Counter()
    for split, scenes in dataset.manifest.splits.items():
        row = Counter(types.get(scene, "no episodes") for scene in scenes)
        totals.update(row)
        table.add_row(split, *(str(row[t]) for t in SCENE_TYPES), str(len(scenes)))
    table.add_row("all", *(str(totals[t]) for t in SCENE_TYPES), str(sum(totals.values())), style="bold")
    return table


def category_table(dataset: Dataset, *, top: int = 25) -> Table:
    """Goal categories: episodes per category and task, most frequent first."""
    counts: dict[str, Counter] = {}
    for episode in dataset.episodes():
        counts.setdefault(episode.goal_category, Counter())[episode.task] += 1
    tasks = sorted({t for c in counts.values() for t in c})
    table = Table(title=f"goal categories ({len(counts)})")
    table.add_column("category")
    for task in tasks:
        table.add_column(task, justify="right")
    table.add_column("total", justify="right")
    ranked = sorted(counts.items(), key=lambda item: (-sum(item[1].values()), item[0]))
    for category, by_task in ranked[:top]:
        table.add_row(category, *(str(by_task.get(t, 0)) for t in tasks), str(sum(by_task.values())))
    if len(ranked) > top:
        rest = ranked[top:]
        table.add_row(
            f"... {len(rest)} more", *("" for _ in tasks), str(sum(sum(c.values()) for _, c in rest))
        )
    return table


def _circle(x: float, y: float, r: float, n: int = 48) -> np.ndarray:
    a = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    return np.stack([x + r * np.cos(a), y + r * np.sin(a)], axis=1)


def _footprint(obj) -> np.ndarray:
    """Corners (4, 2) of an object annotation's oriented footprint."""
    c, s = math.cos(obj.yaw), math.sin(obj.yaw)
    hx, hy = obj.size[0] / 2.0, obj.size[1] / 2.0
    local = np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])
    return local @ np.array([[c, s], [-s, c]]) + np.asarray(obj.center[:2])


def _polyline(points: np.ndarray) -> np.ndarray:
    return np.stack([points[:-1], points[1:]], axis=1) if len(points) > 1 else np.zeros((0, 2, 2))


def draw_episode(
    scene_dir: Path, episode: Episode, rollout: Sequence[Sequence[float]] | None, out: Path
) -> Path:
    """The scene's bird's-eye view with the episode: start and heading, goals with their success
    circles, the reference path and the verification rollout; for VLN, the instruction's landmarks and
    where along the rollout each directive was carried out."""
    from navverse.scene.bev import BevOverlay, render_bev
    from navverse.scene.directory import read_scene

    overlays = []
    if episode.info is not None:  # else a private split's public record: no goals, no reference path
        goals = [
            _circle(g.position[0], g.position[1], g.radius + episode.info.success_distance)
            for g in episode.goals
        ]
        rims = np.concatenate([_polyline(np.vstack([c, c[:1]])) for c in goals])
        overlays.append(
            BevOverlay(
                "goal: success distance",
                rims,
                color="tab:green",
                linewidth=1.2,
                polygons=goals,
                fill_alpha=0.2,
            )
        )
        reference = np.asarray(episode.reference_path)[:, :2]
        overlays.append(BevOverlay("reference path", _polyline(reference), color="tab:blue", linewidth=1.6))
    if rollout:
        poses = np.asarray(rollout)[:, 1:3]
        overlays.append(
            BevOverlay("verification rollout", _polyline(poses), color="tab:orange", linewidth=1.2)
        )
    scene = read_scene(scene_dir)
    if episode.instruction is not None and episode.instruction.landmarks:
        objects = {o.id: o for o in scene.annotations.objects}
        outlines = [_footprint(objects[lm.object_id]) for lm in episode.instruction.landmarks]
        edges = np.concatenate([_polyline(np.vstack([o, o[:1]])) for o in outlines])
        overlays.append(BevOverlay("instruction landmark", edges, color="tab:pink", linewidth=2.2))
        if rollout:
            rows = np.asarray(rollout)
            at = np.searchsorted(rows[:, 0], episode.instruction.directive_times).clip(0, len(rows) - 1)
            marks = [_circle(px, py, 0.18) for px, py in rows[at, 1:3]]
            overlays.append(BevOverlay("instruction step", polygons=marks, color="black", fill_alpha=0.7))
    x, y = episode.start_position[:2]
    yaw = episode.start_yaw
    tip = (x + 0.8 * math.cos(yaw), y + 0.8 * math.sin(yaw))
    arrow = [[(x, y), tip]]
    for side in (-1.0, 1.0):
        back = yaw + math.pi + side * math.radians(25)
        arrow.append([tip, (tip[0] + 0.35 * math.cos(back), tip[1] + 0.35 * math.sin(back))])
    overlays.append(BevOverlay("start and heading", np.asarray(arrow), color="tab:red", linewidth=2.0,
                               polygons=[_circle(x, y, 0.25)], fill_alpha=0.8))  # fmt: skip
    out.parent.mkdir(parents=True, exist_ok=True)
    render_bev(scene, out, overlays=overlays)
    return out


@dataclass
class ReplayReport:
    """Outcome of replaying episodes' oracle rollouts under physics."""

    replayed: int = 0
    reached: int = 0
    failures: list[tuple[str, str]] = field(default_factory=list)  # (episode id, reason)
    bound_violations: list[tuple[str, str]] = field(default_factory=list)


def check_bounds(
    episode: Episode,
    *,
    sampling: SamplingSettings | None = None,
    verification: VerificationSettings | None = None,
) -> str | None:
    """Why an episode breaks the dataset's distance or duration bounds, None if it keeps them.

    The bounds are those of the settings the dataset was sampled and verified with: the geodesic
    distance within ``sampling.path_length``, the rollout's duration within
    ``verification.duration_s`` and its length within ``verification.traveled_m`` (the settings'
    defaults when not given).
    """
    from navverse.episodes.sampling import SamplingSettings
    from navverse.episodes.verification import VerificationSettings

    path_length = (sampling or SamplingSettings()).path_length
    verification = verification or VerificationSettings()
    duration_s, traveled_m = verification.duration_s, verification.traveled_m
    info = episode.info
    if not path_length[0] <= info.geodesic_distance <= path_length[1]:
        return f"geodesic distance {info.geodesic_distance} m outside {list(path_length)}"
    v = info.verification
    if v is None:
        return "no verification"
    if not duration_s[0] < v.duration_s <= duration_s[1]:
        return f"duration {v.duration_s} s outside ({duration_s[0]}, {duration_s[1]}]"
    if not traveled_m[0] < v.traveled_m < traveled_m[1]:
        return f"traveled {v.traveled_m} m outside ({traveled_m[0]}, {traveled_m[1]})"
    if not 0.0 <= v.oracle_success_time_s <= v.duration_s:
        return "no oracle success during the rollout"
    return None


def replay(
    episodes: Sequence[Episode],
    scene_dirs: Mapping[str, Path],
    *,
    embodiment: str,
    jobs: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> ReplayReport:
    """Run each episode's oracle rollout again from the packaged episode; check it reaches a goal.

    ``progress(scenes done, scenes)`` is called as scenes finish (see
    :func:`~navverse.episodes.verification.verify_episodes`).
    """
    from navverse.episodes.verification import verify_episodes

    report = ReplayReport()
    for episode in episodes:
        reason = check_bounds(episode)
        if reason is not None:
            report.bound_violations.append((episode.episode_id, reason))
    results = verify_episodes(
        list(episodes), dict(scene_dirs), embodiment=embodiment, jobs=jobs, progress=progress
    )
    for result in results:
        report.replayed += 1
        terminated = result.reason in ("fall", "stuck", "out_of_bounds", "timeout")
        if result.verification.oracle_success_time_s >= 0.0 and not terminated:
            report.reached += 1
        else:
            report.failures.append((result.episode_id, result.reason or "?"))
    return report
