"""Submissions (DESIGN.md §3): reading JSONL (or ``.jsonl.gz``) and reporting every problem at once.

One JSON object per line::

    {"episode_id": "office-s1-objnav-0003",
     "trajectory": [[t, x, y, z, qx, qy, qz, qw], ...],   # s, world frame, robot base; t increasing
     "stop": true,                                         # the agent called stop at the last row
     "collisions": [12.3, 40.1],                           # optional: times of non-ground contacts
     "termination": "stop"}                                # optional: what the simulator reported

:func:`read_submission` keeps every record that is valid and lists a :class:`Problem` (line number,
episode id, what is wrong) for every one that is not: unreadable JSON, missing or wrongly typed fields,
unknown or duplicate episode ids (every copy of a duplicate is invalid), rows that are not 8 numbers,
NaN or infinite values, time that does not increase, quaternions that are not unit length. The
evaluator scores the valid records and counts the episodes without one as failures. A file that cannot
be read as text lines at all raises :class:`SubmissionError`.
"""

from __future__ import annotations

import gzip
import json
import os
import zlib
from collections.abc import Collection
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from navverse.errors import NavverseError

__all__ = ["FIELDS", "Problem", "Submission", "SubmissionError", "TrajectoryRecord", "read_submission"]

FIELDS = ("episode_id", "trajectory", "stop", "collisions", "termination")
"""Keys a record may have; the first three are required."""
QUATERNION_TOLERANCE = 1e-3
"""Largest | ||q|| - 1 | accepted."""


class SubmissionError(NavverseError):
    """A submission file cannot be read at all."""


@dataclass(frozen=True)
class Problem:
    """Something wrong with one line of a submission (line numbers start at 1)."""

    line: int
    episode_id: str | None
    message: str

    def __str__(self) -> str:
        where = f"line {self.line}" + (f" ({self.episode_id})" if self.episode_id else "")
        return f"{where}: {self.message}"


@dataclass(frozen=True, eq=False)
class TrajectoryRecord:
    """One valid episode of a submission.

    Attributes
    ----------
    episode_id : str
    trajectory : ndarray of float64, shape (K, 8)
        ``[t, x, y, z, qx, qy, qz, qw]`` rows, ``t`` increasing.
    stop : bool
    collisions : ndarray of float64 or None
        Times of reported non-ground contacts; None when the submission does not say.
    termination : str or None
    line : int
    """

    episode_id: str
    trajectory: np.ndarray
    stop: bool
    collisions: np.ndarray | None
    termination: str | None
    line: int


@dataclass(frozen=True, eq=False)
class Submission:
    """The valid records of a file and the problems of the others."""

    path: Path
    records: dict[str, TrajectoryRecord]
    problems: list[Problem]
    lines: int


def _open_lines(path: Path) -> list[str]:
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise SubmissionError(f"submission {path} does not exist") from None
    except OSError as exc:
        raise SubmissionError(f"cannot read submission {path}: {exc.strerror or exc}") from None
    if raw[:2] == b"\x1f\x8b":
        try:
            raw = gzip.decompress(raw)
        except (OSError, EOFError, zlib.error) as exc:
            raise SubmissionError(f"{path} is a damaged gzip file ({exc}); write it again") from None
    elif path.suffix == ".gz":
        raise SubmissionError(f"{path} ends in .gz but is not gzip-compressed; name it .jsonl or gzip it")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SubmissionError(
            f"{path} is not UTF-8 text (byte {exc.start}): a submission is JSON lines, one episode per line"
        ) from None
    return text.splitlines()


def _check_trajectory(value: Any) -> tuple[np.ndarray | None, str | None]:
    """The trajectory as an array, or why it is not one."""
    if not isinstance(value, list) or not value:
        return None, "trajectory must be a non-empty list of [t, x, y, z, qx, qy, qz, qw] rows"
    widths = [len(row) if isinstance(row, list) else -1 for row in value]
    bad = [i for i, w in enumerate(widths) if w != 8]
    if bad:
        i = bad[0]
        what = "is not a list" if widths[i] < 0 else f"has {widths[i]} values"
        more = f" (and {len(bad) - 1} more rows)" if len(bad) > 1 else ""
        return None, f"trajectory row {i} {what}, not 8 [t, x, y, z, qx, qy, qz, qw]{more}"
    try:
        rows = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        return None, "trajectory rows must hold numbers only"
    finite = np.isfinite(rows).all(axis=1)
    if not finite.all():
        i = int(np.flatnonzero(~finite)[0])
        return None, f"trajectory row {i} holds NaN or infinity ({int((~finite).sum())} such rows)"
    if rows[0, 0] < 0.0:
        return None, f"trajectory time starts at {rows[0, 0]:g} s, before 0"
    steps = np.diff(rows[:, 0])
    if (steps <= 0.0).any():
        i = int(np.flatnonzero(steps <= 0.0)[0]) + 1
        return (
            None,
            f"trajectory time does not increase at row {i} ({rows[i - 1, 0]:g} s then {rows[i, 0]:g} s)",
        )
    norm = np.linalg.norm(rows[:, 4:8], axis=1)
    off = np.abs(norm - 1.0) > QUATERNION_TOLERANCE
    if off.any():
        i = int(np.flatnonzero(off)[0])
        return None, f"trajectory row {i} has a quaternion of length {norm[i]:.4f}, not 1 ([qx, qy, qz, qw])"
    return rows, None


def _check_record(data: Any, line: int) -> tuple[TrajectoryRecord | None, list[str], str | None]:
    """The record, the messages of its problems, and its episode id if one can be read."""
    if not isinstance(data, dict):
        return None, [f"a line must be a JSON object, not {type(data).__name__}"], None
    episode_id = data.get("episode_id")
    messages = []
    if not isinstance(episode_id, str) or not episode_id:
        messages.append("episode_id is missing or not a string")
        episode_id = None
    unknown = sorted(set(data) - set(FIELDS))
    if unknown:
        messages.append(f"unknown keys {unknown} (a record has {', '.join(FIELDS)})")
    trajectory, why = _check_trajectory(data.get("trajectory"))
    if why:
        messages.append(why)
    stop = data.get("stop")
    if not isinstance(stop, bool):
        messages.append("stop must be true or false")
    collisions = data.get("collisions")
    times = None
    if collisions is not None:
        try:
            times = np.array(collisions, dtype=np.float64).reshape(-1)
            if not isinstance(collisions, list) or not np.isfinite(times).all():
                raise ValueError
        except (TypeError, ValueError):
            messages.append("collisions must be a list of finite times (s)")
    termination = data.get("termination")
    if termination is not None and not isinstance(termination, str):
        messages.append("termination must be a string or null")
    if messages:
        return None, messages, episode_id
    record = TrajectoryRecord(episode_id, trajectory, stop, times, termination, line)
    return record, [], episode_id


def read_submission(
    path: str | os.PathLike[str], *, episode_ids: Collection[str] | None = None
) -> Submission:
    """Read a submission, keeping the valid records and listing every problem.

    Parameters
    ----------
    path : path
        A ``.jsonl`` file, optionally gzipped.
    episode_ids : collection of str, optional
        The episodes the submission may hold; others are problems ("unknown episode id").

    Raises
    ------
    SubmissionError
        If the file is missing, not gzip when named ``.gz``, damaged, not UTF-8 text, or has no line
        that is JSON.
    """
    path = Path(path)
    lines = _open_lines(path)
    known = set(episode_ids) if episode_ids is not None else None
    records: dict[str, TrajectoryRecord] = {}
    problems: list[Problem] = []
    seen: dict[str, list[int]] = {}
    parsed = 0
    for number, text in enumerate(lines, start=1):
        if not text.strip():
            continue
        try:
            data = json.loads(text)
        except ValueError as exc:
            problems.append(Problem(number, None, f"not valid JSON ({exc.msg}, column {exc.colno})"))
            continue
        parsed += 1
        record, messages, episode_id = _check_record(data, number)
        if episode_id is not None:
            seen.setdefault(episode_id, []).append(number)
            if known is not None and episode_id not in known:
                messages = [*messages, "unknown episode id: not in the dataset split being scored"]
                record = None
        problems.extend(Problem(number, episode_id, m) for m in messages)
        if record is not None:
            records[record.episode_id] = record
    if parsed == 0 and any(t.strip() for t in lines):
        raise SubmissionError(f"{path} has no line of JSON: a submission is JSON lines, one episode per line")
    for episode_id, numbers in seen.items():
        if len(numbers) > 1:
            others = ", ".join(map(str, numbers))
            for number in numbers:
                problems.append(
                    Problem(number, episode_id, f"duplicate episode id (lines {others}); none is scored")
                )
            records.pop(episode_id, None)
    problems.sort(key=lambda p: (p.line, p.message))
    return Submission(path, records, problems, len(lines))
