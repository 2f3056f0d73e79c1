"""The documented journeys of a newcomer, run as printed.

Blocks of the README and of the documentation pages that follow a line ``<!-- journey: NAME -->`` are
the commands (``bash``) or the program (``python``) of journey NAME. A journey shown in several files
must be the same everywhere. The test runs them from a folder that stands for a fresh clone (the
shipped OSM extract at the path the docs give), with the installed ``navverse`` on the ``PATH``:

- ``own-city``: a workspace of one's own (``navverse init``, whose printed next commands must be the
  block's next lines), a 300 m window of a real extract built, the oracle run on five episodes and
  scored with the command ``run-agent`` prints (the last line of the block must be that command):
  SR 100 %;
- ``python-api``: the Python API example, in that workspace, saving an RGB frame.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

REPO = Path(__file__).resolve().parents[1]
MARKER = re.compile(r"^<!-- journey: ([a-z0-9-]+) -->\n```(bash|python)\n(.*?)^```", re.M | re.S)

TIMEOUT = 1200
"""Seconds a journey's step may take (a hang, e.g. a worker waiting for its parent's lock, fails)."""


def journeys(files: list[Path] | None = None) -> dict[str, tuple[str, str, list[str]]]:
    """``{name: (language, code, files showing it)}`` of the journeys marked in ``files`` (default:
    README.md and docs/*.md); a journey shown differently in two places is an error."""
    found: dict[str, tuple[str, str, list[str]]] = {}
    for path in files or [REPO / "README.md", *sorted((REPO / "docs").glob("**/*.md"))]:
        for name, language, code in MARKER.findall(path.read_text()):
            shown = str(path.relative_to(REPO)) if path.is_relative_to(REPO) else str(path)
            if name in found:
                assert found[name][:2] == (language, code), f"journey {name!r} differs in {shown}"
                found[name][2].append(shown)
            else:
                found[name] = (language, code, [shown])
    return found


def _env(home: Path) -> dict[str, str]:
    """The environment of a newcomer's shell: the installed navverse first on the PATH, no workspace
    or scene search path inherited from the test run, no terminal width."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("NAVVERSE_") and k != "COLUMNS"}
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    env["HOME"] = str(home)
    return env


def test_the_journeys_are_marked_where_a_newcomer_reads_them():
    found = journeys()
    assert {"own-city", "python-api"} <= set(found), sorted(found)
    assert "README.md" in found["python-api"][2] and "README.md" in found["own-city"][2]
    assert any(f.startswith("docs/") for f in found["own-city"][2])


def test_a_journey_shown_twice_must_be_the_same(tmp_path: Path):
    block = "<!-- journey: x -->\n```bash\n{}\n```\n"
    (tmp_path / "a.md").write_text(block.format("navverse build"))
    (tmp_path / "b.md").write_text(block.format("navverse build --force"))
    with pytest.raises(AssertionError, match="differs"):
        journeys([tmp_path / "a.md", tmp_path / "b.md"])


@pytest.mark.slow(seconds=120)
def test_own_city_then_the_python_api_run_as_documented(tmp_path: Path):
    found = journeys()
    language, commands, _ = found["own-city"]
    assert language == "bash"
    lines = [line for line in commands.splitlines() if line.strip()]
    assert lines[0].startswith("navverse init ../my-city --city data/raw/osm/")
    clone = tmp_path / "clone"  # stands for the fresh clone: the extract where the docs say it is
    extract = lines[0].split("--city ")[1].split()[0]
    (clone / extract).parent.mkdir(parents=True)
    shutil.copyfile(REPO / extract, clone / extract)
    env = _env(tmp_path)

    *steps, scoring = lines
    script = "set -euo pipefail\n" + "\n".join(steps) + "\n"
    done = subprocess.run(["bash", "-c", script], cwd=clone, env=env, capture_output=True, text=True,
                          timeout=TIMEOUT)  # fmt: skip
    output = done.stdout + done.stderr
    assert done.returncode == 0, output[-4000:]
    printed = done.stdout.split("\nnext:\n", 1)[1].splitlines()
    assert [line.strip() for line in printed[:3]] == steps[1:4], "init's next commands are not the docs'"
    hint = re.search(r"score it with: (.*)$", done.stdout, re.M)
    assert hint is not None, done.stdout[-2000:]
    assert hint.group(1) == scoring, "the docs' scoring command is not the one run-agent prints"

    workspace = tmp_path / "my-city"
    scored = subprocess.run(["bash", "-c", scoring], cwd=workspace, env=env, capture_output=True, text=True,
                            timeout=TIMEOUT)  # fmt: skip
    assert scored.returncode == 0, (scored.stdout + scored.stderr)[-4000:]
    metrics = json.loads((workspace / "eval-out" / "metrics.json").read_text())
    assert metrics["scope"]["scored"] == 5 and metrics["overall"]["success"] == 1.0
    assert "PARTIAL" in scored.stdout and "Traceback" not in scored.stdout + scored.stderr

    language, program, _ = found["python-api"]
    assert language == "python"
    (workspace / "example.py").write_text(program)
    ran = subprocess.run(
        [sys.executable, "example.py"], cwd=workspace, env=env, capture_output=True, text=True
    )
    assert ran.returncode == 0, (ran.stdout + ran.stderr)[-4000:]
    frame = np.asarray(Image.open(workspace / "frame.png"))
    assert frame.ndim == 3 and frame.shape[2] == 3 and frame.shape[0] >= 100
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 20  # a picture, not a blank
