"""Running the ``navverse`` command on a throw-away workspace of toy stages, in a subprocess."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path
from typing import Any

import psutil

REPO = Path(__file__).resolve().parents[2]
DRIVER = """\
import sys

import navverse.cli as cli

cli.STAGES_PACKAGE = "tests.pipeline.cli_stages"
if __name__ == "__main__":  # workers are spawned: they import this file without running it
    sys.exit(cli.main())
"""


def toy_workspace(root: Path, recipes: dict[str, str]) -> Path:
    """A workspace at ``root`` with ``recipes`` {file name: YAML} and the driver script."""
    (root / "recipes").mkdir(parents=True)
    for name, text in recipes.items():
        (root / "recipes" / name).write_text(text)
    (root / "drive.py").write_text(DRIVER)
    return root


def start(root: Path, *args: str, marker: str | None = None) -> subprocess.Popen[str]:
    """Start ``navverse <args>`` in its own session, every process of it tagged with ``marker``."""
    marker = marker or uuid.uuid4().hex
    env = {**os.environ, "NAVVERSE_ROOT": str(root), "PYTHONPATH": str(REPO), "NAVVERSE_TEST_MARKER": marker}
    process = subprocess.Popen(
        [sys.executable, str(root / "drive.py"), *args],
        env=env,
        cwd=root,
        start_new_session=True,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    _started.append((process, marker))
    return process


_started: list[tuple[subprocess.Popen[str], str]] = []
"""The commands :func:`start` started, with their markers, since :func:`end_leftovers` last ran."""


def end_leftovers() -> None:
    """Kill every process of the commands :func:`start` started that still runs, found by its marker:
    a test that failed midway leaves its build waiting at a gate (on Ray, a whole cluster), which
    would otherwise share the machine with the tests that follow."""
    for process, marker in _started:
        for member in marked(marker):
            with contextlib.suppress(psutil.Error):
                member.kill()
        with contextlib.suppress(subprocess.TimeoutExpired):  # reaped and its pipes closed (a no-op if done)
            process.communicate(timeout=30)
    _started.clear()


def run(root: Path, *args: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    """Run ``navverse <args>`` to its end."""
    process = start(root, *args)
    out, err = process.communicate(timeout=timeout)
    return subprocess.CompletedProcess(process.args, process.returncode, out, err)


def marked(marker: str) -> list[psutil.Process]:
    """Running (not zombie) processes tagged with ``marker``."""
    found = []
    for process in psutil.process_iter():
        try:
            tagged = process.environ().get("NAVVERSE_TEST_MARKER") == marker
            if tagged and process.status() != psutil.STATUS_ZOMBIE:
                found.append(process)
        except psutil.Error:
            continue
    return found


GATED = "seeds: [1, 2, 3, 4]\nstages:\n  toy_slow: {{parts: 3, delay_s: 0, child: {child}, gate: gate}}\n"
"""A recipe of four slow stages that wait for the file ``gate`` (``child``: each starts a child process)."""

INTERRUPTED = "interrupted; 4 stages left unfinished, run the same command to resume"
"""What an interrupted build of :data:`GATED` prints on stderr, last."""


def start_mid_build(root: Path, marker: str, *args: str) -> subprocess.Popen[str]:
    """Start ``navverse build -j 2 <args>`` and return once both workers wait at the gate, in the
    middle of their stages (the build is killed and the test fails if they do not within 120 s)."""
    process = start(root, "build", "-j", "2", *args, marker=marker)
    running = root / "data" / "built" / "tmp"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        logs = list(running.glob("log-*.log")) if running.is_dir() else []
        if len(logs) == 2 and all("waiting for gate" in log.read_text() for log in logs):
            return process
        time.sleep(0.05)
    process.kill()
    raise AssertionError("the build did not start its stages")


def none_left(marker: str, *, within: float = 5.0) -> list[str]:
    """The processes tagged ``marker`` still running after ``within`` seconds (empty when all ended)."""
    deadline = time.monotonic() + within
    while (left := marked(marker)) and time.monotonic() < deadline:
        time.sleep(0.05)
    return [" ".join(p.cmdline()) for p in left]


def built_files(root: Path) -> dict[str, dict]:
    """{artifact dir name: manifest 'files'} of every committed artifact."""
    found = {}
    for manifest in sorted((root / "data" / "built" / "artifacts").glob("*/*/manifest.json")):
        found[manifest.parent.name] = json.loads(manifest.read_text())["files"]
    return found


def sigint_probe(task: Any, conn: Any, parent_pid: int) -> None:
    """Stands in for ``pipeline.worker.child_main``: reports whether SIGINT was blocked at the start."""
    from pipeline.worker import TaskResult

    blocked = signal.SIGINT in signal.pthread_sigmask(signal.SIG_BLOCK, [])
    conn.send(("result", TaskResult(task.node_id, ok=True, stats={"sigint_blocked": blocked})))
    conn.close()
