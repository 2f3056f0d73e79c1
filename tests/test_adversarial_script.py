"""scripts/adversarial.py keeps working: it lists its cases and runs cheap ones under the memory cap."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).resolve().parent.parent / "scripts" / "adversarial.py"


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=600, env=_env()
    )


def _env() -> dict[str, str]:
    import os

    return {**os.environ, "COLUMNS": "200"}


def test_every_break_of_the_issue_has_a_case():
    listing = _run("--list")
    assert listing.returncode == 0, listing.stderr
    breaks = {line.split("break")[1].split()[0] for line in listing.stdout.splitlines() if "break" in line}
    assert breaks == {str(n) for n in range(1, 11)} | {"osm"}


def test_hostile_osm_files_are_refused_under_the_cap():
    result = _run("--only", "osm-billion-laughs", "osm-gzip-bomb", "--cap-mb", "1024")
    assert result.returncode == 0, result.stdout[-3000:]
    assert "every case passed" in result.stdout
    assert result.stdout.count(" ok ") >= 4  # validate and build of each


def test_hostile_recipes_pass_under_the_cap():
    result = _run("--only", "alias-bomb", "deep-maps", "fifo-recipe", "--cap-mb", "1024")
    assert result.returncode == 0, result.stdout[-3000:]
    assert "every case passed" in result.stdout
    assert result.stdout.count(" ok ") >= 4  # alias-bomb, deep-maps, and fifo-recipe's two commands


def test_a_case_that_breaks_its_promise_fails_the_run():
    # A 1 MB cap cannot hold any navverse process: the run must report the step over the cap and fail.
    result = _run("--only", "tag-int", "--cap-mb", "1")
    assert result.returncode == 1
    assert "over the cap" in result.stdout


def test_an_interrupted_build_is_signalled_while_a_stage_runs():
    # The signal waits for a running stage's log, so the build is always caught running (exit 130),
    # however fast the machine; the next build resumes and finishes.
    result = _run("--only", "ctrl-c-build", "--cap-mb", "1024")
    assert result.returncode == 0, result.stdout[-3000:]
    assert "every case passed" in result.stdout  # the first build exited 130, as the case expects
    assert result.stdout.count(" ok ") >= 2  # interrupted, then resumed
