"""Built scene directories found in a store written by the build engine."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from navverse.errors import SceneError
from navverse.scene.locate import built_scene_dir, built_scene_dirs
from pipeline.store import ArtifactStore


def _commit(store: ArtifactStore, target: str, stage: str, output: str, key: str) -> Path:
    """Commit an artifact as the engine does and link it as the target's output."""
    tmp = store.new_tmp(stage, output, key)
    (tmp / "scene.json").write_text("{}")
    artifact = store.commit(tmp, store.artifact_path(stage, output, key), {"key": key})
    store.link_target(target, output, artifact)
    return artifact


def test_the_scene_artifact_is_found_before_the_geometry(tmp_path):
    store = ArtifactStore(tmp_path)
    geometry = _commit(store, "office", "decimate", "geometry", "g1")
    assert built_scene_dir(tmp_path, "office") == geometry.resolve()  # no navmesh yet
    scene = _commit(store, "office", "navmesh", "scene", "s1")
    assert built_scene_dir(tmp_path, "office") == scene.resolve() == store.target_output("office", "scene")


def test_missing_and_uncommitted_scenes_name_the_build_command(tmp_path):
    store = ArtifactStore(tmp_path)
    with pytest.raises(SceneError, match=r"scene 'office' is not built: run 'navverse build office'"):
        built_scene_dir(tmp_path, "office")
    half = tmp_path / "artifacts" / "navmesh" / "scene-s2"  # no manifest: never trusted
    half.mkdir(parents=True)
    store.link_target("office", "scene", half)
    with pytest.raises(SceneError, match="navverse build office"):
        built_scene_dir(tmp_path, "office")


def test_one_directory_per_scene_of_the_episodes(tmp_path):
    store = ArtifactStore(tmp_path)
    dirs = {s: _commit(store, s, "navmesh", "scene", f"k-{s}") for s in ("b-street", "a-flat")}
    episodes = [SimpleNamespace(scene_id=s) for s in ("b-street", "a-flat", "b-street")]
    found = built_scene_dirs(iter(episodes), built_dir=tmp_path)
    assert list(found) == ["a-flat", "b-street"]
    assert found == {s: d.resolve() for s, d in dirs.items()}
    with pytest.raises(SceneError, match="navverse build c-park"):
        built_scene_dirs([*episodes, SimpleNamespace(scene_id="c-park")], built_dir=tmp_path)
