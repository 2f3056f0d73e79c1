"""A toy dataset version written by hand for the evaluator's tests: the episodes given, split ``eval``
over the scenes ``tiny_room`` and ``tiny_room_b``, with a manifest the reader verifies."""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path

from navverse.dataset import (
    FORMAT_VERSION,
    Dataset,
    Episode,
    EpisodeFile,
    counts_table,
    write_json_gz,
)
from navverse.files import file_sha256


def write_toy_dataset(
    root: Path, episodes: Sequence[Episode], *, thresholds: Mapping[str, list[float]] | None = None
) -> Dataset:
    """Write `episodes` as ``eval/<task>.json.gz`` files and their manifest under `root`; open it."""
    tasks = sorted({e.task for e in episodes})
    for task in tasks:
        chosen = [e for e in episodes if e.task == task]
        write_json_gz(EpisodeFile(episodes=chosen).model_dump(mode="json"), root / "eval" / f"{task}.json.gz")
    splits = {"eval": ["tiny_room", "tiny_room_b"]}
    files = {name: file_sha256(root / name) for name in (f"eval/{task}.json.gz" for task in tasks)}
    manifest = {
        "format_version": FORMAT_VERSION, "name": "toy", "version": "1.0", "toolkit_version": "0.1.0",
        "recipe": "recipes/datasets/toy.yaml", "recipe_hash": "0" * 64, "embodiment": "spot",
        "scene_hashes": {}, "splits": splits, "counts": counts_table(episodes, splits),
        "difficulty_thresholds": dict(thresholds or {}), "files": files,
    }  # fmt: skip
    (root / "manifest.json").write_text(json.dumps(manifest))
    return Dataset(root)
