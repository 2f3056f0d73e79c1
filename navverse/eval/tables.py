"""Evaluation outputs: ``metrics.json``, Markdown and CSV tables in the layout of the paper's tables.

Tables (Markdown in ``tables.md``, each also as ``<name>.csv``):

* ``task_scene`` — SR / SPL / SoftSPL / OS / NE per task × scene type (the paper's Table 2);
* ``safety_efficiency`` — CR, ADO, NSR, CE per scene type (Table 3);
* ``failures`` — #Fail and the shares of wrong goal, fall and timeout (and invalid) per task (Table 4);
* ``difficulty`` — SR / SPL per task × difficulty, with the thresholds (Table 5);
* ``transition`` — per task over the indoor-to-outdoor episodes: Ind-Only, Reach-Out, CE before and
  after the exit, and the post-exit failures' shares of wrong goal, fall and timeout (the paper's
  stage-wise transition table); written only when the split has indoor-to-outdoor episodes;
* ``episodes.csv`` — one row per episode.

``instruction_types.md`` and ``.csv`` (and the ``instruction_types`` key of ``metrics.json``) hold the
paper's PlaceNav instruction-type table: SR and SPL over all, outdoor and indoor-to-outdoor PlaceNav
episodes, with their numbers, for each submission scored (one per instruction type: Store Category,
VLN Instruction, Intention Driven); written only when the split has PlaceNav episodes.

Every table ends with an ``all`` row: the overall means, or for ``transition`` those of the
indoor-to-outdoor episodes (the ``scene_type`` group ``i2o``).
"""

from __future__ import annotations

import csv
import io
import json
import os
from collections.abc import Sequence
from pathlib import Path

from navverse.dataset import INSTRUCTION_TYPES
from navverse.eval.metrics import METRICS
from navverse.eval.protocol import describe
from navverse.eval.scoring import EvalResult
from navverse.files import atomic_write

__all__ = [
    "INSTRUCTION_TYPE_NAMES",
    "TABLES",
    "cell_text",
    "has_table",
    "instruction_type_entries",
    "instruction_type_table",
    "provenance_lines",
    "scope_text",
    "table_rows",
    "write_outputs",
]

PERCENT = {"success", "spl", "soft_success", "soft_spl", "os", "cr", "nsr", "sdtw", "ndtw", "ind_only",
           "reach_out", "post_exit_wrong_goal", "post_exit_fall", "post_exit_timeout"}  # fmt: skip
TABLES = {
    "task_scene": ("task_scene_type", ("success", "spl", "soft_spl", "os", "ne")),
    "safety_efficiency": ("scene_type", ("cr", "ado", "nsr", "ce")),
    "failures": ("task", ("failures", "wrong_goal_share", "fall_share", "timeout_share", "invalid_share")),
    "difficulty": ("task_difficulty", ("success", "spl", "soft_spl")),
    "transition": ("i2o_task", ("ind_only", "reach_out", "ce_pre_exit", "ce_post_exit", "post_exit_failures",
                                "post_exit_wrong_goal", "post_exit_fall", "post_exit_timeout")),
}  # fmt: skip
TOTALS = {"i2o_task": ("scene_type", "i2o")}
"""The group of the ``all`` row of a grouping's table, when not the overall one."""
GROUP_NAMES = {"task_scene_type": "task / scene", "scene_type": "scene type", "task": "task",
               "task_difficulty": "task / difficulty", "i2o_task": "task (i2o)"}  # fmt: skip
HEADERS = {
    "success": "SR (%)", "spl": "SPL (%)", "soft_spl": "SoftSPL (%)", "os": "OS (%)", "ne": "NE (m)",
    "cr": "CR (%)", "ado": "ADO (m)", "nsr": "NSR (%)", "ce": "CE (cells/m)", "failures": "#Fail",
    "wrong_goal_share": "wrong goal (%)", "fall_share": "fall (%)", "timeout_share": "timeout (%)",
    "invalid_share": "invalid (%)", "ind_only": "Ind-Only (%)", "reach_out": "Reach-Out (%)",
    "ce_pre_exit": "CE pre-exit (cells/m)", "ce_post_exit": "CE post-exit (cells/m)",
    "post_exit_failures": "#post-exit fail", "post_exit_wrong_goal": "post-exit wrong goal (%)",
    "post_exit_fall": "post-exit fall (%)", "post_exit_timeout": "post-exit timeout (%)",
}  # fmt: skip


INSTRUCTION_TYPE_NAMES = {"category": "Store Category", "route": "VLN Instruction",
                          "intention": "Intention Driven"}  # fmt: skip
"""The paper's name of each PlaceNav instruction type (the rows of its instruction-type table)."""
INSTRUCTION_TYPE_SCENES = (
    ("all", "All", "task", "placenav"),
    ("outdoor", "Outdoor", "task_scene_type", "placenav/outdoor"),
    ("i2o", "Indoor-to-Outdoor", "task_scene_type", "placenav/i2o"),
)
"""The column groups of the instruction-type table: key, title, and the grouping and group of
:attr:`EvalResult.groups <navverse.eval.scoring.EvalResult>` their values are read from."""
INSTRUCTION_TYPE_METRICS = ("success", "spl")


def cell_text(name: str, value: float | None) -> str:
    """A metric value as a table shows it: percentages for rates, counts as integers, "–" if undefined."""
    if value is None:
        return "–"
    if name in PERCENT or name.endswith("_share"):
        return f"{100.0 * value:.1f}"
    if name in ("failures", "post_exit_failures"):
        return str(int(value))
    return f"{value:.2f}"


def has_table(result: EvalResult, table: str) -> bool:
    """Whether a table has any group to show (``transition`` needs indoor-to-outdoor episodes)."""
    return bool(result.groups.get(TABLES[table][0]))


def table_rows(
    result: EvalResult, table: str, *, n_columns: bool = False
) -> tuple[list[str], list[list[str]]]:
    """Header and rows of one of :data:`TABLES` (the last row is the ``all`` one, see :data:`TOTALS`).

    A metric defined on fewer episodes than its row's shows its own N: in the cell as ``(n=...)``, or,
    with `n_columns` (for CSV files a program reads), as an ``N`` column after every metric.
    """
    grouping, columns = TABLES[table]
    header = [GROUP_NAMES[grouping], "episodes"]
    for c in columns:
        header += [HEADERS.get(c, c), *([f"{HEADERS.get(c, c)} N"] if n_columns and _has_n(c) else [])]
    rows = []
    total_grouping, total_key = TOTALS.get(grouping, ("overall", "all"))
    groups = dict(result.groups.get(grouping, {}))
    total = result.groups.get(total_grouping, {}).get(total_key)
    if total is not None:
        groups["all"] = total
    for key, entry in groups.items():
        row = [key, str(entry["episodes"])]
        for c in columns:
            if n_columns:
                row += [cell_text(c, entry.get(c)), *([str(entry.get(f"{c}_n", 0))] if _has_n(c) else [])]
            else:
                row.append(_cell(c, entry))
        rows.append(row)
    return header, rows


def _has_n(name: str) -> bool:
    """Whether a column is a metric with its own N (label shares and counts are over the row's episodes)."""
    return name in METRICS


def _cell(name: str, entry: dict) -> str:
    """A metric's cell: its value, and its own N when it is defined on fewer episodes than the row's."""
    text = cell_text(name, entry.get(name))
    n = entry.get(f"{name}_n")
    return text if n is None or n == entry["episodes"] or entry.get(name) is None else f"{text} (n={n})"


def scope_text(result: EvalResult) -> str:
    """What a result's numbers are over, in one sentence (partial scoring said as such)."""
    scope = result.scope
    if not scope:
        return ""
    split, total, scored = scope.get("split", "?"), scope["split_episodes"], scope["scored"]
    if result.partial:
        return (
            f"PARTIAL: scored over the {scored} submitted episodes of the {total} in split {split} "
            "(--episodes submitted); not comparable with a full scoring."
        )
    missing = scope.get("missing", 0)
    tail = f"; {missing} without a valid record count as failures" if missing else ""
    return f"Scored over all {total} episodes of split {split}{tail}."


def provenance_lines(result: EvalResult) -> list[str]:
    """The lines under a table's title: what was scored, the track, and how N is shown."""
    lines = [scope_text(result)] if result.scope else []
    lines.append(f"Track: {describe(result.track)}.")
    lines.append(
        "N: `episodes` is the row's episode count; a metric defined on fewer of them (trajectory measures "
        "need a valid record, exit metrics a start indoors) shows its own as (n=...)."
    )
    return lines


def instruction_type_entries(results: Sequence[EvalResult]) -> list[dict]:
    """The PlaceNav instruction-type table's rows as data, one per result with an instruction type.

    Parameters
    ----------
    results : sequence of EvalResult
        Scorings of submissions of one split, each under its own instruction type
        (:attr:`EvalResult.instruction_type`; results without one are left out).

    Returns
    -------
    list of dict
        In the order of :data:`~navverse.dataset.INSTRUCTION_TYPES`: ``instruction_type``, ``name``
        (:data:`INSTRUCTION_TYPE_NAMES`), ``submission``, and for ``all``, ``outdoor`` and ``i2o``
        PlaceNav episodes ``{"episodes": n, "success": SR, "spl": SPL}`` (rates in 0..1; None when
        there are no such episodes), read from the results' groups.
    """
    chosen = [r for r in results if r.instruction_type in INSTRUCTION_TYPES]
    chosen.sort(key=lambda r: INSTRUCTION_TYPES.index(r.instruction_type))
    entries = []
    for result in chosen:
        entry: dict = {
            "instruction_type": result.instruction_type,
            "name": INSTRUCTION_TYPE_NAMES[result.instruction_type],
            "submission": result.submission,
            "track": describe(result.track),
        }
        for key, _, grouping, group in INSTRUCTION_TYPE_SCENES:
            values = result.groups.get(grouping, {}).get(group, {})
            entry[key] = {"episodes": int(values.get("episodes", 0))}
            entry[key].update({name: values.get(name) for name in INSTRUCTION_TYPE_METRICS})
        entries.append(entry)
    return entries


def instruction_type_table(entries: Sequence[dict]) -> tuple[list[str], list[list[str]]]:
    """Header and rows of the instruction-type table (from :func:`instruction_type_entries`): the
    paper's row names, then N, SR (%) and SPL (%) for all, outdoor and indoor-to-outdoor episodes."""
    header = ["instruction type"]
    for _, title, _, _ in INSTRUCTION_TYPE_SCENES:
        header += [f"{title} N", *(f"{title} {HEADERS[name]}" for name in INSTRUCTION_TYPE_METRICS)]
    rows = []
    for entry in entries:
        row = [entry["name"]]
        for key, *_ in INSTRUCTION_TYPE_SCENES:
            cells = entry[key]
            row += [str(cells["episodes"]), *(cell_text(n, cells[n]) for n in INSTRUCTION_TYPE_METRICS)]
        rows.append(row)
    return header, rows


def _markdown(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def _write_csv(path: Path, header: Sequence[str], rows: Sequence[Sequence[object]]) -> None:
    text = io.StringIO(newline="")
    writer = csv.writer(text)
    writer.writerow(header)
    writer.writerows(rows)
    _write_text(path, text.getvalue())


def _write_text(path: Path, text: str) -> None:
    with atomic_write(path) as handle:
        handle.write(text.encode("utf-8"))


def _write_instruction_types(out: Path, entries: Sequence[dict]) -> None:
    """``instruction_types.md`` and ``.csv`` of the entries; without entries, removes earlier ones."""
    if not entries:
        for suffix in ("md", "csv"):
            (out / f"instruction_types.{suffix}").unlink(missing_ok=True)
        return
    header, rows = instruction_type_table(entries)
    _write_csv(out / "instruction_types.csv", header, rows)
    parts = ["# PlaceNav by instruction type", "", _markdown(header, rows), ""]
    parts += ["SR and SPL in %, over the PlaceNav episodes; N: episodes scored. Submissions:", ""]
    parts += [
        f"- {e['name']} ({e['instruction_type']}): {e['submission'] or 'unknown'}, track {e['track']}"
        for e in entries
    ]
    _write_text(out / "instruction_types.md", "\n".join(parts) + "\n")


def write_outputs(
    result: EvalResult, out: str | os.PathLike[str], *, meta: dict, others: Sequence[EvalResult] = ()
) -> Path:
    """Write ``metrics.json``, ``tables.md``, one CSV per table and ``episodes.csv`` into `out`.

    A table without groups (``transition`` for a split without indoor-to-outdoor episodes) is left out,
    and a CSV of it from an earlier run in `out` is removed. When the split has PlaceNav episodes, the
    instruction-type table of `result` and `others` (the same split scored under the other instruction
    types) is written too (:func:`instruction_type_entries`); every other output is `result`'s.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    entries = instruction_type_entries([result, *others]) if result.instruction_type is not None else []
    metrics = {
        "meta": meta,
        "scope": result.scope,
        "track": result.track,
        "definitions": {n: m.description for n, m in METRICS.items() if not n.startswith("_")},
        "overall": result.groups["overall"]["all"],
        **{k: v for k, v in result.groups.items() if k != "overall"},
        "difficulty_thresholds": {k: list(v) for k, v in result.difficulty_thresholds.items()},
        **({"instruction_types": entries} if entries else {}),
        "problems": result.problems,
        "episodes": result.episodes,
    }
    _write_text(out / "metrics.json", json.dumps(metrics, indent=1, sort_keys=False) + "\n")
    parts = [f"# Evaluation of {meta.get('submission', 'a submission')}", "", *provenance_lines(result), ""]
    for table in TABLES:
        if not has_table(result, table):
            (out / f"{table}.csv").unlink(missing_ok=True)
            continue
        _write_csv(out / f"{table}.csv", *table_rows(result, table, n_columns=True))
        header, rows = table_rows(result, table)
        parts += [f"## {table.replace('_', ' ')}", "", _markdown(header, rows), ""]
    if result.difficulty_thresholds:
        parts.append(
            "Difficulty by geodesic length: "
            + "; ".join(
                f"{t}: easy < {a:.2f} m <= medium < {b:.2f} m <= hard"
                for t, (a, b) in sorted(result.difficulty_thresholds.items())
            )
        )
    _write_text(out / "tables.md", "\n".join(parts) + "\n")
    _write_instruction_types(out, entries)
    if result.episodes:
        names = list(result.episodes[0])
        _write_csv(out / "episodes.csv", names, [[row[n] for n in names] for row in result.episodes])
    return out
