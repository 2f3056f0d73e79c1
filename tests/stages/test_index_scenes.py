"""A dataset's scenes as one target: index_scenes builds the linked scenes and lists each with its type
and hash; given a published manifest, scenes that differ from it, are missing or are not its own fail
the build by name, exit 1, no traceback, and nothing written."""

from __future__ import annotations

import json

import pytest

from navverse.dataset import built_version
from navverse.scene.directory import scene_hash
from tests.stages.conftest import Built, copy_built, navverse_command

INDEX = """\
manual: true
links:
  scene: [{scenes}]
stages:
  index_scenes: {{{params}}}
"""


@pytest.fixture(scope="module")
def built(tiny_build: Built, tmp_path_factory: pytest.TempPathFactory) -> Built:
    """The tiny build (apartment scenes and their dataset) copied, with the dataset's manifest kept
    beside the recipes as if published."""
    built = copy_built(tiny_build, tmp_path_factory.mktemp("index") / "ws")
    manifest = built_version(built.output("tiny", "dataset")) / "manifest.json"
    (built.workspace.recipes_dir / "published.json").write_text(manifest.read_text())
    return built


def _index(built: Built, name: str, scenes: str, params: str = ""):
    (built.workspace.recipes_dir / f"{name}.yaml").write_text(INDEX.format(scenes=scenes, params=params))
    return navverse_command(built.workspace.root, "build", name)


def test_the_index_lists_every_linked_scene_with_its_type_and_hash(built: Built) -> None:
    result = _index(built, "apartments", "apartment-s*", "dataset: published.json")
    assert result.returncode == 0, result.stdout + result.stderr
    index = json.loads((built.output("apartments", "scenes") / "scenes.json").read_text())
    assert index["counts"] == {"indoor": 2, "outdoor from maps": 0} and index["dataset"] == "tiny v1.0"
    for scene in ("apartment-s0", "apartment-s1"):
        assert index["scenes"][scene] == {
            "scene_type": "indoor",
            "scene_hash": scene_hash(built.output(scene, "scene")),
            "map": None,
        }


def test_scenes_unlike_the_published_ones_fail_by_name(built: Built) -> None:
    published = built.workspace.recipes_dir / "published.json"
    manifest = json.loads(published.read_text())
    manifest["scene_hashes"]["apartment-s0"] = "0" * 64  # as if the dataset had been built from other code
    (built.workspace.recipes_dir / "altered.json").write_text(json.dumps(manifest))
    result = _index(built, "altered-apartments", "apartment-s0", "dataset: altered.json")
    output = result.stdout + result.stderr
    assert result.returncode == 1 and "Traceback" not in output, output
    assert "apartment-s0: scene hash" in output and "differs from the dataset's 000000000000" in output
    assert "apartment-s1: not built (the dataset names it; link it)" in output
    assert not (built.workspace.built_dir / "targets" / "altered-apartments").exists()
