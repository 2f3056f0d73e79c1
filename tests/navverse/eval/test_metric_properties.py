"""Properties of the measures and metrics over arbitrary valid trajectories.

Trajectories as validation lets through and beyond (finite values of any size, far outside the scene,
a single row, times up to 1e300 s, tilted bodies) never make :func:`measure` raise, and every metric
stays in its range (``navverse.eval.metrics``): SR, SPL, SS, SoftSPL, OS, CR, NSR, nDTW, SDTW, Ind-Only,
Reach-Out and the post-exit shares in [0, 1]; NE, P, CE, ADO, the speed and the pre/post-exit CE finite
and >= 0; the label one of the scored labels.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from navverse.eval.measures import EpisodeTarget, Robot, measure
from navverse.eval.metrics import LABELS, METRICS, compute_metrics
from navverse.scene.fields import SceneFields

ROBOT = Robot(name="spot", radius=0.6, length=1.1, width=0.5)
UNIT = ("success", "spl", "soft_success", "soft_spl", "os", "cr", "nsr", "ndtw", "sdtw", "ind_only",
        "reach_out", "post_exit_wrong_goal", "post_exit_fall", "post_exit_timeout")  # fmt: skip
NON_NEGATIVE = ("ne", "path_length", "ce", "ado", "speed", "ce_pre_exit", "ce_post_exit")
UNDEFINED_AT_TIMES = (
    "post_exit_wrong_goal",
    "post_exit_fall",
    "post_exit_timeout",
    "ce_post_exit",
    "ce_pre_exit",
)
"""Undefined (NaN) for some episodes they apply to: post-exit ones unless the robot reached outdoors (the
shares also unless it failed), CE before the exit when it starts outdoors."""


def house() -> SceneFields:
    """20 x 10 m at 0.25 m: floor and grass, a wall at x = 10 with a door, indoors left of it."""
    shape = (40, 80)
    terrain = np.zeros(shape, dtype=np.int16)
    terrain[:, 60:] = 1
    obstacle = np.zeros(shape, dtype=bool)
    obstacle[:, 40] = True
    obstacle[18:22, 40] = False
    indoor = np.zeros(shape, dtype=bool)
    indoor[:, :40] = True
    from scipy import ndimage

    distance = (ndimage.distance_transform_edt(~obstacle) * 0.25).astype(np.float32)
    return SceneFields((0.0, 0.0), 0.25, terrain, obstacle, distance, ("floor", "grass"), indoor)


FIELDS = {"house": house()}
PREFERRED = {"house": np.array([True, False, False])}


def target(task: str, scene_type: str) -> EpisodeTarget:
    return EpisodeTarget(
        episode_id="e",
        scene_id="house",
        task=task,
        goal_centers=np.array([[15.0, 5.0, 0.5], [3.0, 8.0, 0.5]]),
        goal_radii=np.array([0.5, 0.3]),
        geodesic=12.0,
        reference_path=np.array([[2.0, 5.0, 0.0], [10.0, 5.0, 0.0], [15.0, 5.0, 0.0]]),
        scene_type=scene_type,
    )


finite = st.floats(allow_nan=False, allow_infinity=False)
coordinate = st.floats(-5.0, 25.0) | st.floats(-1e7, 1e7) | finite
steps = st.floats(1e-6, 400.0) | st.floats(1e-6, 1e300)


@st.composite
def quaternions(draw) -> list[float]:
    """Unit quaternions: level, or any orientation (tilted ones fall)."""
    if draw(st.booleans()):
        return [0.0, 0.0, 0.0, 1.0]
    q = np.array(draw(st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4)))
    norm = np.linalg.norm(q)
    return (q / norm).tolist() if norm > 1e-3 else [0.0, 0.0, 0.0, 1.0]


@st.composite
def trajectories(draw) -> np.ndarray:
    """(K, 8) rows: time from 0 (or later) in increasing steps, any finite positions, unit quaternions."""
    count = draw(st.integers(1, 12))
    times = np.cumsum([draw(st.floats(0.0, 1e3) | st.just(1e300)), *(draw(steps) for _ in range(count - 1))])
    for i in range(1, count):  # strictly increasing, as validated (a tiny step after 1e300 s adds nothing)
        times[i] = max(times[i], np.nextafter(times[i - 1], np.inf))
    rows = [[t, draw(coordinate), draw(coordinate), draw(coordinate), *draw(quaternions())] for t in times]
    return np.array(rows, dtype=np.float64)


episodes = st.tuples(
    trajectories(),
    st.sampled_from([("objnav", "indoor"), ("vln", "indoor"), ("objnav", "i2o"), ("vln", "i2o")]),
    st.booleans(),
    st.none() | st.lists(st.floats(0.0, 400.0), max_size=3),
)


@given(st.lists(episodes, min_size=1, max_size=4))
def test_metrics_of_arbitrary_trajectories_stay_in_their_ranges(batch):
    trajectories_ = [rows for rows, *_ in batch]
    targets = [target(*kind) for _, kind, *_ in batch]
    collisions = [None if c is None else np.array(c) for *_, c in batch]
    m = measure(
        trajectories_, targets, robot=ROBOT, stops=[stop for _, _, stop, _ in batch], collisions=collisions,
        fields=FIELDS, preferred=PREFERRED,
    )  # fmt: skip
    assert np.all(m["cells"] >= 1) and np.all(np.isfinite(m["traveled"]))
    m["geodesic"] = np.full(len(batch), 12.0)
    m["success_distance"] = np.full(len(batch), 1.6)
    m["valid"] = np.ones(len(batch))
    values = compute_metrics(m)
    assert set(values["label"]) <= set(LABELS) - {"invalid"}
    for i, (rows, (task, scene_type), _, _) in enumerate(batch):
        for name in (*UNIT, *NON_NEGATIVE):
            value = float(values[name][i])
            if not METRICS[name].applies(task, scene_type):
                continue
            if name in UNDEFINED_AT_TIMES and math.isnan(value):
                continue
            assert math.isfinite(value), (name, value)
            assert value >= 0.0, (name, value)
            if name in UNIT:
                assert value <= 1.0, (name, value)
        assert values["spl"][i] <= values["success"][i]
        assert values["soft_spl"][i] <= values["soft_success"][i] + 1e-12
        if len(rows) == 1:
            assert values["path_length"][i] == 0.0 and values["ce"][i] == 1.0
