"""Interrupts and shutdowns: Ctrl-C and SIGTERM end every process of a build with one line, a killed
build leaves no process behind, a dead worker or a full disk is one clear line per stage."""

from __future__ import annotations

import logging
import os
import signal
import subprocess
import sys

import pytest

from pipeline.worker import QuietFileHandler
from tests.pipeline.cli_helpers import (
    GATED,
    INTERRUPTED,
    REPO,
    marked,
    none_left,
    run,
    start_mid_build,
    toy_workspace,
)


@pytest.mark.parametrize(
    ("signum", "whole_group", "code"),
    [(signal.SIGINT, True, 130), (signal.SIGTERM, False, 143)],
    ids=["ctrl-c-to-the-group", "sigterm-to-the-build"],
)
def test_interrupt_ends_every_process_with_one_line(tmp_path, signum, whole_group, code):
    root = toy_workspace(tmp_path / "ws", {"slow.yaml": GATED.format(child="true")})
    marker = f"interrupt-{os.getpid()}-{signum}"
    build = start_mid_build(root, marker)
    assert len(marked(marker)) >= 6  # the build, its resource tracker, 2 workers and their children
    if whole_group:
        os.killpg(build.pid, signum)  # what a terminal does on Ctrl-C
    else:
        os.kill(build.pid, signum)
    out, err = build.communicate(timeout=30)
    assert build.returncode == code
    assert err.strip() == INTERRUPTED
    assert "Traceback" not in out + err and "KeyboardInterrupt" not in out + err
    assert none_left(marker) == []
    assert not [p for p in (root / "data" / "built" / "tmp").iterdir() if p.is_dir()]
    log = (root / "data" / "built" / "logs" / "slow-s1" / "toy_slow.log").read_text()
    assert "waiting for gate" in log and log.rstrip().endswith("interrupted: the build was stopped")
    (root / "gate").touch()
    resumed = run(root, "build", "-j", "2")
    assert resumed.returncode == 0 and "4 built, 0 cached" in resumed.stdout


def test_killed_build_leaves_no_process_behind(tmp_path):
    root = toy_workspace(tmp_path / "ws", {"slow.yaml": GATED.format(child="false")})
    marker = f"killed-{os.getpid()}"
    build = start_mid_build(root, marker)
    helpers = {p.pid: " ".join(p.cmdline()) for p in marked(marker) if p.pid != build.pid}
    assert any("resource_tracker" in c for c in helpers.values())
    assert sum("spawn_main" in c for c in helpers.values()) == 2
    os.kill(build.pid, signal.SIGKILL)
    build.communicate(timeout=30)
    assert none_left(marker) == []


def test_a_killed_worker_fails_its_stage_only(tmp_path):
    recipes = {
        "doomed.yaml": "stages:\n  toy_slow: {parts: 5, delay_s: 0, die_at: 3}\n",
        "fine.yaml": "stages:\n  toy_slow: {parts: 2, delay_s: 0}\n",
    }
    result = run(toy_workspace(tmp_path / "ws", recipes), "build", "-j", "2")
    assert result.returncode == 1 and "1 built" in result.stdout and "1 failed" in result.stdout
    died = "the worker process died (SIGKILL: killed, or out of memory)"
    assert f"FAILED doomed:toy_slow: {died}" in result.stdout
    log = (tmp_path / "ws" / "data" / "built" / "logs" / "doomed" / "toy_slow.log").read_text()
    assert "part 3 of 5" in log and log.rstrip().endswith(died)


@pytest.mark.parametrize("jobs", ["2", "0"], ids=["workers", "in-process"])
def test_full_disk_is_one_line_per_stage(tmp_path, jobs):
    recipes = {
        "full.yaml": "seeds: [1, 2]\nstages:\n  toy_full_disk: {}\n",
        "fine.yaml": "stages:\n  toy_slow: {parts: 2, delay_s: 0}\n",
    }
    result = run(toy_workspace(tmp_path / "ws", recipes), "build", "-j", jobs)
    text = result.stdout + result.stderr
    assert result.returncode == 1 and "1 built" in result.stdout and "2 failed" in result.stdout
    assert "Logging error" not in text and "Traceback" not in text
    advice = "no space left on device while writing"
    assert text.count(advice) == 2
    for seed in (1, 2):
        line = next(line for line in text.splitlines() if f"FAILED full-s{seed}:toy_full_disk" in line)
        assert advice in line and line.endswith("free space and run the same command to resume")


def test_quiet_file_handler_keeps_the_error_and_prints_nothing(capfd):
    handler = QuietFileHandler("/dev/full")
    logger = logging.getLogger("tests.pipeline.quiet")
    logger.addHandler(handler)
    logger.propagate = False
    try:
        assert logging.raiseExceptions  # a plain handler would print a "Logging error" traceback
        for index in range(20):
            logger.error("line %d", index)
    finally:
        logger.removeHandler(handler)
        handler.close()
    assert isinstance(handler.error, OSError) and handler.error.errno == 28
    captured = capfd.readouterr()
    assert captured.err == "" and captured.out == ""


PROBE = """
import pipeline.executors as executors
from pipeline.worker import StageTask
from tests.pipeline.cli_helpers import sigint_probe

executors.child_main = sigint_probe
if __name__ == "__main__":
    task = StageTask(*(["x"] * 6), 0, "k", {}, {}, {}, {}, (), "/nowhere", "v")
    executor = executors.LocalProcessExecutor(1)
    for _ in range(2):
        print(executor.submit(task).result(timeout=60).stats["sigint_blocked"])
    executor.close()
"""


def test_workers_start_with_sigint_blocked(tmp_path):
    """A Ctrl-C while a worker starts (before it ignores SIGINT) must not print its traceback; the
    first start is checked in a fresh interpreter (starting the resource tracker unblocks SIGINT)."""
    script = tmp_path / "probe.py"
    script.write_text(PROBE)
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    command = [sys.executable, str(script)]
    result = subprocess.run(command, env=env, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["True", "True"]
