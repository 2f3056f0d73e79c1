"""Evaluation outputs: ``metrics.json``, Markdown and CSV tables in the layout of the paper's tables.

Tables (Markdown in ``tables.md``, each also as ``<name>.csv``):

* ``task_scene`` — SR / SPL / SoftSPL / OS / NE per task × scene type (the paper's Table 2);
* ``safety_efficiency`` — CR, ADO, NSR, CE per scene type (Table 3);
* ``failures`` — #Fail and the shares of wrong goal, fall and timeout (and invalid) per task (Table 4);
* ``difficulty`` — SR / SPL per task × difficulty, with the thresholds (Table 5);
* ``episodes.csv`` — one row per episode.
"""

from __future__ import annotations

import csv
import json
import os
from collections.abc import Sequence
from pathlib import Path

from navverse.eval.metrics import METRICS
from navverse.eval.scoring import EvalResult

__all__ = ["TABLES", "table_rows", "write_outputs"]

PERCENT = {"success", "spl", "soft_success", "soft_spl", "os", "cr", "nsr", "sdtw", "ndtw"}
TABLES = {
    "task_scene": ("task_scene_type", ("success", "spl", "soft_spl", "os", "ne")),
    "safety_efficiency": ("scene_type", ("cr", "ado", "nsr", "ce")),
    "failures": ("task", ("failures", "wrong_goal_share", "fall_share", "timeout_share", "invalid_share")),
    "difficulty": ("task_difficulty", ("success", "spl", "soft_spl")),
}
GROUP_NAMES = {"task_scene_type": "task / scene", "scene_type": "scene type", "task": "task",
               "task_difficulty": "task / difficulty"}  # fmt: skip
HEADERS = {
    "success": "SR (%)", "spl": "SPL (%)", "soft_spl": "SoftSPL (%)", "os": "OS (%)", "ne": "NE (m)",
    "cr": "CR (%)", "ado": "ADO (m)", "nsr": "NSR (%)", "ce": "CE (cells/m)", "failures": "#Fail",
    "wrong_goal_share": "wrong goal (%)", "fall_share": "fall (%)", "timeout_share": "timeout (%)",
    "invalid_share": "invalid (%)",
}  # fmt: skip


def _cell(name: str, value: float | None) -> str:
    if value is None:
        return "–"
    if name in PERCENT or name.endswith("_share"):
        return f"{100.0 * value:.1f}"
    if name == "failures":
        return str(int(value))
    return f"{value:.2f}"


def table_rows(result: EvalResult, table: str) -> tuple[list[str], list[list[str]]]:
    """Header and rows of one of :data:`TABLES` (the last row is the overall one)."""
    grouping, columns = TABLES[table]
    header = [GROUP_NAMES[grouping], "episodes"]
    header += [HEADERS.get(c, c) for c in columns]
    rows = []
    groups = {**result.groups[grouping], "all": result.groups["overall"]["all"]}
    for key, entry in groups.items():
        rows.append([key, str(entry["episodes"]), *(_cell(c, entry.get(c)) for c in columns)])
    return header, rows


def _markdown(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def _write_csv(path: Path, header: Sequence[str], rows: Sequence[Sequence[object]]) -> None:
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        writer.writerows(rows)


def write_outputs(result: EvalResult, out: str | os.PathLike[str], *, meta: dict) -> Path:
    """Write ``metrics.json``, ``tables.md``, one CSV per table and ``episodes.csv`` into `out`."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    metrics = {
        "meta": meta,
        "definitions": {n: m.description for n, m in METRICS.items() if not n.startswith("_")},
        "overall": result.groups["overall"]["all"],
        **{k: v for k, v in result.groups.items() if k != "overall"},
        "difficulty_thresholds": {k: list(v) for k, v in result.difficulty_thresholds.items()},
        "problems": result.problems,
        "episodes": result.episodes,
    }
    (out / "metrics.json").write_text(json.dumps(metrics, indent=1, sort_keys=False) + "\n")
    parts = [f"# Evaluation of {meta.get('submission', 'a submission')}", ""]
    for table in TABLES:
        header, rows = table_rows(result, table)
        _write_csv(out / f"{table}.csv", header, rows)
        parts += [f"## {table.replace('_', ' ')}", "", _markdown(header, rows), ""]
    if result.difficulty_thresholds:
        parts.append(
            "Difficulty by geodesic length: "
            + "; ".join(
                f"{t}: easy < {a:.2f} m <= medium < {b:.2f} m <= hard"
                for t, (a, b) in sorted(result.difficulty_thresholds.items())
            )
        )
    (out / "tables.md").write_text("\n".join(parts) + "\n")
    if result.episodes:
        names = list(result.episodes[0])
        _write_csv(out / "episodes.csv", names, [[row[n] for n in names] for row in result.episodes])
    return out
