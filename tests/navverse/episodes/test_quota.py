"""Quotas: a split and task keeps at most its quota, spread over the scenes, whatever the input order."""

from __future__ import annotations

from collections import Counter

import pytest

from navverse.dataset import DatasetError, Episode
from navverse.episodes.packaging import apply_quota
from tests.navverse.test_dataset import episode

SPLITS = {"train": ["a", "b", "c"], "eval": ["d"]}


def _candidates() -> list[Episode]:
    sizes = {"a": 9, "b": 3, "c": 6, "d": 5}  # per scene, objnav; vln has 4 per scene
    episodes = [episode(i, scene, task="objnav") for scene, n in sizes.items() for i in range(n)]
    return episodes + [episode(i, scene, task="vln") for scene in sizes for i in range(4)]


def test_a_quota_keeps_that_many_spread_over_the_scenes():
    episodes = _candidates()
    kept, report = apply_quota(episodes, SPLITS, {"train": {"objnav": 10}, "eval": {"vln": 2}}, seed=0)
    per_scene = Counter((e.scene_id, e.task) for e in kept)
    # 10 over scenes of 9, 3 and 6 candidates: round-robin gives 4, 3 and 3 (b runs out after three turns)
    assert sorted(per_scene[(s, "objnav")] for s in "abc") == [3, 3, 4]
    assert per_scene[("b", "objnav")] == 3
    assert per_scene[("d", "vln")] == 2
    assert per_scene[("d", "objnav")] == 5  # no quota: all kept
    assert all(per_scene[(s, "vln")] == 4 for s in "abc")
    assert report == {
        "eval": {"vln": {"available": 4, "quota": 2, "kept": 2}},
        "train": {"objnav": {"available": 18, "quota": 10, "kept": 10}},
    }
    assert [e.episode_id for e in kept] == [e.episode_id for e in episodes if e in kept]  # input order kept


def test_the_choice_depends_on_the_seed_not_on_the_input_order():
    episodes = _candidates()
    quota = {"train": {"objnav": 7}}
    first = {e.episode_id for e in apply_quota(episodes, SPLITS, quota, seed=3)[0]}
    again = {e.episode_id for e in apply_quota(list(reversed(episodes)), SPLITS, quota, seed=3)[0]}
    other = {e.episode_id for e in apply_quota(episodes, SPLITS, quota, seed=4)[0]}
    assert first == again
    assert first != other


def test_a_quota_above_what_is_there_keeps_all_and_reports_the_shortfall():
    episodes = _candidates()
    kept, report = apply_quota(episodes, SPLITS, {"eval": {"objnav": 50, "placenav": 5}}, seed=0)
    assert len(kept) == len(episodes)
    assert report["eval"]["objnav"] == {"available": 5, "quota": 50, "kept": 5}
    assert report["eval"]["placenav"] == {"available": 0, "quota": 5, "kept": 0}


def test_a_quota_for_an_unknown_split_is_refused_naming_the_splits():
    with pytest.raises(DatasetError, match=r"quota names splits val .*\(eval, train\)"):
        apply_quota(_candidates(), SPLITS, {"val": {"objnav": 3}}, seed=0)
