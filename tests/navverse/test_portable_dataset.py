"""A dataset shipped with its scenes: ``navverse export scenes`` in the workspace that built it, then
``run-agent``, ``eval``, ``show episode`` and ``validate dataset`` with ``--scenes`` (or
``$NAVVERSE_SCENES``) in a directory with no workspace at all."""

from __future__ import annotations

import json
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from navverse.dataset import Dataset, DatasetError, Episode, EpisodeInfo, Verification
from navverse.episodes.packaging import write_dataset
from navverse.errors import SceneError
from navverse.files import file_sha256
from navverse.scene.directory import scene_hash
from tests.navverse.test_env import build_room, table_episodes

NAVVERSE = str(Path(sys.executable).with_name("navverse"))
DATASET = Path("episodes") / "room" / "v1.0"


def _episodes() -> list[Episode]:
    """Three short ObjNav episodes to the table of the test room (their figures within the dataset's
    bounds, so `validate dataset` passes them)."""
    verification = Verification(embodiment="spot", duration_s=8.0, traveled_m=5.5, oracle_success_time_s=6.0)
    info = EpisodeInfo(
        geodesic_distance=5.5,
        euclidean_distance=4.0,
        closest_goal_object_id=1,
        success_distance=1.6,
        verification=verification,
    )
    return table_episodes(3, first_y=3.0, step=0.8, end=(5.5, 5.0), info=info)


def _run(cwd: Path, *args: str, **env: str) -> subprocess.CompletedProcess[str]:
    """``navverse ARGS`` in `cwd`, with neither NAVVERSE_ROOT nor NAVVERSE_SCENES unless given."""
    base = {k: v for k, v in os.environ.items() if k not in ("NAVVERSE_ROOT", "NAVVERSE_SCENES")}
    return subprocess.run(
        [NAVVERSE, *args], env={**base, **env}, cwd=cwd, capture_output=True, text=True, timeout=300
    )


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A workspace whose build store holds the room and whose ``episodes/`` holds a dataset in it."""
    root = tmp_path_factory.mktemp("workspace")
    (root / "recipes").mkdir()
    artifact = root / "data" / "built" / "artifacts" / "navmesh" / "scene-0"
    artifact.mkdir(parents=True)
    build_room(artifact)
    (artifact / "manifest.json").write_text("{}")  # a committed artifact, as the engine leaves it
    (artifact / "stage.log").write_text("built\n")
    link = root / "data" / "built" / "targets" / "env_room" / "scene"
    link.parent.mkdir(parents=True)
    link.symlink_to(artifact)
    episodes = _episodes()
    rollouts = {e.episode_id: [[0.0, *e.start_position[:2], 0.55, 0.0, 0.0, 0.0, 1.0]] for e in episodes}
    hashes = {"env_room": scene_hash(artifact)}
    write_dataset(root / DATASET, episodes, rollouts, name="room", version="1.0",
                  splits={"eval": ["env_room"]}, embodiment="spot", recipe="room.yaml", recipe_hash="0",
                  scene_hashes=hashes, toolkit_version="0")  # fmt: skip
    return root


@pytest.fixture(scope="module")
def exported(workspace: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A directory with no workspace holding a copy of the dataset version and its scene pack."""
    made = _run(workspace, "export", "scenes", str(DATASET), "pack", "--split", "eval")
    assert made.returncode == 0, made.stderr
    assert "wrote pack: 1 scenes, 3 files" in " ".join(made.stdout.split())
    away = tmp_path_factory.mktemp("elsewhere")
    shutil.copytree(workspace / DATASET, away / "room" / "v1.0")
    shutil.copytree(workspace / "pack", away / "pack", symlinks=True)
    return away


def test_the_pack_holds_copies_of_the_scene_files_and_their_checksums(workspace: Path, exported: Path):
    pack, artifact = (
        workspace / "pack",
        (workspace / "data" / "built" / "targets" / "env_room" / "scene").resolve(),
    )
    names = sorted(p.name for p in (pack / "env_room").iterdir())
    assert names == ["navmesh.bin", "scene.json", "scene.usdc"]  # not the store's manifest.json, stage.log
    for name in names:
        copy = (pack / "env_room" / name).lstat()
        assert (
            stat.S_ISREG(copy.st_mode) and copy.st_ino != (artifact / name).stat().st_ino
        )  # copied, not linked
    index = json.loads((pack / "scenes.json").read_text())
    manifest = Dataset(workspace / DATASET).manifest
    assert index["dataset"] == {
        "name": "room",
        "version": "1.0",
        "manifest_sha256": Dataset(workspace / DATASET).manifest_sha256,
    }
    assert index["split"] == "eval" and list(index["scenes"]) == ["env_room"]
    entry = index["scenes"]["env_room"]
    assert entry["scene_hash"] == manifest.scene_hashes["env_room"] == scene_hash(pack / "env_room")
    assert entry["files"] == {name: file_sha256(artifact / name) for name in names}


def test_an_existing_pack_is_not_overwritten(workspace: Path, exported: Path):
    before = (workspace / "pack" / "scenes.json").read_bytes()
    again = _run(workspace, "export", "scenes", str(DATASET), "pack")
    assert again.returncode == 1 and "Traceback" not in again.stderr
    assert "pack already exists (a directory, not empty): give a new directory" in " ".join(
        again.stderr.split()
    )
    assert (workspace / "pack" / "scenes.json").read_bytes() == before


def test_the_oracle_runs_and_is_scored_where_there_is_no_workspace(exported: Path):
    cache = str(exported / "cache")
    ran = _run(exported, "run-agent", "--dataset", "room/v1.0", "--scenes", "pack", "--agent", "oracle",
               "--jobs", "0", "--out", "oracle.jsonl", NAVVERSE_CACHE_DIR=cache)  # fmt: skip
    assert ran.returncode == 0, ran.stderr
    records = [json.loads(line) for line in (exported / "oracle.jsonl").read_text().splitlines()]
    assert [r["episode_id"] for r in records] == [e.episode_id for e in _episodes()]
    assert all(r["stop"] for r in records)
    scored = _run(exported, "eval", "--dataset", "room/v1.0", "--scenes", "pack",
                  "--submission", "oracle.jsonl", "--out", "scored", NAVVERSE_CACHE_DIR=cache)  # fmt: skip
    assert scored.returncode == 0, scored.stderr
    metrics = json.loads((exported / "scored" / "metrics.json").read_text())
    assert metrics["overall"]["success"] == 1.0 and metrics["overall"]["episodes"] == 3


def test_the_environment_variable_finds_the_pack_too(exported: Path):
    path = os.pathsep.join([str(exported / "nowhere"), str(exported / "pack")])
    drawn = _run(exported, "show", "episode", "room/v1.0", "env_room-objnav-0001", "-o", "ep.png",
                 NAVVERSE_SCENES=path)  # fmt: skip
    assert drawn.returncode == 0, drawn.stderr
    assert (exported / "ep.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_missing_scene_names_every_place_and_what_to_do(exported: Path):
    failed = _run(exported, "run-agent", "--dataset", "room/v1.0", "--agent", "oracle", "--out", "x.jsonl")
    assert failed.returncode == 1 and "Traceback" not in failed.stderr
    lines = failed.stderr.splitlines()
    assert lines[0] == "error: scene 'env_room' not found; looked in, in order:"
    assert lines[1].startswith(
        f"  1. the workspace's build store: no recipes/ folder in {exported.resolve()}"
    )
    assert (
        "--scenes DIR" in lines[2]
        and "navverse export scenes" in lines[2]
        and "navverse build env_room" in lines[2]
    )
    assert not (exported / "x.jsonl").exists()


def test_a_pack_of_other_scenes_is_refused_by_hash(exported: Path, tmp_path: Path):
    tampered = tmp_path / "tampered"
    shutil.copytree(exported / "pack", tampered)
    navmesh = tampered / "env_room" / "navmesh.bin"
    navmesh.write_bytes(navmesh.read_bytes() + b"\0")
    checked = _run(exported, "validate", "dataset", "room/v1.0", "--scenes", str(tampered))
    assert checked.returncode == 1 and "Traceback" not in checked.stderr
    expected = Dataset(exported / "room" / "v1.0").manifest.scene_hashes["env_room"]
    text = " ".join(checked.stderr.split())
    got = scene_hash(tampered / "env_room")
    assert (
        f"1. --scenes {tampered}: scene hash {got[:12]}… differs from the dataset's {expected[:12]}…" in text
    )
    good = _run(exported, "validate", "dataset", "room/v1.0", "--scenes", str(tampered), "--scenes", "pack")
    assert good.returncode == 0, good.stderr
    assert f"env_room: {(exported / 'pack' / 'env_room').resolve()}" in good.stdout


def test_the_reader_finds_an_episodes_scene(exported: Path):
    dataset = Dataset(exported / "room" / "v1.0")
    episode = next(dataset.episodes())
    assert (
        dataset.scene_dir(episode, search=[exported / "pack"]) == (exported / "pack" / "env_room").resolve()
    )
    assert (
        dataset.scene_dir("env_room", search=[exported / "pack"])
        == (exported / "pack" / "env_room").resolve()
    )
    with pytest.raises(DatasetError, match="has no scene 'office'"):
        dataset.scene_dir("office", search=[exported / "pack"])
    with pytest.raises(SceneError, match=r"1\. --scenes .*nowhere: no such directory"):
        dataset.scene_dir(episode, search=[exported / "nowhere"])
