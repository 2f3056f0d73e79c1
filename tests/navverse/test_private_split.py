"""Private splits: a test split published without its goals, the goals in a private file apart."""

from __future__ import annotations

import gzip
import json
import math
from pathlib import Path

import pytest

from navverse.dataset import (
    PUBLIC_FORMAT_VERSION,
    Dataset,
    DatasetError,
    Episode,
    EpisodeInfo,
    Goal,
    Instruction,
    Landmark,
    local_dataset,
    publish,
    read_json_gz,
)
from navverse.dataset.private import private_dir, withhold
from navverse.episodes.merging import merge_parts
from navverse.episodes.packaging import write_dataset

GOAL = Goal(object_id=7, category="bed", position=(5.25, 2.75, 0.3), radius=1.0, size=(2.0, 1.6, 0.6))


def episode(number: int, scene: str, *, task: str = "objnav") -> Episode:
    instruction = None
    if task == "vln":
        instruction = Instruction(
            instruction_text="Walk past the sofa and stop at the bed.",
            template_text="Walk past the {0} and stop at the {1}.",
            instruction_type="landmark",
            landmarks=[Landmark(object_id=3, category="sofa", step=0)],
            directive_times=[4.5],
        )
    return Episode(
        episode_id=f"{scene}-{task}-{number:04d}",
        scene_id=scene,
        scene_type="indoor",
        task=task,
        start_position=(0.0, 0.0, 0.0),
        start_rotation=(0.0, 0.0, math.sin(0.2), math.cos(0.2)),
        object_category="bed",
        goals=[GOAL],
        instruction=instruction,
        reference_path=[(0.0, 0.0, 0.0), (3.4, 2.0, 0.0)],
        info=EpisodeInfo(
            geodesic_distance=6.0 + number,
            euclidean_distance=5.4,
            closest_goal_object_id=7,
            success_distance=1.6,
        ),
    )


SCENES = {"train": ["flat-s0"], "eval": ["flat-s1"], "test": ["flat-s2"]}


def build(out: Path, *, name: str = "tiny", version: str = "1.0", splits: dict | None = None) -> Path:
    splits = SCENES if splits is None else splits
    scenes = [s for members in splits.values() for s in members]
    episodes = [episode(i, scene, task=task) for i, scene in enumerate(scenes) for task in ("objnav", "vln")]
    rollouts = {e.episode_id: [[0.0, 0.0, 0.0, 0.55, 0.0, 0.0, 0.0, 1.0]] for e in episodes}
    write_dataset(
        out,
        episodes,
        rollouts,
        name=name,
        version=version,
        splits=splits,
        embodiment="spot",
        recipe="recipes/datasets/tiny.yaml",
        recipe_hash="abc",
        scene_hashes={s: str(i) for i, s in enumerate(scenes)},
        toolkit_version="0.1.0",
    )
    return out


def test_a_test_split_is_published_without_its_goals_and_they_go_to_a_private_file(tmp_path: Path):
    root = build(tmp_path / "tiny" / "v1.0")
    manifest = json.loads((root / "manifest.json").read_text())
    assert manifest["format_version"] == "1.3"
    assert sorted(manifest["private"]) == ["test"]
    assert "test/objnav.json.gz" in manifest["files"]
    assert not any(n.startswith("test/") and "rollouts" in n for n in manifest["files"])  # no test paths
    public = read_json_gz(root / "test" / "vln.json.gz")
    assert public["goals_by_category"] == {}
    (record,) = public["episodes"]
    assert record["goals"] == [] and record["reference_path"] == [] and record["info"] is None
    assert record["instruction"]["instruction_text"].startswith("Walk past the sofa")
    assert record["instruction"]["landmarks"] == [] and record["instruction"]["directive_times"] == []
    text = b"".join(gzip.decompress(p.read_bytes()) for p in (root / "test").iterdir())
    text += (root / "manifest.json").read_bytes()
    assert b"5.25" not in text and b"3.4" not in text  # neither the goal nor the reference path shows
    private = private_dir(root) / "test.private.json.gz"
    assert private.is_file() and private.parent == tmp_path / "tiny" / "private" / "v1.0"
    assert b"5.25" in gzip.decompress(private.read_bytes())


def test_without_the_private_file_a_private_split_has_no_goals_and_scoring_it_says_how(tmp_path: Path):
    root = build(tmp_path / "tiny" / "v1.0")
    dataset = Dataset(root)
    dataset.verify()
    assert dataset.private_splits == {"test"} and not dataset.has_goals("test") and dataset.has_goals("eval")
    episodes = list(dataset.episodes(split="test"))
    assert [e.withheld for e in episodes] == [True, True] and all(not e.goals for e in episodes)
    assert dataset.rollout(episodes[0]) is None
    with pytest.raises(DatasetError, match=r"keeps its goals private.*--private DIR.*private/v1.0"):
        dataset.require_goals("test", what="scoring")
    dataset.require_goals("eval", what="scoring")  # public goals: nothing to say


def test_with_the_private_file_the_episodes_are_whole_and_checked_against_their_public_records(
    tmp_path: Path,
):
    root = build(tmp_path / "tiny" / "v1.0")
    dataset = Dataset(root, private=private_dir(root))
    dataset.verify()
    episodes = list(dataset.episodes(split="test"))
    assert [e.goals for e in episodes] == [[GOAL], [GOAL]]
    assert episodes[1].instruction.landmarks[0].category == "sofa"
    assert dataset.rollout(episodes[0]) == [[0.0, 0.0, 0.0, 0.55, 0.0, 0.0, 0.0, 1.0]]
    assert [withhold(e) for e in episodes] == list(Dataset(root).episodes(split="test"))
    assert local_dataset(root).has_goals("test")  # found beside the version


def test_a_public_record_that_gives_a_goal_away_or_a_private_file_not_its_own_is_refused(tmp_path: Path):
    root = build(tmp_path / "a" / "v1.0")
    other = build(tmp_path / "b" / "v1.0", name="other")
    with pytest.raises(DatasetError, match="checksum"):
        Dataset(root, private=private_dir(other)).verify()
    # The manifest's checksum of the public file is updated, as someone re-packaging by hand would:
    # the content check still finds the goal.
    leaky = tmp_path / "leaky" / "v1.0"
    build(leaky)
    path = leaky / "test" / "objnav.json.gz"
    content = read_json_gz(path)
    content["episodes"][0]["goals"] = [GOAL.model_dump(mode="json")]
    from navverse.dataset import file_sha256, write_json_gz

    write_json_gz(content, path)
    manifest = json.loads((leaky / "manifest.json").read_text())
    manifest["files"]["test/objnav.json.gz"] = file_sha256(path)
    (leaky / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(DatasetError, match=r"private split test, gives away its goals"):
        Dataset(leaky).verify()


def test_a_dataset_without_a_private_split_keeps_its_format_and_bytes(tmp_path: Path):
    root = build(tmp_path / "tiny" / "v1.0", splits={"train": ["flat-s0"], "eval": ["flat-s1"]})
    text = (root / "manifest.json").read_text()
    assert json.loads(text)["format_version"] == PUBLIC_FORMAT_VERSION == "1.2"
    assert "private" not in text and not private_dir(root).exists()
    with pytest.raises(DatasetError, match=r"--private .* has no private split.*leave --private out"):
        Dataset(root, private=tmp_path)


def test_publishing_puts_the_private_files_beside_the_version_and_merging_keeps_them_private(tmp_path: Path):
    episodes_dir = tmp_path / "episodes"
    built = build(tmp_path / "built" / "tiny" / "v1.0")
    path, written = publish(built, episodes_dir)
    assert written and (episodes_dir / "tiny" / "private" / "v1.0" / "test.private.json.gz").is_file()
    assert publish(built, episodes_dir) == (path, False)
    assert sorted(p.name for p in (episodes_dir / "tiny").iterdir()) == ["private", "v1.0"]
    assert Dataset(episodes_dir / "tiny").root == path  # the private folder is not a version

    part = build(
        tmp_path / "built" / "part" / "v1.0", name="part", splits={"train": ["flat-s3"], "test": ["flat-s4"]}
    )
    merged = merge_parts([local_dataset(path), local_dataset(part)])
    assert merged.splits["test"] == ["flat-s2", "flat-s4"]
    assert all(e.goals for e in merged.episodes)  # whole episodes from the private files
    out = tmp_path / "merged" / "v1.0"
    write_dataset(
        out, merged.episodes, merged.rollouts, name="merged", version="1.0", splits=merged.splits,
        embodiment="spot", recipe="r", recipe_hash="h", scene_hashes=merged.scene_hashes, toolkit_version="0",
    )  # fmt: skip
    whole = Dataset(out, private=private_dir(out))
    whole.verify()
    assert len(list(whole.episodes(split="test"))) == 4
    assert all(e.withheld for e in Dataset(out).episodes(split="test"))
