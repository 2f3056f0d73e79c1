"""The dataset contract: deterministic files, the reader, format versions, immutable published versions."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from navverse.dataset import (
    FORMAT_VERSION,
    Dataset,
    DatasetError,
    Episode,
    EpisodeInfo,
    Goal,
    goal_distance,
    publish,
    read_json_gz,
    write_json_gz,
)
from navverse.episodes.packaging import assign_splits, difficulty_of, difficulty_thresholds, write_dataset


def episode(number: int, scene: str, *, task: str = "objnav", length: float = 10.0) -> Episode:
    goal = Goal(object_id=7, category="bed", position=(5.0, 2.0, 0.3), radius=1.0, size=(2.0, 1.6, 0.6))
    return Episode(
        episode_id=f"{scene}-{task}-{number:04d}",
        scene_id=scene,
        scene_type="indoor",
        task=task,
        start_position=(0.0, 0.0, 0.0),
        start_rotation=(0.0, 0.0, math.sin(0.2), math.cos(0.2)),
        object_category="bed",
        goals=[goal],
        reference_path=[(0.0, 0.0, 0.0), (3.4, 2.0, 0.0)],
        info=EpisodeInfo(
            geodesic_distance=length, euclidean_distance=5.4, closest_goal_object_id=7, success_distance=1.6
        ),
    )


def build(out: Path, *, version: str = "1.0", lengths: tuple[float, ...] = (6.0, 9.0, 12.0, 20.0)) -> Path:
    episodes = [episode(i, "flat-s0" if i % 2 else "flat-s1", length=x) for i, x in enumerate(lengths)]
    rollouts = {e.episode_id: [[0.0, 0.0, 0.0, 0.55, 0.0, 0.0, 0.0, 1.0]] for e in episodes}
    write_dataset(
        out,
        episodes,
        rollouts,
        name="tiny",
        version=version,
        splits={"train": ["flat-s0"], "eval": ["flat-s1"]},
        embodiment="spot",
        recipe="recipes/datasets/tiny.yaml",
        recipe_hash="abc",
        scene_hashes={"flat-s0": "1", "flat-s1": "2"},
        toolkit_version="0.1.0",
    )
    return out


def test_json_gz_is_deterministic_and_round_trips(tmp_path: Path):
    data = {"b": [1.5, 2], "a": {"z": None, "y": "text"}}
    first = write_json_gz(data, tmp_path / "a.json.gz").read_bytes()
    second = write_json_gz(dict(reversed(list(data.items()))), tmp_path / "b.json.gz").read_bytes()
    assert first == second  # sorted keys, no time stamp
    assert read_json_gz(tmp_path / "a.json.gz") == data
    (tmp_path / "bad.json.gz").write_bytes(b"not gzip")
    with pytest.raises(DatasetError, match="not a gzipped JSON file"):
        read_json_gz(tmp_path / "bad.json.gz")


def test_goal_distance_is_3d_from_the_base_to_the_goal_edge():
    goal = Goal(object_id=1, category="bed", position=(5.0, 2.0, 0.3), radius=1.0, size=(2.0, 1.6, 0.6))
    assert goal_distance((8.0, 6.0, 0.3), goal) == pytest.approx(4.0)  # 5 m to the centre, minus 1 m
    assert goal_distance((8.0, 2.0, 4.3), goal) == pytest.approx(4.0)  # 3 m across and 4 m up
    assert goal_distance((5.5, 2.0, 0.8), goal) == 0.0  # within the radius


def test_written_datasets_read_back_by_split_task_and_type(tmp_path: Path):
    root = build(tmp_path / "tiny" / "v1.0")
    dataset = Dataset(root)
    assert dataset.splits == ["eval", "train"] and dataset.tasks("train") == ["objnav"]
    assert [e.episode_id for e in dataset.episodes(split="train")] == [
        "flat-s0-objnav-0001",
        "flat-s0-objnav-0003",
    ]
    assert len(list(dataset.episodes(scene_type="outdoor"))) == 0
    assert dataset.manifest.counts == {"eval": {"objnav": {"indoor": 2}}, "train": {"objnav": {"indoor": 2}}}
    assert dataset.episode("flat-s1-objnav-0002").info.difficulty == "hard"
    assert dataset.rollout(dataset.episode("flat-s1-objnav-0000")) == [
        [0.0, 0.0, 0.0, 0.55, 0.0, 0.0, 0.0, 1.0]
    ]
    assert dataset.verify_checksums() == []
    assert Dataset(tmp_path / "tiny").root == root  # the dataset folder opens its newest version
    with pytest.raises(DatasetError, match="no split 'test'"):
        list(dataset.episodes(split="test"))
    with pytest.raises(DatasetError, match="no episode 'nope'"):
        dataset.episode("nope")


def test_same_episodes_give_the_same_bytes(tmp_path: Path):
    a, b = build(tmp_path / "a"), build(tmp_path / "b")
    for name in json.loads((a / "manifest.json").read_text())["files"]:
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    assert (a / "manifest.json").read_bytes() == (b / "manifest.json").read_bytes()


@pytest.mark.parametrize(
    ("version", "message"),
    [
        ("2.0", "Update the toolkit"),
        ("0.9", "Rebuild the dataset"),
        ("1.9", "Update the toolkit"),
        ("one", "major.minor"),
    ],
)
def test_other_format_versions_are_refused_with_what_to_do(tmp_path: Path, version: str, message: str):
    root = build(tmp_path / "tiny" / "v1.0")
    manifest = json.loads((root / "manifest.json").read_text())
    manifest["format_version"] = version
    (root / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(DatasetError, match=message):
        Dataset(root)
    assert FORMAT_VERSION == "1.3"


def test_an_older_minor_format_is_read(tmp_path: Path):
    root = build(tmp_path / "tiny" / "v1.0")
    manifest = json.loads((root / "manifest.json").read_text())
    manifest["format_version"] = "1.0"  # before PlaceNav episodes had their instructions by type
    del manifest["look_version"]  # and before scenes had looks (1.2)
    (root / "manifest.json").write_text(json.dumps(manifest))
    assert Dataset(root).manifest.format_version == "1.0"
    assert Dataset(root).manifest.look_version is None


def test_missing_or_malformed_datasets_say_so(tmp_path: Path):
    with pytest.raises(DatasetError, match="not a dataset version"):
        Dataset(tmp_path)
    root = build(tmp_path / "tiny" / "v1.0")
    (root / "manifest.json").write_text(json.dumps({"format_version": "1.0", "name": "tiny"}))
    with pytest.raises(DatasetError, match="malformed"):
        Dataset(root)


def test_a_published_version_is_immutable(tmp_path: Path):
    episodes_dir = tmp_path / "episodes"
    first = build(tmp_path / "built-1")
    path, written = publish(first, episodes_dir)
    assert written and path == episodes_dir / "tiny" / "v1.0" and Dataset(path).verify_checksums() == []
    assert publish(build(tmp_path / "built-again"), episodes_dir) == (
        path,
        False,
    )  # same content: nothing to do
    changed = build(tmp_path / "built-2", lengths=(6.0, 9.0, 12.0, 21.0))
    with pytest.raises(
        DatasetError, match=r"already published with different content.*bump the dataset version"
    ):
        publish(changed, episodes_dir)
    bumped = build(tmp_path / "built-3", version="1.1", lengths=(6.0, 9.0, 12.0, 21.0))
    assert publish(bumped, episodes_dir)[0] == episodes_dir / "tiny" / "v1.1"
    assert sorted(p.name for p in (episodes_dir / "tiny").iterdir()) == ["v1.0", "v1.1"]  # no staging left


def test_splits_are_scene_disjoint_and_complete():
    scenes = ["apartment-s0", "apartment-s1", "office-s0", "office-s1"]
    assert assign_splits(scenes, {"train": ["*-s0"], "eval": ["*-s1"]}) == {
        "train": ["apartment-s0", "office-s0"],
        "eval": ["apartment-s1", "office-s1"],
    }
    with pytest.raises(DatasetError, match="'office-s1' matches no split"):
        assign_splits(scenes, {"train": ["*-s0"], "eval": ["apartment-s1"]})
    with pytest.raises(DatasetError, match="'apartment-s0' matches the splits train, eval"):
        assign_splits(scenes, {"train": ["*-s0"], "eval": ["apartment-*", "office-s1"]})


def test_difficulty_tertiles_per_task():
    episodes = [episode(i, "a", length=float(i + 1)) for i in range(9)]
    episodes += [episode(i, "a", task="vln", length=100.0 + i) for i in range(3)]
    thresholds = difficulty_thresholds(episodes)
    assert thresholds["objnav"] == pytest.approx((3.667, 6.333), abs=1e-3)
    assert thresholds["vln"] == pytest.approx((100.667, 101.333), abs=1e-3)
    labels = [difficulty_of(e.info.geodesic_distance, thresholds["objnav"]) for e in episodes[:9]]
    assert labels == ["easy"] * 3 + ["medium"] * 3 + ["hard"] * 3


def test_each_rollout_file_is_read_once_however_many_rollouts_are_asked(tmp_path: Path, monkeypatch):
    dataset = Dataset(build(tmp_path / "tiny" / "v1.0"))
    loads: list[str] = []
    real_load = Dataset._load
    monkeypatch.setattr(Dataset, "_load", lambda self, name: loads.append(name) or real_load(self, name))
    episodes = list(dataset.episodes())
    assert all(dataset.rollout(e) is not None for e in episodes) and len(episodes) == 4
    rollout_files = [name for name in loads if name.endswith(".rollouts.json.gz")]
    assert sorted(rollout_files) == ["eval/objnav.rollouts.json.gz", "train/objnav.rollouts.json.gz"]
