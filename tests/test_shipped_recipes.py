"""Every shipped recipe loads, validates and forms a valid build graph (dry run)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pipeline.dag import build_graph
from pipeline.recipes import RecipeLoader
from pipeline.stage import discover
from pipeline.workspace import Workspace

REPO = Path(__file__).resolve().parents[1]
WORKSPACE = Workspace(REPO)
RECIPES = sorted(
    p.relative_to(WORKSPACE.recipes_dir).as_posix()
    for p in WORKSPACE.recipes_dir.rglob("*.yaml")
    if not p.is_relative_to(WORKSPACE.presets_dir)
)


@pytest.fixture(scope="module")
def loader() -> RecipeLoader:
    return RecipeLoader(WORKSPACE, stages=discover("stages"))


def test_there_are_shipped_recipes():
    assert len(RECIPES) >= 6


@pytest.mark.parametrize("recipe", RECIPES)
def test_recipe_validates_and_plans(recipe: str, loader: RecipeLoader):
    targets = loader.load([WORKSPACE.recipes_dir / recipe])
    assert targets, f"{recipe} expands to no target"
    graph = build_graph(targets, universe=loader.load())
    assert graph.order and all(node.key for node in graph.nodes.values())
    for target in targets:
        assert any(node.target.id == target.id for node in graph.nodes.values())
