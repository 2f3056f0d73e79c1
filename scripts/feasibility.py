"""The feasibility diagnostic (the paper's ``tab:feasibility``): SR and SPL of the reference agents by
task and scene type.

Each agent (``oracle``: the reference path; ``gt_goal``: a navmesh plan to the closest goal;
``frontier``: exploration with depth and the semantic sensor; ``random``: random discrete actions) runs
over a split of a dataset with ``navverse run-agent``'s runner, its submission is scored, and the table
gives SR, SPL (and N) per task × scene type and agent::

    python scripts/feasibility.py --dataset episodes/navverse-mini/v2.2 --split eval --out feasibility
    python scripts/feasibility.py --dataset ... --agents oracle random --limit 30   # a quicker look

With ``--limit`` each agent runs that many episodes spread over the split and is scored over them
(``--episodes submitted``: the table says N). Submissions are kept in ``--out`` and reused when present
(delete them to run again); the table is written as ``feasibility.md`` and ``feasibility.json``.
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
from navverse.eval.scoring import EvalResult, score
from navverse.eval.submission import read_submission
from pipeline.workspace import Workspace

AGENTS = ("oracle", "gt_goal", "frontier", "random")
_ORDER = {"objnav": 0, "placenav": 1, "vln": 2, "indoor": 0, "outdoor": 1, "i2o": 2}


def run_and_score(
    dataset: Dataset, agent: str, *, split: str, scene_dirs: dict, out: Path, limit: int | None, jobs: int
) -> EvalResult:
    """The agent's submission on the split (run unless kept in ``out``), scored."""
    path = out / f"{agent}.jsonl.gz"
    if not path.is_file():
        run_agent(dataset, agent=agent, split=split, embodiment=dataset.manifest.embodiment,
                  scene_dirs=scene_dirs, out=path, jobs=jobs, limit=limit)  # fmt: skip
    ids = [e.episode_id for e in dataset.episodes(split=split)]
    submission = read_submission(path, episode_ids=ids)
    which = "submitted" if limit is not None else "all"
    return score(dataset, submission, split=split, scene_dirs=scene_dirs, episodes=which)


def feasibility_rows(results: dict[str, EvalResult]) -> list[dict]:
    """One row per task × scene type: per agent its SR, SPL and N (None where the agent ran no such
    episode)."""
    keys = sorted(
        {k for r in results.values() for k in r.groups.get("task_scene_type", {})},
        key=lambda k: tuple(_ORDER.get(p, 9) for p in k.split("/")),
    )
    rows = []
    for key in [*keys, "all"]:
        task, _, scene_type = key.partition("/")
        row: dict = {"task": task, "scene_type": scene_type or "all"}
        for agent, result in results.items():
            group = (
                result.groups["overall"]["all"] if key == "all" else result.groups["task_scene_type"].get(key)
            )
            row[agent] = (
                None
                if group is None
                else {"sr": group["success"], "spl": group["spl"], "n": group["episodes"]}
            )
        rows.append(row)
    return rows


def _sr_spl(cell: dict) -> str:
    """A cell's SR and SPL in percent."""
    return f"{100 * cell['sr']:.1f} / {100 * cell['spl']:.1f}"


def markdown(rows: list[dict], agents: Sequence[str]) -> str:
    """The table in Markdown: SR / SPL (%) with N per agent."""
    lines = ["| task | scene type | " + " | ".join(f"{a} SR / SPL (%)" for a in agents) + " |"]
    lines.append("|" + "---|" * (2 + len(agents)))
    for row in rows:
        cells = ["–" if row[a] is None else f"{_sr_spl(row[a])} (n={row[a]['n']})" for a in agents]
        lines.append(f"| {row['task']} | {row['scene_type']} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    """Run and score every agent, print and save the table; the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dataset", required=True, help="episodes/<name>/v<version>")
    parser.add_argument("--split", default="eval", help="the split run (default: eval)")
    parser.add_argument(
        "--agents", nargs="+", default=list(AGENTS), help="built-in agents (default: all four)"
    )
    parser.add_argument("--limit", type=int, default=None, help="episodes per agent, spread over the split")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="processes per run")
    parser.add_argument("--scenes", action="append", default=[], help="where to look for scenes first")
    parser.add_argument("--out", default="feasibility", help="folder for submissions and the table")
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
        out.mkdir(parents=True, exist_ok=True)
        results = {}
        for agent in args.agents:
            console.print(
                f"{agent} on {dataset.manifest.name} v{dataset.manifest.version} / {args.split} ..."
            )
            results[agent] = run_and_score(
                dataset,
                agent,
                split=args.split,
                scene_dirs=scene_dirs,
                out=out,
                limit=args.limit,
                jobs=args.jobs,
            )
    except NavverseError as exc:
        Console(stderr=True).print(f"error: {exc}", style="red", markup=False, highlight=False)
        return 1
    rows = feasibility_rows(results)
    name = f"{dataset.manifest.name} v{dataset.manifest.version}"
    table = Table(title=f"feasibility: SR / SPL (%) on {name} / {args.split}")
    for column in ("task", "scene type", *args.agents):
        table.add_column(column, justify="left" if column in ("task", "scene type") else "right")
    for row in rows:
        cells = ("–" if row[a] is None else f"{_sr_spl(row[a])} ({row[a]['n']})" for a in args.agents)
        table.add_row(row["task"], row["scene_type"], *cells)
    console.print(table)
    (out / "feasibility.json").write_text(json.dumps(rows, indent=2) + "\n")
    (out / "feasibility.md").write_text(markdown(rows, args.agents))
    return 0


if __name__ == "__main__":
    sys.exit(main())
