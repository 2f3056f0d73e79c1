"""The indoor-to-outdoor transition analysis on hand-worked trajectories (the paper's stage-wise table).

The scene is 20 x 10 m at 0.1 m cells, all floor, no obstacles; its indoor region is the left half
(x < 10). Rows are one a second at z = 0 and level unless said otherwise; every value below was worked
out on paper: CE = |1 m cells| / max(P, 1 m), the path split at the first row outdoors (the exit row,
which belongs to both parts).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from navverse.eval.measures import EpisodeTarget, Robot, measure
from navverse.eval.metrics import METRICS, compute_metrics
from navverse.eval.scoring import EvalResult, group_means, metric_rows
from navverse.eval.tables import table_rows, write_outputs
from navverse.scene.fields import SceneFields, indoor_raster

ROBOT = Robot(name="spot", radius=0.6, length=1.1, width=0.5)  # success distance 1.6 m
LEVEL = (0.0, 0.0, 0.0, 1.0)
TILTED = (math.sin(math.radians(30)), 0.0, 0.0, math.cos(math.radians(30)))  # 60 degrees about x
GOAL = (16.5, 8.5, 0.0)  # outdoors; radius 0.5


def house() -> SceneFields:
    shape = (100, 200)
    indoor = np.zeros(shape, dtype=bool)
    indoor[:, :100] = True
    return SceneFields(
        (0.0, 0.0),
        0.1,
        np.zeros(shape, dtype=np.int16),
        np.zeros(shape, dtype=bool),
        np.full(shape, 50.0, dtype=np.float32),
        ("floor",),
        indoor,
    )


def street() -> SceneFields:
    """The same ground without an indoor region."""
    fields = house()
    return SceneFields(
        fields.origin, fields.cell, fields.terrain, fields.obstacle, fields.distance, ("floor",)
    )


FIELDS = {"house": house(), "street": street()}
PREFERRED = {"house": np.array([True, False]), "street": np.array([True, False])}


def target(scene_type="i2o", task="objnav", scene="house") -> EpisodeTarget:
    return EpisodeTarget(
        episode_id="e",
        scene_id=scene,
        task=task,
        goal_centers=np.array([GOAL]),
        goal_radii=np.array([0.5]),
        geodesic=15.0,
        reference_path=np.zeros((0, 3)),
        scene_type=scene_type,
    )


def rows(xy, times=None, quats=None) -> np.ndarray:
    points = np.column_stack([np.asarray(xy, dtype=float), np.zeros(len(xy))])
    times = np.arange(len(points), dtype=float) if times is None else np.asarray(times, dtype=float)
    quats = np.tile(LEVEL, (len(points), 1)) if quats is None else np.asarray(quats, dtype=float)
    return np.column_stack([times, points, quats])


# Never leaves: 7 m along y = 5.5, cells x = 1..8; stops far from the goal (an indoor wrong goal).
STAY = rows([(1.5 + k, 5.5) for k in range(8)])
# Wanders indoors, exits at row 4 (x = 12.5), reaches the goal.
#   before, rows 0..4: up 2, back 2, east 4, east 3 = 11 m; cells (5,5) (5,6) (5,7), (6..12, 5): 10
#   after, rows 4..6: north 3, east 3 = 6 m; cells (12,5..8), (13..15, 8): 7
#   whole: 17 m, 10 + 7 - 1 shared cell (12,5) = 16 cells
WANDER = rows([(5.5, 5.5), (5.5, 7.5), (5.5, 5.5), (9.5, 5.5), (12.5, 5.5), (12.5, 8.5), (15.5, 8.5)])
# Exits at row 1 and falls at row 3 (row 4 is not scored): before 2 m, cells x = 8..10; after 3 m, x = 10..13.
FALL = rows(
    [(8.5, 2.5), (10.5, 2.5), (12.5, 2.5), (13.5, 2.5), (14.5, 2.5)],
    quats=[LEVEL, LEVEL, LEVEL, TILTED, LEVEL],
)
# Exits at row 1 and stands until 301 s (that row is not scored): before 2 m, x = 9..11; after 0 m, 1 cell.
TIMEOUT = rows([(9.5, 8.5), (11.5, 8.5), (11.5, 8.5), (11.5, 8.5)], times=[0, 100, 200, 301])
# Exits at row 1 and stops 5.33 m from the goal: before 1 m, x = 9..10; after 1 m, x = 10..11.
WRONG = rows([(9.5, 5.5), (10.5, 5.5), (11.5, 5.5)])
# PlaceNav, never leaves and times out: 2 m north at x = 2.5 (rows 0..1), cells (2,2) (2,3) (2,4).
STAY_TIMEOUT = rows([(2.5, 2.5), (2.5, 4.5), (2.5, 4.5)], times=[0, 150, 301])


def evaluate(trajectories, targets, stops, valid=None) -> dict[str, np.ndarray]:
    m = measure(
        trajectories,
        targets,
        robot=ROBOT,
        stops=stops,
        collisions=[np.zeros(0)] * len(trajectories),
        fields=FIELDS,
        preferred=PREFERRED,
    )
    valid = np.ones(len(targets)) if valid is None else np.asarray(valid, dtype=float)
    for name in m:
        m[name] = np.where(valid > 0, m[name], np.nan)  # what scoring gives an episode without a record
    m["geodesic"] = np.array([t.geodesic for t in targets])
    m["success_distance"] = np.full(len(targets), 1.6)
    m["valid"] = valid
    return compute_metrics(m)


def test_exit_measures_on_hand_worked_trajectories():
    trajectories = [STAY, WANDER, FALL, TIMEOUT, WRONG]
    m = evaluate(trajectories, [target()] * 5, stops=[True, True, False, False, True])
    assert list(m["label"]) == ["wrong_goal", "success", "fall", "timeout", "wrong_goal"]
    assert m["ind_only"].tolist() == [1.0, 0.0, 0.0, 0.0, 0.0]
    assert m["reach_out"].tolist() == [0.0, 1.0, 1.0, 1.0, 1.0]
    assert m["ce_pre_exit"] == pytest.approx([8 / 7, 10 / 11, 3 / 2, 3 / 2, 2 / 1])
    assert np.isnan(m["ce_post_exit"][0])  # never left
    assert m["ce_post_exit"][1:] == pytest.approx([7 / 6, 4 / 3, 1 / 1, 2 / 1])  # P = 0 counts as 1 m
    assert m["ce"][:2] == pytest.approx([8 / 7, 16 / 17])  # the whole path, unchanged
    # Post-exit failure causes: defined for the failed episodes that reached outdoors only.
    for name, expected in {
        "post_exit_wrong_goal": [0.0, 0.0, 1.0],
        "post_exit_fall": [1.0, 0.0, 0.0],
        "post_exit_timeout": [0.0, 1.0, 0.0],
    }.items():
        assert np.isnan(m[name][:2]).all()  # an indoor wrong goal, a success
        assert m[name][2:].tolist() == expected


def test_starting_outdoors_or_coming_back_in():
    outside = rows([(12.5, 5.5), (13.5, 5.5)])  # the exit row is row 0: nothing before it
    back = rows([(9.5, 5.5), (10.5, 5.5), (9.5, 5.5)])  # after the exit, rows 1..2: 1 m, x = 9..10
    m = evaluate([outside, back], [target(), target()], stops=[True, True])
    assert m["reach_out"].tolist() == [1.0, 1.0]
    assert np.isnan(m["ce_pre_exit"][0]) and m["ce_post_exit"][0] == pytest.approx(2.0)
    assert m["ce_pre_exit"][1] == pytest.approx(2.0) and m["ce_post_exit"][1] == pytest.approx(2.0)


def test_only_indoor_to_outdoor_episodes_with_an_indoor_region_get_exit_measures():
    names = ("ind_only", "reach_out", "ce_pre_exit", "ce_post_exit", "post_exit_wrong_goal")
    targets = [
        target(),
        target(scene_type="indoor"),
        target(scene_type="outdoor", scene="street"),
        target(scene="street"),  # i2o without an indoor region
        target(scene_type=""),  # unknown scene type
    ]
    m = evaluate([WRONG] * 5, targets, stops=[True] * 5)
    assert m["ind_only"][0] == 0.0 and m["post_exit_wrong_goal"][0] == 1.0
    for name in names:
        assert np.isnan(m[name][1:]).all(), name
    # Nothing else changes with the scene type or the indoor region.
    for name in ("success", "spl", "soft_spl", "os", "ne", "ce", "cr", "ado", "nsr", "path_length"):
        assert np.unique(m[name]).size == 1, name
    assert all(METRICS[n].scene_types == ("i2o",) for n in names)


def test_batched_equals_one_at_a_time():
    trajectories = [STAY, WANDER, FALL, TIMEOUT, WRONG, STAY_TIMEOUT]
    targets = [target(), target(scene_type="indoor"), target(), target(scene="street"), target(), target()]
    stops = [True, True, False, False, True, False]
    together = evaluate(trajectories, targets, stops)
    for i in range(len(trajectories)):
        alone = evaluate([trajectories[i]], [targets[i]], [stops[i]])
        for name, values in together.items():
            assert alone[name][0] == values[i] or (np.isnan(alone[name][0]) and np.isnan(values[i])), name


def facts(i, task, scene_type):
    return {"episode_id": f"e{i}", "scene_id": "house", "task": task, "scene_type": scene_type,
            "difficulty": "easy"}  # fmt: skip


def transition_result() -> EvalResult:
    """ObjNav i2o: STAY, WANDER, FALL, TIMEOUT twice, WRONG and one without a record; PlaceNav i2o:
    STAY_TIMEOUT; and an indoor ObjNav episode (WANDER), which the transition analysis leaves out."""
    episodes = [
        (STAY, True, "objnav", "i2o"),
        (WANDER, True, "objnav", "i2o"),
        (FALL, False, "objnav", "i2o"),
        (TIMEOUT, False, "objnav", "i2o"),
        (TIMEOUT, False, "objnav", "i2o"),
        (WRONG, True, "objnav", "i2o"),
        (WRONG, True, "objnav", "i2o"),  # no valid record: invalid
        (STAY_TIMEOUT, False, "placenav", "i2o"),
        (WANDER, True, "objnav", "indoor"),
    ]
    values = evaluate(
        [e[0] for e in episodes],
        [target(scene_type=e[3], task=e[2]) for e in episodes],
        stops=[e[1] for e in episodes],
        valid=[0.0 if i == 6 else 1.0 for i in range(len(episodes))],
    )
    episode_rows = metric_rows([facts(i, e[2], e[3]) for i, e in enumerate(episodes)], values)
    return EvalResult(episodes=episode_rows, groups=group_means(episode_rows))


def test_transition_groups_and_table(tmp_path):
    result = transition_result()
    rows = result.episodes
    assert rows[6]["label"] == "invalid" and rows[6]["ind_only"] is None  # no trajectory: undefined
    assert rows[8]["ind_only"] is None and rows[8]["ce_pre_exit"] is None  # indoor episode
    groups = result.groups["i2o_task"]
    assert list(groups) == ["objnav", "placenav"]
    objnav = groups["objnav"]
    assert objnav["episodes"] == 7 and objnav["post_exit_failures"] == 4
    assert objnav["ind_only"] == pytest.approx(1 / 6, abs=1e-6)  # of the 6 valid ones
    assert objnav["reach_out"] == pytest.approx(5 / 6, abs=1e-6)
    ce_pre = [8 / 7, 10 / 11, 3 / 2, 3 / 2, 3 / 2, 2]
    assert objnav["ce_pre_exit"] == pytest.approx(np.mean(ce_pre), abs=1e-6)  # 1.425325
    assert objnav["ce_post_exit"] == pytest.approx(np.mean([7 / 6, 4 / 3, 1, 1, 2]), abs=1e-6)  # 1.3
    # Of the 4 post-exit failures (FALL, TIMEOUT twice, WRONG): wrong goal 1, fall 1, timeout 2.
    shares = [objnav[f"post_exit_{label}"] for label in ("wrong_goal", "fall", "timeout")]
    assert shares == [0.25, 0.25, 0.5]
    placenav = groups["placenav"]
    assert placenav["ind_only"] == 1.0 and placenav["ce_pre_exit"] == pytest.approx(1.5)
    assert placenav["ce_post_exit"] is None and placenav["post_exit_timeout"] is None
    # The indoor episode does not count in the task's transition means either.
    assert result.groups["task"]["objnav"]["ind_only"] == pytest.approx(1 / 6, abs=1e-6)

    header, table = table_rows(result, "transition")
    assert header == [
        "task (i2o)",
        "episodes",
        "Ind-Only (%)",
        "Reach-Out (%)",
        "CE pre-exit (cells/m)",
        "CE post-exit (cells/m)",
        "#post-exit fail",
        "post-exit wrong goal (%)",
        "post-exit fall (%)",
        "post-exit timeout (%)",
    ]
    assert table == [
        # a metric defined on fewer episodes than the row's states its own N
        [
            "objnav",
            "7",
            "16.7 (n=6)",
            "83.3 (n=6)",
            "1.43 (n=6)",
            "1.30 (n=5)",
            "4",
            "25.0 (n=4)",
            "25.0 (n=4)",
            "50.0 (n=4)",
        ],
        ["placenav", "1", "100.0", "0.0", "1.50", "–", "0", "–", "–", "–"],
        # all i2o episodes (not the indoor one): CE pre (8.551948 + 1.5) / 7 = 1.435993
        [
            "all",
            "8",
            "28.6 (n=7)",
            "71.4 (n=7)",
            "1.44 (n=7)",
            "1.30 (n=5)",
            "4",
            "25.0 (n=4)",
            "25.0 (n=4)",
            "50.0 (n=4)",
        ],
    ]
    out = write_outputs(result, tmp_path / "out", meta={"submission": "test"})
    csv_lines = (out / "transition.csv").read_text().splitlines()
    assert csv_lines[0].startswith("task (i2o),episodes,Ind-Only (%),Ind-Only (%) N,Reach-Out (%),")
    assert csv_lines[1] == "objnav,7,16.7,6,83.3,6,1.43,6,1.30,5,4,25.0,4,25.0,4,50.0,4"  # value, its N
    assert "## transition" in (out / "tables.md").read_text()


def test_no_transition_table_without_indoor_to_outdoor_episodes(tmp_path):
    mixed = transition_result()
    keep = [r for r in mixed.episodes if r["scene_type"] != "i2o"]
    result = EvalResult(episodes=keep, groups=group_means(keep))
    assert result.groups["i2o_task"] == {}
    assert all(r[n] is None for r in keep for n in ("ind_only", "reach_out", "ce_pre_exit", "ce_post_exit"))
    out = tmp_path / "out"
    out.mkdir()
    (out / "transition.csv").write_text("stale\n")  # from an earlier run with i2o episodes
    write_outputs(result, out, meta={"submission": "test"})
    tables = (out / "tables.md").read_text()
    assert "transition" not in tables and "Ind-Only" not in tables
    assert not (out / "transition.csv").exists()
    for name in ("task_scene", "safety_efficiency", "failures", "difficulty"):
        assert (out / f"{name}.csv").is_file() and f"## {name.replace('_', ' ')}" in tables
    # The existing tables are what they were: the indoor WANDER episode is a success, CE 16/17.
    header, table = table_rows(result, "safety_efficiency")
    assert table[0][0] == "indoor" and table[0][header.index("CE (cells/m)")] == f"{16 / 17:.2f}"


def test_indoor_raster():
    triangle = [(0.0, 0.0), (3.6, 0.0), (0.0, 3.6)]  # cell centres (c + 0.5, r + 0.5) with c + r <= 2
    got = indoor_raster([triangle], (0.0, 0.0), (4, 4), 1.0)
    assert got.sum() == 6 and got[0, 2] and got[2, 0] and not got[1, 2]
    square = [(2.0, 2.0), (9.0, 2.0), (9.0, 9.0), (2.0, 9.0)]  # reaches beyond the grid: clipped
    both = indoor_raster([triangle, square], (0.0, 0.0), (4, 4), 1.0)
    assert both.sum() == 6 + 4 and both[3, 3] and both[2, 2]
    assert not indoor_raster([], (0.0, 0.0), (4, 4), 1.0).any()
    assert not indoor_raster([[(20, 20), (21, 20), (21, 21)]], (0.0, 0.0), (4, 4), 1.0).any()
