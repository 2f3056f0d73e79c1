"""Building: cache hits and misses, atomic commits, seeds, failures that spare the rest."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from rich.console import Console

from pipeline.dag import build_graph
from pipeline.executors import InlineExecutor, LocalProcessExecutor
from pipeline.recipes import RecipeLoader
from pipeline.runner import plan, run_build, target_status
from pipeline.store import MANIFEST_NAME, ArtifactStore
from tests.pipeline.conftest import write


def _build(workspace, stages, *, executor=InlineExecutor, force=()):
    targets = RecipeLoader(workspace, stages=stages).load()
    graph = build_graph(targets)
    store = ArtifactStore(workspace.built_dir)
    report = run_build(graph, store, executor, force=force, console=Console(quiet=True))
    return graph, store, report


def _total(store: ArtifactStore, target: str) -> float:
    return json.loads((store.targets_dir / target / "total" / "total.json").read_text())["total"]


def test_build_then_nothing_to_do(workspace, stages):
    graph, store, report = _build(workspace, stages)
    assert report.ok and len(report.built) == len(graph.nodes) == 7 and not report.cached
    summary = json.loads((store.targets_dir / "all" / "summary" / "summary.json").read_text())
    assert summary["totals"] == [_total(store, "alpha-s0"), _total(store, "alpha-s1"), _total(store, "beta")]
    _, _, again = _build(workspace, stages)
    assert not again.built and len(again.cached) == 7
    assert set(target_status(graph, store).values()) == {"fresh"}


def test_manifest_records_files_stats_and_run(workspace, stages):
    graph, store, _ = _build(workspace, stages)
    node = graph.nodes["beta:ex_numbers"]
    path = store.artifact_path("ex_numbers", "numbers", node.artifact_keys["numbers"])
    manifest = json.loads((path / MANIFEST_NAME).read_text())
    assert manifest["key"] == node.artifact_keys["numbers"] and manifest["target"] == "beta"
    assert manifest["stats"] == {"count": 4}
    assert manifest["files"]["numbers.npy"]["size"] == (path / "numbers.npy").stat().st_size
    assert manifest["run"]["peak_rss_mb"] > 0 and manifest["run"]["wall_s"] >= 0
    assert "stage ex_numbers for beta" in (path / "stage.log").read_text()


def test_editing_one_recipe_rebuilds_only_its_dependents(workspace, stages):
    _, store, _ = _build(workspace, stages)
    before = _total(store, "alpha-s0")
    write(
        workspace.recipes_dir / "group" / "beta.yaml",
        """
        extends: base
        seed: 7
        stages:
          ex_sum: {offset: 3.5}
    """,
    )
    edited = build_graph(RecipeLoader(workspace, stages=stages).load())
    status = target_status(edited, store)
    assert status["beta"] == "stale" and status["all"] == "stale" and status["alpha-s0"] == "fresh"
    _, _, report = _build(workspace, stages)
    assert sorted(report.built) == ["all:ex_gather", "beta:ex_sum"]
    assert len(report.cached) == 5
    assert _total(store, "alpha-s0") == before
    assert target_status(edited, store)["beta"] == "fresh"


def test_seeds_are_derived_per_target_and_stage(workspace, stages):
    graph, store, _ = _build(workspace, stages)
    numbers = {
        t: np.load(store.targets_dir / t / "numbers" / "numbers.npy") for t in ("alpha-s0", "alpha-s1")
    }
    assert not np.allclose(numbers["alpha-s0"], numbers["alpha-s1"])
    seeds = {n.id: n.seed for n in graph.nodes.values()}
    assert seeds["alpha-s0:ex_numbers"] != seeds["alpha-s0:ex_sum"]
    # rebuilding from scratch gives the same numbers (no global RNG)
    for child in (store.artifacts_dir, store.targets_dir):
        __import__("shutil").rmtree(child)
    _build(workspace, stages)
    assert np.array_equal(
        np.load(store.targets_dir / "alpha-s0" / "numbers" / "numbers.npy"), numbers["alpha-s0"]
    )


def test_failure_spares_independent_targets(workspace, stages):
    write(
        workspace.recipes_dir / "group" / "beta.yaml",
        """
        extends: base
        stages:
          ex_sum: {fail: true}
    """,
    )
    _graph, store, report = _build(workspace, stages)
    assert list(report.failed) == ["beta:ex_sum"]
    assert "ValueError: asked to fail" in report.failed["beta:ex_sum"].error
    assert "asked to fail" in Path(report.failed["beta:ex_sum"].log_path).read_text()
    assert list(report.skipped) == ["all:ex_gather"]
    assert {"alpha-s0:ex_sum", "alpha-s1:ex_sum", "beta:ex_numbers"} <= set(report.built)
    assert not list(store.tmp_dir.iterdir())  # the failed run left no work directory behind
    assert not (store.targets_dir / "beta" / "total").exists()


def test_directory_without_manifest_is_never_trusted(workspace, stages):
    graph, store, _ = _build(workspace, stages)
    node = graph.nodes["beta:ex_numbers"]
    path = store.artifact_path("ex_numbers", "numbers", node.artifact_keys["numbers"])
    good = (path / "numbers.npy").read_bytes()
    (path / MANIFEST_NAME).unlink()
    (path / "numbers.npy").write_bytes(b"garbage")
    assert plan(graph, store)["beta:ex_numbers"] == "build"
    _, _, report = _build(workspace, stages)
    assert "beta:ex_numbers" in report.built
    assert (path / "numbers.npy").read_bytes() == good and (path / MANIFEST_NAME).is_file()


def test_stale_tmp_of_dead_process_is_cleaned(workspace, stages):
    store = ArtifactStore(workspace.built_dir)
    dead = store.tmp_dir / "ex_numbers.numbers-abc.999999999.deadbeef"
    dead.mkdir(parents=True)
    (dead / "half.npy").write_bytes(b"x")
    mine = store.new_tmp("ex_numbers", "numbers", "def")
    assert store.clean_stale_tmp() == 1
    assert not dead.exists() and mine.exists()


def test_force_rebuilds_selected_targets(workspace, stages):
    _build(workspace, stages)
    _, _, report = _build(workspace, stages, force=["beta"])
    assert sorted(report.built) == ["beta:ex_numbers", "beta:ex_sum"]


def test_process_executor_runs_in_parallel_and_reports_progress(workspace, stages):
    write(
        workspace.recipes_dir / "slow.yaml", "seeds: [1, 2]\nstages: {ex_slow: {files: 4, delay_s: 0.01}}\n"
    )
    _graph, store, report = _build(workspace, stages, executor=lambda: LocalProcessExecutor(2))
    assert report.ok and "slow-s1:ex_slow" in report.built
    pids = {
        json.loads((store.targets_dir / t / "numbers" / MANIFEST_NAME).read_text())["run"]["peak_rss_mb"]
        for t in ("slow-s1", "slow-s2")
    }
    assert all(p > 0 for p in pids)
