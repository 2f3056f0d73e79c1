"""What the API and the pages show of submissions: a submission's view, and the leaderboard.

The leaderboard of a split holds, per team and track, the team's best public submission that is
scored: the highest overall SPL, then SR, then the earliest. Its entries are ranked the same way.
"""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Iterable, Mapping
from datetime import datetime, timezone
from typing import Any

__all__ = ["best_entries", "iso_time", "overall", "rank_key", "submission_view", "track_text"]


def iso_time(seconds: float | None) -> str | None:
    """Unix seconds as ISO 8601 in UTC, to the second (``2025-05-01T12:00:00Z``); None stays None."""
    if seconds is None:
        return None
    return datetime.fromtimestamp(seconds, timezone.utc).isoformat(timespec="seconds").replace("+00:00", "Z")


def track_text(track: Mapping[str, Any]) -> str:
    """A track in one line: ``standard (depth, rgb)``, or ``unspecified``."""
    from navverse.eval.protocol import describe

    return describe(dict(track))


def _result(row: sqlite3.Row) -> dict:
    return json.loads(row["result"]) if row["result"] else {}


def submission_view(row: sqlite3.Row) -> dict:
    """A submission as ``GET /api/submissions/<id>`` shows it to its team: ids, status, times, track,
    instruction type; ``metrics`` (the public group means with their N) and ``scope`` when done,
    ``error`` when failed."""
    view: dict[str, Any] = {
        "id": row["id"],
        "name": row["name"],
        "split": row["split"],
        "public": bool(row["public"]),
        "status": row["status"],
        "created": iso_time(row["created"]),
        "scored": iso_time(row["scored_at"]),
        "track": json.loads(row["track"]),
        "instruction_type": row["instruction_type"],
    }
    if row["status"] == "done":
        result = _result(row)
        view["metrics"] = result.get("groups", {})
        view["scope"] = result.get("scope", {})
    if row["status"] == "failed":
        view["error"] = row["error"]
    return view


def overall(metrics: Mapping[str, Any]) -> Mapping[str, Any]:
    """The ``all`` group of a result's ``overall`` grouping (empty if absent)."""
    return metrics.get("overall", {}).get("all", {})


def rank_key(view: Mapping[str, Any]) -> tuple[float, float, str, str]:
    """Sort key of a scored submission: the highest overall SPL, then SR, then the earliest."""
    total = overall(view.get("metrics", {}))
    spl, sr = total.get("spl"), total.get("success")
    return (
        -(spl if spl is not None else -1.0),
        -(sr if sr is not None else -1.0),
        view["created"],
        view["id"],
    )


def best_entries(rows: Iterable[sqlite3.Row]) -> list[dict]:
    """The leaderboard of public scored submissions `rows`: per team and track name, the best
    (:func:`rank_key`), ranked; each entry a submission's view with ``team``, ``rank`` and
    ``track_text``."""
    best: dict[tuple[str, str], dict] = {}
    for row in rows:
        view = submission_view(row)
        view["team"] = row["team"]
        key = (row["team"], str(view["track"].get("name", "unspecified")))
        if key not in best or rank_key(view) < rank_key(best[key]):
            best[key] = view
    entries = sorted(best.values(), key=rank_key)
    for rank, entry in enumerate(entries, start=1):
        entry["rank"] = rank
        entry["track_text"] = track_text(entry["track"])
    return entries
