"""How many candidates navverse-full samples per scene, from navverse-mini's measured yields.

A part of navverse-mini (``navverse-mini-indoor``, ``navverse-outdoor``, ``navverse-i2o``) asks for
``scenes × episodes_per_scene`` candidates of each task and publishes fewer: sampling can fall short,
verification rejects some, instructions drop some. Its **yield** per task is published / asked. A
part of navverse-full (``navverse-full-indoor``, ``-outdoor``, ``-i2o``) needs, in each split, the
paper's count (``tab:episode_counts``) over the split's scenes; it samples the largest per-scene need
of its splits divided by the yield, times a margin, and ``package_dataset: quota`` keeps the paper's
count. This script derives those numbers from the built navverse-mini parts and compares them with
navverse-full's recipes::

    make episodes                       # builds navverse-mini and its parts
    python scripts/full_sizing.py       # the table; --check exits 1 where a recipe asks for too few

With ``--dataset DIR`` it compares a built or published dataset version with the paper instead: its
episodes per split, task and scene type against ``tab:episode_counts``, cell by cell (exit 1 on any
difference)::

    python scripts/full_sizing.py --dataset episodes/navverse-full/v1.0
"""

from __future__ import annotations

import argparse
import fnmatch
import math
import sys
from collections.abc import Sequence

from rich.console import Console
from rich.table import Table

from pipeline.recipes import RecipeLoader, Target
from pipeline.stage import discover
from pipeline.store import ArtifactStore
from pipeline.workspace import Workspace

# The paper's Table (tab:episode_counts): episodes per task, scene type and split.
PAPER_COUNTS: dict[tuple[str, str], dict[str, int]] = {
    ("objnav", "indoor"): {"train": 2200, "eval": 150},
    ("objnav", "outdoor"): {"train": 700, "eval": 82},
    ("objnav", "i2o"): {"train": 800, "eval": 95},
    ("placenav", "outdoor"): {"train": 1450, "eval": 68},
    ("placenav", "i2o"): {"train": 1400, "eval": 55},
    ("vln", "indoor"): {"train": 850, "eval": 150},
    ("vln", "outdoor"): {"train": 850, "eval": 150},
    ("vln", "i2o"): {"train": 850, "eval": 150},
}
MEASURED_PARTS = {"indoor": "navverse-mini-indoor", "outdoor": "navverse-outdoor", "i2o": "navverse-i2o"}
FULL_PARTS = {
    "indoor": "navverse-full-indoor",
    "outdoor": "navverse-full-outdoor",
    "i2o": "navverse-full-i2o",
}


def stage_params(target: Target, stage: str):
    """The validated parameters of `stage` in `target`."""
    return next(call.params for call in target.stages if call.spec.name == stage)


def linked_scenes(target: Target, targets: dict[str, Target]) -> list[str]:
    """Ids of the scene targets `target` links as ``scene``."""
    patterns = target.links["scene"].targets
    return sorted(t for t in targets if t != target.id and any(fnmatch.fnmatchcase(t, p) for p in patterns))


def scenes_by_split(target: Target, targets: dict[str, Target]) -> dict[str, list[str]]:
    """Linked scenes of each split of `target`'s package_dataset (first matching split)."""
    splits = stage_params(target, "package_dataset").splits
    out: dict[str, list[str]] = {split: [] for split in splits}
    for scene in linked_scenes(target, targets):
        for split, globs in splits.items():
            if any(fnmatch.fnmatchcase(scene, g) for g in globs):
                out[split].append(scene)
                break
    return out


def measured_yields(
    targets: dict[str, Target], store: ArtifactStore
) -> dict[tuple[str, str], tuple[int, int]]:
    """Per (task, scene type): (published, asked) of the built navverse-mini parts.

    Raises
    ------
    SystemExit
        When a part is not built (run ``make episodes`` first).
    """
    out = {}
    for scene_type, part in MEASURED_PARTS.items():
        built = store.target_output(part, "dataset")
        manifest = store.read_manifest(built) if built is not None else None
        if manifest is None:
            raise SystemExit(f"{part} is not built here: run `make episodes` first")
        counts = manifest["stats"]["counts"]
        scenes = len(linked_scenes(targets[part], targets))
        for task, spec in stage_params(targets[part], "sample_episodes").tasks.items():
            published = sum(split.get(task, {}).get(scene_type, 0) for split in counts.values())
            out[(task, scene_type)] = (published, scenes * spec.episodes_per_scene)
    return out


def sizing_rows(targets: dict[str, Target], store: ArtifactStore, *, margin: float) -> list[dict]:
    """One row per (task, scene type) of the paper's table: the yield, per-scene needs, the derived and
    the recipe's candidates per scene, and the recipe's quotas."""
    yields = measured_yields(targets, store)
    rows = []
    for (task, scene_type), wanted in PAPER_COUNTS.items():
        full = targets[FULL_PARTS[scene_type]]
        by_split = scenes_by_split(full, targets)
        published, asked = yields[(task, scene_type)]
        rate = published / asked if asked else 0.0
        need = {split: wanted[split] / max(1, len(by_split.get(split, []))) for split in wanted}
        derived = math.ceil(max(need.values()) / rate * margin) if rate else None
        spec = stage_params(full, "sample_episodes").tasks.get(task)
        quota = stage_params(full, "package_dataset").quota or {}
        rows.append({
            "task": task,
            "scene_type": scene_type,
            "published": published,
            "asked": asked,
            "yield": rate,
            "scenes": {split: len(by_split.get(split, [])) for split in wanted},
            "need_per_scene": need,
            "derived": derived,
            "recipe": spec.episodes_per_scene if spec else 0,
            "quota": {split: quota.get(split, {}).get(task) for split in wanted},
            "paper": wanted,
        })  # fmt: skip
    return rows


def problems(rows: Sequence[dict]) -> list[str]:
    """Where navverse-full's recipes ask for fewer candidates than derived, or set other quotas."""
    out = []
    for row in rows:
        cell = f"{row['task']} {row['scene_type']}"
        if row["derived"] is None:
            out.append(f"{cell}: navverse-mini published none, so no yield is measured")
        elif row["recipe"] < row["derived"]:
            out.append(f"{cell}: the recipe samples {row['recipe']} per scene, {row['derived']} are needed")
        if row["quota"] != row["paper"]:
            out.append(f"{cell}: quota {row['quota']} is not the paper's {row['paper']}")
    return out


def count_differences(counts: dict[str, dict[str, dict[str, int]]]) -> list[tuple[str, str, str, int, int]]:
    """Each (split, task, scene type, paper, dataset) cell where a dataset's manifest ``counts`` differ
    from the paper's, including cells the paper does not have."""
    out = []
    cells = {(split, task, scene_type) for (task, scene_type), by in PAPER_COUNTS.items() for split in by}
    cells |= {
        (s, t, st)
        for s, tasks in counts.items()
        for t, types in tasks.items()
        for st, n in types.items()
        if n
    }
    for split, task, scene_type in sorted(cells):
        paper = PAPER_COUNTS.get((task, scene_type), {}).get(split, 0)
        got = counts.get(split, {}).get(task, {}).get(scene_type, 0)
        if got != paper:
            out.append((split, task, scene_type, paper, got))
    return out


def compare_dataset(path: str) -> int:
    """Print a dataset's counts beside the paper's; 1 if any cell differs."""
    from navverse.dataset import Dataset

    manifest = Dataset(path).manifest
    table = Table(title=f"{manifest.name} v{manifest.version} against tab:episode_counts")
    for column in ("task", "scene type", "paper train", "dataset train", "paper eval", "dataset eval"):
        table.add_column(column, justify="left" if column in ("task", "scene type") else "right")
    for (task, scene_type), paper in PAPER_COUNTS.items():
        got = {split: manifest.counts.get(split, {}).get(task, {}).get(scene_type, 0) for split in paper}
        table.add_row(
            task, scene_type, str(paper["train"]), str(got["train"]), str(paper["eval"]), str(got["eval"])
        )
    Console(width=120).print(table)
    differing = count_differences(manifest.counts)
    for split, task, scene_type, paper, got in differing:
        print(f"  {split} {task} {scene_type}: {got} episodes, the paper has {paper}")
    if not differing:
        print("every cell equals the paper's")
    return 1 if differing else 0


def main(argv: Sequence[str] | None = None) -> int:
    """Print the sizing table; with ``--check``, the exit status says whether the recipes agree."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--margin", type=float, default=1.15, help="candidates beyond the need (1.15)")
    parser.add_argument("--check", action="store_true", help="exit 1 when a recipe asks for too few")
    parser.add_argument("--dataset", metavar="DIR", help="compare a dataset version's counts with the paper")
    args = parser.parse_args(argv)
    if args.dataset:
        return compare_dataset(args.dataset)
    workspace = Workspace.find()
    loader = RecipeLoader(workspace, stages=discover("stages"))
    targets = {t.id: t for t in loader.load()}
    rows = sizing_rows(targets, ArtifactStore(workspace.built_dir), margin=args.margin)
    table = Table(title=f"navverse-full candidates per scene (margin {args.margin})")
    for column in ("task", "scene type", "mini published / asked", "yield", "scenes train / eval",
                   "paper train / eval", "need per scene", "derived", "recipe", "quota"):  # fmt: skip
        table.add_column(column)
    for row in rows:
        table.add_row(
            row["task"],
            row["scene_type"],
            f"{row['published']} / {row['asked']}",
            f"{row['yield']:.3f}",
            f"{row['scenes']['train']} / {row['scenes']['eval']}",
            f"{row['paper']['train']} / {row['paper']['eval']}",
            " / ".join(f"{v:.1f}" for v in row["need_per_scene"].values()),
            str(row["derived"]),
            str(row["recipe"]),
            " / ".join(str(v) for v in row["quota"].values()),
        )
    Console(width=160).print(table)
    found = problems(rows)
    for line in found:
        print(f"  {line}")
    return 1 if args.check and found else 0


if __name__ == "__main__":
    sys.exit(main())
