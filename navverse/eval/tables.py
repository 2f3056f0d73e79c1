"""Evaluation outputs: ``metrics.json``, Markdown and CSV tables in the layout of the paper's tables.

Tables (Markdown in ``tables.md``, each also as ``<name>.csv``):

* ``task_scene`` — SR / SPL / SoftSPL / OS / NE per task × scene type (the paper's Table 2);
* ``safety_efficiency`` — CR, ADO, NSR, CE per scene type (Table 3);
* ``failures`` — #Fail and the shares of wrong goal, fall and timeout (and invalid) per task (Table 5;
  here over all the row's episodes);
* ``difficulty`` — SR / SPL per task × difficulty, with the thresholds (Table 6);
* ``transition`` — per task over the indoor-to-outdoor episodes: Ind-Only, Reach-Out, CE before and
  after the exit, and the post-exit failures' shares of wrong goal, fall and timeout (the paper's
  stage-wise transition table, Table 4); written only when the split has indoor-to-outdoor episodes;
* ``episodes.csv`` — one row per episode.

Every value carries its n, the number of episodes it is over: the ``episodes`` column is the row's, and
a metric defined on fewer of them shows its own, as ``(n=...)`` in Markdown or an ``N`` column in CSV.
After the tables, ``tables.md`` defines every column they show (:func:`glossary_markdown`, from the
declarations of :mod:`navverse.eval.metrics`) and lists the scored episode ids
(:func:`scored_episode_groups`).

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
import textwrap
from collections.abc import Iterable, Sequence
from pathlib import Path

from navverse.dataset import INSTRUCTION_TYPES
from navverse.eval.metrics import METRICS, STATISTICS, Metric, Statistic, definition
from navverse.eval.protocol import describe
from navverse.eval.scoring import EvalResult
from navverse.files import atomic_write

__all__ = [
    "HEADERS",
    "INSTRUCTION_TYPE_NAMES",
    "PERCENT",
    "TABLES",
    "cell_text",
    "glossary",
    "glossary_markdown",
    "has_table",
    "instruction_type_entries",
    "instruction_type_table",
    "provenance_lines",
    "scope_text",
    "scored_episode_groups",
    "shown_columns",
    "table_rows",
    "write_outputs",
]

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
DEFINED: dict[str, Metric | Statistic] = {
    **{name: spec for name, spec in METRICS.items() if not name.startswith("_")},
    **STATISTICS,
}
"""Every value a table can show, by name: the public metrics and the group statistics."""


def _header(spec: Metric | Statistic) -> str:
    """A column's name: the abbreviation, with the unit in parentheses when it has one."""
    return f"{spec.abbreviation} ({spec.unit})" if spec.unit else spec.abbreviation


HEADERS = {name: _header(spec) for name, spec in DEFINED.items()}
"""Column name of each metric and statistic (``SR (%)``), from its declaration."""
PERCENT = frozenset(name for name, spec in DEFINED.items() if spec.unit == "%")
"""The rates: shown in %."""
COUNTS = frozenset(name for name, spec in STATISTICS.items() if not spec.unit)
"""The counts of episodes: shown as integers."""
ROW_N = "episodes"
"""The column holding a row's n (its number of episodes)."""
WRAP = 100
"""Width of the lists of episode ids in ``tables.md``."""


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
    if name in PERCENT:
        return f"{100.0 * value:.1f}"
    if name in COUNTS:
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
    header = [GROUP_NAMES[grouping], ROW_N]
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


def shown_columns(result: EvalResult) -> list[str]:
    """The metrics and statistics the tables of `result` show, each once, in table order (tables without
    groups left out, as :func:`write_outputs` leaves them out)."""
    names: dict[str, None] = {}
    for table, (_, columns) in TABLES.items():
        if has_table(result, table):
            names.update(dict.fromkeys(columns))
    return list(names)


def glossary(names: Iterable[str]) -> list[dict[str, str]]:
    """The definitions of the named metrics and statistics, each once, in the order given.

    Returns
    -------
    list of dict
        ``name`` (the key in ``metrics.json``), ``column`` (the name in the tables, :data:`HEADERS`),
        ``title`` (the full name), ``description`` (one line) and ``better`` (``higher`` or ``lower``).

    Raises
    ------
    KeyError
        If a name is neither a registered metric nor a group statistic.
    """
    entries = []
    for name in dict.fromkeys(names):
        spec = definition(name)
        entries.append(
            {
                "name": name,
                "column": HEADERS[name],
                "title": spec.title,
                "description": spec.description,
                "better": "higher" if spec.higher_is_better else "lower",
            }
        )
    return entries


def glossary_markdown(names: Iterable[str]) -> str:
    """A Markdown table defining the named metrics and statistics (:func:`glossary`): column, full name,
    definition, which way is better, and the key in ``metrics.json`` and ``episodes.csv``."""
    lines = ["| column | full name | definition | better | key |", "|---|---|---|---|---|"]
    for e in glossary(names):
        cells = [e["column"], e["title"], e["description"], e["better"]]
        lines.append("| " + " | ".join(_md_cell(c) for c in cells) + f" | `{e['name']}` |")
    return "\n".join(lines)


def _md_cell(text: str) -> str:
    """Text for a Markdown table cell: on one line, pipes escaped."""
    return " ".join(text.split()).replace("|", "\\|")


def scored_episode_groups(result: EvalResult) -> list[tuple[str, list[str]]]:
    """The ids of the scored episodes by task / scene type, in the order of the ``task_scene`` table.

    Returns
    -------
    list of (str, list of str)
        The group (``objnav/indoor``) and its episode ids, sorted.
    """
    groups: dict[str, list[str]] = {}
    for row in result.episodes:
        groups.setdefault(f"{row['task']}/{row['scene_type']}", []).append(str(row["episode_id"]))
    order = list(result.groups.get("task_scene_type", {}))
    keys = [k for k in order if k in groups] + sorted(set(groups) - set(order))
    return [(key, sorted(groups[key])) for key in keys]


def _id_block(ids: Sequence[str]) -> list[str]:
    """Episode ids as a fenced block of comma-separated lines (ids are never split)."""
    text = textwrap.fill(", ".join(ids), width=WRAP, break_long_words=False, break_on_hyphens=False)
    return ["```text", text, "```"]


def _scored_markdown(result: EvalResult) -> list[str]:
    """The ``Scored episodes`` section of ``tables.md``: every scored id, by task / scene type, and
    those without a valid record again on their own."""
    count = len(result.episodes)
    split = result.scope.get("split")
    where = f" of split {split}" if split else ""
    parts = [
        "## Scored episodes",
        "",
        f"The {count} episodes{where} in the means above, by task / scene type (ids sorted).",
        "",
    ]
    for key, ids in scored_episode_groups(result):
        parts += [f"### {key.replace('/', ' / ')} ({len(ids)})", "", *_id_block(ids), ""]
    invalid = sorted(str(r["episode_id"]) for r in result.episodes if r["label"] == "invalid")
    if invalid:
        parts += [
            f"### without a valid record, scored as failures ({len(invalid)})",
            "",
            *_id_block(invalid),
            "",
        ]
    return parts


def _definition_json(spec: Metric | Statistic) -> dict:
    """A metric's or statistic's declaration as ``metrics.json`` holds it."""
    return {
        "title": spec.title,
        "abbreviation": spec.abbreviation,
        "description": spec.description,
        "formula": spec.formula,
        "unit": spec.unit,
        "reference": spec.reference,
        "higher_is_better": spec.higher_is_better,
    }


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
        "n: `episodes` is the row's episode count, the n of every value in the row; a metric defined on "
        "fewer of them (trajectory measures need a valid record, exit metrics a start indoors) shows its "
        "own as (n=...). Every column is defined under Metrics, after the tables."
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


_GLOSSARY_NOTE = (
    "Each column of the tables above. A value is the mean over its n episodes (`episodes`, or its own "
    "(n=...)) of the per-episode value defined here, except the counts (#); rates are in %."
)


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
    parts += ["", "## Metrics", "", glossary_markdown(INSTRUCTION_TYPE_METRICS)]
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
        "definitions": {n: _definition_json(m) for n, m in METRICS.items() if not n.startswith("_")},
        "statistic_definitions": {n: _definition_json(s) for n, s in STATISTICS.items()},
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
        parts.append("")
    shown = shown_columns(result)
    if shown:
        parts += ["## Metrics", "", _GLOSSARY_NOTE, "", glossary_markdown(shown), ""]
    parts += _scored_markdown(result)
    _write_text(out / "tables.md", "\n".join(parts).rstrip("\n") + "\n")
    _write_instruction_types(out, entries)
    if result.episodes:
        names = list(result.episodes[0])
        _write_csv(out / "episodes.csv", names, [[row[n] for n in names] for row in result.episodes])
    return out
