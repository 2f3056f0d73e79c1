"""Submission validation: every problem at once, with its line; valid records kept; corrupt files refused."""

from __future__ import annotations

import gzip
import json
from pathlib import Path

import numpy as np
import pytest

from navverse.eval.submission import SubmissionError, read_submission

GOOD = [[0.0, 1.0, 2.0, 0.5, 0.0, 0.0, 0.0, 1.0], [0.1, 1.1, 2.0, 0.5, 0.0, 0.0, 0.0, 1.0]]
IDS = {"a", "b", "c", "d", "e", "f", "g", "h", "i", "j"}


def record(episode_id: str, trajectory=GOOD, **extra) -> dict:
    return {"episode_id": episode_id, "trajectory": trajectory, "stop": True, **extra}


def write(path: Path, lines: list) -> Path:
    text = "\n".join(line if isinstance(line, str) else json.dumps(line) for line in lines) + "\n"
    if path.suffix == ".gz":
        path.write_bytes(gzip.compress(text.encode()))
    else:
        path.write_text(text)
    return path


def test_every_problem_is_reported_with_its_line(tmp_path: Path):
    nan_row = [GOOD[0], [0.1, float("nan"), 2.0, 0.5, 0.0, 0.0, 0.0, 1.0]]
    lines = [
        record("a", collisions=[1.0], termination="stop"),  # 1: fine
        record("b", nan_row),  # 2: NaN
        record("c"),  # 3: duplicate of line 6
        record("zzz"),  # 4: unknown id
        record("d", [GOOD[1], GOOD[0]]),  # 5: time goes back
        record("c"),  # 6: duplicate
        record("e", [[0.0, 1.0, 2.0, 0.5, 0.0, 0.0, 0.0, 2.0]]),  # 7: quaternion length 2
        record("f", [[0.0, 1.0, 2.0]]),  # 8: 3 values
        "{not json",  # 9
        {"episode_id": "g", "trajectory": GOOD},  # 10: no stop
        record("h", extra_key=1),  # 11: unknown key
        "",  # 12: blank lines are fine
        record("i", collisions="often"),  # 13
    ]
    submission = read_submission(write(tmp_path / "s.jsonl", lines), episode_ids=IDS)
    assert sorted(submission.records) == ["a"]
    found = {(p.line, p.episode_id): p.message for p in submission.problems}
    assert "NaN or infinity" in found[(2, "b")] and "row 1" in found[(2, "b")]
    assert "duplicate episode id (lines 3, 6)" in found[(3, "c")] and (6, "c") in found
    assert "unknown episode id" in found[(4, "zzz")]
    assert "does not increase at row 1" in found[(5, "d")]
    assert "length 2.0000" in found[(7, "e")]
    assert "has 3 values, not 8" in found[(8, "f")]
    assert "not valid JSON" in found[(9, None)]
    assert "stop must be true or false" in found[(10, "g")]
    assert "unknown keys ['extra_key']" in found[(11, "h")]
    assert "collisions must be a list" in found[(13, "i")]
    assert len(submission.problems) == 11
    assert str(submission.problems[0]).startswith("line 2 (b): ")
    kept = submission.records["a"]
    assert (
        kept.trajectory.shape == (2, 8) and kept.stop and kept.collisions.tolist() == [1.0] and kept.line == 1
    )


def test_gzip_and_plain_read_the_same(tmp_path: Path):
    lines = [record("a"), record("b", [[0.0, 0, 0, 0, 0, 0, 0, 1]])]
    plain = read_submission(write(tmp_path / "s.jsonl", lines))
    packed = read_submission(write(tmp_path / "s.jsonl.gz", lines))
    assert sorted(plain.records) == sorted(packed.records) == ["a", "b"]
    np.testing.assert_array_equal(plain.records["a"].trajectory, packed.records["a"].trajectory)
    assert plain.records["a"].collisions is None  # not reported: the evaluator checks the footprint


@pytest.mark.parametrize(
    ("content", "name", "message"),
    [
        (b"\x1f\x8b\x08\x00garbage", "s.jsonl.gz", "damaged gzip"),
        (b'{"episode_id": "a"}\n', "s.jsonl.gz", "not gzip-compressed"),
        (b"\xff\xfe\x00binary", "s.jsonl", "not UTF-8"),
        (b"episode,trajectory\na,1\n", "s.jsonl", "no line of JSON"),
    ],
)
def test_corrupt_files_are_refused(tmp_path: Path, content: bytes, name: str, message: str):
    (tmp_path / name).write_bytes(content)
    with pytest.raises(SubmissionError, match=message):
        read_submission(tmp_path / name)
    with pytest.raises(SubmissionError, match="does not exist"):
        read_submission(tmp_path / "missing.jsonl")
