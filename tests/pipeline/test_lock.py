"""The workspace lock: one build (or clean) at a time; a second one waits, or refuses with --no-wait."""

from __future__ import annotations

import os
import select
import threading
import time
from pathlib import Path

import pytest

from pipeline.lock import WorkspaceBusyError, running_build, workspace_lock
from tests.pipeline.cli_helpers import built_files, run, start, toy_workspace

SLOW = "seeds: [1, 2]\nstages:\n  toy_slow: {parts: 4, delay_s: 0.05, gate: gate}\n"


def _wait_for(predicate, timeout: float = 60.0) -> None:
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.05)


def test_second_holder_waits_or_refuses(tmp_path):
    lock = tmp_path / "built" / "build.lock"
    assert running_build(lock) is None  # no file yet
    with workspace_lock(lock):
        assert running_build(lock) == f"another build (pid {os.getpid()})"
        busy = rf"another build \(pid {os.getpid()}\) holds the workspace"
        with pytest.raises(WorkspaceBusyError, match=busy), workspace_lock(lock, wait=False):
            pass
        told: list[str] = []
        acquired = threading.Event()

        def second() -> None:
            with workspace_lock(lock, on_wait=told.append):
                acquired.set()

        thread = threading.Thread(target=second)
        thread.start()
        _wait_for(lambda: bool(told))
        assert not acquired.is_set()
    thread.join(10)
    assert acquired.is_set() and told == [f"another build (pid {os.getpid()})"]
    assert running_build(lock) is None


def _stage_runs(log: Path) -> int:
    return log.read_text().count("stage toy_slow for")


def _read_until(process, text: str, timeout: float = 60.0) -> str:
    """What ``process`` wrote to stderr until ``text`` (it keeps running)."""
    seen = ""
    deadline = time.monotonic() + timeout
    while text not in seen and time.monotonic() < deadline:
        if select.select([process.stderr], [], [], 0.5)[0]:
            seen += os.read(process.stderr.fileno(), 4096).decode()
    return seen


def test_two_concurrent_builds_one_waits_and_finds_everything_fresh(tmp_path):
    root = toy_workspace(tmp_path / "ws", {"slow.yaml": SLOW})
    clean = toy_workspace(tmp_path / "clean", {"slow.yaml": SLOW})
    (clean / "gate").touch()
    first = start(root, "build", "-j", "2")
    running = root / "data" / "built" / "tmp"
    # The first build holds the lock, its stages wait at the gate.
    _wait_for(lambda: len([p for p in running.glob("log-*.log") if "waiting for" in p.read_text()]) == 2)
    second = start(root, "build", "-j", "2")
    waited = _read_until(second, "waiting")
    refused = run(root, "build", "--no-wait")
    (root / "gate").touch()
    out_first, err_first = first.communicate(timeout=120)
    out_second, err_second = second.communicate(timeout=120)

    assert refused.returncode == 1 and "holds the workspace" in refused.stderr
    assert "--no-wait" in refused.stderr and "Traceback" not in refused.stderr
    assert first.returncode == 0 and "2 built" in out_first, err_first
    assert second.returncode == 0, err_second
    assert f"another build (pid {first.pid}) holds the workspace; waiting… — Ctrl-C to stop" in waited
    assert "Nothing to do" in out_second
    assert run(clean, "build", "-j", "2").returncode == 0
    assert built_files(root) == built_files(clean)
    for target in ("slow-s1", "slow-s2"):
        assert _stage_runs(root / "data" / "built" / "logs" / target / "toy_slow.log") == 1
        assert _stage_runs(root / "data" / "built" / "targets" / target / "numbers" / "stage.log") == 1


def test_clean_waits_for_the_lock(tmp_path):
    root = toy_workspace(tmp_path / "ws", {"slow.yaml": "stages:\n  toy_slow: {parts: 1, delay_s: 0}\n"})
    assert run(root, "build", "-j", "0").returncode == 0
    artifacts = root / "data" / "built" / "artifacts"
    with workspace_lock(root / "data" / "built" / "build.lock"):
        cleaning = start(root, "clean", "--all")
        assert "holds the workspace; waiting" in _read_until(cleaning, "waiting")
        assert any(artifacts.iterdir())  # nothing removed while the lock is held
    out, _ = cleaning.communicate(timeout=60)
    assert cleaning.returncode == 0 and "removed every build output" in out
    assert not artifacts.exists()
