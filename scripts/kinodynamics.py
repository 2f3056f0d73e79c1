"""The embodiment and friction diagnostic (the paper's ``tab:robot_performance_main``).

The ``oracle`` agent follows every reference path of a split with each robot, with every terrain
class's friction set to each μ, and the table gives SR and mean speed (path length / duration) per
scene type and over all:

    python scripts/kinodynamics.py --dataset episodes/navverse-mini/v2.2 --split eval --out kinodynamics

SR is given twice: with the robot's own success distance (1.0 + r_robot) and with the episode's (the
one its goal regions were built for, the dataset's embodiment): a path that ends at the edge of a
Spot goal region does not bring a robot of smaller r_robot within its own, smaller, success distance.
Submissions are kept in ``--out``, in a folder per dataset version, split and limit named with the
dataset's manifest checksum, and reused when present (delete them to run again): a dataset rebuilt
under the same version, or another dataset or split, runs afresh.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from rich.console import Console
from rich.table import Table

from navverse.dataset import Dataset
from navverse.errors import NavverseError
from navverse.eval.runner import run_agent
from navverse.eval.scoring import score
from navverse.eval.submission import read_submission
from navverse.scene_types import SCENE_TYPES
from pipeline.workspace import Workspace


def _rows(robot: str, mu: float, own: list[dict], by_episode: list[dict]) -> list[dict]:
    """Per scene type (and ``all``): episodes run, SR with the robot's own and with the episode's success
    distance, falls and mean speed, over the episodes with a valid trajectory."""
    episode_label = {r["episode_id"]: r["label"] for r in by_episode}
    run = [r for r in own if r["label"] != "invalid"]
    rows = []
    for scene_type in [*sorted({r["scene_type"] for r in run}, key=SCENE_TYPES.index), "all"]:
        group = [r for r in run if scene_type in ("all", r["scene_type"])]
        if not group:  # no valid trajectory at all: nothing to tell
            continue
        reached = sum(episode_label[r["episode_id"]] == "success" for r in group)
        rows.append({
            "robot": robot,
            "friction": mu,
            "scene_type": scene_type,
            "episodes": len(group),
            "sr_own_tolerance": sum(r["label"] == "success" for r in group) / len(group),
            "sr_episode_tolerance": reached / len(group),
            "falls": sum(r["label"] == "fall" for r in group),
            "mean_speed": sum(r["speed"] for r in group) / len(group),
        })  # fmt: skip
    return rows


def _runs_folder(dataset: Dataset, *, split: str, limit: int | None) -> str:
    """The folder of a dataset version's runs on a split: its name, version, split, episode limit and
    the first 12 digits of its manifest's checksum (the dataset's content)."""
    every = "all" if limit is None else f"limit{limit}"
    name = f"{dataset.manifest.name}-v{dataset.manifest.version}"
    return f"{name}-{split}-{every}-{dataset.manifest_sha256[:12]}"


def main(argv: Sequence[str] | None = None) -> int:
    """Run the oracle per robot and friction, score it, print and save the table; the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dataset", required=True, help="episodes/<name>/v<version>")
    parser.add_argument("--split", default="eval")
    parser.add_argument("--robots", nargs="+", default=["spot", "turtlebot"])
    parser.add_argument("--friction", nargs="+", type=float, default=[0.5, 1.0])
    parser.add_argument("--limit", type=int, default=None, help="episodes per run, spread over the split")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--scenes", action="append", default=[], help="where to look for scenes first")
    parser.add_argument("--out", default="kinodynamics", help="folder for submissions and the table")
    args = parser.parse_args(argv)
    console = Console()
    try:
        dataset = Dataset(args.dataset)
        dataset.verify()
        scene_dirs = dataset.scene_dirs(
            dataset.episodes(split=args.split),
            search=args.scenes,
            built_dir=lambda: Workspace.find().built_dir,
        )
        out = Path(args.out)
        runs = out / _runs_folder(dataset, split=args.split, limit=args.limit)
        runs.mkdir(parents=True, exist_ok=True)
        rows = []
        for robot in args.robots:
            for mu in args.friction:
                submission_path = runs / f"oracle-{robot}-mu{mu:g}.jsonl.gz"
                if not submission_path.is_file():
                    console.print(f"oracle with {robot} at μ = {mu:g} ...")
                    run_agent(dataset, agent="oracle", split=args.split, embodiment=robot,
                              scene_dirs=scene_dirs, out=submission_path, jobs=args.jobs, limit=args.limit,
                              terrain_friction=mu)  # fmt: skip
                ids = [e.episode_id for e in dataset.episodes(split=args.split)]
                submission = read_submission(submission_path, episode_ids=ids)
                scored = {
                    who: score(dataset, submission, split=args.split, scene_dirs=scene_dirs, embodiment=who)
                    for who in (robot, dataset.manifest.embodiment)
                }
                rows += _rows(robot, mu, scored[robot].episodes, scored[dataset.manifest.embodiment].episodes)
    except NavverseError as exc:
        Console(stderr=True).print(f"error: {exc}", style="red", markup=False, highlight=False)
        return 1
    table = Table(
        title=f"oracle execution on {dataset.manifest.name} v{dataset.manifest.version} / {args.split}"
    )
    for column in (
        "robot",
        "μ",
        "scene type",
        "episodes",
        "SR own tol. (%)",
        "SR episode tol. (%)",
        "falls",
        "speed (m/s)",
    ):
        table.add_column(column, justify="left" if column == "robot" else "right")
    for row in rows:
        table.add_row(row["robot"], f"{row['friction']:g}", row["scene_type"], str(row["episodes"]),
                      f"{100 * row['sr_own_tolerance']:.1f}", f"{100 * row['sr_episode_tolerance']:.1f}",
                      str(row["falls"]), f"{row['mean_speed']:.2f}")  # fmt: skip
    console.print(table)
    (out / "kinodynamics.json").write_text(json.dumps(rows, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
