"""Properties of submission validation: it is total, and what it accepts is within bounds.

Whatever the bytes of a file or the JSON value of a field, :func:`read_submission` returns a
:class:`Submission` or raises :class:`SubmissionError`, never anything else; every record it keeps is a
finite (K, 8) float array with unit quaternions, increasing time and positions within the bounds.
"""

from __future__ import annotations

import gzip
import json
import math
import tempfile
from pathlib import Path

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from navverse.eval.measures import POSITION_LIMIT
from navverse.eval.submission import (
    FIELDS,
    MAX_ABS_COORD,
    QUATERNION_TOLERANCE,
    Box,
    Limits,
    Submission,
    SubmissionError,
    read_submission,
)

LEVEL = [0.0, 0.0, 0.0, 1.0]
BOX = Box((-60.0, -60.0, -50.0), (70.0, 70.0, 53.0), "scene room's bounds grown by 50 m")
SMALL = Limits(text_bytes=64 * 2**10, line_bytes=8 * 2**10, lines=50, rows=20, collisions=20, depth=8)

scalars = (
    st.none()
    | st.booleans()
    | st.integers(min_value=-(10**400), max_value=10**400)
    | st.floats()
    | st.text(max_size=8)
    | st.sampled_from([1e308, -1e308, 1e5, 1e5 + 1, 5e-324, 0.0, -0.0, 1.0])
)
json_values = st.recursive(
    scalars,
    lambda inner: st.lists(inner, max_size=9) | st.dictionaries(st.text(max_size=6), inner, max_size=4),
    max_leaves=24,
)
coordinates = st.floats(-200.0, 200.0) | st.floats(allow_nan=False, allow_infinity=False) | st.just(1e5)
rows = st.lists(
    st.tuples(st.floats(0.0, 1e6), coordinates, coordinates, coordinates).map(lambda r: [*r, *LEVEL]),
    min_size=1,
    max_size=8,
)
row_like = st.lists(st.lists(scalars, min_size=8, max_size=8), min_size=1, max_size=4)


def _read(content: bytes, name: str = "s.jsonl", **kwargs) -> Submission | None:
    """Read `content` as a submission file; None when it is refused with a SubmissionError."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / name
        path.write_bytes(content)
        try:
            return read_submission(path, **kwargs)
        except SubmissionError:
            return None


def _check_kept(submission: Submission | None, bounds: dict[str, Box] | None = None) -> None:
    """Every kept record is a valid trajectory within the bounds."""
    if submission is None:
        return
    for episode_id, record in submission.records.items():
        rows = record.trajectory
        assert rows.dtype == np.float64 and rows.ndim == 2 and rows.shape[1] == 8 and len(rows) >= 1
        assert np.isfinite(rows).all() and rows[0, 0] >= 0.0 and (np.diff(rows[:, 0]) > 0).all()
        assert np.all(np.abs(np.linalg.norm(rows[:, 4:], axis=1) - 1.0) <= QUATERNION_TOLERANCE)
        assert np.abs(rows[:, 1:4]).max() <= MAX_ABS_COORD
        # ...and within the range the measures take exactly: a kept record is scored as submitted.
        assert np.abs(rows[:, 1:4]).max() < POSITION_LIMIT
        if bounds is not None:
            box = bounds[episode_id]
            assert (rows[:, 1:4] >= box.low).all() and (rows[:, 1:4] <= box.high).all()
        assert isinstance(record.stop, bool)
        if record.collisions is not None:
            assert record.collisions.dtype == np.float64 and np.isfinite(record.collisions).all()
        assert record.termination is None or isinstance(record.termination, str)


@given(st.binary(max_size=600), st.sampled_from(["s.jsonl", "s.jsonl.gz"]), st.booleans())
def test_arbitrary_bytes_give_a_submission_or_a_submission_error(content: bytes, name: str, packed: bool):
    if packed:
        content = gzip.compress(content)
    _check_kept(_read(content, name, limits=SMALL))


@given(st.lists(st.text(max_size=40) | st.just("[" * 40) | st.just('{"a": ' * 30), max_size=8))
def test_arbitrary_text_lines_give_a_submission_or_a_submission_error(lines: list[str]):
    _check_kept(_read("\n".join(lines).encode("utf-8", "surrogatepass"), limits=SMALL))


@given(st.sampled_from([*FIELDS, "extra"]), json_values | row_like)
def test_any_json_value_in_any_field_is_a_problem_or_a_valid_record(key: str, value):
    record = {"episode_id": "a", "trajectory": [[0.0, 1.0, 2.0, 0.5, *LEVEL]], "stop": True, key: value}
    line = json.dumps(record)  # NaN and Infinity as Python's json writes them
    bounds = {"a": BOX}
    submission = _read(line.encode() + b"\n", episode_ids=["a"], bounds=bounds, limits=SMALL)
    assert submission is not None  # a line of JSON: never refused as a whole
    _check_kept(submission, bounds)
    kept = "a" in submission.records
    assert kept != bool(submission.problems)
    if key == "extra" or (isinstance(value, bool) and key == "trajectory"):
        assert not kept
    if key == "trajectory" and kept:
        assert not any(isinstance(v, (bool, str)) or v is None for row in value for v in row)


@given(rows)
def test_a_trajectory_is_kept_exactly_when_every_position_is_within_the_bounds(trajectory: list[list[float]]):
    times = np.cumsum([abs(row[0]) + 0.1 for row in trajectory])
    trajectory = [[float(t), *row[1:]] for t, row in zip(times, trajectory, strict=True)]
    line = json.dumps({"episode_id": "a", "trajectory": trajectory, "stop": False})
    bounds = {"a": BOX}
    submission = _read(line.encode(), episode_ids=["a"], bounds=bounds)
    inside = all(BOX.low[i] <= row[1 + i] <= BOX.high[i] for row in trajectory for i in range(3))
    assert ("a" in submission.records) == inside
    _check_kept(submission, bounds)
    without_scenes = _read(line.encode())
    near = all(abs(v) <= MAX_ABS_COORD and math.isfinite(v) for row in trajectory for v in row[1:4])
    assert ("a" in without_scenes.records) == near
    _check_kept(without_scenes)


def _reference_structure(raw: bytes) -> tuple[int, int, int]:
    """(arrays and objects, commas, deepest nesting) outside strings, a character at a time (a backslash
    escapes a quote; outside strings valid JSON has none)."""
    containers = commas = depth = deepest = 0
    in_string = escaped = False
    for byte in raw:
        char = chr(byte)
        if char == '"' and not escaped:
            in_string = not in_string
        elif not in_string and char in "[{":
            containers, depth = containers + 1, depth + 1
            deepest = max(deepest, depth)
        elif not in_string and char in "]}":
            depth -= 1
        elif not in_string and char == ",":
            commas += 1
        escaped = char == "\\" and not escaped
    return containers, commas, deepest


@given(
    json_values.map(lambda v: json.dumps(v).encode())
    | st.binary(max_size=60)
    | st.text(alphabet='[]{}",\\ab', max_size=60).map(str.encode)
)
def test_the_line_scan_counts_what_a_character_loop_counts(raw: bytes):
    from navverse.eval import submission

    expected = _reference_structure(raw)
    for size in (3, 7, submission._SCAN_BYTES):  # chunk borders anywhere: in escapes, strings, runs
        original = submission._SCAN_BYTES
        submission._SCAN_BYTES = size
        try:
            found = submission._structure(raw)
        finally:
            submission._SCAN_BYTES = original
        assert (found.containers, found.commas, found.deepest) == expected


@given(
    json_values.map(lambda v: json.dumps(v).encode())
    | st.binary(max_size=200)
    | st.text(alphabet='[]{}",ab', max_size=200).map(str.encode)
)
def test_the_scan_of_a_line_without_escapes_counts_what_a_character_loop_counts(raw: bytes):
    from navverse.eval import submission

    raw = raw.replace(b"\\", b"")  # the fast scan's lines: no backslash, any number of quotes
    expected = _reference_structure(raw)
    for size in (2, 5, submission._SCAN_BYTES):
        original = submission._SCAN_BYTES
        submission._SCAN_BYTES = size
        try:
            found = submission._plain_structure(raw)
        finally:
            submission._SCAN_BYTES = original
        assert (found.containers, found.commas, found.deepest) == expected
        assert found.in_string == raw.count(b'"') % 2
