"""Build shipped scene recipes through the engine, in this process, in a throw-away workspace.

Also the tiny dataset (ObjNav and VLN over ``apartment-s0``/``-s1``) that the dataset, run-agent and
report tests share (fixtures ``built`` and ``dataset``, built once per test module), and
:func:`navverse_command` to run the ``navverse`` command in such a workspace.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

import pytest
from rich.console import Console

from navverse.dataset import Dataset, built_version
from pipeline.dag import build_graph
from pipeline.executors import make_executor
from pipeline.recipes import RecipeLoader
from pipeline.runner import BuildReport, run_build
from pipeline.stage import discover
from pipeline.store import ArtifactStore
from pipeline.workspace import Workspace

REPO = Path(__file__).resolve().parents[2]


@dataclass
class Built:
    """A workspace after a build."""

    workspace: Workspace
    store: ArtifactStore
    report: BuildReport

    def output(self, target: str, artifact: str) -> Path:
        path = self.store.target_output(target, artifact)
        assert path is not None, f"{target}/{artifact} was not built"
        return path

    def manifest(self, target: str, artifact: str) -> dict:
        manifest = self.store.read_manifest(self.output(target, artifact))
        assert manifest is not None
        return manifest


def workspace_with(root: Path, recipes: Iterable[str], extra: dict[str, str] | None = None) -> Workspace:
    """A workspace with the shipped presets, the named shipped recipes and ``extra`` {path: text}."""
    workspace = Workspace(root)
    shutil.copytree(REPO / "recipes" / "presets", workspace.presets_dir)
    for recipe in recipes:
        target = workspace.recipes_dir / recipe
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(REPO / "recipes" / recipe, target)
    for relative, text in (extra or {}).items():
        path = workspace.recipes_dir / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return workspace


def build_all(workspace: Workspace) -> Built:
    """Build every target of the workspace in this process."""
    targets = RecipeLoader(workspace, stages=discover("stages")).load()
    store = ArtifactStore(workspace.built_dir)
    report = run_build(build_graph(targets), store, lambda: make_executor(0), console=Console(quiet=True))
    return Built(workspace, store, report)


NAVVERSE = str(Path(sys.executable).with_name("navverse"))
SCENES = "scenes/indoor/apartment.yaml"
DATASET = """\
extends: dataset
seed: 3
links:
  scene: [apartment-s*]
stages:
  sample_episodes:
    tasks:
      objnav: {episodes_per_scene: 6}
      vln: {episodes_per_scene: 6}
    categories: [bed, sofa, toilet, fridge, oven, bathtub, bench, desk, wardrobe, sink, armchair]
  verify_episodes:
    keyframes: 2
  package_dataset:
    version: "1.0"
    splits: {train: ["*-s0"], eval: ["*-s1"]}
"""


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Built:
    """A workspace with the apartment scenes and the tiny dataset built."""
    workspace = workspace_with(tmp_path_factory.mktemp("ds"), [SCENES], {"datasets/tiny.yaml": DATASET})
    result = build_all(workspace)
    assert result.report.ok, result.report
    return result


@pytest.fixture(scope="module")
def dataset(built: Built) -> Dataset:
    """The tiny dataset's built version."""
    return Dataset(built_version(built.output("tiny", "dataset")))


def scene_dirs(built: Built) -> dict[str, Path]:
    """The built scene directory of each scene of the tiny dataset."""
    return {s: built.output(s, "scene") for s in ("apartment-s0", "apartment-s1")}


def navverse_command(root: Path, *args: str) -> subprocess.CompletedProcess[str]:
    """Run ``navverse ARGS`` with ``root`` as the workspace; its output is captured."""
    env = {**os.environ, "NAVVERSE_ROOT": str(root)}
    return subprocess.run([NAVVERSE, *args], env=env, capture_output=True, text=True, cwd=root, timeout=600)
