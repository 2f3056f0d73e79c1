"""Shipped recipes built on Ray: two procedural apartments and a tiny dataset over them (the scene stages
indoor_layout, decimate and navmesh, and every dataset stage) on a local Ray with 2 worker CPUs give
byte-identical artifacts to the local build the stage tests share (:func:`~tests.conftest.tiny_build`,
built in a test process), even when a Ray worker running a stage is killed mid-build (the stage is run
again)."""

from __future__ import annotations

import contextlib
import hashlib
import threading
import time
from pathlib import Path

import psutil
import pytest
import ray  # a dev dependency: these tests must run wherever the suite does
from rich.console import Console

from pipeline.dag import build_graph
from pipeline.executors import make_executor
from pipeline.recipes import RecipeLoader
from pipeline.runner import run_build
from pipeline.stage import discover
from pipeline.store import LOG_NAME, MANIFEST_NAME, ArtifactStore
from tests.stages.conftest import DATASET, SCENES, Built, workspace_with


def _build_on_ray(root: Path) -> ArtifactStore:
    """The apartments and the tiny dataset built on a Ray with 2 worker CPUs."""
    workspace = workspace_with(root, [SCENES], {"datasets/tiny.yaml": DATASET})
    targets = RecipeLoader(workspace, stages=discover("stages")).load()
    store = ArtifactStore(workspace.built_dir)
    report = run_build(
        build_graph(targets), store, lambda: make_executor(2, kind="ray"), console=Console(quiet=True)
    )
    assert report.ok, report.failed
    return store


def _digests(store: ArtifactStore) -> dict[str, str]:
    """sha256 of every file of every artifact but its manifest and log, by artifact directory and file."""
    return {
        str(path.relative_to(store.artifacts_dir)): hashlib.sha256(path.read_bytes()).hexdigest()
        for path in sorted(store.artifacts_dir.rglob("*"))
        if path.is_file() and path.name not in (MANIFEST_NAME, LOG_NAME)
    }


VICTIM = "ray::navverse-stage tiny:verify_episodes"
"""The process title of the Ray worker killed: the one verifying the tiny dataset (the longest stage)."""


class _Killer(threading.Thread):
    """Kills the Ray worker running the :data:`VICTIM` stage (SIGKILL), once."""

    def __init__(self) -> None:
        super().__init__(daemon=True)
        self.killed: str | None = None
        self.stop = threading.Event()

    def run(self) -> None:
        own = psutil.Process()  # Ray started here: its workers descend from this process, no one else's
        while not self.stop.is_set() and self.killed is None:
            for process in own.children(recursive=True):
                try:
                    title = " ".join(process.cmdline())
                except psutil.Error:  # ended meanwhile
                    continue
                if title.startswith(VICTIM):
                    time.sleep(0.5)  # well inside the stage
                    with contextlib.suppress(psutil.Error):
                        process.kill()
                        self.killed = title
                    break
            self.stop.wait(0.05)


@pytest.mark.slow(seconds=90)
def test_the_shipped_recipes_build_byte_identical_on_ray_and_locally(
    tiny_build: Built, tmp_path: Path
) -> None:
    local = _digests(tiny_build.store)
    assert any("dataset" in key for key in local) and any("navmesh.bin" in key for key in local)
    killer = _Killer()
    killer.start()
    try:
        on_ray = _digests(_build_on_ray(tmp_path / "ray"))
    finally:
        killer.stop.set()
        killer.join()
        if ray.is_initialized():
            ray.shutdown()
    assert killer.killed is not None  # a stage's worker was killed, and the build still completed
    assert on_ray == local
