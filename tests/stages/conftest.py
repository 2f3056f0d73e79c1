"""Build shipped scene recipes through the engine, in this process, in a throw-away workspace."""

from __future__ import annotations

import shutil
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from rich.console import Console

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
