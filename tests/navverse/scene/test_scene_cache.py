"""A scene read through the cache is the scene read through USD, and a warm read needs no USD."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import navverse.scene.directory as directory
from navverse.scene.directory import read_scene, write_scene_dir
from navverse.scene.geometry import MeshData, Scene, Surface, Texture
from navverse.scene.scene_cache import cached_scene, scene_cache_path
from tests.scenes import quad

REPO = Path(__file__).resolve().parents[3]


def _textured(scene: Scene) -> Scene:
    """``scene`` with two more floor surfaces sharing one texture, and one with a texture of its own."""
    checker = Texture("checker", np.arange(48, dtype=np.uint8).reshape(4, 4, 3))
    dots = Texture("dots", np.full((2, 3, 3), 200, np.uint8))
    uvs = np.array([[[0, 0], [2, 0], [2, 2]], [[0, 0], [2, 2], [0, 2]]], dtype=np.float32)

    def floor(x: float, textures: tuple[Texture, ...], index: list[int]) -> MeshData:
        plain = quad(x, 10.0, x + 2.0, 12.0, 0.0)
        return MeshData(plain.vertices, plain.faces, None, uvs, np.array(index, np.int16), textures)

    extra = (
        Surface("floor_a", "floor", floor(0.0, (checker,), [0, -1])),
        Surface("floor_b", "floor", floor(3.0, (dots, checker), [1, 0])),
    )
    return Scene(scene.annotations, scene.surfaces + extra, scene.objects)


def _same(a: Scene, b: Scene) -> None:
    assert a.annotations == b.annotations
    assert [(s.name, s.terrain_class) for s in a.surfaces] == [(s.name, s.terrain_class) for s in b.surfaces]
    meshes_a = [s.mesh for s in a.surfaces] + [o.mesh for o in a.objects]
    meshes_b = [s.mesh for s in b.surfaces] + [o.mesh for o in b.objects]
    assert len(meshes_a) == len(meshes_b)
    for first, second in zip(meshes_a, meshes_b, strict=True):
        for name in ("vertices", "faces", "face_colors", "face_uvs", "face_texture"):
            left, right = getattr(first, name), getattr(second, name)
            assert (left is None) == (right is None), name
            if left is not None:
                assert left.dtype == right.dtype and np.array_equal(left, right), name
        assert [t.name for t in first.textures] == [t.name for t in second.textures]
        assert all(s.same_image(t) for s, t in zip(first.textures, second.textures, strict=True))


@pytest.fixture
def scene_dir(tiny_scene: Scene, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("NAVVERSE_CACHE_DIR", str(tmp_path / "cache"))
    (tmp_path / "scene").mkdir()
    return write_scene_dir(_textured(tiny_scene), tmp_path / "scene", bev=False).root


def test_the_cached_scene_is_the_scene_read_through_usd(scene_dir: Path, monkeypatch: pytest.MonkeyPatch):
    through_usd = read_scene(scene_dir)
    first = cached_scene(scene_dir)  # read through USD, and kept
    assert scene_cache_path(scene_dir).is_file()

    def no_usd(_: Path) -> Scene:
        raise AssertionError("read through USD although the scene is cached")

    monkeypatch.setattr(directory, "read_scene", no_usd)
    again = cached_scene(scene_dir)
    _same(first, through_usd)
    _same(again, through_usd)
    floor_a, floor_b = (s.mesh for s in again.surfaces if s.name in ("floor_a", "floor_b"))
    shared = {t.name: t for t in floor_b.textures}["checker"]
    assert floor_a.textures[0] is shared  # a texture meshes share is read once


def test_a_damaged_or_stale_cache_file_is_read_through_usd_again(scene_dir: Path):
    path = scene_cache_path(scene_dir)
    through_usd = read_scene(scene_dir)
    cached_scene(scene_dir)
    path.write_bytes(path.read_bytes()[:200])  # cut short
    _same(cached_scene(scene_dir), through_usd)
    assert len(path.read_bytes()) > 200  # written again
    # A changed scene has another key: its cache file is a new one.
    usd = scene_dir / "scene.usdc"
    usd.write_bytes(usd.read_bytes())  # the same bytes: the same key
    assert scene_cache_path(scene_dir) == path
    (scene_dir / "navmesh.bin").write_bytes(b"a navmesh")
    assert scene_cache_path(scene_dir) != path


def test_a_cache_that_cannot_be_written_still_gives_the_scene(
    scene_dir: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
):
    blocked = tmp_path / "blocked"
    blocked.write_text("a file where the cache folder would be")
    monkeypatch.setenv("NAVVERSE_CACHE_DIR", str(blocked))
    _same(cached_scene(scene_dir), read_scene(scene_dir))


def test_a_warm_read_imports_no_usd(scene_dir: Path):
    cached_scene(scene_dir)
    code = (
        "import sys\n"
        "from navverse.scene.scene_cache import cached_scene\n"
        f"scene = cached_scene({str(scene_dir)!r})\n"
        "print(len(scene.surfaces), 'pxr' in sys.modules)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": str(REPO)},
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == [str(len(read_scene(scene_dir).surfaces)), "False"]
