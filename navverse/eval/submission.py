"""Submissions (DESIGN.md §3): reading JSONL (or ``.jsonl.gz``) and reporting every problem at once.

One JSON object per line::

    {"episode_id": "office-s1-objnav-0003",
     "trajectory": [[t, x, y, z, qx, qy, qz, qw], ...],   # s, world frame, robot base; t increasing
     "stop": true,                                         # the agent called stop at the last row
     "collisions": [12.3, 40.1],                           # optional: times of non-ground contacts
     "termination": "stop",                                # optional: what the simulator reported
     "instruction_type": "route",                          # optional, PlaceNav: the instruction given
     "track": {"name": "standard", "sensors": ["depth", "rgb"], "privileged": false}}  # optional

``instruction_type`` is one of :data:`~navverse.dataset.INSTRUCTION_TYPES` (``category``, ``route``,
``intention``: which of a PlaceNav episode's instructions the agent was given; absent or null means
``category``). The evaluator reads it on PlaceNav records only; all of a submission's must agree.
``track`` says which sensors and privileges the agent used (:mod:`navverse.eval.protocol`; the runner
writes it); all of a submission's records must agree.

:func:`read_submission` keeps every record that is valid and lists a :class:`Problem` (line number,
episode id, what is wrong) for every one that is not: unreadable JSON, missing or wrongly typed fields
(``true``/``false`` are not numbers), unknown or duplicate episode ids (every copy of a duplicate is
invalid), rows that are not 8 numbers, NaN or infinite values, time that does not increase, quaternions
that are not unit length, positions farther than :data:`MAX_ABS_COORD` from the origin or, when the
scenes are known, outside the scene's bounds grown by :data:`BOUNDS_MARGIN` (:func:`episode_bounds`).
The evaluator scores the valid records and counts the episodes without one as failures.

A submission is read as a stream, a line at a time, within the caps of :class:`Limits`: a line longer
than :data:`MAX_LINE_BYTES`, nested deeper than :data:`MAX_DEPTH`, or with more rows or values than a
record may have is a problem of that line (checked before the line is parsed); a file of more than
:data:`MAX_TEXT_BYTES` (after decompression) or :data:`MAX_LINES` lines, or whose valid records hold
more than :data:`MAX_KEPT_ROWS` rows in all, raises :class:`SubmissionError`, as does a file that cannot
be read as UTF-8 text lines at all. Only the valid trajectories are kept, as float arrays; at most
:data:`MAX_PROBLEMS` problems are listed (:attr:`Submission.omitted` counts the others).
"""

from __future__ import annotations

import gzip
import itertools
import json
import os
import re
import zlib
from collections.abc import Collection, Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from navverse.dataset import INSTRUCTION_TYPES
from navverse.errors import NavverseError
from navverse.eval.protocol import check_track

if TYPE_CHECKING:
    from navverse.dataset import Episode

__all__ = [
    "BOUNDS_MARGIN",
    "FIELDS",
    "MAX_ABS_COORD",
    "MAX_COLLISIONS",
    "MAX_DEPTH",
    "MAX_KEPT_ROWS",
    "MAX_LINES",
    "MAX_LINE_BYTES",
    "MAX_PROBLEMS",
    "MAX_ROWS",
    "MAX_TEXT_BYTES",
    "MAX_TEXT_CHARS",
    "Box",
    "Limits",
    "Problem",
    "Submission",
    "SubmissionError",
    "TrajectoryRecord",
    "episode_bounds",
    "read_submission",
]

FIELDS = ("episode_id", "trajectory", "stop", "collisions", "termination", "instruction_type", "track")
"""Keys a record may have; the first three are required."""
QUATERNION_TOLERANCE = 1e-3
"""Largest | ||q|| - 1 | accepted."""

MAX_TEXT_BYTES = 256 * 2**20
"""Largest submission: 256 MiB of text (after decompression, for a gzipped file). A 10 Hz trajectory of
300 s written at full float precision is about 0.5 MB."""
MAX_LINE_BYTES = 32 * 2**20
"""Longest line (32 MiB): room for :data:`MAX_ROWS` rows at full float precision."""
MAX_LINES = 1_000_000
"""Most lines in a submission, blank ones included."""
MAX_ROWS = 100_000
"""Most rows in one trajectory: 10 Hz for 2.8 hours (episodes are scored up to 300 s)."""
MAX_COLLISIONS = 500_000
"""Most collision times in one record (contacts are logged per 50 Hz control tick)."""
MAX_DEPTH = 32
"""Deepest nesting of JSON arrays and objects on a line (a record nests 3 deep: object, trajectory,
row); checked before parsing, so deep nesting is a problem of its line, never a RecursionError."""
MAX_TEXT_CHARS = 200
"""Longest ``episode_id`` and ``termination`` string."""
MAX_KEPT_ROWS = 4_000_000
"""Most rows kept over all valid records (256 MiB as float64); beyond it the file is refused."""
MAX_PROBLEMS = 10_000
"""Most problems listed; the others are only counted (:attr:`Submission.omitted`)."""
MAX_ABS_COORD = 1e5
"""Largest |x|, |y| or |z| of a position (m), checked with or without the scenes' bounds."""
BOUNDS_MARGIN = 50.0
"""How far outside its scene's bounds (m, on every axis) a position may be (:func:`episode_bounds`)."""

_GZIP_MAGIC = b"\x1f\x8b"
_SKIP_CHUNK = 2**20
"""Bytes read at a time when skipping a line that is too long."""
_SIZE_CHUNK = 2**18
"""Bytes decompressed at a time when measuring a gzip file's text."""
_SCAN_BYTES = 2**18
"""Bytes of a line scanned at once by :func:`_structure`."""
_STEP = np.zeros(256, dtype=np.int8)  # +1 opens an array or object, -1 closes one
_STEP[list(b"[{")] = 1
_STEP[list(b"]}")] = -1
_CLOSED_STRING = re.compile(rb'"[^"]*"')
"""A string of a line without backslashes (linear: it cannot backtrack over a quote)."""
_NOT_BRACKETS = bytes(sorted(set(range(256)) - set(b"[]{}")))
_PLAIN_BYTES_PER_QUOTE = 16
"""A line with more quotes than one per this many bytes is scanned with numpy: cutting out millions of
strings one at a time is slower."""


class SubmissionError(NavverseError):
    """A submission file cannot be read at all."""


@dataclass(frozen=True)
class Limits:
    """Caps on what a submission may hold; every field defaults to the module constant of its name.

    Attributes
    ----------
    text_bytes, line_bytes, lines, rows, collisions, depth, kept_rows, problems : int
        :data:`MAX_TEXT_BYTES`, :data:`MAX_LINE_BYTES`, :data:`MAX_LINES`, :data:`MAX_ROWS`,
        :data:`MAX_COLLISIONS`, :data:`MAX_DEPTH`, :data:`MAX_KEPT_ROWS`, :data:`MAX_PROBLEMS`.
    abs_coord : float
        :data:`MAX_ABS_COORD`.
    """

    text_bytes: int = MAX_TEXT_BYTES
    line_bytes: int = MAX_LINE_BYTES
    lines: int = MAX_LINES
    rows: int = MAX_ROWS
    collisions: int = MAX_COLLISIONS
    depth: int = MAX_DEPTH
    kept_rows: int = MAX_KEPT_ROWS
    problems: int = MAX_PROBLEMS
    abs_coord: float = MAX_ABS_COORD


@dataclass(frozen=True)
class Box:
    """Where an episode's positions may be: an axis-aligned box (m, world frame) and what it is."""

    low: tuple[float, ...]
    high: tuple[float, ...]
    name: str


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
    instruction_type : str or None
        The PlaceNav instruction type the record says its agent was given (one of
        :data:`~navverse.dataset.INSTRUCTION_TYPES`); None when it does not say.
    track : dict or None
        The sensors and privileges its agent used (:mod:`navverse.eval.protocol`); None when it does
        not say.
    """

    episode_id: str
    trajectory: np.ndarray
    stop: bool
    collisions: np.ndarray | None
    termination: str | None
    line: int
    instruction_type: str | None = None
    track: dict | None = None


@dataclass(frozen=True, eq=False)
class Submission:
    """The valid records of a file and the problems of the others.

    ``omitted`` counts the problems found beyond the first :attr:`Limits.problems`, which are listed.
    """

    path: Path
    records: dict[str, TrajectoryRecord]
    problems: list[Problem]
    lines: int
    omitted: int = 0


def episode_bounds(
    episodes: Iterable[Episode],
    scene_dirs: Mapping[str, str | os.PathLike[str]],
    *,
    margin: float = BOUNDS_MARGIN,
) -> dict[str, Box]:
    """The box each episode's positions must be in: its scene's bounds grown by `margin` on every axis.

    Parameters
    ----------
    episodes : iterable of Episode
        The episodes of the split scored.
    scene_dirs : mapping
        Built scene directory by scene id (its ``scene.json`` has the bounds).
    margin : float, optional
        Meters added on every side (default :data:`BOUNDS_MARGIN`).

    Returns
    -------
    dict
        :class:`Box` by episode id, for :func:`read_submission`'s ``bounds``.

    Raises
    ------
    SceneError
        If a scene's ``scene.json`` is missing or invalid.
    """
    from navverse.scene.directory import read_annotations

    boxes: dict[str, Box] = {}
    out = {}
    for episode in episodes:
        scene = episode.scene_id
        if scene not in boxes:
            bounds = read_annotations(Path(scene_dirs[scene])).bounds
            low = tuple(float(v) - margin for v in bounds.min)
            high = tuple(float(v) + margin for v in bounds.max)
            boxes[scene] = Box(low, high, f"scene {scene}'s bounds grown by {margin:g} m")
        out[episode.episode_id] = boxes[scene]
    return out


def _size(size: int) -> str:
    """A number of bytes for people: ``256 MiB``, ``4 KiB``, ``1.5 GiB``, ``100 bytes``."""
    for unit, scale in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if size >= scale:
            return f"{size / scale:.3g} {unit}"
    return f"{size} bytes"


def _open_stream(handle: IO[bytes], path: Path, limits: Limits) -> tuple[IO[bytes], bool]:
    """The open file as a binary stream (decompressed if gzip) and whether it is gzip; a SubmissionError if
    its text is larger than ``limits.text_bytes``."""
    magic = handle.read(2)
    handle.seek(0)
    if magic == _GZIP_MAGIC:
        _check_unpacked_size(handle, path, limits)
        handle.seek(0)
        return gzip.GzipFile(fileobj=handle, mode="rb"), True
    if path.suffix == ".gz":
        raise SubmissionError(f"{path} ends in .gz but is not gzip-compressed; name it .jsonl or gzip it")
    size = os.fstat(handle.fileno()).st_size
    if size > limits.text_bytes:
        raise SubmissionError(_too_big(path, limits, f"is {_size(size)}"))
    return handle, False


def _check_unpacked_size(handle: IO[bytes], path: Path, limits: Limits) -> None:
    """Refuse a gzip file that decompresses to more than ``limits.text_bytes``, before parsing any of it
    (decompressing alone is fast; it is done a chunk at a time)."""
    total = 0
    try:
        with gzip.GzipFile(fileobj=handle, mode="rb") as stream:
            while (chunk := stream.read(_SIZE_CHUNK)) and total <= limits.text_bytes:
                total += len(chunk)
    except (OSError, EOFError, zlib.error) as exc:
        raise SubmissionError(f"{path} is a damaged gzip file ({exc}); write it again") from None
    if total > limits.text_bytes:
        raise SubmissionError(_too_big(path, limits, f"has more than {_size(limits.text_bytes)} of text"))


def _too_big(path: Path, limits: Limits, what: str) -> str:
    return (
        f"{path} {what}: a submission holds at most {_size(limits.text_bytes)} of text (decompressed); "
        "write fewer rows (10 Hz is plenty) or fewer digits"
    )


def _raw_lines(stream: IO[bytes], path: Path, limits: Limits) -> Iterator[tuple[int, bytes | None]]:
    """Each line (without its end) and its number; None for a line longer than ``limits.line_bytes``,
    whose text is skipped, never held."""
    total = 0
    number = 0
    while True:
        raw = stream.readline(limits.line_bytes + 1)
        if not raw:
            return
        number += 1
        if number > limits.lines:
            raise SubmissionError(
                f"{path} has more than {limits.lines:,} lines: a submission is one line per episode"
            )
        total += len(raw)
        too_long = len(raw) > limits.line_bytes and not raw.endswith(b"\n")
        while too_long and raw and not raw.endswith(b"\n") and total <= limits.text_bytes:
            raw = stream.readline(_SKIP_CHUNK)  # skip the rest of the line, a chunk at a time
            total += len(raw)
        if total > limits.text_bytes:
            raise SubmissionError(_too_big(path, limits, f"has more than {_size(limits.text_bytes)} of text"))
        yield number, None if too_long else raw.rstrip(b"\r\n")


def _lines(path: Path, limits: Limits) -> Iterator[tuple[int, bytes | None]]:
    """The lines of a submission, read as a stream; SubmissionError if it cannot be read."""
    packed = False
    try:
        with path.open("rb") as handle:
            stream, packed = _open_stream(handle, path, limits)
            with stream:
                yield from _raw_lines(stream, path, limits)
    except FileNotFoundError:
        raise SubmissionError(f"submission {path} does not exist") from None
    except (OSError, EOFError, zlib.error) as exc:
        if packed:
            raise SubmissionError(f"{path} is a damaged gzip file ({exc}); write it again") from None
        raise SubmissionError(
            f"cannot read submission {path}: {getattr(exc, 'strerror', None) or exc}"
        ) from None


_ID_PATTERN = re.compile(rb'"episode_id"\s*:\s*"([^"\\]{1,%d})"' % MAX_TEXT_CHARS)


def _id_of(raw: bytes) -> str | None:
    """The episode id a line names, read without parsing it (to label problems of unparsed lines)."""
    found = _ID_PATTERN.search(raw)
    return found.group(1).decode("utf-8", "replace") if found else None


@dataclass
class _Structure:
    """What :func:`_structure` has counted so far of a line, outside strings."""

    containers: int = 0
    commas: int = 0
    deepest: int = 0
    depth: int = 0
    in_string: int = 0  # 1 inside a string
    backslashes: int = 0  # length of the run of backslashes that ends the text scanned


def _plain_structure(raw: bytes) -> _Structure:
    """:func:`_structure` of a line without backslashes, where every quote opens or closes a string: its
    strings cut out at C speed, then the brackets left counted :data:`_SCAN_BYTES` at a time."""
    state = _Structure()
    outside = _CLOSED_STRING.sub(b"", raw)
    if raw.count(b'"') % 2:  # the last quote opens a string the line does not close
        outside = outside[: outside.index(b'"')]
        state.in_string = 1
    brackets = outside.translate(None, _NOT_BRACKETS)
    state.commas = outside.count(b",")
    state.containers = brackets.count(b"[") + brackets.count(b"{")
    for start in range(0, len(brackets), _SCAN_BYTES):
        c = np.frombuffer(
            brackets, dtype=np.uint8, count=min(_SCAN_BYTES, len(brackets) - start), offset=start
        )
        depth = np.cumsum(_STEP[c], dtype=np.int64) + state.depth
        state.deepest = max(state.deepest, int(depth.max()))
        state.depth = int(depth[-1])
    return state


def _structure(raw: bytes) -> _Structure:
    """The arrays and objects, commas and deepest nesting of a line, outside strings (exact for valid JSON
    and for the valid start of a line), scanned :data:`_SCAN_BYTES` at a time with numpy: linear in the
    line's length whatever it holds (a regex over strings with escapes is quadratic on unclosed ones). A
    line without backslashes and with few strings (every line a submission writer makes of ids without
    escapes: a trajectory is numbers) takes :func:`_plain_structure`, which finds the same at C speed."""
    if b"\\" not in raw and raw.count(b'"') <= len(raw) // _PLAIN_BYTES_PER_QUOTE:
        return _plain_structure(raw)
    state = _Structure()
    for start in range(0, len(raw), _SCAN_BYTES):
        c = np.frombuffer(raw, dtype=np.uint8, count=min(_SCAN_BYTES, len(raw) - start), offset=start)
        index = np.arange(len(c))
        slash = c == ord("\\")
        last_other = np.maximum.accumulate(np.where(slash, -1, index))
        run = np.where(last_other < 0, index + 1 + state.backslashes, index - last_other)  # ends at i
        escaped = np.empty(len(c), dtype=bool)  # after an odd run of backslashes
        escaped[0] = state.backslashes % 2 == 1
        escaped[1:] = run[:-1] % 2 == 1
        quotes = np.cumsum((c == ord('"')) & ~escaped) + state.in_string
        outside = quotes % 2 == 0
        step = _STEP[c] * outside
        moves = step[step != 0]
        if len(moves):
            depth = np.cumsum(moves, dtype=np.int64) + state.depth
            state.deepest = max(state.deepest, int(depth.max()))
            state.depth = int(depth[-1])
        state.containers += int((moves > 0).sum())
        state.commas += int(((c == ord(",")) & outside).sum())
        state.in_string = int(quotes[-1] % 2)
        state.backslashes = int(run[-1])
    return state


def _scan(raw: bytes, limits: Limits) -> str | None:
    """Why a line must not be parsed (too many arrays or values, too deep), or None. Brackets and commas
    inside strings do not count; the exact scan runs only when the counts over the whole line (strings
    included, so at least as large) could pass a cap."""
    containers = raw.count(b"[") + raw.count(b"{")
    most_values = 9 * limits.rows + limits.collisions + 16
    if containers <= limits.depth and raw.count(b",") <= most_values:
        return None  # too few arrays and objects to nest deeper than the cap or to exceed the rows
    found = _structure(raw)
    if found.containers > limits.rows + 8:
        return (
            f"the line holds {found.containers:,} JSON arrays and objects: a trajectory has at most "
            f"{limits.rows:,} rows"
        )
    if found.commas > most_values:
        return (
            f"the line holds more than {most_values:,} values: a record has at most {limits.rows:,} rows "
            f"of 8 numbers and {limits.collisions:,} collision times"
        )
    if found.deepest > limits.depth:
        return f"JSON nested {found.deepest:,} deep: a record nests at most 3 deep (object, trajectory, row)"
    return None


def _json_type(value: Any) -> str:
    """The JSON name of a parsed value's type."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    names = {str: "a string", float: "a number", int: "a number", list: "an array", dict: "an object"}
    return names.get(type(value), type(value).__name__)


def _short(value: Any, most: int = 40) -> str:
    text = repr(value)
    return text if len(text) <= most else text[: most - 3] + "..."


def _first_non_number(rows: list[list[Any]]) -> tuple[int, int] | None:
    """Row and column of the first value that is not a JSON number (``true``/``false`` are not)."""
    if set(map(type, itertools.chain.from_iterable(rows))) == {float}:  # at C speed
        return None
    for i, row in enumerate(rows):
        for j, v in enumerate(row):
            if type(v) is not float:
                return i, j
    return None  # pragma: no cover - the first test found one


def _check_trajectory(value: Any, limits: Limits) -> tuple[np.ndarray | None, str | None]:
    """The trajectory as an array, or why it is not one."""
    if not isinstance(value, list) or not value:
        return None, "trajectory must be a non-empty list of [t, x, y, z, qx, qy, qz, qw] rows"
    if len(value) > limits.rows:
        return (
            None,
            f"trajectory has {len(value):,} rows, more than {limits.rows:,}: subsample it (10 Hz is plenty)",
        )
    if set(map(type, value)) == {list} and set(map(len, value)) == {8}:  # at C speed
        bad = []
    else:
        widths = [len(row) if isinstance(row, list) else -1 for row in value]
        bad = [i for i, w in enumerate(widths) if w != 8]
    if bad:
        i = bad[0]
        what = "is not a list" if widths[i] < 0 else f"has {widths[i]} values"
        more = f" (and {len(bad) - 1} more rows)" if len(bad) > 1 else ""
        return None, f"trajectory row {i} {what}, not 8 [t, x, y, z, qx, qy, qz, qw]{more}"
    where = _first_non_number(value)
    if where is not None:
        i, j = where
        return None, f"trajectory row {i} value {j} is {_json_type(value[i][j])}, not a number"
    rows = np.fromiter(itertools.chain.from_iterable(value), np.float64, 8 * len(value)).reshape(-1, 8)
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


def _check_position(rows: np.ndarray, box: Box | None, limits: Limits) -> str | None:
    """Why a trajectory's positions are not where the robot can be, or None."""
    xyz = rows[:, 1:4]
    far = (np.abs(xyz) > limits.abs_coord).any(axis=1)
    if far.any():
        i = int(np.flatnonzero(far)[0])
        return (
            f"trajectory row {i} is at ({', '.join(f'{v:.6g}' for v in xyz[i])}) m, more than "
            f"{limits.abs_coord:g} m from the origin on an axis ({int(far.sum())} of {len(xyz)} rows): "
            "positions are meters in the scene's world frame"
        )
    if box is None:
        return None
    out = ((xyz < np.asarray(box.low)) | (xyz > np.asarray(box.high))).any(axis=1)
    if not out.any():
        return None
    i = int(np.flatnonzero(out)[0])
    extent = ", ".join(f"{lo:.1f}..{hi:.1f}" for lo, hi in zip(box.low, box.high, strict=True))
    return (
        f"trajectory row {i} is at ({', '.join(f'{v:.6g}' for v in xyz[i])}) m, outside {box.name} "
        f"(x, y, z in {extent}; {int(out.sum())} of {len(xyz)} rows): positions are meters in the scene's "
        "world frame"
    )


def _check_collisions(value: Any, limits: Limits) -> tuple[np.ndarray | None, str | None]:
    """The reported collision times as an array (None: not reported), or why they are not valid."""
    if value is None:
        return None, None
    why = "collisions must be a list of finite times (s)"
    if not isinstance(value, list):
        return None, f"{why}, not {_json_type(value)}"
    if len(value) > limits.collisions:
        return None, f"{why}: {len(value):,} are more than {limits.collisions:,}"
    if value and set(map(type, value)) != {float}:
        return None, f"{why}; it holds {_json_type(next(v for v in value if type(v) is not float))}"
    times = np.array(value, dtype=np.float64)
    if not np.isfinite(times).all():
        return None, f"{why}; it holds NaN or infinity"
    return times, None


def _check_text(data: dict, key: str, *, required: bool) -> tuple[str | None, str | None]:
    """A string field (at most :data:`MAX_TEXT_CHARS` characters), or why it is not one."""
    value = data.get(key)
    if value is None and not required:
        return None, None
    what = "a non-empty string" if required else "a string or null"
    if not isinstance(value, str) or (required and not value):
        return None, f"{key} must be {what}, not {_json_type(value) if key in data else 'missing'}"
    if len(value) > MAX_TEXT_CHARS:
        return None, f"{key} has {len(value):,} characters, more than {MAX_TEXT_CHARS}"
    return value, None


def _check_instruction_type(data: dict) -> tuple[str | None, str | None]:
    """The record's instruction type (None: not given), or why it is not one of the types."""
    value, why = _check_text(data, "instruction_type", required=False)
    if why is None and value is not None and value not in INSTRUCTION_TYPES:
        why = f"instruction_type must be one of {', '.join(INSTRUCTION_TYPES)} (or null), not {_short(value)}"
    return (None, why) if why else (value, None)


def _check_record(
    data: Any, line: int, *, box_of: Mapping[str, Box] | None, limits: Limits
) -> tuple[TrajectoryRecord | None, list[str], str | None]:
    """The record, the messages of its problems, and its episode id if one can be read."""
    if not isinstance(data, dict):
        return None, [f"a line must be a JSON object, not {_json_type(data)}"], None
    episode_id, why = _check_text(data, "episode_id", required=True)
    messages = [why] if why else []
    unknown = sorted(key for key in data if key not in FIELDS)
    if unknown:
        listed = ", ".join(_short(key) for key in unknown[:5]) + (", ..." if len(unknown) > 5 else "")
        messages.append(f"unknown keys [{listed}] (a record has {', '.join(FIELDS)})")
    trajectory, why = _check_trajectory(data.get("trajectory"), limits)
    if trajectory is not None:
        why = _check_position(trajectory, (box_of or {}).get(episode_id or ""), limits)
    if why:
        messages.append(why)
    stop = data.get("stop")
    if not isinstance(stop, bool):
        messages.append(
            f"stop must be true or false, not {_json_type(stop) if 'stop' in data else 'missing'}"
        )
    times, why = _check_collisions(data.get("collisions"), limits)
    if why:
        messages.append(why)
    termination, why = _check_text(data, "termination", required=False)
    if why:
        messages.append(why)
    instruction_type, why = _check_instruction_type(data)
    if why:
        messages.append(why)
    track, why = check_track(data.get("track"))
    if why:
        messages.append(why)
    if messages or episode_id is None or trajectory is None:  # (either None comes with a message)
        return None, messages, episode_id
    record = TrajectoryRecord(episode_id, trajectory, stop, times, termination, line, instruction_type, track)
    return record, [], episode_id


_TOO_DEEP = "JSON nested too deep"


def _parse(raw: bytes, number: int, path: Path) -> tuple[Any, str | None]:
    """The JSON value of a line, or why it is not JSON. Integers are read as floats, so no literal is
    too large to convert; a line that is not UTF-8 makes the whole file unreadable."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SubmissionError(
            f"{path} line {number} is not UTF-8 text (byte {exc.start}): a submission is JSON lines, "
            "one episode per line"
        ) from None
    try:
        return json.loads(text, parse_int=float), None
    except RecursionError:
        return None, _TOO_DEEP
    except ValueError as exc:
        if isinstance(exc, json.JSONDecodeError):
            return None, f"not valid JSON ({exc.msg}, column {exc.colno})"
        return None, f"not valid JSON ({exc})"


@dataclass(eq=False)
class _Reader:
    """What reading a submission has gathered so far."""

    path: Path
    limits: Limits
    known: set[str] | None
    bounds: Mapping[str, Box] | None
    records: dict[str, TrajectoryRecord] = field(default_factory=dict)
    problems: list[Problem] = field(default_factory=list)
    omitted: int = 0
    seen: dict[str, list[int]] = field(default_factory=dict)
    kept_rows: int = 0
    lines_read: int = 0  # lines that are not blank
    not_json: int = 0  # lines that are not JSON

    def problem(self, line: int, episode_id: str | None, message: str) -> None:
        if len(self.problems) < self.limits.problems:
            self.problems.append(Problem(line, episode_id, message))
        else:
            self.omitted += 1

    def line(self, number: int, raw: bytes | None) -> None:
        """Check one line: keep its record if valid, else note its problems."""
        if raw is not None and (not raw or raw.isspace()):
            return
        self.lines_read += 1
        if raw is None:
            self.problem(number, None, f"the line is longer than {_size(self.limits.line_bytes)}, not read")
            return
        why = _scan(raw, self.limits)
        if why is not None:
            self.episode(number, _id_of(raw), [why], None)
            return
        data, why = _parse(raw, number, self.path)
        if why is not None:
            self.not_json += why != _TOO_DEEP  # JSON, too deep for the parser
            self.problem(number, None, why)
            return
        record, messages, episode_id = _check_record(data, number, box_of=self.bounds, limits=self.limits)
        self.episode(number, episode_id, messages, record)

    def episode(
        self, number: int, episode_id: str | None, messages: list[str], record: TrajectoryRecord | None
    ) -> None:
        """Note the record (or the problems) of a line naming `episode_id`."""
        if episode_id is not None:
            if self.known is None or episode_id in self.known:
                self.seen.setdefault(episode_id, []).append(number)
            else:
                messages = [*messages, "unknown episode id: not in the dataset split being scored"]
                record = None
        for message in messages:
            self.problem(number, episode_id, message)
        if record is not None:
            self.keep(record)

    def keep(self, record: TrajectoryRecord) -> None:
        """Keep a valid record, within ``limits.kept_rows`` rows in all."""
        old = self.records.get(record.episode_id)
        self.kept_rows += len(record.trajectory) - (len(old.trajectory) if old is not None else 0)
        if self.kept_rows > self.limits.kept_rows:
            raise SubmissionError(
                f"{self.path}: its valid records hold more than {self.limits.kept_rows:,} trajectory rows in "
                "all; write fewer rows (10 Hz is plenty)"
            )
        self.records[record.episode_id] = record

    def finish(self, lines: int) -> Submission:
        """The submission, once every line is read: duplicates dropped, problems in line order."""
        if self.not_json and self.not_json == self.lines_read:
            raise SubmissionError(
                f"{self.path} has no line of JSON: a submission is JSON lines, one episode per line"
            )
        for episode_id, numbers in self.seen.items():
            if len(numbers) > 1:
                others = ", ".join(map(str, numbers[:10])) + (", ..." if len(numbers) > 10 else "")
                for number in numbers:
                    self.problem(number, episode_id, f"duplicate episode id (lines {others}); none is scored")
                self.records.pop(episode_id, None)
        self.problems.sort(key=lambda p: (p.line, p.message))
        return Submission(self.path, self.records, self.problems, lines, self.omitted)


def read_submission(
    path: str | os.PathLike[str],
    *,
    episode_ids: Collection[str] | None = None,
    bounds: Mapping[str, Box] | None = None,
    limits: Limits | None = None,
) -> Submission:
    """Read a submission, keeping the valid records and listing every problem.

    Parameters
    ----------
    path : path
        A ``.jsonl`` file, optionally gzipped.
    episode_ids : collection of str, optional
        The episodes the submission may hold; others are problems ("unknown episode id").
    bounds : mapping, optional
        :class:`Box` by episode id (:func:`episode_bounds`): a trajectory with a position outside its
        episode's box is a problem. Without it, only :data:`MAX_ABS_COORD` bounds positions.
    limits : Limits, optional
        The caps (default: ``Limits()``, the module constants).

    Raises
    ------
    SubmissionError
        If the file is missing, not gzip when named ``.gz``, damaged, not UTF-8 text, has no line that
        is JSON, or exceeds ``limits.text_bytes``, ``limits.lines`` or ``limits.kept_rows``.
    """
    path = Path(path)
    limits = limits or Limits()
    reader = _Reader(path, limits, set(episode_ids) if episode_ids is not None else None, bounds)
    lines = 0
    for lines, raw in _lines(path, limits):
        reader.line(lines, raw)
    return reader.finish(lines)
