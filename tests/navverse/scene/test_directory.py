from __future__ import annotations

from pathlib import Path

import pytest

from navverse.errors import SceneError
from navverse.scene.directory import (
    BEV_PNG,
    SCENE_JSON,
    SCENE_USD,
    read_annotations,
    read_scene,
    write_scene_dir,
)
from navverse.scene.geometry import Scene


def test_writing_twice_gives_identical_files(tiny_scene: Scene, tmp_path: Path) -> None:
    first, second = tmp_path / "one", tmp_path / "two"
    first.mkdir()
    second.mkdir()
    files = write_scene_dir(tiny_scene, first)
    write_scene_dir(tiny_scene, second)
    assert sorted(p.name for p in first.iterdir()) == sorted([SCENE_USD, SCENE_JSON, BEV_PNG])
    assert files.usd == first / SCENE_USD
    for name in (SCENE_USD, SCENE_JSON, BEV_PNG):
        assert (first / name).read_bytes() == (second / name).read_bytes(), name
    assert read_annotations(first) == tiny_scene.annotations


def test_missing_scene_dir_tells_how_to_build_it(tmp_path: Path) -> None:
    with pytest.raises(SceneError, match=r"does not exist.*navverse build city_07"):
        read_scene(tmp_path / "city_07")
    with pytest.raises(SceneError, match=r"navverse build city_07"):
        read_annotations(tmp_path / "city_07")


def test_incomplete_scene_dir_names_the_missing_file(tiny_scene: Scene, tmp_path: Path) -> None:
    scene_dir = tmp_path / "tiny_room"
    scene_dir.mkdir()
    write_scene_dir(tiny_scene, scene_dir, bev=False)
    (scene_dir / SCENE_USD).unlink()
    with pytest.raises(SceneError, match=r"no scene\.usdc.*navverse build tiny_room"):
        read_scene(scene_dir)
    (scene_dir / SCENE_JSON).unlink()
    with pytest.raises(SceneError, match=r"no scene\.json"):
        read_annotations(scene_dir)


def test_write_needs_an_existing_directory(tiny_scene: Scene, tmp_path: Path) -> None:
    with pytest.raises(SceneError, match="does not exist"):
        write_scene_dir(tiny_scene, tmp_path / "nope")
