"""The shipped recipes built on Ray: the blockout scenes, two procedural apartments and a tiny dataset
on a local Ray with 2 worker CPUs give byte-identical artifacts to the local process executor, even
when a Ray worker running a stage is killed mid-build (the stage is run again)."""

from __future__ import annotations

import contextlib
import hashlib
import threading
import time
from pathlib import Path

import psutil
import ray  # a dev dependency: these tests must run wherever the suite does
from rich.console import Console

from pipeline.dag import build_graph
from pipeline.executors import make_executor
from pipeline.recipes import RecipeLoader
from pipeline.runner import run_build
from pipeline.stage import discover
from pipeline.store import LOG_NAME, MANIFEST_NAME, ArtifactStore
from tests.stages.conftest import DATASET, SCENES, workspace_with

BLOCKOUT = [f"scenes/blockout/{name}.yaml" for name in ("box-room", "corridor", "two-rooms")]


def _build(root: Path, kind: str) -> ArtifactStore:
    workspace = workspace_with(root, [*BLOCKOUT, SCENES], {"datasets/tiny.yaml": DATASET})
    targets = RecipeLoader(workspace, stages=discover("stages")).load()
    store = ArtifactStore(workspace.built_dir)
    report = run_build(
        build_graph(targets), store, lambda: make_executor(2, kind=kind), console=Console(quiet=True)
    )
    assert report.ok, (kind, report.failed)
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
        while not self.stop.is_set() and self.killed is None:
            for process in psutil.process_iter(["pid", "cmdline"]):
                title = " ".join(process.info["cmdline"] or [])
                if title.startswith(VICTIM):
                    time.sleep(0.5)  # well inside the stage
                    with contextlib.suppress(psutil.Error):
                        process.kill()
                        self.killed = title
                    break
            self.stop.wait(0.05)


def test_the_shipped_recipes_build_byte_identical_on_ray_and_locally(tmp_path: Path) -> None:
    local = _digests(_build(tmp_path / "local", "local"))
    assert any("dataset" in key for key in local) and any("navmesh.bin" in key for key in local)
    killer = _Killer()
    killer.start()
    try:
        on_ray = _digests(_build(tmp_path / "ray", "ray"))
    finally:
        killer.stop.set()
        killer.join()
        if ray.is_initialized():
            ray.shutdown()
    assert killer.killed is not None  # a stage's worker was killed, and the build still completed
    assert on_ray == local
