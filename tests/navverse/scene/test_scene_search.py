"""The scene search path: --scenes directories, then $NAVVERSE_SCENES, then the workspace's build store;
scene packs and build stores; a scene of another hash is passed over and named in the error."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from navverse.errors import NavverseError, SceneError
from navverse.scene.directory import scene_hash
from navverse.scene.locate import SCENES_ENV, cached_scene_hash, find_scene_dirs, scene_search_path

NO_ENV: dict[str, str] = {}


def _scene(directory: Path, content: str) -> Path:
    """A scene directory whose files hold `content` (scene_hash reads bytes, whatever they are)."""
    directory.mkdir(parents=True)
    for name in ("scene.json", "scene.usdc", "navmesh.bin"):
        (directory / name).write_text(f"{name} of {content}")
    return directory


def _pack(root: Path, scene_id: str, content: str) -> Path:
    """A scene pack ``root/<scene_id>/`` holding one scene."""
    return _scene(root / scene_id, content)


def _store(root: Path, scene_id: str, content: str, *, committed: bool = True) -> Path:
    """A build store ``root/targets/<scene_id>/scene`` -> an artifact (with its manifest when committed)."""
    artifact = _scene(root / "artifacts" / "navmesh" / f"scene-{scene_id}-{content}", content)
    if committed:
        (artifact / "manifest.json").write_text("{}")
    link = root / "targets" / scene_id / "scene"
    link.parent.mkdir(parents=True, exist_ok=True)
    link.symlink_to(artifact)
    return artifact


def test_each_scene_is_taken_from_the_first_place_that_has_it(tmp_path: Path):
    first, second = _pack(tmp_path / "a", "flat", "a"), _pack(tmp_path / "b", "flat", "b")
    _pack(tmp_path / "b", "park", "b")
    env_dir = _pack(tmp_path / "env", "street", "env")
    _pack(tmp_path / "env", "park", "env")
    store = _store(tmp_path / "built", "street", "store")
    _store(tmp_path / "built", "yard", "store")
    stored_yard = (tmp_path / "built" / "targets" / "yard" / "scene").resolve()
    found = find_scene_dirs(
        ["yard", "flat", "street", "park", "flat"],
        search=[tmp_path / "a", tmp_path / "b"],
        built_dir=tmp_path / "built",
        environ={SCENES_ENV: str(tmp_path / "env")},
    )
    assert list(found) == ["flat", "park", "street", "yard"]  # once each, sorted
    assert found["flat"] == first.resolve() != second.resolve()  # --scenes in the order given
    assert found["park"] == (tmp_path / "b" / "park").resolve()  # --scenes before $NAVVERSE_SCENES
    assert found["street"] == env_dir.resolve() != store  # $NAVVERSE_SCENES before the build store
    assert found["yard"] == stored_yard  # the build store last


def test_the_environment_variable_is_a_path_list_read_at_each_call(tmp_path: Path, monkeypatch):
    _pack(tmp_path / "one", "flat", "one")
    two = _pack(tmp_path / "two", "park", "two")
    value = os.pathsep.join([str(tmp_path / "missing"), "", str(tmp_path / "one"), str(tmp_path / "two")])
    monkeypatch.setenv(SCENES_ENV, value)
    places = scene_search_path([tmp_path / "given"])
    assert [(p.source, p.path) for p in places] == [
        ("--scenes", tmp_path / "given"),
        ("$NAVVERSE_SCENES", tmp_path / "missing"),  # the empty entry is skipped
        ("$NAVVERSE_SCENES", tmp_path / "one"),
        ("$NAVVERSE_SCENES", tmp_path / "two"),
    ]
    assert find_scene_dirs(["park"]) == {"park": two.resolve()}
    monkeypatch.delenv(SCENES_ENV)
    with pytest.raises(SceneError, match="scene 'park' not found"):
        find_scene_dirs(["park"])


def test_a_directory_may_be_a_pack_or_a_build_store(tmp_path: Path):
    packed = _pack(tmp_path / "pack", "flat", "p")
    stored = _store(tmp_path / "store", "flat", "s")
    _store(tmp_path / "half", "flat", "h", committed=False)  # no manifest: never trusted
    assert find_scene_dirs(["flat"], search=[tmp_path / "pack"], environ=NO_ENV)["flat"] == packed.resolve()
    assert find_scene_dirs(["flat"], search=[tmp_path / "store"], environ=NO_ENV)["flat"] == stored
    with pytest.raises(SceneError, match=r"1\. --scenes .*half: not there"):
        find_scene_dirs(["flat"], search=[tmp_path / "half"], environ=NO_ENV)


def test_a_scene_of_another_hash_is_passed_over_and_named_in_the_error(tmp_path: Path):
    old = _pack(tmp_path / "old", "flat", "old")
    new = _pack(tmp_path / "new", "flat", "new")
    _store(tmp_path / "built", "flat", "rebuilt")
    wanted = scene_hash(new)
    hashes = {"flat": wanted}
    found = find_scene_dirs(
        ["flat"], search=[tmp_path / "old", tmp_path / "new"], hashes=hashes, built_dir=tmp_path / "built"
    )
    assert found == {"flat": new.resolve()}
    (tmp_path / "empty").mkdir()
    with pytest.raises(SceneError) as error:
        find_scene_dirs(
            ["flat"],
            search=[tmp_path / "old", tmp_path / "nowhere"],
            hashes=hashes,
            built_dir=tmp_path / "built",
            environ={SCENES_ENV: str(tmp_path / "empty")},
        )
    lines = str(error.value).splitlines()
    assert lines[0] == "scene 'flat' not found; looked in, in order:"
    assert lines[1] == (
        f"  1. --scenes {tmp_path / 'old'}: scene hash {scene_hash(old)[:12]}… differs from the "
        f"dataset's {wanted[:12]}… ({old.resolve()})"
    )
    assert lines[2] == f"  2. --scenes {tmp_path / 'nowhere'}: no such directory"
    assert lines[3] == f"  3. $NAVVERSE_SCENES {tmp_path / 'empty'}: not there"
    assert lines[4].startswith(f"  4. the workspace's build store ({tmp_path / 'built'}): scene hash ")
    assert "differs from the dataset's" in lines[4]
    for advice in ("--scenes DIR", "$NAVVERSE_SCENES", "navverse export scenes", "navverse build flat"):
        assert advice in lines[5]


def test_a_rebuilt_scene_of_the_build_store_is_used_with_a_warning_only_when_asked(tmp_path: Path):
    rebuilt = _store(tmp_path / "built", "flat", "rebuilt")
    hashes = {"flat": "0" * 64}
    warnings: list[str] = []
    found = find_scene_dirs(
        ["flat"],
        hashes=hashes,
        built_dir=tmp_path / "built",
        environ=NO_ENV,
        rebuilt="warn",
        warn=warnings.append,
    )
    assert found == {"flat": rebuilt}
    short = scene_hash(rebuilt)[:12]
    assert warnings == [
        f"scene 'flat' in the workspace's build store ({rebuilt}) has scene hash {short}…, "
        "not the dataset's 000000000000… (rebuilt since the dataset was packaged?); using it as built now"
    ]
    _pack(tmp_path / "pack", "flat", "other")  # a pack of another hash is never used
    with pytest.raises(SceneError, match="differs from the dataset's"):
        find_scene_dirs(["flat"], search=[tmp_path / "pack"], hashes=hashes, environ=NO_ENV, rebuilt="warn")


def test_the_build_store_is_asked_for_only_when_needed(tmp_path: Path):
    calls = []

    def no_workspace() -> Path:
        calls.append(1)
        raise NavverseError("no recipes/ folder in /x or its parents")

    packed = _pack(tmp_path / "pack", "flat", "p")
    assert find_scene_dirs(["flat"], search=[tmp_path / "pack"], built_dir=no_workspace, environ=NO_ENV) == {
        "flat": packed.resolve()
    }
    assert calls == []
    with pytest.raises(SceneError) as error:
        find_scene_dirs(["flat", "park"], search=[tmp_path / "pack"], built_dir=no_workspace, environ=NO_ENV)
    assert "  2. the workspace's build store: no recipes/ folder in /x or its parents" in str(error.value)
    assert "scene 'park' not found" in str(error.value) and calls == [1]


def test_the_hash_is_computed_again_once_a_file_changes(tmp_path: Path):
    scene = _pack(tmp_path / "pack", "flat", "p")
    before = cached_scene_hash(scene)
    assert before == scene_hash(scene) == cached_scene_hash(scene)
    (scene / "navmesh.bin").write_text("another navmesh, longer than before")
    after = cached_scene_hash(scene)
    assert after == scene_hash(scene) != before
    (scene / "textures").mkdir()
    (scene / "textures" / "sign.png").write_bytes(b"png")
    assert cached_scene_hash(scene) == scene_hash(scene) != after
