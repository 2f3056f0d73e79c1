"""The counts table of a manifest: episodes per split, task and scene type."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from navverse.records.schema import Episode

__all__ = ["counts_table"]


def counts_table(
    episodes: Sequence[Episode], splits: Mapping[str, Sequence[str]]
) -> dict[str, dict[str, dict[str, int]]]:
    """``{split: {task: {scene_type: count}}}`` of episodes, their split given by their scene."""
    split_of = {scene: split for split, scenes in splits.items() for scene in scenes}
    table: dict[str, dict[str, dict[str, int]]] = {}
    for episode in episodes:
        split = split_of[episode.scene_id]
        by_task = table.setdefault(split, {}).setdefault(episode.task, {})
        by_task[episode.scene_type] = by_task.get(episode.scene_type, 0) + 1
    return {
        s: {t: dict(sorted(c.items())) for t, c in sorted(tasks.items())}
        for s, tasks in sorted(table.items())
    }
