"""PlaceNav instruction types through submissions, the runner's records and the evaluator's table."""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import numpy as np
import pytest

from navverse.cli import build_parser
from navverse.commands.evaluate import _read_for_eval
from navverse.dataset import (
    Dataset,
    Episode,
)
from navverse.errors import NavverseError
from navverse.eval.agent_workers import Results, RunSettings
from navverse.eval.runner import RunError, _check_instruction_type, _read_partial
from navverse.eval.scoring import EvalResult, instruction_type_of, score
from navverse.eval.submission import Submission, SubmissionError, TrajectoryRecord, read_submission
from navverse.eval.tables import instruction_type_entries, instruction_type_table, write_outputs
from navverse.scene.directory import write_scene_dir
from tests.navverse.eval.test_report import CHAIR, TABLE, TO_CHAIR, TO_TABLE, _episode, _rows
from tests.navverse.eval.toy_dataset import write_toy_dataset
from tests.navverse.scene.conftest import build_scene

GOOD = [[0.0, 1.0, 2.0, 0.5, 0.0, 0.0, 0.0, 1.0], [0.1, 1.1, 2.0, 0.5, 0.0, 0.0, 0.0, 1.0]]
STAY = [TO_TABLE[0], (8.0, 2.2, 0.55)]  # stops 3 m from anything: a wrong goal
# (id, scene, scene type, task, goal, reference path); "tiny_room_b" is the same scene under another id.
EPISODES = [
    ("pn-0", "tiny_room", "i2o", "placenav", TABLE, TO_TABLE),
    ("pn-1", "tiny_room", "i2o", "placenav", CHAIR, TO_CHAIR),
    ("pn-2", "tiny_room_b", "outdoor", "placenav", TABLE, TO_TABLE),
    ("pn-3", "tiny_room_b", "outdoor", "placenav", CHAIR, TO_CHAIR),
    ("on-0", "tiny_room_b", "outdoor", "objnav", TABLE, TO_TABLE),
]
# Which placenav episodes each run reaches (the others stop far from their goal).
REACHED = {"category": {"pn-0", "pn-2", "pn-3"}, "route": {"pn-0"}, "intention": set()}


def _placenav(spec: tuple) -> Episode:
    episode = _episode(*spec).model_dump(mode="json")
    if spec[3] == "placenav":
        episode["place_category"], episode["object_category"] = episode["object_category"], None
        episode["instructions"] = {
            kind: {"instruction_text": f"{kind} text", "template_text": "", "instruction_type": kind}
            for kind in REACHED
        }
    return Episode.model_validate(episode)


def _dataset(root: Path) -> Dataset:
    return write_toy_dataset(root, [_placenav(spec) for spec in EPISODES])


def _write_run(path: Path, kind: str | None, reached: set[str], *, mixed: str | None = None) -> Path:
    """A submission: every episode followed to its goal (reached) or stopped near its start."""
    lines = []
    for episode_id, *_, path_points in EPISODES:
        points = path_points if episode_id in reached or episode_id == "on-0" else STAY
        record = {"episode_id": episode_id, "trajectory": _rows(points), "stop": True}
        if kind is not None:
            record["instruction_type"] = mixed if mixed and episode_id == "pn-3" else kind
        lines.append(json.dumps(record))
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture(scope="module")
def toy(tmp_path_factory: pytest.TempPathFactory) -> tuple[Dataset, dict, Path]:
    root = tmp_path_factory.mktemp("instruction_types")
    scene_dir = root / "scenes" / "tiny_room"
    scene_dir.mkdir(parents=True)
    write_scene_dir(build_scene(), scene_dir, bev=False)
    return _dataset(root / "toy" / "v1.0"), {"tiny_room": scene_dir, "tiny_room_b": scene_dir}, root


@pytest.fixture(scope="module")
def results(toy) -> dict[str, EvalResult]:
    dataset, scene_dirs, root = toy
    ids = [spec[0] for spec in EPISODES]
    out = {}
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("NAVVERSE_CACHE_DIR", str(root / "cache"))
        for kind, reached in REACHED.items():
            written = _write_run(root / f"{kind}.jsonl", None if kind == "category" else kind, reached)
            submission = read_submission(written, episode_ids=ids)
            assert not submission.problems
            out[kind] = score(dataset, submission, split="eval", scene_dirs=scene_dirs)
    return out


# ---------------------------------------------------------------------------------------------- submissions


def test_the_submission_field_is_kept_or_a_problem_of_its_line(tmp_path: Path):
    lines = [
        {"episode_id": "a", "trajectory": GOOD, "stop": True, "instruction_type": "route"},
        {"episode_id": "b", "trajectory": GOOD, "stop": True, "instruction_type": None},
        {"episode_id": "c", "trajectory": GOOD, "stop": True},
        {"episode_id": "d", "trajectory": GOOD, "stop": True, "instruction_type": "Route"},
        {"episode_id": "e", "trajectory": GOOD, "stop": True, "instruction_type": 3},
        {"episode_id": "f", "trajectory": GOOD, "stop": True, "instruction_type": "x" * 500},
        {"episode_id": "g", "trajectory": GOOD, "stop": True, "instruction_type": "intention"},
    ]
    path = tmp_path / "s.jsonl"
    path.write_text("\n".join(json.dumps(line) for line in lines) + "\n")
    submission = read_submission(path, episode_ids="abcdefg")
    kept = {k: r.instruction_type for k, r in submission.records.items()}
    assert kept == {"a": "route", "b": None, "c": None, "g": "intention"}
    assert [(p.line, p.episode_id, p.message) for p in submission.problems] == [
        (4, "d", "instruction_type must be one of category, route, intention (or null), not 'Route'"),
        (5, "e", "instruction_type must be a string or null, not a number"),
        (6, "f", "instruction_type has 500 characters, more than 200"),
    ]


def _record(episode_id: str, line: int, kind: str | None) -> TrajectoryRecord:
    return TrajectoryRecord(episode_id, np.array(GOOD), True, None, None, line, kind)


def test_a_submission_is_under_one_instruction_type():
    episodes = [_placenav(spec) for spec in EPISODES]

    def of(*records: TrajectoryRecord) -> str | None:
        submission = Submission(Path("run.jsonl"), {r.episode_id: r for r in records}, [], len(records))
        return instruction_type_of(submission, episodes)

    assert of() == "category"  # no valid PlaceNav record: nothing says otherwise
    assert of(_record("pn-0", 1, None), _record("pn-1", 2, "category")) == "category"
    assert (
        of(_record("pn-0", 1, "route"), _record("pn-2", 2, "route"), _record("on-0", 3, "intention"))
        == "route"
    )
    with pytest.raises(SubmissionError) as error:
        of(_record("pn-0", 1, "route"), _record("pn-1", 2, None), _record("pn-2", 3, "route"))
    message = str(error.value)
    assert "run.jsonl: its PlaceNav records disagree on instruction_type" in message
    assert "1 say 'category' (first on line 2); 2 say 'route' (first on line 1)" in message
    no_placenav = [e for e in episodes if e.task != "placenav"]
    assert instruction_type_of(Submission(Path("x"), {}, [], 0), no_placenav) is None


# ---------------------------------------------------------------------------------------------- the runner


def test_timeout_records_and_resumes_keep_the_instruction_type(tmp_path: Path):
    records: dict = {}
    with (tmp_path / "sink").open("w") as sink:
        results = Results(records, sink, lambda: None)
        row = [0.0, 1.0, 2.0, 0.5, 0.0, 0.0, 0.0, 1.0]
        results.handle(("begin", "pn-0", row, "intention"))
        results.time_out("pn-0", "too slow")
        results.handle(("begin", "on-0", row, None))
        results.time_out("on-0", "too slow")
    assert (
        records["pn-0"]["instruction_type"] == "intention"
        and records["pn-0"]["termination"] == "agent_timeout"
    )
    assert "instruction_type" not in records["on-0"]
    settings = RunSettings("random", "d", "1.0", "eval", "spot", instruction_type="route")
    partial = tmp_path / "run.jsonl.partial"
    partial.write_text(
        json.dumps({"navverse_run": {**settings.__dict__}}) + "\n" + json.dumps(records["pn-0"]) + "\n"
    )
    assert list(_read_partial(partial, settings)) == ["pn-0"]
    other = RunSettings("random", "d", "1.0", "eval", "spot", instruction_type="intention")
    assert _read_partial(partial, other) == {}  # another instruction type does not resume


def test_the_runner_refuses_route_without_instructions():
    episodes = [_placenav(spec) for spec in EPISODES]
    bare = [Episode.model_validate({**e.model_dump(mode="json"), "instructions": {}}) for e in episodes]
    _check_instruction_type(episodes, "route")
    _check_instruction_type(bare, "category")
    with pytest.raises(RunError, match="needs the PlaceNav episodes' instructions, and 4 have none"):
        _check_instruction_type(bare, "intention")
    with pytest.raises(RunError, match="choose from: category, route, intention"):
        _check_instruction_type(episodes, "landmark")


def test_the_command_line_takes_the_instruction_type_and_several_submissions():
    parser = build_parser()
    args = parser.parse_args(["run-agent", "--dataset", "d", "--agent", "random", "--out", "o.jsonl",
                              "--instruction-type", "intention"])  # fmt: skip
    assert args.instruction_type == "intention"
    args = parser.parse_args(["run-agent", "--dataset", "d", "--agent", "random", "--out", "o.jsonl"])
    assert args.instruction_type == "category"
    with pytest.raises(SystemExit):
        parser.parse_args(
            ["run-agent", "--dataset", "d", "--agent", "x", "--out", "o", "--instruction-type", "v"]
        )
    args = parser.parse_args(["eval", "--dataset", "d", "--submission", "a.jsonl", "--submission", "b.jsonl"])
    assert args.submission == ["a.jsonl", "b.jsonl"]


# ---------------------------------------------------------------------------------------------- the table


def test_each_submission_is_scored_under_its_type(results):
    assert {k: r.instruction_type for k, r in results.items()} == {k: k for k in REACHED}
    for kind, result in results.items():
        success = {row["episode_id"] for row in result.episodes if row["success"] == 1.0}
        assert success == REACHED[kind] | {"on-0"}


def _expected(result: EvalResult, scene_type: str | None) -> tuple[int, float, float]:
    rows = [r for r in result.episodes if r["task"] == "placenav" and scene_type in (None, r["scene_type"])]
    return len(rows), float(np.mean([r["success"] for r in rows])), float(np.mean([r["spl"] for r in rows]))


def test_the_table_has_a_row_per_instruction_type_in_the_papers_order(results):
    given = [results["route"], results["intention"], results["category"]]
    entries = instruction_type_entries(given)
    assert [e["instruction_type"] for e in entries] == ["category", "route", "intention"]
    assert [e["name"] for e in entries] == ["Store Category", "VLN Instruction", "Intention Driven"]
    sr = {
        e["instruction_type"]: (e["all"]["success"], e["outdoor"]["success"], e["i2o"]["success"])
        for e in entries
    }
    assert sr == {"category": (0.75, 1.0, 0.5), "route": (0.25, 0.0, 0.5), "intention": (0.0, 0.0, 0.0)}
    for entry in entries:
        result = results[entry["instruction_type"]]
        assert entry["submission"].endswith(f"{entry['instruction_type']}.jsonl")
        for key, scene_type in (("all", None), ("outdoor", "outdoor"), ("i2o", "i2o")):
            n, success, spl = _expected(result, scene_type)
            assert entry[key]["episodes"] == n == (4 if key == "all" else 2)
            assert entry[key]["success"] == pytest.approx(success)
            assert entry[key]["spl"] == pytest.approx(spl, abs=1e-6)
    category_spl = entries[0]["all"]["spl"]
    assert 0.5 < category_spl <= 0.75  # three of four reached, along their reference paths
    header, rows = instruction_type_table(entries)
    assert header == ["instruction type", "All N", "All SR (%)", "All SPL (%)", "Outdoor N", "Outdoor SR (%)",
                      "Outdoor SPL (%)", "Indoor-to-Outdoor N", "Indoor-to-Outdoor SR (%)",
                      "Indoor-to-Outdoor SPL (%)"]  # fmt: skip
    assert rows[0][:3] == ["Store Category", "4", "75.0"] and rows[0][3] == f"{100 * category_spl:.1f}"
    assert rows[1][:2] == ["VLN Instruction", "4"] and rows[1][2::3] == ["25.0", "0.0", "50.0"]
    assert rows[2][2::3] == ["0.0", "0.0", "0.0"]


def test_the_outputs_hold_the_table(results, tmp_path: Path):
    first = results["route"]
    out = write_outputs(first, tmp_path / "out", meta={"submission": "route.jsonl"},
                        others=[results["category"], results["intention"]])  # fmt: skip
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["overall"] == first.groups["overall"]["all"]  # the main outputs are the first's
    assert [e["instruction_type"] for e in metrics["instruction_types"]] == ["category", "route", "intention"]
    assert metrics["instruction_types"][1]["i2o"] == {"episodes": 2, "success": 0.5, "spl": pytest.approx(
        first.groups["task_scene_type"]["placenav/i2o"]["spl"])}  # fmt: skip
    with (out / "instruction_types.csv").open() as handle:
        table = list(csv.reader(handle))
    assert [row[0] for row in table] == [
        "instruction type",
        "Store Category",
        "VLN Instruction",
        "Intention Driven",
    ]
    assert table[1][1:3] == ["4", "75.0"]
    text = (out / "instruction_types.md").read_text()
    assert "| Intention Driven | 4 | 0.0 |" in text and "- VLN Instruction (route):" in text
    # One submission: the table has its row alone.
    write_outputs(results["category"], out, meta={})
    metrics = json.loads((out / "metrics.json").read_text())
    assert [e["name"] for e in metrics["instruction_types"]] == ["Store Category"]
    assert len((out / "instruction_types.csv").read_text().splitlines()) == 2
    # A split without PlaceNav episodes: no table, and an earlier one is removed.
    write_outputs(EvalResult(first.episodes, first.groups), out, meta={})
    assert "instruction_types" not in json.loads((out / "metrics.json").read_text())
    assert not (out / "instruction_types.md").exists() and not (out / "instruction_types.csv").exists()


def test_eval_refuses_mixed_or_repeated_instruction_types(toy, tmp_path: Path):
    dataset, scene_dirs, _ = toy
    route = _write_run(tmp_path / "route.jsonl", "route", REACHED["route"])
    again = _write_run(tmp_path / "again.jsonl", "route", set())
    category = _write_run(tmp_path / "category.jsonl", None, set())
    mixed = _write_run(tmp_path / "mixed.jsonl", "route", set(), mixed="intention")

    def read(*paths: Path) -> list[Submission]:
        args = argparse.Namespace(submission=[str(p) for p in paths], split="eval")
        return _read_for_eval(args, dataset, scene_dirs)

    assert [s.path.name for s in read(route, category)] == ["route.jsonl", "category.jsonl"]
    with pytest.raises(
        NavverseError, match=r"route.jsonl and .*again.jsonl were both run under instruction type 'route'"
    ):
        read(route, again)
    with pytest.raises(
        SubmissionError, match=r"1 say 'intention' \(first on line 4\); 3 say 'route' \(first on line 1\)"
    ):
        read(mixed)
