"""What a stage run made, in one short line for the build summary.

A stage declares the figures that say what it made (``@stage(..., summary=...)``): keys of the stats
it records with ``ctx.record``, which every artifact's manifest keeps under ``stats``. The line is
made from those stats alone, so a run reused from the cache is described from its artifact's
manifest just as a run of this build is from its result.

Values are shown by kind: a number as it is (a float rounded to three significant digits, or to a
whole number from 100 up), text as it is, a list by its length, and a dict of counts (numbers, or
dicts of them) as its total followed by its largest entries, e.g. ``dropped 3 (not a closed ring 2,
degenerate geometry 1)``; a dict of anything else lists its entries. A key the stats lack is left
out.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["MAX_ENTRIES", "describe_stats", "stats_value"]

MAX_ENTRIES = 4
"""Entries of a dict of counts shown (the largest); the others are counted as ``+N more``."""


def describe_stats(stats: Mapping[str, Any], fields: Sequence[tuple[str, str]]) -> str:
    """The summary line of a run: ``label value`` for each declared field its stats have.

    Parameters
    ----------
    stats : mapping
        What the run recorded (``ctx.record``; a manifest's ``stats``).
    fields : sequence of (str, str)
        ``(label, key)`` pairs (:attr:`pipeline.stage.StageSpec.summary`); a key may be a dotted
        path into nested dicts.

    Returns
    -------
    str
        E.g. ``buildings 23, dropped 2 (not a closed ring 2), road km 2.59``; empty when no field
        is found.
    """
    parts = []
    for label, key in fields:
        value = stats_value(stats, key)
        if value is not None:
            parts.append(f"{label} {_show(value)}")
    return ", ".join(parts)


def stats_value(stats: Mapping[str, Any], key: str) -> Any:
    """The value at the dotted path ``key`` of ``stats``, or None where it leads nowhere."""
    value: Any = stats
    for part in key.split("."):
        if not isinstance(value, Mapping) or part not in value:
            return None
        value = value[part]
    return value


def _show(value: Any) -> str:
    if isinstance(value, Mapping):
        return _show_mapping(value)
    if isinstance(value, (list, tuple)):
        return str(len(value))
    if _is_number(value):
        return _number(value)
    return str(value)


def _show_mapping(value: Mapping[str, Any]) -> str:
    if not value:
        return "0"
    counts = _counts(value)
    if counts is None:  # not counts: the entries as they are
        entries = (f"{key} {_show(item)}" for key, item in value.items() if item is not None)
        return f"({', '.join(entries)})"
    ranked = sorted(((key, n) for key, n in counts.items() if n), key=lambda entry: -entry[1])
    shown = [f"{key} {_number(n)}" for key, n in ranked[:MAX_ENTRIES]]
    if len(ranked) > MAX_ENTRIES:
        shown.append(f"+{len(ranked) - MAX_ENTRIES} more")
    total = _number(sum(counts.values()))
    return f"{total} ({', '.join(shown)})" if shown else total


def _counts(value: Mapping[str, Any]) -> dict[str, float] | None:
    """``{key: count}`` of a dict of counts (a nested dict counts as its total); None if not counts."""
    counts: dict[str, float] = {}
    for key, item in value.items():
        if _is_number(item):
            counts[str(key)] = item
        elif isinstance(item, Mapping) and (inner := _counts(item)) is not None:
            counts[str(key)] = sum(inner.values())
        else:
            return None
    return counts


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _number(value: float) -> str:
    if isinstance(value, int) or not math.isfinite(value):
        return str(value)
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    if abs(value) >= 100:
        return f"{value:.0f}"
    return f"{value:.3g}"
