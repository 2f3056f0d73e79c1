"""A dataset made of datasets: two dataset recipes over different scenes merged by a third into one
version whose scenes keep their parts' splits, whose episodes and rollouts are the parts' with the
difficulty relabelled over the whole; parts over the same scene are refused."""

from __future__ import annotations

import shutil

import pytest

from navverse.dataset import Dataset, built_version
from tests.stages.conftest import SCENES, Built, build_all, workspace_with

PART = """\
extends: dataset
manual: true
seed: 3
links:
  scene: [{scene}]
stages:
  sample_episodes:
    tasks:
      objnav: {{episodes_per_scene: 5}}
    categories: [bed, sofa, toilet, fridge, oven, bathtub, bench, desk, wardrobe, sink, armchair]
  package_dataset:
    version: "1.0"
    splits: {{{split}: ["*"]}}
"""
MERGED = """\
seed: 0
links:
  parts: {artifact: dataset, targets: [part-a, part-b]}
stages:
  merge_datasets: {version: "2.0"}
"""


@pytest.fixture(scope="module")
def built(tiny_build: Built, tmp_path_factory: pytest.TempPathFactory) -> Built:
    """The parts and their merge built over the apartment scenes the test process has built
    (:func:`~tests.conftest.tiny_build`: its store is copied, so the scenes are cached)."""
    extra = {
        "datasets/part-a.yaml": PART.format(scene="apartment-s0", split="train"),
        "datasets/part-b.yaml": PART.format(scene="apartment-s1", split="eval"),
        "datasets/merged.yaml": MERGED,
    }
    workspace = workspace_with(tmp_path_factory.mktemp("merge"), [SCENES], extra)
    shutil.copytree(tiny_build.workspace.built_dir, workspace.built_dir, symlinks=True)
    result = build_all(workspace)
    assert result.report.ok, result.report
    return result


def test_the_merged_dataset_holds_both_parts_with_their_splits(built: Built) -> None:
    parts = [Dataset(built_version(built.output(p, "dataset"))) for p in ("part-a", "part-b")]
    merged = Dataset(built_version(built.output("merged", "dataset")))
    merged.verify()
    assert (merged.manifest.name, merged.manifest.version) == ("merged", "2.0")
    assert merged.manifest.splits == {"eval": ["apartment-s1"], "train": ["apartment-s0"]}
    ids = sorted(e.episode_id for p in parts for e in p.episodes())
    assert ids and sorted(e.episode_id for e in merged.episodes()) == ids
    for part in parts:
        for episode in part.episodes():
            mine = merged.episode(episode.episode_id)
            assert mine.start_position == episode.start_position and mine.goals == episode.goals
            assert merged.rollout(mine) == part.rollout(episode)
    difficulties = {e.info.difficulty for e in merged.episodes()}
    assert difficulties == {"easy", "medium", "hard"}  # tertiles over the merged episodes
    stats = built.manifest("merged", "dataset")["stats"]
    assert [p["name"] for p in stats["parts"]] == ["part-a", "part-b"]


def test_parts_over_the_same_scene_are_refused(built: Built, navverse_here) -> None:
    root = built.workspace.root
    (root / "recipes" / "datasets" / "part-c.yaml").write_text(
        PART.format(scene="apartment-s1", split="eval")
    )
    (root / "recipes" / "datasets" / "overlap.yaml").write_text(
        MERGED.replace("part-a, part-b", "part-b, part-c")
    )
    result = navverse_here(root, "build", "overlap", "--jobs", "0")
    output = " ".join((result.stdout + result.stderr).split())
    assert result.returncode == 1 and "Traceback" not in output
    assert "scene 'apartment-s1' is in both part-b v1.0 and part-c v1.0" in output
