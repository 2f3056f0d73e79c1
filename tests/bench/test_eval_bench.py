"""bench/eval.py on a few short records: the vectorised metrics and its plain-Python reference agree.

This is the cross-check of ``navverse.eval.measures`` and ``navverse.eval.metrics`` against the
definitions written out again, row by row, in ``bench/eval.py`` (:func:`reference_scores`); no timing
is asserted.
"""

from __future__ import annotations

import importlib.util
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from navverse.eval import measures, metrics
from navverse.eval.scoring import robot_for

BENCH = Path(__file__).resolve().parents[2] / "bench" / "eval.py"
# 299 s at 5 Hz: cheap, long enough for the records that run 2 s over to be cut at 300 s, and steps of
# up to ~0.5 m, so coverage subdivides them.
SMALL = ["--trajectories", "20", "--hz", "5", "--seconds", "299", "--reference", "20", "--scene-size", "80"]


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("bench_eval", BENCH)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    try:
        spec.loader.exec_module(module)
        yield module
    finally:
        sys.modules.pop(spec.name, None)


def test_ours_and_the_reference_agree(bench, tmp_path):
    out = tmp_path / "eval.json"
    assert bench.main([*SMALL, "--json", str(out)]) == 0
    report = json.loads(out.read_text())
    assert report["trajectories"] == 20
    assert report["reference"]["trajectories"] == 20
    assert set(report["agreement"]) == {*bench.COMPARED, "label"}
    for name, entry in report["agreement"].items():
        assert entry["disagree"] == [], name
        assert entry["max_abs_diff"] <= 1e-6 * max(1.0, abs(report["means"].get(name, 0.0))), name
    assert report["labels"] == {"fall": 2, "success": 6, "timeout": 10, "wrong_goal": 2}


def test_the_records_exercise_every_branch(bench):
    """Each definition is compared on both sides of its cases, or the agreement above would prove little."""
    robot = robot_for("spot")
    fields = bench.synthetic_fields(80.0, 0)
    grid = bench.PlainGrid.of(fields, set(bench.SCENE_PREFERRED) | set(robot.extra_surfaces))
    records = [bench.synthetic_record(i, seed=0, hz=5.0, seconds=299.0, fields=fields) for i in range(20)]
    scores = [bench.reference_scores(r, robot, grid) for r in records]
    assert {s["label"] for s in scores} == {"success", "wrong_goal", "fall", "timeout"}
    assert any(r.rows[-1, 0] > 300.0 for r in records)  # cut at 300 s
    assert any(s["cr"] == 1.0 for s in scores) and any(s["cr"] == 0.0 for s in scores)
    assert any(s["os"] == 1.0 and s["label"] == "timeout" for s in scores)  # passed the goal
    assert any(s["path_length"] == 0.0 and s["spl"] == 1.0 for s in scores)  # L = P = 0
    assert any(s["soft_success"] == 1.0 and s["ne"] == 0.0 for s in scores)  # d_0 = 0
    assert any(0.0 < s["nsr"] < 1.0 for s in scores)
    dtw = [s["ndtw"] for s in scores if not math.isnan(s["ndtw"])]
    assert len(dtw) >= 6 and any(0.05 < v < 0.99 for v in dtw)
    steps = np.concatenate([np.hypot(*np.diff(r.rows[:, 1:3], axis=0).T) for r in records])
    assert (steps > 0.25).any()  # coverage subdivides these
    for r in records:
        assert np.allclose(np.linalg.norm(r.rows[:, 4:8], axis=1), 1.0)
        assert r.target.goal_centers.shape == (len(r.target.goal_radii), 3)


@pytest.mark.parametrize(
    ("module", "name", "value"), [(measures, "TIMEOUT_S", 200.0), (metrics, "CE_EPSILON", 2.0)]
)
def test_a_changed_definition_fails_the_run(bench, monkeypatch, module, name, value):
    monkeypatch.setattr(module, name, value)
    assert bench.main(SMALL) == 1


def test_agreement_flags_a_difference(bench):
    ours = {name: np.array([0.5, 1.0]) for name in bench.COMPARED}
    ours["label"] = np.array(["success", "timeout"], dtype=object)
    reference = [{**{name: 0.5 for name in bench.COMPARED}, "label": "success"},
                 {**{name: 1.0 for name in bench.COMPARED}, "label": "timeout"}]  # fmt: skip
    assert all(not e["disagree"] for e in bench.agreement(ours, reference).values())
    reference[1]["ce"] = 1.0 + 2e-6
    reference[0]["label"] = "fall"
    found = bench.agreement(ours, reference)
    assert [d["record"] for d in found["ce"]["disagree"]] == [1]
    assert [d["record"] for d in found["label"]["disagree"]] == [0]
