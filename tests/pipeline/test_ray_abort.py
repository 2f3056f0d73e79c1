"""Stopping a build on Ray: the running stage's worker ends and its future raises, with a Ray the
executor started and with one this process had started before (the executor leaves Ray either way,
cancelling nothing); and ``ctx.map`` on Ray raises the lowest failing item's error without cancelling
chunks, which could abort the caller."""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import psutil
import pytest
import ray  # a dev dependency: these tests must run wherever the suite does

from pipeline import Params, StageContext, stage
from pipeline.context import FanOut, MapError, run_map
from pipeline.dag import build_graph
from pipeline.executors import WorkerDiedError
from pipeline.ray_executor import RayExecutor
from pipeline.recipes import RecipeLoader
from pipeline.runner import _task
from pipeline.stage import registered_stages
from pipeline.store import ArtifactStore
from pipeline.workspace import Workspace
from tests.pipeline.cli_helpers import (
    GATED,
    INTERRUPTED,
    marked,
    none_left,
    run,
    start_mid_build,
    toy_workspace,
)
from tests.pipeline.conftest import write


class GateParams(Params):
    gate: str
    pidfile: str


@stage(name="rab_gate", outputs=["done"])
def rab_gate(ctx: StageContext, params: GateParams) -> None:
    """Writes its process id, then waits (at most 120 s) for the gate file (``done.txt``)."""
    Path(params.pidfile).write_text(str(os.getpid()))
    deadline = time.monotonic() + 120
    while not Path(params.gate).exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    (ctx.output / "done.txt").write_text("through the gate")


def _gate_task(root: Path):
    workspace = Workspace(root)
    gate, pidfile = root / "gate", root / "worker.pid"
    write(
        workspace.recipes_dir / "gated.yaml",
        f"stages:\n  rab_gate: {{gate: '{gate}', pidfile: '{pidfile}'}}\n",
    )
    targets = RecipeLoader(workspace, stages={"rab_gate": registered_stages()["rab_gate"]}).load()
    graph = build_graph(targets)
    store = ArtifactStore(workspace.built_dir)
    return _task(graph.nodes["gated:rab_gate"], graph, store, replace=False), pidfile


def _wait_for_pid(pidfile: Path, *, within: float = 90.0) -> int:
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        if pidfile.is_file() and pidfile.read_text():
            return int(pidfile.read_text())
        time.sleep(0.05)
    pytest.fail("the stage did not start on Ray")


def _gone(pid: int, *, within: float = 30.0) -> bool:
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        if not psutil.pid_exists(pid) or psutil.Process(pid).status() == psutil.STATUS_ZOMBIE:
            return True
        time.sleep(0.1)
    return False


@pytest.mark.parametrize("owner", ["started-here", "joined"])
def test_abort_ends_the_running_stage(tmp_path, owner):
    if ray.is_initialized():
        ray.shutdown()
    if owner == "joined":
        ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, configure_logging=False)
    try:
        executor = RayExecutor(None, 2)
        task, pidfile = _gate_task(tmp_path / "ws")
        future = executor.submit(task)
        pid = _wait_for_pid(pidfile)
        executor.abort()
        with pytest.raises(WorkerDiedError, match="interrupted"):
            future.result(timeout=60)
        assert _gone(pid), f"the stage's Ray worker {pid} still runs after abort"
        assert not ray.is_initialized()  # the executor left Ray
        executor.close()
        assert not ray.is_initialized()  # and closing it started none
    finally:
        if ray.is_initialized():
            ray.shutdown()


def fails_early(item: int) -> int:
    """Raises on items 2 and 30; the other items return at once (their chunks end while the error is
    handled: the moment a cancellation would race their replies)."""
    if item in (2, 30):
        raise ValueError(f"bad item {item}")
    return -item


def test_map_error_on_ray_leaves_the_caller_running(ray_instance):
    for _ in range(5):
        with pytest.raises(MapError, match=r"raised on item 2 of 40: ValueError: bad item 2"):
            run_map(fails_early, list(range(40)), fanout=FanOut("ray", 2), chunksize=1)
    time.sleep(1.0)  # replies of the chunks still running arrive meanwhile
    assert run_map(fails_early, [1, 3], fanout=FanOut("ray", 2), chunksize=1) == [-1, -3]


@pytest.mark.slow(seconds=25)
def test_ctrl_c_on_a_ray_build_ends_every_process_and_the_build_resumes(tmp_path):
    root = toy_workspace(tmp_path / "ws", {"slow.yaml": GATED.format(child="true")})
    marker = f"ray-interrupt-{os.getpid()}"
    build = start_mid_build(root, marker, "--executor", "ray")
    assert len(marked(marker)) >= 5  # the build, Ray's own processes, the two stage workers
    os.killpg(build.pid, signal.SIGINT)  # what a terminal does on Ctrl-C
    out, err = build.communicate(timeout=60)
    assert build.returncode == 130
    assert err.strip().endswith(INTERRUPTED)  # after Ray's own banner
    assert "Traceback" not in out + err
    assert none_left(marker, within=15) == []
    log = (root / "data" / "built" / "logs" / "slow-s1" / "toy_slow.log").read_text()
    assert "waiting for gate" in log and log.rstrip().endswith("interrupted: the build was stopped")
    (root / "gate").touch()
    resumed = run(root, "build", "-j", "2", "--executor", "ray", timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    assert "4 built, 0 cached" in resumed.stdout
