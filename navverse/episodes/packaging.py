"""Packaging verified episodes as a dataset version: scene-disjoint splits, difficulty, files and manifest."""

from __future__ import annotations

import fnmatch
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from navverse.dataset import (
    PRIVATE_FORMAT_VERSION,
    PUBLIC_FORMAT_VERSION,
    DatasetError,
    DatasetManifest,
    Episode,
    EpisodeFile,
    Goal,
    counts_table,
    write_json_gz,
)
from navverse.dataset.private import PRIVATE_SPLITS, PrivateSplit, private_dir, private_file_name, withhold
from navverse.files import atomic_write, file_sha256
from navverse.look.settings import LOOK_VERSION

__all__ = ["apply_quota", "assign_splits", "difficulty_of", "difficulty_thresholds", "write_dataset"]


def assign_splits(scene_ids: Sequence[str], patterns: Mapping[str, Sequence[str]]) -> dict[str, list[str]]:
    """Scenes of each split, by glob patterns over scene ids: every scene in exactly one split.

    Raises
    ------
    DatasetError
        If a scene matches no split or several, or a split gets no scene.
    """
    splits: dict[str, list[str]] = {name: [] for name in patterns}
    problems = []
    for scene in sorted(scene_ids):
        matched = [
            name for name, globs in patterns.items() if any(fnmatch.fnmatchcase(scene, g) for g in globs)
        ]
        if len(matched) != 1:
            where = "no split" if not matched else f"the splits {', '.join(matched)}"
            problems.append(f"scene {scene!r} matches {where}")
            continue
        splits[matched[0]].append(scene)
    for name, scenes in splits.items():
        if not scenes and not problems:
            problems.append(f"split {name!r} ({', '.join(patterns[name])}) gets no scene")
    if problems:
        raise DatasetError(
            "splits must put every scene in exactly one split (scene-disjoint): "
            + "; ".join(problems)
            + ". Fix the patterns under package_dataset: splits"
        )
    return splits


def apply_quota(
    episodes: Sequence[Episode],
    splits: Mapping[str, Sequence[str]],
    quota: Mapping[str, Mapping[str, int]],
    *,
    seed: int,
) -> tuple[list[Episode], dict[str, dict[str, dict[str, int]]]]:
    """Keep at most ``quota[split][task]`` episodes of each split and task, spread over the scenes.

    Where a split and task has more episodes than its quota, the scenes give one episode each in
    turn (scenes by id, each scene's episodes in an order drawn from `seed` and the episode id) until
    the quota is met, so every scene keeps about the same share and the choice does not depend on
    the order of `episodes`. Splits and tasks without a quota keep everything.

    Parameters
    ----------
    episodes : sequence of Episode
        The packaged candidates.
    splits : mapping
        Scene ids of each split (from :func:`assign_splits`).
    quota : mapping
        Most episodes per split and task, e.g. ``{"eval": {"objnav": 150}}``.
    seed : int
        Draws the order within each scene.

    Returns
    -------
    kept : list of Episode
        The episodes kept, in the order of `episodes`.
    report : dict
        ``{split: {task: {"available": n, "quota": q, "kept": k}}}`` for every quota given.
    """
    import zlib

    unknown = sorted(set(quota) - set(splits))
    if unknown:
        raise DatasetError(
            f"quota names splits {', '.join(unknown)} that package_dataset: splits does not define "
            f"({', '.join(sorted(splits))})"
        )
    split_of = {scene: split for split, scenes in splits.items() for scene in scenes}
    by_cell: dict[tuple[str, str], dict[str, list[Episode]]] = {}
    for episode in episodes:
        by_cell.setdefault((split_of[episode.scene_id], episode.task), {}).setdefault(
            episode.scene_id, []
        ).append(episode)
    dropped: set[str] = set()
    report: dict[str, dict[str, dict[str, int]]] = {}
    for split, tasks in sorted(quota.items()):
        for task, limit in sorted(tasks.items()):
            by_scene = by_cell.get((split, task), {})
            available = sum(map(len, by_scene.values()))
            queues = [
                sorted(group, key=lambda e: (zlib.crc32(f"{seed}:{e.episode_id}".encode()), e.episode_id))
                for _, group in sorted(by_scene.items())
            ]
            chosen: set[str] = set()
            depth = 0
            while len(chosen) < min(limit, available):
                for queue in queues:
                    if depth < len(queue) and len(chosen) < limit:
                        chosen.add(queue[depth].episode_id)
                depth += 1
            dropped.update(e.episode_id for queue in queues for e in queue if e.episode_id not in chosen)
            report.setdefault(split, {})[task] = {"available": available, "quota": limit, "kept": len(chosen)}
    return [e for e in episodes if e.episode_id not in dropped], report


def difficulty_thresholds(episodes: Sequence[Episode]) -> dict[str, tuple[float, float]]:
    """Per task, the 1/3 and 2/3 quantiles of the geodesic path length (m): Easy / Medium / Hard."""
    lengths: dict[str, list[float]] = {}
    for episode in episodes:
        lengths.setdefault(episode.task, []).append(episode.info.geodesic_distance)
    return {
        task: (round(float(np.quantile(values, 1 / 3)), 3), round(float(np.quantile(values, 2 / 3)), 3))
        for task, values in sorted(lengths.items())
    }


def difficulty_of(length: float, thresholds: tuple[float, float]) -> str:
    """``easy`` below the first threshold, ``medium`` below the second, else ``hard``."""
    return "easy" if length < thresholds[0] else ("medium" if length < thresholds[1] else "hard")


def write_dataset(
    out: Path,
    episodes: Sequence[Episode],
    rollouts: Mapping[str, list[list[float]]],
    *,
    name: str,
    version: str,
    splits: Mapping[str, Sequence[str]],
    embodiment: str,
    recipe: str,
    recipe_hash: str,
    scene_hashes: Mapping[str, str],
    toolkit_version: str,
) -> DatasetManifest:
    """Write ``<split>/<task>.json.gz``, ``<split>/<task>.rollouts.json.gz`` and ``manifest.json``.

    Episodes get their difficulty label; files list episodes by id; the manifest holds the counts per
    split, task and scene type, the difficulty thresholds and the SHA-256 of every file. A split of
    :data:`~navverse.dataset.private.PRIVATE_SPLITS` gets its public episode files (withheld, no
    rollouts) in `out` and its private file beside the version
    (:func:`~navverse.dataset.private.private_dir`), whose SHA-256 the manifest records.
    """
    if not episodes:
        raise DatasetError(f"dataset {name!r} has no episode to package: see the verification's rejections")
    thresholds = difficulty_thresholds(episodes)
    labelled = []
    for e in episodes:
        difficulty = difficulty_of(e.info.geodesic_distance, thresholds[e.task])
        labelled.append(e.model_copy(update={"info": e.info.model_copy(update={"difficulty": difficulty})}))
    split_of = {scene: split for split, scenes in splits.items() for scene in scenes}
    files: dict[str, str] = {}
    groups: dict[tuple[str, str], list[Episode]] = {}
    for episode in sorted(labelled, key=lambda e: e.episode_id):
        groups.setdefault((split_of[episode.scene_id], episode.task), []).append(episode)
    private: dict[str, dict[str, dict]] = {}
    for (split, task), group in sorted(groups.items()):
        content = _episode_file(group)
        group_rollouts = {e.episode_id: rollouts[e.episode_id] for e in group}
        if split in PRIVATE_SPLITS:
            private.setdefault(split, {"files": {}, "rollouts": {}})
            private[split]["files"][task] = content
            private[split]["rollouts"][task] = group_rollouts
            public = _episode_file([withhold(e) for e in group])
            files[f"{split}/{task}.json.gz"] = file_sha256(
                write_json_gz(public.model_dump(mode="json"), out / f"{split}/{task}.json.gz")
            )
            continue
        for relative, data in (
            (f"{split}/{task}.json.gz", content.model_dump(mode="json")),
            (f"{split}/{task}.rollouts.json.gz", group_rollouts),
        ):
            files[relative] = file_sha256(write_json_gz(data, out / relative))
    private_sha256 = {}
    for split, parts in sorted(private.items()):
        record = PrivateSplit(name=name, version=version, split=split, **parts)
        target = private_dir(out) / private_file_name(split)
        private_sha256[split] = file_sha256(write_json_gz(record.model_dump(mode="json"), target))
    manifest = DatasetManifest(
        format_version=PRIVATE_FORMAT_VERSION if private_sha256 else PUBLIC_FORMAT_VERSION,
        name=name,
        version=version,
        toolkit_version=toolkit_version,
        recipe=recipe,
        recipe_hash=recipe_hash,
        embodiment=embodiment,
        scene_hashes=dict(sorted(scene_hashes.items())),
        splits={k: sorted(v) for k, v in sorted(splits.items())},
        counts=counts_table(labelled, splits),
        difficulty_thresholds=thresholds,
        files=files,
        look_version=LOOK_VERSION,
        private=private_sha256,
    )
    with atomic_write(out / "manifest.json") as handle:
        handle.write(manifest.to_json())
    return manifest


def _episode_file(group: Sequence[Episode]) -> EpisodeFile:
    """The episode file of one split and task: its episodes, their goals by scene and category, and
    the task's category ids."""
    goals: dict[str, dict[int, Goal]] = {}
    for episode in group:
        for goal in episode.goals:
            goals.setdefault(f"{episode.scene_id}_{goal.category}", {})[goal.object_id] = goal
    categories = sorted({e.goal_category for e in group})
    return EpisodeFile(
        episodes=list(group),
        goals_by_category={key: [by_id[k] for k in sorted(by_id)] for key, by_id in sorted(goals.items())},
        category_to_task_category_id={c: i for i, c in enumerate(categories)},
    )
