"""A verified cache: corrupt artifacts are found (by size, or by sha256), reported and replaced."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest
from rich.console import Console

import navverse.cli as cli
import pipeline.store as store_module
from pipeline.dag import build_graph
from pipeline.executors import InlineExecutor
from pipeline.recipes import RecipeLoader
from pipeline.runner import find_corrupt, plan, run_build, target_status
from pipeline.store import MANIFEST_NAME, ArtifactStore
from pipeline.workspace import Workspace


def _build(workspace, stages, *, force=(), verify="size"):
    graph = build_graph(RecipeLoader(workspace, stages=stages).load())
    store = ArtifactStore(workspace.built_dir)
    console = Console(record=True, width=400)
    report = run_build(graph, store, InlineExecutor, force=force, verify=verify, console=console)
    return graph, store, report, console.export_text()


def _numbers(store: ArtifactStore, graph, node_id: str = "beta:ex_numbers") -> Path:
    node = graph.nodes[node_id]
    return store.artifact_path(node.stage, "numbers", node.artifact_keys["numbers"])


def _fresh_copy(workspace: Workspace, tmp_path: Path, stages) -> Path:
    """The same recipes built in a workspace of their own: the bytes a clean build gives."""
    other = Workspace(tmp_path / "clean")
    shutil.copytree(workspace.recipes_dir, other.recipes_dir)
    _build(other, stages)
    return other.built_dir


def test_truncated_file_is_found_by_size_reported_and_rebuilt_to_the_same_bytes(workspace, stages, tmp_path):
    graph, store, _, _ = _build(workspace, stages)
    path = _numbers(store, graph)
    size = (path / "numbers.npy").stat().st_size
    os.truncate(path / "numbers.npy", 10)

    corrupt = find_corrupt(graph, store)
    assert list(corrupt) == ["beta:ex_numbers"]
    [problem] = corrupt["beta:ex_numbers"]
    assert problem.file == "numbers.npy"
    assert problem.problem == f"size differs ({size} bytes recorded, 10 on disk)"
    assert target_status(graph, store, corrupt=corrupt)["beta"] == "corrupt"
    assert plan(graph, store, corrupt=corrupt)["beta:ex_numbers"] == "build"

    _, _, report, output = _build(workspace, stages)  # the cheap size check, no --verify
    assert "corrupt: artifacts/ex_numbers/" in output and "/numbers.npy size differs" in output
    assert "; rebuilding beta:ex_numbers" in output
    assert sorted(report.built) == ["beta:ex_numbers"]  # its consumers' keys did not change
    clean = _fresh_copy(workspace, tmp_path, stages)
    relative = path.relative_to(store.root)
    assert (path / "numbers.npy").read_bytes() == (clean / relative / "numbers.npy").read_bytes()
    assert not find_corrupt(graph, store, level="hash")


def test_a_file_not_in_the_manifest_makes_the_artifact_corrupt(workspace, stages):
    graph, store, _, _ = _build(workspace, stages)
    path = _numbers(store, graph)
    (path / "stray.txt").write_text("left here")
    [problem] = find_corrupt(graph, store)["beta:ex_numbers"]
    assert problem.file == "stray.txt" and problem.problem == "is not in the manifest"
    _, _, report, _ = _build(workspace, stages)
    assert "beta:ex_numbers" in report.built and not (path / "stray.txt").exists()


def test_same_size_damage_needs_verify(workspace, stages):
    graph, store, _, _ = _build(workspace, stages)
    file = _numbers(store, graph) / "numbers.npy"
    good = file.read_bytes()
    file.write_bytes(good[:-1] + bytes([good[-1] ^ 0xFF]))
    assert not find_corrupt(graph, store)  # sizes agree
    [problem] = find_corrupt(graph, store, level="hash")["beta:ex_numbers"]
    assert problem.file == "numbers.npy" and "sha256" in problem.problem
    _, _, plain, _ = _build(workspace, stages)
    assert not plain.built
    _, _, verified, output = _build(workspace, stages, verify="hash")
    assert list(verified.built) == ["beta:ex_numbers"] and "content differs" in output
    assert file.read_bytes() == good


def test_force_replaces_the_committed_directory(workspace, stages):
    graph, store, _, _ = _build(workspace, stages)
    path = _numbers(store, graph)
    before = path.stat().st_ino
    good = (path / "numbers.npy").read_bytes()
    (path / "numbers.npy").write_bytes(b"x" * len(good))  # same size: only --force or --verify see it
    _, _, report, _ = _build(workspace, stages, force=["beta"])
    assert sorted(report.built) == ["beta:ex_numbers", "beta:ex_sum"]
    assert path.stat().st_ino != before  # a new directory, swapped in
    assert (path / "numbers.npy").read_bytes() == good
    assert not list(store.tmp_dir.iterdir())  # the old directory is gone


def test_manifest_of_another_format_is_not_trusted(workspace, stages):
    graph, store, _, _ = _build(workspace, stages)
    manifest_path = _numbers(store, graph) / MANIFEST_NAME
    manifest = json.loads(manifest_path.read_text())
    manifest["manifest_format"] = store_module.MANIFEST_FORMAT + 1
    manifest_path.write_text(json.dumps(manifest))
    assert plan(graph, store)["beta:ex_numbers"] == "build"
    _, _, report, _ = _build(workspace, stages)
    assert "beta:ex_numbers" in report.built
    assert json.loads(manifest_path.read_text())["manifest_format"] == store_module.MANIFEST_FORMAT


@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "rename-aside"])
def test_commit_with_replace_swaps_the_directory(tmp_path, monkeypatch, exchange):
    if not exchange:
        monkeypatch.setattr(store_module, "_exchange", lambda first, second: False)
    store = ArtifactStore(tmp_path)
    final = store.artifact_path("s", "out", "k1")
    for content, replace in (("old", False), ("ignored", False), ("new", True)):
        tmp = store.new_tmp("s", "out", "k1")
        (tmp / "a.txt").write_text(content)
        files = {"a.txt": {"size": len(content), "sha256": "0" * 64}}
        store.commit(tmp, final, {"key": "k1", "files": files}, replace=replace)
        expected = "old" if content == "ignored" else content  # without replace the first one stays
        assert (final / "a.txt").read_text() == expected
    assert not list(store.tmp_dir.iterdir())


def test_status_verify_names_the_file_and_exits_1(tmp_path, monkeypatch, capsys):
    root = tmp_path / "ws"
    (root / "recipes").mkdir(parents=True)
    (root / "recipes" / "slow.yaml").write_text("stages:\n  toy_slow: {parts: 2, delay_s: 0}\n")
    monkeypatch.setenv("NAVVERSE_ROOT", str(root))
    monkeypatch.setattr("navverse.cli.STAGES_PACKAGE", "tests.pipeline.cli_stages")
    assert cli.main(["build", "-j", "0"]) == 0
    part = root / "data" / "built" / "targets" / "slow" / "numbers" / "part_001.npy"
    part.write_bytes(part.read_bytes()[:-1] + b"!")  # same size
    capsys.readouterr()
    assert cli.main(["status"]) == 0
    assert "1 fresh" in capsys.readouterr().out
    assert cli.main(["status", "--verify"]) == 1
    out = capsys.readouterr().out
    assert "corrupt" in out and "part_001.npy content differs" in out and "(slow:toy_slow)" in out
    assert cli.main(["build", "-j", "0", "--verify"]) == 0
    assert "; rebuilding slow:toy_slow" in capsys.readouterr().out
    assert cli.main(["status", "--verify"]) == 0
