"""Hostile submissions are refused, record by record or as a whole file, within bounded memory.

Each test is a break that once crashed the evaluator or exhausted memory: far positions (1e7 m, 1e9 m),
gzip bombs, deeply nested JSON, values of the wrong JSON type, and ``eval --out`` places that cannot be
written. The caps are lowered through :class:`~navverse.eval.submission.Limits`, so the files stay small.
"""

from __future__ import annotations

import argparse
import gzip
import json
import tracemalloc
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from rich.console import Console

from navverse.cli import build_parser, main
from navverse.commands.evaluate import cmd_eval
from navverse.commands.validate import cmd_validate_submission
from navverse.eval.measures import EpisodeTarget, Robot, measure
from navverse.eval.metrics import compute_metrics
from navverse.eval.submission import (
    BOUNDS_MARGIN,
    Box,
    Limits,
    SubmissionError,
    episode_bounds,
    read_submission,
)
from navverse.scene.directory import write_scene_dir
from navverse.scene.fields import SceneFields
from tests.navverse.scene.conftest import build_scene

LEVEL = [0.0, 0.0, 0.0, 1.0]
GOOD = [[0.0, 1.0, 2.0, 0.5, *LEVEL], [0.1, 1.1, 2.0, 0.5, *LEVEL]]
BOX = Box((-10.0, -10.0, -5.0), (20.0, 20.0, 5.0), "scene room's bounds grown by 50 m")
ROBOT = Robot(name="spot", radius=0.6, length=1.1, width=0.5)
FLOOR = SceneFields((0.0, 0.0), 0.5, np.zeros((20, 20), np.int16), np.zeros((20, 20), bool),
                    np.full((20, 20), 3.0, np.float32), ("floor",))  # fmt: skip


def record(episode_id: str = "a", trajectory=GOOD, **extra) -> dict:
    return {"episode_id": episode_id, "trajectory": trajectory, "stop": True, **extra}


def write(path: Path, lines: list, *, packed: bool = False) -> Path:
    text = "".join((line if isinstance(line, str) else json.dumps(line)) + "\n" for line in lines).encode()
    path.write_bytes(gzip.compress(text) if packed else text)
    return path


def steps(count: int) -> list[list[float]]:
    """`count` rows a tenth of a second and a centimeter apart."""
    return [[0.1 * i, 1.0 + 0.01 * i, 2.0, 0.5, *LEVEL] for i in range(count)]


def far(x: float) -> list[list[float]]:
    """The record that broke eval: two rows a second apart, the second `x` meters away."""
    return [[0.0, 0.0, 0.0, 0.0, *LEVEL], [1.0, x, 0.0, 0.0, *LEVEL]]


def peak_bytes(function, *args, **kwargs) -> tuple[object, int]:
    """The result of a call and the most memory (bytes) Python and numpy allocated during it."""
    tracemalloc.start()
    try:
        result = function(*args, **kwargs)
        return result, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


# --- far positions -------------------------------------------------------------------------------------


@pytest.mark.parametrize("x", [1e7, 1e9, -2e5])
def test_positions_far_from_the_origin_are_refused_without_scenes(tmp_path: Path, x: float):
    submission = read_submission(write(tmp_path / "s.jsonl", [record("a", far(x)), record("b")]))
    assert sorted(submission.records) == ["b"]
    [problem] = submission.problems
    assert (problem.line, problem.episode_id) == (1, "a")
    assert (
        "trajectory row 1 is at" in problem.message
        and "more than 100000 m from the origin" in problem.message
    )


def test_positions_outside_the_scene_bounds_are_refused(tmp_path: Path):
    lines = [
        record("a", far(1000.0)),  # inside ±100 km, far outside the scene
        record("b", [[0.0, 19.9, -9.9, 4.9, *LEVEL]]),  # inside the box
        record("c", [[0.0, 0.0, 0.0, 0.0, *LEVEL], [1.0, 0.0, 0.0, -6.0, *LEVEL]]),  # below it
    ]
    boxes = {"a": BOX, "b": BOX, "c": BOX}
    submission = read_submission(write(tmp_path / "s.jsonl", lines), episode_ids=boxes, bounds=boxes)
    assert sorted(submission.records) == ["b"]
    found = {p.episode_id: p.message for p in submission.problems}
    assert "row 1 is at (1000, 0, 0) m, outside scene room's bounds grown by 50 m" in found["a"]
    assert "x, y, z in -10.0..20.0, -10.0..20.0, -5.0..5.0; 1 of 2 rows" in found["a"]
    assert "row 1 is at (0, 0, -6) m, outside" in found["c"]


def test_episode_bounds_are_the_scene_bounds_grown_by_the_margin(tmp_path: Path):
    scene = build_scene()
    (tmp_path / "room").mkdir()
    write_scene_dir(scene, tmp_path / "room", bev=False)
    episodes = [SimpleNamespace(episode_id=f"e{i}", scene_id="room") for i in range(2)]
    boxes = episode_bounds(episodes, {"room": tmp_path / "room"})
    bounds = scene.annotations.bounds
    assert boxes["e0"] is boxes["e1"]
    np.testing.assert_allclose(boxes["e0"].low, np.asarray(bounds.min) - BOUNDS_MARGIN)
    np.testing.assert_allclose(boxes["e0"].high, np.asarray(bounds.max) + BOUNDS_MARGIN)
    assert boxes["e0"].name == "scene room's bounds grown by 50 m"


@pytest.mark.parametrize("x", [1e7, 1e9, 1e300])
def test_a_far_record_that_skips_validation_is_measured_in_bounded_memory(x: float):
    target = EpisodeTarget("a", "room", "vln", np.array([[5.0, 5.0, 0.0]]), np.array([0.5]), 5.0,
                           np.array([[0.0, 0.0, 0.0], [5.0, 5.0, 0.0]]), "indoor")  # fmt: skip
    trajectories = [np.array(far(x)), np.array(far(-x))]
    m, peak = peak_bytes(
        measure, trajectories, [target, target], robot=ROBOT, stops=[True, True], collisions=[None, None],
        fields={"room": FLOOR}, preferred={"room": np.array([True, False])},
    )  # fmt: skip
    assert peak < 32 * 2**20  # was 4.7 GB for 1e7 m, 29.8 GiB asked for 1e9 m
    assert np.all(m["cells"] >= 2) and np.all(np.isfinite(m["cells"]))
    assert np.all((m["dtw_score"] >= 0.0) & (m["dtw_score"] <= 1.0))
    m.update(geodesic=np.full(2, 5.0), success_distance=np.full(2, 1.6), valid=np.ones(2))
    values = compute_metrics(m)
    assert list(values["label"]) == ["wrong_goal", "wrong_goal"]
    assert np.all(np.isfinite(values["ce"])) and np.all(values["spl"] == 0.0)


# --- streaming and caps --------------------------------------------------------------------------------


def test_a_gzip_bomb_of_valid_lines_is_refused_while_streaming(tmp_path: Path):
    line = json.dumps(record("a")) + "\n"
    bomb = tmp_path / "bomb.jsonl.gz"
    bomb.write_bytes(gzip.compress(line.encode() * (8 * 2**20 // len(line)), 9))  # 8 MiB of text
    assert bomb.stat().st_size < 2**20
    with pytest.raises(SubmissionError, match=r"more than 1 MiB of text: a submission holds at most 1 MiB"):
        read_submission(bomb, limits=Limits(text_bytes=2**20))


def test_a_gzip_bomb_of_zeros_is_refused_without_holding_its_text(tmp_path: Path):
    bomb = tmp_path / "zeros.jsonl.gz"
    bomb.write_bytes(gzip.compress(b"\0" * 16 * 2**20, 9))  # 16 MiB, no line end
    message, peak = peak_bytes(_refusal, bomb, Limits(text_bytes=8 * 2**20, line_bytes=2**20))
    assert "more than 8 MiB of text: a submission holds at most 8 MiB of text (decompressed)" in message
    assert peak < 4 * 2**20  # read and skipped a chunk at a time, never held whole


def test_a_line_of_zeros_is_skipped_a_chunk_at_a_time(tmp_path: Path):
    bomb = tmp_path / "zeros.jsonl.gz"
    bomb.write_bytes(gzip.compress(b"\0" * 6 * 2**20 + b"\n" + json.dumps(record("a")).encode(), 9))
    submission, peak = peak_bytes(read_submission, bomb, limits=Limits(line_bytes=2**20))
    assert list(submission.records) == ["a"]
    assert [str(p) for p in submission.problems] == ["line 1: the line is longer than 1 MiB, not read"]
    assert peak < 4 * 2**20  # not the 6 MiB line


def _refusal(path: Path, limits: Limits) -> str:
    """The message of the SubmissionError reading `path` raises."""
    with pytest.raises(SubmissionError) as caught:
        read_submission(path, limits=limits)
    return str(caught.value)


def test_a_plain_file_over_the_cap_is_refused_before_reading(tmp_path: Path):
    path = write(tmp_path / "s.jsonl", [record("a")] * 100)
    with pytest.raises(SubmissionError, match=r"s.jsonl is 13.1 KiB: a submission holds at most 1000 bytes"):
        read_submission(path, limits=Limits(text_bytes=1000))


def test_a_long_line_is_a_problem_of_its_line_and_the_next_lines_are_read(tmp_path: Path):
    long = record("a", steps(400))
    path = write(tmp_path / "s.jsonl", [long, record("b"), long], packed=True)
    submission = read_submission(path, limits=Limits(line_bytes=4096))
    assert sorted(submission.records) == ["b"]
    assert [(p.line, p.episode_id) for p in submission.problems] == [(1, None), (3, None)]
    assert "the line is longer than 4 KiB, not read" in submission.problems[0].message


def test_too_many_lines_refuse_the_file(tmp_path: Path):
    path = write(tmp_path / "s.jsonl", [record("a"), "", "", record("b")])
    with pytest.raises(SubmissionError, match="more than 3 lines: a submission is one line per episode"):
        read_submission(path, limits=Limits(lines=3))


def test_a_100k_deep_line_is_a_problem_not_a_recursion_error(tmp_path: Path):
    deep = '{"episode_id": "a", "stop": true, "trajectory": ' + "[" * 100_000 + "]" * 100_000 + "}"
    submission = read_submission(write(tmp_path / "s.jsonl", [deep, record("b")]))
    assert sorted(submission.records) == ["b"]
    [problem] = submission.problems
    assert (problem.line, problem.episode_id) == (1, "a")
    assert "JSON nested 100,001 deep: a record nests at most 3 deep" in problem.message
    unscanned = read_submission(write(tmp_path / "u.jsonl", [deep]), limits=Limits(depth=10**6))
    assert [p.message for p in unscanned.problems] == ["JSON nested too deep"]  # json's RecursionError
    brackets_in_strings = record("c", termination="[" * 100_000)  # not nesting: inside a string
    submission = read_submission(write(tmp_path / "t.jsonl", [brackets_in_strings]))
    assert "termination has 100,000 characters" in submission.problems[0].message


def test_rows_and_values_over_the_caps_are_problems_before_parsing(tmp_path: Path):
    limits = Limits(rows=10, collisions=5)
    lines = [
        record("a", steps(10)),  # 10 rows: fine
        record("b", steps(12)),  # 12 rows: counted once parsed
        record("c", steps(40)),  # 42 arrays: refused before parsing
        record("d", collisions=[1.0] * 6),
        record("e", collisions=[1.0] * 200),  # too many values: refused before parsing
    ]
    submission = read_submission(write(tmp_path / "s.jsonl", lines), limits=limits)
    assert sorted(submission.records) == ["a"]
    found = {p.episode_id: p.message for p in submission.problems}
    assert "trajectory has 12 rows, more than 10: subsample it" in found["b"]
    assert "the line holds 42 JSON arrays and objects: a trajectory has at most 10 rows" in found["c"]
    assert "collisions must be a list of finite times (s): 6 are more than 5" in found["d"]
    assert "the line holds more than 111 values" in found["e"]


def test_kept_rows_over_the_cap_refuse_the_file(tmp_path: Path):
    path = write(tmp_path / "s.jsonl", [record(str(i), steps(6)) for i in range(4)])
    assert len(read_submission(path, limits=Limits(kept_rows=24)).records) == 4
    with pytest.raises(SubmissionError, match="more than 23 trajectory rows in all"):
        read_submission(path, limits=Limits(kept_rows=23))


def test_problems_beyond_the_cap_are_counted(tmp_path: Path):
    path = write(tmp_path / "s.jsonl", ["{bad"] * 7 + [record("a")])
    submission = read_submission(path, limits=Limits(problems=3))
    assert len(submission.problems) == 3 and submission.omitted == 4 and list(submission.records) == ["a"]


# --- every JSON value in every field -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ('{"episode_id": "a", "stop": true, "trajectory": [[1' + "0" * 400 + ", 0, 0, 0, 0, 0, 0, 1]]}",
         "row 0 holds NaN or infinity"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, 1' + "0" * 5000 + ", 0, 0, 0, 0, 0, 1]]}",
         "row 0 holds NaN or infinity"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, 1e400, 0, 0, 0, 0, 0, 1]]}',
         "row 0 holds NaN or infinity"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, true, 0, 0, 0, 0, 0, 1]]}',
         "row 0 value 1 is true, not a number"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, 0, 0, 0, 0, 0, 0, true]]}',
         "row 0 value 7 is true, not a number"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, "1.5", 0, 0, 0, 0, 0, 1]]}',
         "row 0 value 1 is a string, not a number"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, null, 0, 0, 0, 0, 0, 1]]}',
         "row 0 value 1 is null, not a number"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, [1], 0, 0, 0, 0, 0, 1]]}',
         "row 0 value 1 is an array, not a number"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, {"x": 1}, 0, 0, 0, 0, 0, 1]]}',
         "row 0 value 1 is an object, not a number"),
        ('{"episode_id": "a", "stop": true, "trajectory": {"rows": []}}',
         "trajectory must be a non-empty list"),
        ('{"episode_id": 1' + "0" * 400 + ', "stop": true, "trajectory": [[0, 0, 0, 0, 0, 0, 0, 1]]}',
         "episode_id must be a non-empty string, not a number"),
        ('{"episode_id": "a", "stop": 1, "trajectory": [[0, 0, 0, 0, 0, 0, 0, 1]]}',
         "stop must be true or false, not a number"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, 0, 0, 0, 0, 0, 0, 1]], "collisions": [true]}',
         "collisions must be a list of finite times (s); it holds true"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, 0, 0, 0, 0, 0, 0, 1]], "collisions": '
         "[1" + "0" * 400 + "]}", "collisions must be a list of finite times (s); it holds NaN or infinity"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, 0, 0, 0, 0, 0, 0, 1]], "collisions": ["1"]}',
         "it holds a string"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, 0, 0, 0, 0, 0, 0, 1]], "collisions": [[1.0]]}',
         "it holds an array"),
        ('{"episode_id": "a", "stop": true, "trajectory": [[0, 0, 0, 0, 0, 0, 0, 1]], "termination": {}}',
         "termination must be a string or null, not an object"),
        ("[1, 2]", "a line must be a JSON object, not an array"),
        ("1" + "0" * 5000, "a line must be a JSON object, not a number"),
    ],
)  # fmt: skip
def test_every_json_value_in_every_field_is_a_problem_not_an_exception(
    tmp_path: Path, line: str, message: str
):
    submission = read_submission(write(tmp_path / "s.jsonl", [line, record("ok")]))
    assert list(submission.records) == ["ok"]
    [problem] = submission.problems
    assert problem.line == 1 and message in problem.message


# --- the commands --------------------------------------------------------------------------------------


def _fake_store(root: Path, scene_dir: Path, scene_ids: list[str]) -> Path:
    """A build store whose ``targets/<scene>/scene`` links to `scene_dir` (a committed artifact)."""
    (scene_dir / "manifest.json").write_text("{}")
    for scene in scene_ids:
        link = root / "targets" / scene / "scene"
        link.parent.mkdir(parents=True)
        link.symlink_to(scene_dir)
    return root


@pytest.fixture(scope="module")
def toy(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """A dataset of six episodes in two scenes (the report tests' toy dataset) and its build store."""
    from tests.navverse.eval.test_report import EPISODES, _dataset

    root = tmp_path_factory.mktemp("toy")
    scene_dir = root / "scene"
    scene_dir.mkdir()
    write_scene_dir(build_scene(), scene_dir, bev=False)
    dataset = _dataset(root / "toy" / "v1.0")
    store = _fake_store(root / "built", scene_dir, sorted({spec[1] for spec in EPISODES}))
    return dataset.root, store


def test_validate_submission_checks_the_scene_bounds_when_the_scenes_are_built(tmp_path: Path, toy, capsys):
    dataset, store = toy
    path = write(tmp_path / "s.jsonl", [record("room-objnav-0000", far(1000.0))])
    args = argparse.Namespace(submission=str(path), dataset=str(dataset), split="eval")
    console = Console(width=300)
    assert cmd_validate_submission(args, console, built_dir=lambda: store) == 1
    out = capsys.readouterr().out
    assert (
        "line 1 (room-objnav-0000): trajectory row 1 is at (1000, 0, 0) m, outside scene tiny_room's" in out
    )
    assert "0 of 6 episodes of eval valid; 1 problems, 5 missing" in out
    assert cmd_validate_submission(args, console) == 1  # 6 missing episodes; bounds unchecked
    assert "note: the scenes' bounds are not checked" in capsys.readouterr().out
    args = argparse.Namespace(submission=str(path), dataset=None, split="eval")
    assert cmd_validate_submission(args, console) == 0
    assert "1 valid records; 0 problems (no --dataset" in capsys.readouterr().out
    path = write(tmp_path / "t.jsonl", [record("room-objnav-0000", far(1e7))])
    args = argparse.Namespace(submission=str(path), dataset=None, split="eval")
    assert cmd_validate_submission(args, console) == 1
    assert "more than 100000 m from the origin" in capsys.readouterr().out


def test_eval_scores_a_far_record_as_invalid(tmp_path: Path, toy, capsys, monkeypatch):
    dataset, store = toy
    monkeypatch.setenv("NAVVERSE_CACHE_DIR", str(tmp_path / "cache"))
    path = write(tmp_path / "s.jsonl", [record("room-objnav-0000", far(1e9))])
    args = build_parser().parse_args(  # every option's default, as the command gets them
        ["eval", "--submission", str(path), "--dataset", str(dataset), "--out", str(tmp_path / "out")]
    )
    assert cmd_eval(args, Console(width=300), built_dir=lambda: store) == 0
    metrics = json.loads((tmp_path / "out" / "metrics.json").read_text())
    assert {row["label"] for row in metrics["episodes"]} == {"invalid"}
    assert "more than 100000 m from the origin" in metrics["problems"][0]


@pytest.mark.parametrize("where", ["file", "under_a_file", "unwritable"])
def test_eval_out_that_cannot_be_written_is_a_clear_error(tmp_path: Path, capsys, where: str):
    (tmp_path / "taken").write_text("")
    out, message = {
        "file": (tmp_path / "taken", "is a file: give a directory"),
        "under_a_file": (
            tmp_path / "taken" / "out",
            "taken is a file, not a directory; choose another --out",
        ),
        "unwritable": (Path("/proc/navverse-out"), "cannot write into /proc"),
    }[where]
    argv = ["eval", "--dataset", str(tmp_path / "none"), "--submission", str(tmp_path / "none.jsonl")]
    assert main([*argv, "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert f"error: --out {out}" in err and message in err and "Traceback" not in err
