"""Inputs read under another name (renamed links) and stages skipped in a chain (passthrough)."""

from __future__ import annotations

import json

import pytest
from rich.console import Console

from pipeline import Input, Params, StageContext, stage
from pipeline.dag import build_graph
from pipeline.errors import DagError, RecipeError
from pipeline.executors import InlineExecutor
from pipeline.recipes import RecipeLoader
from pipeline.runner import describe_plan, plan, run_build
from pipeline.store import ArtifactStore
from tests.pipeline.conftest import write


def _annex_workspace(workspace):
    """Target 'house' makes its own geometry and reads target 'shop''s geometry as 'building'."""
    write(workspace.recipes_dir / "shop.yaml", "stages: {ex_block: {size: 3.0}}\n")
    write(
        workspace.recipes_dir / "house.yaml",
        """
        stages:
          ex_block: {size: 1.5}
          ex_annex: {}
        links:
          building: {artifact: geometry, targets: [shop]}
        """,
    )
    return workspace


def test_a_renamed_link_reads_another_targets_artifact_beside_its_own(workspace, stages):
    _annex_workspace(workspace)
    targets = RecipeLoader(workspace, stages=stages).load()
    graph = build_graph([t for t in targets if t.id == "house"], universe=targets)
    node = graph.nodes["house:ex_annex"]
    assert node.inputs == {"geometry": [("house", "geometry")], "building": [("shop", "geometry")]}
    assert graph.dependencies("house:ex_annex") == ["house:ex_block", "shop:ex_block"]

    store = ArtifactStore(workspace.built_dir)
    console = Console(record=True, width=200)
    describe_plan(graph, plan(graph, store), console)
    assert "building<-shop:geometry, geometry<-self" in console.export_text()

    report = run_build(graph, store, InlineExecutor, console=Console(quiet=True))
    assert report.ok, report.failed
    annex = json.loads((store.targets_dir / "house" / "annex" / "annex.json").read_text())
    assert annex == {
        "own": {"size": 1.5, "target": "house"},
        "building": {"size": 3.0, "target": "shop"},
    }


def test_a_declared_rename_binds_to_the_own_artifact_without_a_link(workspace, stages):
    write(workspace.recipes_dir / "solo.yaml", "stages: {ex_block: {}, ex_annex: {}}\n")
    graph = build_graph(RecipeLoader(workspace, stages=stages).load())
    assert graph.nodes["solo:ex_annex"].inputs["building"] == [("solo", "geometry")]


def test_a_plain_list_link_reads_the_declared_artifact(workspace, stages):
    write(workspace.recipes_dir / "shop.yaml", "stages: {ex_block: {}}\n")
    write(
        workspace.recipes_dir / "house.yaml",
        "stages: {ex_block: {}, ex_annex: {}}\nlinks: {building: [shop]}\n",
    )
    graph = build_graph(RecipeLoader(workspace, stages=stages).load())
    assert graph.nodes["house:ex_annex"].inputs["building"] == [("shop", "geometry")]


def test_renamed_link_errors_name_both_names(workspace, stages):
    write(workspace.recipes_dir / "cafe.yaml", "stages: {ex_numbers: {}}\n")
    write(
        workspace.recipes_dir / "house.yaml",
        "stages: {ex_block: {}, ex_annex: {}}\nlinks: {building: {artifact: geometry, targets: [cafe]}}\n",
    )
    targets = RecipeLoader(workspace, stages=stages).load()
    with pytest.raises(DagError) as raised:
        build_graph([t for t in targets if t.id == "house"], universe=targets)
    assert "reads input 'building' (artifact 'geometry') from target 'cafe', which does not produce" in str(
        raised.value
    )


def test_a_link_that_feeds_no_input_is_an_error(workspace, stages):
    write(workspace.recipes_dir / "typo.yaml", "stages: {ex_gather: {}}\nlinks: {totals: [alpha-*]}\n")
    targets = RecipeLoader(workspace, stages=stages).load()
    with pytest.raises(
        DagError, match=r"links name 'totals', which no stage of the target reads \(inputs: total\)"
    ):
        build_graph([t for t in targets if t.id == "typo"], universe=targets)


def test_a_link_key_must_be_an_artifact_name(workspace, stages):
    path = write(workspace.recipes_dir / "bad.yaml", "stages: {ex_gather: {}}\nlinks: {Total: [alpha-*]}\n")
    with pytest.raises(RecipeError, match=r"links\.Total"):
        RecipeLoader(workspace, stages=stages).load([path])


class _Empty(Params):
    pass


@stage(name="ex_self_reader", inputs=[Input("older", artifact="fresh")], outputs=["fresh"])
def _self_reader(ctx: StageContext, params: _Empty) -> None:
    """Fresh from older (a test of a stage reading its own output)."""


def test_a_stage_reading_its_own_output_under_another_name_is_refused(workspace):
    from pipeline.stage import get_stage

    path = write(workspace.recipes_dir / "selfish.yaml", "stages: {ex_self_reader: {}}\n")
    loader = RecipeLoader(workspace, stages={"ex_self_reader": get_stage("ex_self_reader")})
    with pytest.raises(DagError, match=r"reads input 'older' \(artifact 'fresh'\), which it writes itself"):
        build_graph(loader.load([path]))


def test_passthrough_must_name_an_output_and_a_single_input():
    with pytest.raises(TypeError, match="passthrough must map every output"):

        @stage(name="ex_bad_passthrough", inputs=["total"], outputs=["a", "b"], passthrough={"a": "total"})
        def _bad(ctx: StageContext, params: _Empty) -> None:
            """Nothing (a test of passthrough declarations)."""


def _chain_workspace(workspace, *, skip: bool):
    section = "{skip: true}" if skip else "{factor: 3.0}"
    write(
        workspace.recipes_dir / "chain.yaml",
        f"""
        stages:
          ex_numbers: {{count: 3}}
          ex_sum: {{offset: 1.0}}
          ex_decorate: {section}
          ex_publish: {{}}
        """,
    )
    return workspace


def test_a_skipped_stage_passes_its_input_through(workspace, stages):
    _chain_workspace(workspace, skip=True)
    targets = RecipeLoader(workspace, stages=stages).load()
    graph = build_graph([t for t in targets if t.id == "chain"], universe=targets)
    assert "chain:ex_decorate" not in graph.nodes
    assert graph.nodes["chain:ex_publish"].inputs == {"decorated": [("chain", "total")]}
    assert graph.skipped == {"chain:ex_decorate": {"decorated": ("chain", "total")}}

    store = ArtifactStore(workspace.built_dir)
    console = Console(record=True, width=200)
    describe_plan(graph, plan(graph, store), console)
    text = console.export_text()
    assert "decorated<-self:total" in text and "skipped chain:ex_decorate: decorated = self:total" in text

    report = run_build(graph, store, InlineExecutor, console=Console(quiet=True))
    assert report.ok and set(report.built) == {"chain:ex_numbers", "chain:ex_sum", "chain:ex_publish"}
    published = (store.targets_dir / "chain" / "published" / "total.json").read_bytes()
    assert published == (store.targets_dir / "chain" / "total" / "total.json").read_bytes()
    # the skipped stage's output link points at the artifact it stands for
    assert (store.targets_dir / "chain" / "decorated").resolve() == (
        store.targets_dir / "chain" / "total"
    ).resolve()


def test_the_same_chain_not_skipped_runs_the_stage(workspace, stages):
    _chain_workspace(workspace, skip=False)
    targets = RecipeLoader(workspace, stages=stages).load()
    graph = build_graph([t for t in targets if t.id == "chain"], universe=targets)
    store = ArtifactStore(workspace.built_dir)
    assert run_build(graph, store, InlineExecutor, console=Console(quiet=True)).ok
    total = json.loads((store.targets_dir / "chain" / "total" / "total.json").read_text())["total"]
    published = json.loads((store.targets_dir / "chain" / "published" / "total.json").read_text())["total"]
    assert published == pytest.approx(3.0 * total)


def test_skipping_a_stage_without_passthrough_is_a_recipe_error(workspace, stages):
    path = write(workspace.recipes_dir / "noskip.yaml", "stages: {ex_numbers: {skip: true}, ex_sum: {}}\n")
    with pytest.raises(RecipeError, match=r"stage 'ex_numbers' cannot be skipped.*'ex_numbers: null'"):
        RecipeLoader(workspace, stages=stages).load([path])


def test_skip_takes_a_boolean(workspace, stages):
    path = write(workspace.recipes_dir / "chain.yaml", "stages: {ex_decorate: {skip: maybe}}\n")
    with pytest.raises(RecipeError, match="'skip' takes true or false"):
        RecipeLoader(workspace, stages=stages).load([path])
