"""Graph derivation from declared inputs and outputs; errors name the stages."""

from __future__ import annotations

import pytest

from pipeline import Params, StageContext, stage
from pipeline.dag import build_graph
from pipeline.errors import DagError
from pipeline.recipes import RecipeLoader
from tests.pipeline.conftest import write


class _Empty(Params):
    pass


@stage(name="ex_cycle_a", inputs=["beta_art"], outputs=["alpha_art"])
def _cycle_a(ctx: StageContext, params: _Empty) -> None:
    """Alpha from beta (a test of cycle detection)."""


@stage(name="ex_cycle_b", inputs=["alpha_art"], outputs=["beta_art"])
def _cycle_b(ctx: StageContext, params: _Empty) -> None:
    """Beta from alpha (a test of cycle detection)."""


def test_graph_order_links_and_keys(workspace, stages):
    targets = RecipeLoader(workspace, stages=stages).load()
    graph = build_graph(targets)
    order = graph.order
    assert order.index("alpha-s0:ex_numbers") < order.index("alpha-s0:ex_sum") < order.index("all:ex_gather")
    assert graph.nodes["all:ex_gather"].inputs["total"] == [
        ("alpha-s0", "total"),
        ("alpha-s1", "total"),
        ("beta", "total"),
    ]
    keys = [n.key for n in graph.nodes.values()]
    assert len(set(keys)) == len(keys)
    # same recipes -> same keys; another seed -> another key downstream too
    again = build_graph(RecipeLoader(workspace, stages=stages).load())
    assert {n: g.key for n, g in again.nodes.items()} == {n: g.key for n, g in graph.nodes.items()}


def test_selecting_a_fan_in_pulls_its_linked_targets(workspace, stages):
    targets = RecipeLoader(workspace, stages=stages).load()
    graph = build_graph([t for t in targets if t.id == "all"], universe=targets)
    assert {n.target.id for n in graph.nodes.values()} == {"all", "alpha-s0", "alpha-s1", "beta"}


def test_missing_producer_names_the_stage(workspace, stages):
    path = write(workspace.recipes_dir / "orphan.yaml", "stages: {ex_sum: {}}\n")
    targets = RecipeLoader(workspace, stages=stages).load([path])
    with pytest.raises(DagError, match=r"stage 'ex_sum' needs artifact 'numbers'"):
        build_graph(targets)


def test_two_producers_of_one_artifact(workspace, stages):
    path = write(workspace.recipes_dir / "twice.yaml", "stages: {ex_numbers: {}, ex_slow: {}}\n")
    targets = RecipeLoader(workspace, stages=stages).load([path])
    with pytest.raises(DagError, match="produced by both stage 'ex_numbers' and stage 'ex_slow'"):
        build_graph(targets)


def test_cycle_names_the_stages(workspace):
    from pipeline.stage import registered_stages

    registry = registered_stages()
    path = write(workspace.recipes_dir / "cycle.yaml", "stages: {ex_cycle_a: {}, ex_cycle_b: {}}\n")
    loader = RecipeLoader(workspace, stages={k: registry[k] for k in ("ex_cycle_a", "ex_cycle_b")})
    with pytest.raises(DagError, match=r"cycle.*cycle:ex_cycle_a, cycle:ex_cycle_b"):
        build_graph(loader.load([path]))


def test_link_matching_nothing(workspace, stages):
    path = write(workspace.recipes_dir / "lonely.yaml", "stages: {ex_gather: {}}\nlinks: {total: [zzz-*]}\n")
    targets = RecipeLoader(workspace, stages=stages).load([path])
    with pytest.raises(DagError, match="match no target"):
        build_graph(targets)
