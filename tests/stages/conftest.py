"""Build shipped scene recipes through the engine, in this process, in a throw-away workspace.

Also the tiny dataset (ObjNav and VLN over ``apartment-s0``/``-s1``) that the dataset, run-agent,
merge and review tests share (built once per test process by the session fixture ``tiny_build`` of
``tests/conftest.py``; fixtures ``built`` and ``dataset`` give each test module a copy of its own),
and :func:`navverse_command` to run the ``navverse`` command in such a workspace.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Callable, Collection, Iterable
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


def build_all(workspace: Workspace, *, only: Collection[str] | None = None) -> Built:
    """Build every target of the workspace (``only`` those named, when given) in this process."""
    targets = RecipeLoader(workspace, stages=discover("stages")).load()
    targets = [target for target in targets if only is None or target.id in only]
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
  package_dataset:
    version: "1.0"
    splits: {train: ["*-s0"], eval: ["*-s1"]}
"""


def build_tiny(root: Path) -> Built:
    """The apartment scenes (``apartment-s0``, ``-s1``) and the tiny dataset built in a new workspace
    at ``root``, in this process."""
    result = build_all(workspace_with(root, [SCENES], {"datasets/tiny.yaml": DATASET}))
    assert result.report.ok, result.report
    return result


def copy_built(built: Built, root: Path) -> Built:
    """A copy of the workspace of ``built`` at ``root`` (recipes and build store; the store's links
    are relative), to change as a test pleases; its report is the original build's."""
    shutil.copytree(built.workspace.root, root, symlinks=True)
    workspace = Workspace(root)
    return Built(workspace, ArtifactStore(workspace.built_dir), built.report)


@pytest.fixture(scope="module")
def built(tiny_build: Built, tmp_path_factory: pytest.TempPathFactory) -> Built:
    """A workspace with the apartment scenes and the tiny dataset built (a copy of the test process's
    :func:`~tests.conftest.tiny_build`, shared by the module's tests)."""
    return copy_built(tiny_build, tmp_path_factory.mktemp("ds") / "ws")


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


@pytest.fixture
def navverse_here(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> Callable[..., subprocess.CompletedProcess[str]]:
    """:func:`navverse_command`, but in this process (``navverse.cli.main``), with ``root`` as the
    working folder too: for build commands, whose engine hashes the code of the stages once per
    process, seconds that every new ``navverse`` process spends again."""
    from navverse.cli import main

    def run(root: Path, *args: str) -> subprocess.CompletedProcess[str]:
        monkeypatch.setenv("NAVVERSE_ROOT", str(root))
        monkeypatch.chdir(root)
        capsys.readouterr()  # not what came before
        code = main(list(args))
        out, err = capsys.readouterr()
        return subprocess.CompletedProcess(["navverse", *args], code, out, err)

    return run
