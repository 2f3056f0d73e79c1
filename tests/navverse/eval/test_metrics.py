"""The metrics on hand-worked trajectories: every value below was computed on paper from the definitions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navverse.eval import measures
from navverse.eval.measures import DTW_SPACING, EpisodeTarget, Robot, _resample, measure, ndtw, ndtw_many
from navverse.eval.metrics import compute_metrics
from navverse.scene.fields import SceneFields

ROBOT = Robot(name="spot", radius=0.6, length=1.1, width=0.5)  # success distance 1.6 m
LEVEL = (0.0, 0.0, 0.0, 1.0)


def room() -> SceneFields:
    """10 x 10 m at 0.1 m: floor (preferred), a road strip y < 2.5, a wall in the last column (x >= 9.9)."""
    terrain = np.zeros((100, 100), dtype=np.int16)
    terrain[:25, :] = 1
    obstacle = np.zeros((100, 100), dtype=bool)
    obstacle[:, 99] = True
    from scipy import ndimage

    distance = (ndimage.distance_transform_edt(~obstacle) * 0.1).astype(np.float32)
    return SceneFields((0.0, 0.0), 0.1, terrain, obstacle, distance, ("floor", "road"))


FIELDS = {"room": room()}
PREFERRED = {"room": np.array([True, False, False])}


def target(goal=(8.05, 5.05, 0.55), radius=0.5, geodesic=5.0, task="objnav", reference=None) -> EpisodeTarget:
    return EpisodeTarget(
        episode_id="e",
        scene_id="room",
        task=task,
        goal_centers=np.array([goal], dtype=float),
        goal_radii=np.array([radius]),
        geodesic=geodesic,
        reference_path=np.zeros((0, 3)) if reference is None else np.asarray(reference, dtype=float),
        scene_type="indoor",
    )


def rows(points, times=None, quats=None) -> np.ndarray:
    points = np.asarray(points, dtype=float)
    times = np.arange(len(points), dtype=float) if times is None else np.asarray(times, dtype=float)
    quats = np.tile(LEVEL, (len(points), 1)) if quats is None else np.asarray(quats, dtype=float)
    return np.column_stack([times, points, quats])


def score(trajectories, targets, stops, collisions=None):
    collisions = collisions if collisions is not None else [np.zeros(0)] * len(trajectories)
    m = measure(trajectories, targets, robot=ROBOT, stops=stops, collisions=collisions, fields=FIELDS,
                preferred=PREFERRED)  # fmt: skip
    m["geodesic"] = np.array([t.geodesic for t in targets])
    m["success_distance"] = np.full(len(targets), 1.6)
    m["valid"] = np.ones(len(targets))
    return compute_metrics(m)


# Episode A: 6 m along +x at y = 5.05 (1 m/s, a row a second), stop 1 m short of the goal's centre.
A = rows([(1.05 + k, 5.05, 0.55) for k in range(7)])
# Episode B: 3 m along +x on the road strip, stops far from the goal.
B = rows([(1.05 + k, 2.05, 0.55) for k in range(4)])


def test_a_successful_episode():
    m = score([A], [target()], stops=[True])
    assert m["label"][0] == "success"
    assert m["success"][0] == 1.0
    assert m["ne"][0] == pytest.approx(0.5)  # |7.05 - 8.05| - 0.5
    assert m["spl"][0] == pytest.approx(5.0 / 6.0)  # L = 5, P = 6
    assert m["soft_success"][0] == pytest.approx(1.0 - 0.5 / 6.5)  # d_0 = 7 - 0.5
    assert m["soft_spl"][0] == pytest.approx((1.0 - 0.5 / 6.5) * 5.0 / 6.0)
    assert m["os"][0] == 1.0
    assert m["ce"][0] == pytest.approx(7.0 / 6.0)  # cells x = 1..7 at y = 5, over 6 m
    assert m["cr"][0] == 0.0
    assert m["ado"][0] == pytest.approx(np.mean([8.9 - k for k in range(7)]), abs=1e-5)  # to the wall column
    assert m["nsr"][0] == 1.0
    assert m["path_length"][0] == pytest.approx(6.0)
    assert m["speed"][0] == pytest.approx(1.0)


def test_a_stop_far_from_the_goal_is_a_wrong_goal():
    m = score([B], [target()], stops=[True])
    d0 = math.hypot(7.0, 3.0) - 0.5
    assert m["label"][0] == "wrong_goal" and m["success"][0] == 0.0 and m["spl"][0] == 0.0
    assert m["ne"][0] == pytest.approx(4.5)  # (4.05, 2.05) to (8.05, 5.05) is 5 m, minus 0.5
    assert m["soft_success"][0] == pytest.approx(1.0 - 4.5 / d0)
    assert m["soft_spl"][0] == pytest.approx((1.0 - 4.5 / d0) * 5.0 / 5.0)  # L = 5 > P = 3
    assert m["os"][0] == 0.0
    assert m["nsr"][0] == 0.0  # all on the road


def test_falls_and_timeouts():
    tilted = (math.sin(math.radians(30)), 0.0, 0.0, math.cos(math.radians(30)))  # 60 degrees about x
    near = rows([(7.05, 5.05, 0.55), (7.15, 5.05, 0.55), (7.25, 5.05, 0.55), (7.35, 5.05, 0.55)],
                quats=[LEVEL, LEVEL, tilted, LEVEL])  # fmt: skip
    still = rows([(1.05, 5.05, 0.55)] * 4, times=[0.0, 100.0, 200.0, 301.0])
    m = score([near, still], [target(), target()], stops=[True, False])
    assert list(m["label"]) == ["fall", "timeout"]
    assert m["success"].tolist() == [0.0, 0.0] and m["os"][0] == 1.0  # it was within reach before falling
    assert m["path_length"][0] == pytest.approx(0.2)  # scored up to the fall row
    assert m["path_length"][1] == 0.0 and m["ce"][1] == pytest.approx(1.0)  # one cell, P = 0: 1 / max(0, 1)
    assert m["spl"][1] == 0.0


def test_edge_cases_l_zero_p_zero_d0_zero():
    # Starts inside the goal's radius and stays: d_0 = d_T = 0, L = 0, P = 0.
    here = rows([(8.05, 5.05, 0.55)] * 3)
    m = score([here], [target(geodesic=0.0)], stops=[True])
    assert m["label"][0] == "success"
    assert m["spl"][0] == 1.0 and m["soft_success"][0] == 1.0 and m["soft_spl"][0] == 1.0
    # d_0 = 0 but it walks away: SS 0 (no progress possible, and it left).
    away = rows([(8.05, 5.05, 0.55), (8.05, 7.05, 0.55), (8.05, 9.05, 0.55)])
    m = score([away], [target(geodesic=0.0)], stops=[True])
    assert m["soft_success"][0] == 0.0 and m["label"][0] == "wrong_goal"
    assert m["spl"][0] == 0.0


def test_collisions_from_the_submission_or_the_footprint():
    into_wall = rows([(8.05, 5.05, 0.55), (9.05, 5.05, 0.55), (9.65, 5.05, 0.55)])
    # Reported: a contact at 1.5 s counts, one after the last scored row does not.
    m = score(
        [A, A], [target(), target()], stops=[True, True], collisions=[np.array([1.5]), np.array([60.0])]
    )
    assert m["cr"].tolist() == [1.0, 0.0]
    # Not reported: the footprint capsule (0.25 m half-width, 1.1 m long) against the obstacle field.
    m = score([into_wall, A], [target(), target()], stops=[True, True], collisions=[None, None])
    assert m["cr"].tolist() == [1.0, 0.0]


def test_ndtw():
    reference = [(0.0, 0.0, 0.0), (4.0, 0.0, 0.0)]
    assert ndtw(np.array(reference), np.array(reference), threshold=1.6) == pytest.approx(1.0)
    shifted = np.array([(0.0, 1.0, 0.0), (4.0, 1.0, 0.0)])
    # Both resampled to 9 points; the best alignment pairs them in order, 1 m apart: DTW = 9.
    assert ndtw(shifted, np.array(reference), threshold=1.6) == pytest.approx(math.exp(-9.0 / (9 * 1.6)))
    vln = rows([(0.0, 5.05, 0.55), (2.0, 5.05, 0.55), (4.0, 5.05, 0.55)])
    m = score(
        [vln], [target(goal=(4.0, 5.05, 0.55), task="vln", reference=[(0, 5.05, 0), (4, 5.05, 0)])], [True]
    )
    assert m["ndtw"][0] == pytest.approx(1.0) and m["sdtw"][0] == pytest.approx(1.0)


def _ndtw_row_by_row(trajectory: np.ndarray, reference: np.ndarray, threshold: float) -> float:
    """nDTW of one pair, its table filled a row at a time (how :func:`ndtw` computed it before pairs were
    run side by side)."""
    q, r = _resample(trajectory, DTW_SPACING), _resample(reference, DTW_SPACING)
    cost = np.linalg.norm(q[:, None, :] - r[None, :, :], axis=2)
    previous = np.full(len(r) + 1, np.inf)
    previous[0] = 0.0
    for row in cost:
        above = np.minimum(previous[1:], previous[:-1])
        through = np.cumsum(row)
        previous = np.concatenate([[np.inf], np.minimum.accumulate(row + above - through) + through])
    return float(math.exp(-previous[-1] / (len(r) * threshold)))


def _ndtw_textbook(trajectory: np.ndarray, reference: np.ndarray, threshold: float) -> float:
    """nDTW by the recurrence D[i, j] = c[i, j] + min(D[i-1, j], D[i, j-1], D[i-1, j-1]), in plain loops."""
    q, r = _resample(trajectory, DTW_SPACING), _resample(reference, DTW_SPACING)
    table = np.full((len(q) + 1, len(r) + 1), np.inf)
    table[0, 0] = 0.0
    for i in range(1, len(q) + 1):
        for j in range(1, len(r) + 1):
            c = math.dist(q[i - 1], r[j - 1])
            table[i, j] = c + min(table[i - 1, j], table[i, j - 1], table[i - 1, j - 1])
    return math.exp(-table[-1, -1] / (len(r) * threshold))


def test_ndtw_of_many_pairs_equals_each_pair_alone(monkeypatch: pytest.MonkeyPatch):
    rng = np.random.default_rng(5)
    trajectories, references, thresholds = [], [], []
    for k in range(120):
        path = np.cumsum(rng.normal(0.0, rng.uniform(0.05, 2.0), (int(rng.integers(1, 90)), 3)), axis=0)
        reference = np.cumsum(rng.normal(0.0, rng.uniform(0.05, 2.0), (int(rng.integers(2, 40)), 3)), axis=0)
        if k % 11 == 0:  # standing still: one point
            path[:] = path[0]
        if k % 13 == 0:  # a reference of no length
            reference[:] = reference[0]
        trajectories.append(path)
        references.append(reference)
        thresholds.append(float(rng.uniform(0.5, 2.0)))
    alone = [_ndtw_row_by_row(*pair) for pair in zip(trajectories, references, thresholds, strict=True)]
    assert ndtw_many(trajectories, references, thresholds=thresholds).tolist() == alone  # exactly
    for k in (0, 1, 7, 50):
        assert ndtw(trajectories[k], references[k], threshold=thresholds[k]) == alone[k]
        assert alone[k] == pytest.approx(_ndtw_textbook(trajectories[k], references[k], thresholds[k]))
    monkeypatch.setattr(measures, "_DTW_CELLS", 40)  # groups of a few pairs, or one: the same values
    assert ndtw_many(trajectories, references, thresholds=thresholds).tolist() == alone
    assert ndtw_many([], [], thresholds=[]).tolist() == []


def test_batched_equals_one_at_a_time():
    trajectories, targets = [A, B, A], [target(), target(), target(goal=(1.05, 9.05, 0.55))]
    together = score(trajectories, targets, stops=[True, False, True])
    for i in range(3):
        alone = score([trajectories[i]], [targets[i]], stops=[[True, False, True][i]])
        for name, values in together.items():
            assert alone[name][0] == values[i] or (
                alone[name][0] != alone[name][0] and values[i] != values[i]
            )


def test_metric_rows_hold_each_defined_value_rounded_and_none_elsewhere():
    from navverse.eval.metrics import LABELS, METRICS
    from navverse.eval.scoring import metric_rows

    rng = np.random.default_rng(2)
    kinds = [("objnav", "indoor"), ("vln", "i2o"), ("placenav", "outdoor"), ("objnav", "i2o")]
    facts = [
        {"episode_id": f"e{i}", "scene_id": "s", "task": kinds[i % 4][0], "scene_type": kinds[i % 4][1],
         "difficulty": "easy"}
        for i in range(40)
    ]  # fmt: skip
    values = {name: rng.normal(0.0, 10.0, 40) for name in METRICS}
    values["success"] = rng.random(40) < 0.5  # a bool array: its rows hold floats
    values["spl"][::7] = np.nan
    values["ne"][::9] = np.inf
    values["label"] = np.array(LABELS, dtype=object)[rng.integers(0, len(LABELS), 40)]
    rows = metric_rows(facts, values)
    for i, (fact, row) in enumerate(zip(facts, rows, strict=True)):
        assert row["label"] == values["label"][i] and {k: row[k] for k in fact} == fact
        for name, spec in METRICS.items():
            if name.startswith("_"):
                assert name not in row
                continue
            v = float(values[name][i])
            defined = spec.applies(fact["task"], fact["scene_type"]) and math.isfinite(v)
            assert row[name] == (round(v, 6) if defined else None), (i, name)
            assert row[name] is None or type(row[name]) is float
