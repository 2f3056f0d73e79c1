"""The episodes a report draws as cards: bounded, deterministic, every outcome shown, failures first; the
labels they are chosen by, known before scoring; ``navverse eval --pictures``; and what eval keeps to the
end, frozen for the garbage collector while it runs."""

from __future__ import annotations

import math
import random
from collections import Counter

import numpy as np
import pytest

from navverse.eval.measures import EpisodeTarget, Robot, measure, outcome
from navverse.eval.metrics import compute_metrics, termination_labels
from navverse.eval.selection import CARD_ORDER, NO_TRAJECTORY, PICTURES, pictured_episodes
from navverse.scene.fields import SceneFields

TASKS = ("objnav", "vln")
SCENE_TYPES = ("indoor", "i2o")
SCENES = {"indoor": ("flat-a", "flat-b", "flat-c"), "i2o": ("cafe-a", "cafe-b")}


def _rows(counts: dict[str, int]) -> list[dict]:
    """Rows of episodes with each label `counts` times, spread over tasks, scene types and scenes."""
    rows = []
    for label, count in counts.items():
        for k in range(count):
            task, scene_type = TASKS[k % 2], SCENE_TYPES[(k // 2) % 2]
            scenes = SCENES[scene_type]
            scene = scenes[(k // 4) % len(scenes)]
            rows.append({"episode_id": f"{scene}-{task}-{label}-{k:04d}", "label": label, "task": task,
                         "scene_type": scene_type, "scene_id": scene})  # fmt: skip
    return rows


def _labels(rows: list[dict], chosen: list[str]) -> Counter:
    label_of = {row["episode_id"]: row["label"] for row in rows}
    return Counter(label_of[i] for i in chosen)


def test_every_episode_has_a_card_when_there_are_no_more_than_asked():
    rows = _rows({"success": 5, "fall": 2})
    assert pictured_episodes(rows, 7) == [row["episode_id"] for row in rows]
    assert pictured_episodes(rows, 100) == [row["episode_id"] for row in rows]
    assert pictured_episodes(rows, 0) == []


def test_the_labels_take_turns_failures_first():
    rows = _rows({"success": 500, "fall": 10, "timeout": 1, "invalid": 5})
    chosen = pictured_episodes(rows, 10)
    assert len(chosen) == len(set(chosen)) == 10
    # Turns: fall, timeout, success; then fall, success (no timeout is left); ... An episode without a
    # valid record has nothing to picture: it is a row.
    assert _labels(rows, chosen) == {"fall": 5, "timeout": 1, "success": 4}
    assert [_labels(rows, [i]).most_common(1)[0][0] for i in chosen[:4]] == [
        "fall", "timeout", "success", "fall"]  # fmt: skip
    few = pictured_episodes(rows, 2)  # fewer cards than labels: the failures
    assert set(_labels(rows, few)) == {"fall", "timeout"}
    assert CARD_ORDER[0] == NO_TRAJECTORY == "invalid"  # listed first, never pictured
    everyone = _rows({"success": 3, "invalid": 2})
    assert pictured_episodes(everyone, 5) == [row["episode_id"] for row in everyone]  # as many cards as rows


def test_a_label_s_cards_spread_over_tasks_scene_types_and_scenes():
    rows = _rows({"success": 400})
    chosen = pictured_episodes(rows, PICTURES)
    by_id = {row["episode_id"]: row for row in rows}
    groups = Counter((by_id[i]["task"], by_id[i]["scene_type"]) for i in chosen)
    assert len(groups) == 4 and max(groups.values()) - min(groups.values()) <= 1
    for (task, scene_type), _ in groups.items():
        scenes = Counter(by_id[i]["scene_id"] for i in chosen
                         if (by_id[i]["task"], by_id[i]["scene_type"]) == (task, scene_type))  # fmt: skip
        assert set(scenes) == set(SCENES[scene_type]) and max(scenes.values()) - min(scenes.values()) <= 1


def test_the_choice_depends_on_the_episodes_not_on_their_order():
    rows = _rows({"success": 300, "wrong_goal": 40, "timeout": 17})
    chosen = pictured_episodes(rows, 25)
    shuffled = list(rows)
    random.Random(7).shuffle(shuffled)
    assert pictured_episodes(shuffled, 25) == chosen
    # Nor on how the ids are numbered: a scene's episodes come in the order of their ids' hashes.
    first_success = [i for i in chosen if "success" in i]
    assert first_success != sorted(first_success)


def test_a_label_added_later_takes_its_turn_after_the_known_ones():
    rows = _rows({"success": 3, "stuck": 3, "fall": 3})
    chosen = pictured_episodes(rows, 3)
    assert set(_labels(rows, chosen)) == {"fall", "success", "stuck"}
    assert "stuck" in chosen[-1]


def _target(i: int) -> EpisodeTarget:
    goal = [5.0, 1.0 + i, 0.5]
    return EpisodeTarget(
        episode_id=f"e{i}", scene_id="room", task="vln" if i % 2 else "objnav",
        goal_centers=np.array([goal, [2.0, 2.0, 0.5]]), goal_radii=np.array([0.3, 0.2]), geodesic=6.0,
        reference_path=np.array([[0.0, 0.0, 0.5], goal]), scene_type="indoor",
    )  # fmt: skip


def test_the_outcome_measures_and_labels_are_those_of_the_full_scoring():
    rng = np.random.default_rng(3)
    trajectories = []
    for i in range(8):
        k = 5 + 7 * i
        rows = np.zeros((k, 8))
        rows[:, 0] = np.arange(k) * (50.0 if i == 3 else 0.5)  # one runs past 300 s
        rows[:, 1:3] = np.cumsum(rng.normal(0.3, 0.4, (k, 2)), axis=0)
        rows[:, 3] = 0.5
        rows[:, 7] = 1.0
        if i == 5:  # it tilts over 45 degrees halfway
            tilt = math.radians(60) / 2
            rows[k // 2 :, 4], rows[k // 2 :, 7] = math.sin(tilt), math.cos(tilt)
        trajectories.append(rows)
    targets = [_target(i) for i in range(len(trajectories))]
    stops = [bool(i % 3) for i in range(len(trajectories))]
    fields = SceneFields((-50.0, -50.0), 0.5, np.zeros((200, 200), np.int16), np.zeros((200, 200), bool),
                         np.full((200, 200), 10.0, np.float32), ("floor",))  # fmt: skip
    robot = Robot(name="spot", radius=0.6, length=1.1, width=0.5)
    full = measure(trajectories, targets, robot=robot, stops=stops, collisions=[None] * len(trajectories),
                   fields={"room": fields}, preferred={"room": np.array([True, False])})  # fmt: skip
    early = outcome(trajectories, targets, stops=stops)
    for name, values in early.items():
        np.testing.assert_array_equal(values, full[name], err_msg=name)
    inputs = {**full, "geodesic": np.full(8, 6.0), "success_distance": np.full(8, 1.6),
              "valid": np.array([1.0] * 7 + [0.0])}  # fmt: skip
    labels = termination_labels(inputs)
    assert list(labels) == list(compute_metrics(inputs)["label"])
    assert {"fall", "invalid"} <= set(labels) and len(set(labels)) >= 3


def test_navverse_eval_takes_the_number_of_cards():
    from navverse.cli import build_parser
    from navverse.commands.evaluate import _pictures

    parser = build_parser()
    base = ["eval", "--dataset", "d", "--submission", "s.jsonl"]
    assert parser.parse_args(base).pictures == PICTURES == 60
    assert _pictures(parser.parse_args(base).pictures) == 60
    for given, count in (("0", 0), ("7", 7), ("100000", 100_000), (3, 3)):
        assert _pictures(parser.parse_args([*base, "--pictures", str(given)]).pictures) == count
        assert _pictures(given) == count


@pytest.mark.parametrize("bad", ["-1", "many", "2.5", "", "1e3"])
def test_a_bad_number_of_cards_is_a_clear_error_before_any_work(bad: str, tmp_path, capsys):
    from navverse.cli import main

    # The dataset does not exist: the value is refused before anything is read.
    argv = ["eval", "--dataset", str(tmp_path / "none"), "--submission", str(tmp_path / "none.jsonl")]
    assert main([*argv, "--out", str(tmp_path / "out"), f"--pictures={bad}"]) == 1
    err = capsys.readouterr().err
    assert f"error: --pictures {bad}: give the number of episode cards" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


def test_eval_freezes_what_it_keeps_only_while_it_runs():
    import gc

    from navverse.commands.evaluate import _long_lived

    assert gc.get_freeze_count() == 0
    with _long_lived() as settle:
        kept = [[i] for i in range(1000)]
        settle()
        assert gc.get_freeze_count() >= len(kept)
    assert gc.get_freeze_count() == 0
    gc.freeze()  # objects someone else froze stay as they are
    try:
        frozen = gc.get_freeze_count()
        with _long_lived() as settle:
            settle()
            assert gc.get_freeze_count() == frozen
        assert gc.get_freeze_count() == frozen
    finally:
        gc.unfreeze()
