"""The Ray executor: artifacts byte-identical to local ones, lost workers retried, the shared-store check."""

from __future__ import annotations

import hashlib
import json
import os
import signal
from pathlib import Path
from typing import Annotated

import numpy as np
import pytest
import ray  # a dev dependency: these tests must run wherever the suite does
from pydantic import Field
from rich.console import Console

from pipeline import (
    Input,
    Params,
    StageContext,
    ray_executor,
    stage,
)
from pipeline.dag import build_graph
from pipeline.executors import LocalProcessExecutor, make_executor
from pipeline.ray_executor import RayExecutor, StoreNotSharedError, check_store_shared, worker_env
from pipeline.recipes import RecipeLoader
from pipeline.runner import BuildReport, run_build
from pipeline.stage import registered_stages
from pipeline.store import LOG_NAME, MANIFEST_NAME, ArtifactStore
from pipeline.workspace import Workspace
from tests.pipeline.conftest import write

ENV_MARK = "NAVVERSE_RAY_TEST_MARK"


# -- toy stages ---------------------------------------------------------------------------------
class DrawParams(Params):
    count: Annotated[int, Field(ge=1, le=100)] = 6
    parts: Annotated[int, Field(ge=1, le=10)] = 3


@stage(name="rx_draw", outputs=["numbers"])
def rx_draw(ctx: StageContext, params: DrawParams) -> None:
    """Numbers from the stage's generator in parts (with progress), and an environment variable's value."""
    values = ctx.rng.random(params.count)
    for index in range(params.parts):
        np.save(ctx.output / f"part_{index}.npy", values[index :: params.parts])
        ctx.progress(index + 1, params.parts, "parts")
    np.save(ctx.output / "numbers.npy", values)
    (ctx.output / "env.txt").write_text(os.environ.get(ENV_MARK, "<unset>"))


class SumParams(Params):
    offset: Annotated[float, Field(ge=-1e6, le=1e6)] = 0.0


@stage(name="rx_sum", inputs=["numbers"], outputs=["total"])
def rx_sum(ctx: StageContext, params: SumParams) -> None:
    """The sum of the input numbers plus an offset (``total.json``)."""
    values = np.load(ctx.input("numbers") / "numbers.npy")
    (ctx.output / "total.json").write_text(json.dumps({"total": float(values.sum()) + params.offset}))


class GatherParams(Params):
    pass


@stage(name="rx_gather", inputs=[Input("total", many=True)], outputs=["summary"])
def rx_gather(ctx: StageContext, params: GatherParams) -> None:
    """The totals of several targets, in target order (``summary.json``)."""
    totals = [json.loads((p / "total.json").read_text())["total"] for p in ctx.inputs["total"]]
    (ctx.output / "summary.json").write_text(json.dumps({"totals": totals}))


class CrashParams(Params):
    marker: str


@stage(name="rx_crash", outputs=["numbers"])
def rx_crash(ctx: StageContext, params: CrashParams) -> None:
    """Kills its own worker the first time it runs (no marker file yet), then writes numbers."""
    marker = Path(params.marker)
    if not marker.exists():
        marker.write_text(str(os.getpid()))
        os.kill(os.getpid(), signal.SIGKILL)
    np.save(ctx.output / "numbers.npy", ctx.rng.random(4))


STAGES = ("rx_draw", "rx_sum", "rx_gather", "rx_crash")


def _workspace(root: Path, *, crash_marker: Path | None = None) -> Workspace:
    workspace = Workspace(root)
    write(
        workspace.recipes_dir / "group" / "alpha.yaml",
        "seeds: [0, 1]\nstages:\n  rx_draw: {count: 9}\n  rx_sum: {}\n",
    )
    write(
        workspace.recipes_dir / "group" / "beta.yaml",
        "seed: 7\nstages:\n  rx_draw: {}\n  rx_sum: {offset: 2.5}\n",
    )
    write(
        workspace.recipes_dir / "all.yaml", 'stages:\n  rx_gather: {}\nlinks:\n  total: ["alpha-*", "beta"]\n'
    )
    if crash_marker is not None:
        write(workspace.recipes_dir / "crash.yaml", f"stages:\n  rx_crash: {{marker: '{crash_marker}'}}\n")
    return workspace


def _build(
    workspace: Workspace, factory, *, only: set[str] | None = None
) -> tuple[ArtifactStore, BuildReport]:
    """Build the workspace's targets (``only`` those, when given)."""
    registry = registered_stages()
    targets = RecipeLoader(workspace, stages={name: registry[name] for name in STAGES}).load()
    targets = [target for target in targets if only is None or target.id in only]
    store = ArtifactStore(workspace.built_dir)
    report = run_build(build_graph(targets), store, factory, console=Console(quiet=True))
    return store, report


def _artifact_digests(store: ArtifactStore) -> dict[str, str]:
    """``{artifact dir/file: sha256}`` of every file of every artifact but its manifest and log."""
    digests = {}
    for path in sorted(store.artifacts_dir.rglob("*")):
        if path.is_file() and path.name not in (MANIFEST_NAME, LOG_NAME):
            digests[str(path.relative_to(store.artifacts_dir))] = hashlib.sha256(
                path.read_bytes()
            ).hexdigest()
    return digests


class _ProgressSpy:
    """An executor wrapper recording the progress tuples the runner drains."""

    def __init__(self, inner) -> None:
        self.inner, self.jobs, self.progress, self.seen = inner, inner.jobs, self, []

    def get_nowait(self):
        item = self.inner.progress.get_nowait()
        self.seen.append(item)
        return item

    def submit(self, task):
        return self.inner.submit(task)

    def abort(self) -> None:
        self.inner.abort()

    def close(self) -> None:
        self.inner.close()


# -- tests ----------------------------------------------------------------------------------------
@pytest.mark.slow(seconds=15)
def test_ray_artifacts_are_byte_identical_to_local(tmp_path, ray_instance, monkeypatch):
    monkeypatch.setenv(ENV_MARK, "reached the worker")  # set after Ray started: only env_vars carry it
    local_store, local = _build(_workspace(tmp_path / "local"), lambda: LocalProcessExecutor(2))
    spies: list[_ProgressSpy] = []

    def spied_ray() -> _ProgressSpy:
        spies.append(_ProgressSpy(RayExecutor(None, 2)))
        return spies[-1]

    ray_store, on_ray = _build(_workspace(tmp_path / "ray"), spied_ray)
    assert local.ok and on_ray.ok, {n: r.error for n, r in on_ray.failed.items()}
    assert sorted(on_ray.built) == sorted(local.built) and len(on_ray.built) == 7
    digests = _artifact_digests(ray_store)
    assert digests == _artifact_digests(local_store) and len(digests) == 3 * 5 + 3 + 1
    env_file = next(p for p in ray_store.artifacts_dir.rglob("env.txt"))
    assert env_file.read_text() == "reached the worker"
    for artifact in ray_store.artifacts_dir.glob("*/*"):  # same keys, same recorded files
        twin = local_store.artifacts_dir / artifact.relative_to(ray_store.artifacts_dir)
        mine, theirs = (json.loads((p / MANIFEST_NAME).read_text()) for p in (artifact, twin))
        assert mine["files"] == theirs["files"] and mine["key"] == theirs["key"]
        assert mine["run"]["peak_rss_mb"] > 0
    draws = [item for item in spies[0].seen if item[0].endswith(":rx_draw")]
    assert ("beta:rx_draw", 3, 3, "parts") in draws and len(draws) == 3 * 3
    assert ray.is_initialized()  # the executor did not shut down the Ray it did not start


def test_a_killed_worker_is_retried_and_the_build_completes(tmp_path, ray_instance):
    marker = tmp_path / "crashed-once"
    store, report = _build(
        _workspace(tmp_path / "ws", crash_marker=marker), lambda: RayExecutor(None, 2), only={"crash", "beta"}
    )
    assert report.ok, {n: r.error for n, r in report.failed.items()}
    assert marker.is_file() and sorted(report.built) == ["beta:rx_draw", "beta:rx_sum", "crash:rx_crash"]
    numbers = np.load(store.targets_dir / "crash" / "numbers" / "numbers.npy")
    assert numbers.shape == (4,) and np.all((numbers >= 0) & (numbers < 1))
    assert int(marker.read_text()) != os.getpid()  # killed a Ray worker, not this process


def test_a_worker_lost_for_good_fails_only_its_target(tmp_path, ray_instance):
    marker = tmp_path / "crashed-once"  # no retry: the first attempt's death is final
    _, report = _build(
        _workspace(tmp_path / "ws", crash_marker=marker),
        lambda: RayExecutor(None, 2, max_retries=0),
        only={"crash", "beta"},
    )
    assert list(report.failed) == ["crash:rx_crash"]
    assert sorted(report.built) == ["beta:rx_draw", "beta:rx_sum"]  # the other target's stages ran
    error = report.failed["crash:rx_crash"].error
    assert "the Ray worker died" in error and "WorkerCrashedError" in error


def test_the_store_check_refuses_a_store_the_workers_cannot_see(tmp_path, ray_instance, monkeypatch):
    store = ArtifactStore(tmp_path / "ws" / "data" / "built")
    assert check_store_shared(store.root) == 1
    assert not list(store.tmp_dir.iterdir())  # the token is removed after the check
    elsewhere = tmp_path / "other-mount"  # what a node without the shared mount would see
    monkeypatch.setattr(ray_executor, "_token_for_workers", lambda token: str(elsewhere / token.name))
    with pytest.raises(StoreNotSharedError) as info:
        check_store_shared(store.root)
    message = str(info.value)
    assert f"the artifact store {store.root} is not visible to the Ray workers on node" in message
    assert "cannot read" in message and "shared filesystem (NFS, etc.) mounted at the same path" in message
    with pytest.raises(StoreNotSharedError, match="shared filesystem"):
        _build(_workspace(tmp_path / "ws"), lambda: RayExecutor(None, 2))
    assert not list(store.artifacts_dir.glob("*/*"))  # nothing ran


def test_memory_request_comes_from_the_last_recorded_peak(tmp_path, ray_instance):
    from pipeline.ray_executor import memory_request
    from pipeline.runner import _task

    workspace = _workspace(tmp_path / "ws")
    registry = registered_stages()
    targets = RecipeLoader(workspace, stages={name: registry[name] for name in STAGES}).load()
    graph = build_graph([target for target in targets if target.id == "beta"])  # the stage's target only
    store = ArtifactStore(workspace.built_dir)
    node = graph.nodes["beta:rx_draw"]
    assert memory_request(_task(node, graph, store, replace=False)) is None
    run_build(graph, store, lambda: LocalProcessExecutor(1), console=Console(quiet=True))
    manifest = json.loads((store.targets_dir / "beta" / "numbers" / MANIFEST_NAME).read_text())
    peak = manifest["run"]["peak_rss_mb"]
    wanted = memory_request(_task(node, graph, store, replace=False))
    assert wanted == int(peak * 1.25 * 1024 * 1024)
    assert memory_request(_task(node, graph, store, replace=False), cap_bytes=1000.0) == 1000


def test_worker_env_and_make_executor(monkeypatch, tmp_path):
    env = worker_env({"NAVVERSE_ROOT": "/x", "PYTHONHASHSEED": "0", "HOME": "/root"}, [str(tmp_path), ""])
    assert env["NAVVERSE_ROOT"] == "/x" and env["PYTHONHASHSEED"] == "0" and "HOME" not in env
    assert env["PYTHONPATH"].split(os.pathsep) == [str(tmp_path.resolve()), os.path.realpath(os.getcwd())]
    from pipeline.errors import PipelineError

    with pytest.raises(PipelineError, match="does not combine with --executor ray"):
        make_executor(0, kind="ray")
    with pytest.raises(PipelineError, match="use it with --executor ray"):
        make_executor(2, address="auto")
