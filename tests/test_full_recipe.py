"""navverse-full is the paper's benchmark: its scenes per type and split, and quotas at tab:episode_counts."""

from __future__ import annotations

import fnmatch
from pathlib import Path

import pytest

from pipeline.recipes import RecipeLoader, Target
from pipeline.stage import discover
from pipeline.workspace import Workspace
from tests.script_module import load_script

REPO = Path(__file__).resolve().parents[1]


sizing = load_script("full_sizing")


@pytest.fixture(scope="module")
def targets() -> dict[str, Target]:
    return {t.id: t for t in RecipeLoader(Workspace(REPO), stages=discover("stages")).load()}


@pytest.mark.parametrize(
    ("scene_type", "train", "evaluation"), [("indoor", 80, 20), ("outdoor", 40, 10), ("i2o", 40, 10)]
)
def test_each_part_splits_its_scenes_as_the_paper(targets, scene_type: str, train: int, evaluation: int):
    part = targets[sizing.FULL_PARTS[scene_type]]
    linked = sizing.linked_scenes(part, targets)
    by_split = sizing.scenes_by_split(part, targets)
    assert len(linked) == train + evaluation
    assert {split: len(scenes) for split, scenes in by_split.items()} == {"train": train, "eval": evaluation}
    splits = sizing.stage_params(part, "package_dataset").splits
    for scene in linked:  # every scene in exactly one split: the build would refuse otherwise
        matched = [s for s, globs in splits.items() if any(fnmatch.fnmatchcase(scene, g) for g in globs)]
        assert len(matched) == 1, (scene, matched)


def test_the_quotas_are_the_paper_counts_and_total_ten_thousand(targets):
    totals = {"train": 0, "eval": 0}
    for (task, scene_type), counts in sizing.PAPER_COUNTS.items():
        quota = sizing.stage_params(targets[sizing.FULL_PARTS[scene_type]], "package_dataset").quota
        for split, count in counts.items():
            assert quota[split][task] == count, (task, scene_type, split)
            totals[split] += count
    assert totals == {"train": 9100, "eval": 900}


def test_i2o_scenes_stand_in_cities_of_their_own_split(targets):
    outdoor = sizing.scenes_by_split(targets["navverse-full-outdoor"], targets)
    for scene in sizing.linked_scenes(targets["navverse-full-i2o"], targets):
        split = "train" if "-train-" in scene else "eval"
        cities = [
            t for t in targets if any(fnmatch.fnmatchcase(t, p) for p in targets[scene].links["city"].targets)
        ]
        assert cities, scene
        assert set(cities) <= set(outdoor[split]), (scene, sorted(set(cities) - set(outdoor[split])))


def test_the_scenes_target_builds_exactly_the_parts_scenes(targets):
    """navverse-full-scenes links the same 200 scenes as the three parts of navverse-full."""
    parts = set()
    for part in sizing.FULL_PARTS.values():
        parts |= set(sizing.linked_scenes(targets[part], targets))
    scenes = set(sizing.linked_scenes(targets["navverse-full-scenes"], targets))
    assert len(parts) == 200 and scenes == parts, sorted(scenes ^ parts)


def test_a_dataset_s_counts_are_compared_with_the_paper_cell_by_cell():
    counts: dict = {}
    for (task, scene_type), by_split in sizing.PAPER_COUNTS.items():
        for split, n in by_split.items():
            counts.setdefault(split, {}).setdefault(task, {})[scene_type] = n
    assert sizing.count_differences(counts) == []
    counts["eval"]["vln"]["i2o"] = 149
    counts["eval"]["placenav"]["indoor"] = 3  # a cell the paper does not have
    assert sizing.count_differences(counts) == [
        ("eval", "placenav", "indoor", 0, 3),
        ("eval", "vln", "i2o", 150, 149),
    ]
