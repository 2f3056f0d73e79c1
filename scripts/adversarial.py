"""Hostile inputs, run as an adversary would, each under a memory cap, with the peak RSS of each.

Every case prepares a hostile input in a scratch folder (a recipe, a submission, a tampered copy of a
dataset, a damaged cache, an agent that never answers...), runs the ``navverse`` command a user would
run on it in a fresh process session, and checks what came back: the documented exit code, the
message that says what is wrong, no Python traceback, no process left behind, and a peak resident
memory under the cap (the whole process tree, sampled every 20 ms, and the exact peak of the
command's own process). A command that goes over twice the cap or past its time limit is killed and
the case fails.

    python scripts/adversarial.py                    # every case (datasets cases need `make episodes`)
    python scripts/adversarial.py --list             # the cases and the break each reproduces
    python scripts/adversarial.py --only alias-bomb gzip-bomb-lines --cap-mb 1024

Cases that score submissions or tamper with a dataset use ``--dataset`` (default: the newest
navverse-mini version) and its scenes, looked for in ``--scenes`` (default: ``$NAVVERSE_SCENES``, else
the build store of the workspace the dataset is in, e.g. ``../other/data/built`` for
``--dataset ../other/episodes/navverse-mini/v2.2``); without a dataset they are reported as not run.
Exit status: 0 when every case that ran passed.
"""

from __future__ import annotations

import argparse
import contextlib
import gzip
import io
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import psutil
from rich.console import Console
from rich.table import Table

PROJECT = Path(__file__).resolve().parent.parent
SAMPLE_SECONDS = 0.02
"""How often the process tree's memory is sampled."""
ORPHAN_GRACE_SECONDS = 10.0
"""How long processes of a finished command may take to go away before they count as left behind."""
SCENES_ENV = "NAVVERSE_SCENES"
"""Scene folders the commands search after ``--scenes`` (``navverse.scene.locate.SCENES_ENV``)."""
RUNNING_STAGE_LOG = "data/built/tmp/log-*.log"
"""Where a build's worker writes the log of the stage it runs, while it runs (a workspace's path)."""


# ------------------------------------------------------------------------------------------ case model


@dataclass(frozen=True)
class Step:
    """One ``navverse`` command of a case and what it must give.

    Attributes
    ----------
    argv : list of str
        Arguments after ``navverse``.
    codes : tuple of int
        Accepted exit codes.
    expect : str
        A regular expression the command's output (stdout and stderr) must match ("" for none).
    timeout : float
        Seconds before the command is killed (and the case fails).
    cwd : Path or None
        Working directory (default: the case's scratch folder).
    signal_when : tuple of (int, str) or None
        ``(signal, pattern)``: send the signal to the command's process group, as a terminal's Ctrl-C
        does, once a file matching the glob ``pattern`` (relative to the working directory) exists:
        a running stage's log (:data:`RUNNING_STAGE_LOG`) proves the build is under way, so the
        signal never comes after it has finished. ``SIGKILL`` goes to the command's own process only
        (its parent dies). A command that never makes the file runs to its time limit and fails.
    copies : int
        How many copies run at once (concurrent builds in one workspace).
    env : dict
        Extra environment variables.
    """

    argv: list[str]
    codes: tuple[int, ...]
    expect: str = ""
    timeout: float = 120.0
    cwd: Path | None = None
    signal_when: tuple[int, str] | None = None
    copies: int = 1
    env: dict[str, str] = field(default_factory=dict)


@dataclass(frozen=True)
class Case:
    """A hostile input: ``prepare`` writes it under a folder and returns the steps that try it."""

    name: str
    breaks: str
    what: str
    prepare: Callable[[Scratch, Path], list[Step]]
    needs_dataset: bool = False


@dataclass
class Outcome:
    """What one step gave."""

    codes: list[int]
    output: str
    peak_tree_mb: float
    peak_own_mb: float
    seconds: float
    killed: str = ""
    orphans: list[str] = field(default_factory=list)


# ------------------------------------------------------------------------------------------ running


def _navverse() -> list[str]:
    return [sys.executable, "-m", "navverse.cli"]


def _tree_rss(processes: Sequence[psutil.Process]) -> int:
    total = 0
    for root in processes:
        try:
            members = [root, *root.children(recursive=True)]
        except psutil.Error:
            continue
        for member in members:
            with contextlib.suppress(psutil.Error):
                total += member.memory_info().rss
    return total


def _session_members(session: int) -> list[str]:
    found = []
    for process in psutil.process_iter(["pid", "name", "cmdline"]):
        try:
            if os.getsid(process.pid) == session and process.status() != psutil.STATUS_ZOMBIE:
                found.append(
                    f"{process.pid} {' '.join(process.info['cmdline'] or [process.info['name']])[:80]}"
                )
        except (ProcessLookupError, PermissionError, psutil.Error):
            continue
    return found


def run_step(step: Step, *, cwd: Path, cap_bytes: int) -> Outcome:
    """Run ``step`` (its copies at once), sampling memory, and collect what it gave."""
    env = {**os.environ, "PYTHONUNBUFFERED": "1", "COLUMNS": "120", **step.env}
    logs = [tempfile.TemporaryFile() for _ in range(step.copies)]  # noqa: SIM115 (closed below)
    started = time.monotonic()
    popens = [
        subprocess.Popen(
            [*_navverse(), *step.argv],
            cwd=step.cwd or cwd,
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=log,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
        for log in logs
    ]
    watched = [psutil.Process(p.pid) for p in popens]
    sessions = [p.pid for p in popens]
    peak_tree = 0
    peak_own = [0] * len(popens)
    codes: list[int | None] = [None] * len(popens)
    killed = ""
    signalled = False
    while any(code is None for code in codes):
        elapsed = time.monotonic() - started
        peak_tree = max(peak_tree, _tree_rss([w for w, c in zip(watched, codes, strict=True) if c is None]))
        if step.signal_when and not signalled and _exists(step.cwd or cwd, step.signal_when[1]):
            signalled = True
            for popen in popens:
                if step.signal_when[0] == signal.SIGKILL:
                    popen.send_signal(signal.SIGKILL)
                else:
                    os.killpg(popen.pid, step.signal_when[0])
        if not killed and peak_tree > 2 * cap_bytes:
            killed = f"killed at {peak_tree / 2**20:.0f} MB (over twice the cap)"
        elif not killed and elapsed > step.timeout:
            killed = f"killed after {step.timeout:.0f} s (time limit)"
        if killed:
            for popen in popens:
                _kill_session(popen.pid)
        for index, popen in enumerate(popens):
            if codes[index] is None:
                pid, status, usage = os.wait4(popen.pid, os.WNOHANG)
                if pid:
                    codes[index] = os.waitstatus_to_exitcode(status)
                    peak_own[index] = usage.ru_maxrss * 1024
                    popen.returncode = codes[index]
        time.sleep(SAMPLE_SECONDS)
    seconds = time.monotonic() - started
    orphans = _wait_for_sessions(sessions)
    for session in sessions:
        _kill_session(session)
    output = ""
    for log in logs:
        log.seek(0)
        output += log.read().decode("utf-8", "replace")
        log.close()
    return Outcome(
        codes=[int(c) for c in codes if c is not None],
        output=output,
        peak_tree_mb=peak_tree / 2**20,
        peak_own_mb=max(peak_own) / 2**20,
        seconds=seconds,
        killed=killed,
        orphans=orphans,
    )


def _exists(folder: Path, pattern: str) -> bool:
    """Whether a file matching the glob ``pattern`` exists under ``folder``."""
    return next(folder.glob(pattern), None) is not None


def _wait_for_sessions(sessions: Sequence[int]) -> list[str]:
    deadline = time.monotonic() + ORPHAN_GRACE_SECONDS
    while True:
        left = [member for session in sessions for member in _session_members(session)]
        if not left or time.monotonic() > deadline:
            return left
        time.sleep(0.2)


def _kill_session(session: int) -> None:
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(session, signal.SIGKILL)


def judge(step: Step, outcome: Outcome, *, cap_mb: float) -> list[str]:
    """Why the step failed (empty when it passed)."""
    faults = []
    if outcome.killed:
        faults.append(outcome.killed)
    bad_codes = [c for c in outcome.codes if c not in step.codes]
    if bad_codes:
        faults.append(f"exit {bad_codes[0]}, expected {' or '.join(map(str, step.codes))}")
    if "Traceback (most recent call last)" in outcome.output:
        faults.append("a traceback was printed")
    if step.expect and not re.search(step.expect, outcome.output, re.IGNORECASE | re.DOTALL):
        faults.append(f"output does not match {step.expect!r}")
    if outcome.peak_tree_mb > cap_mb * step.copies:
        faults.append(f"peak {outcome.peak_tree_mb:.0f} MB over the cap")
    if outcome.orphans:
        faults.append(f"{len(outcome.orphans)} processes left behind: {outcome.orphans[0]}")
    return faults


# ------------------------------------------------------------------------------------------ scratch inputs


@dataclass
class Scratch:
    """Shared inputs of the cases: the dataset under test and helpers that write hostile files."""

    root: Path
    dataset: Path | None

    def workspace(self, folder: Path, recipes: dict[str, str] | None = None) -> Path:
        """A workspace in ``folder`` with the project's presets and the given recipe files."""
        (folder / "recipes").mkdir(parents=True, exist_ok=True)
        shutil.copytree(PROJECT / "recipes" / "presets", folder / "recipes" / "presets", dirs_exist_ok=True)
        for name, text in (recipes or {}).items():
            path = folder / "recipes" / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
        return folder

    def box_room(self, folder: Path) -> Path:
        """A workspace with the small box-room scene recipe (a blockout and its navmesh)."""
        text = (PROJECT / "recipes" / "scenes" / "blockout" / "box-room.yaml").read_text()
        return self.workspace(folder, {"box-room.yaml": text})

    def built_box_room(self, folder: Path) -> Path:
        """:meth:`box_room`, built (not measured)."""
        workspace = self.box_room(folder)
        subprocess.run([*_navverse(), "build", "--jobs", "1"], cwd=workspace, check=True, capture_output=True)
        return workspace

    def split_episodes(self, split: str = "eval") -> list[str]:
        """Episode ids of a split of the dataset under test."""
        assert self.dataset is not None
        ids = []
        for path in sorted((self.dataset / split).glob("*.json.gz")):
            if path.name.endswith(".rollouts.json.gz"):
                continue
            ids += [e["episode_id"] for e in json.loads(gzip.decompress(path.read_bytes()))["episodes"]]
        return ids

    def valid_line(self, split: str = "eval") -> str:
        """A valid submission line: the verification rollout of the split's first episode that has one."""
        assert self.dataset is not None
        for path in sorted((self.dataset / split).glob("*.rollouts.json.gz")):
            rollouts = json.loads(gzip.decompress(path.read_bytes()))
            for episode_id, rows in sorted(rollouts.items()):
                return json.dumps({"episode_id": episode_id, "stop": True, "trajectory": rows})
        raise SystemExit(f"{self.dataset}/{split} keeps no rollouts to make a valid submission from")

    def tampered_copy(self, folder: Path) -> Path:
        """A copy of the dataset version under test, to damage."""
        assert self.dataset is not None
        copy = folder / "dataset" / self.dataset.parent.name / self.dataset.name
        shutil.copytree(self.dataset, copy)
        return copy


# ------------------------------------------------------------------------------------------ the cases

_EXPECT_RECIPE = r"error|problem"


def _recipe_case(name: str, breaks: str, what: str, text: str | bytes, expect: str = _EXPECT_RECIPE) -> Case:
    """A case that validates one hostile recipe file."""

    def prepare(scratch: Scratch, folder: Path) -> list[Step]:
        workspace = scratch.workspace(folder)
        path = workspace / "recipes" / "hostile.yaml"
        if isinstance(text, bytes):
            path.write_bytes(text)
        else:
            path.write_text(text)
        return [Step(["validate", "recipe", "recipes/hostile.yaml"], (1,), expect, timeout=60, cwd=workspace)]

    return Case(name, breaks, what, prepare)


def _alias_bomb() -> str:
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]" for i in range(1, 10)]
    lines += ["stages:", "  blockout:", "    scene_type: *a9"]
    return "\n".join(lines) + "\n"


def _special_file_case(name: str, what: str, make: Callable[[Path], None]) -> Case:
    """A case whose recipe folder holds a file that is not a regular file (every command must go on)."""

    def prepare(scratch: Scratch, folder: Path) -> list[Step]:
        text = (PROJECT / "recipes" / "scenes" / "blockout" / "box-room.yaml").read_text()
        workspace = scratch.workspace(folder, {"box-room.yaml": text})
        make(workspace / "recipes" / "x.yaml")
        return [
            Step(["validate", "recipe"], (1,), r"x\.yaml", timeout=60, cwd=workspace),
            Step(["build", "box-room", "--dry-run"], (0,), r"box-room", timeout=60, cwd=workspace),
        ]

    return Case(name, "6", what, prepare)


def _deep(kind: str, depth: int) -> str:
    if kind == "list":
        return "stages:\n  blockout:\n    size: " + "[" * depth + "]" * depth + "\n"
    return "stages:\n  blockout:\n    size: " + "{a: " * depth + "1" + "}" * depth + "\n"


def _import_mesh_recipe(mesh: str) -> str:
    params = f"source: {json.dumps(mesh)}, up_axis: z, scene_type: indoor"
    return f"stages:\n  import_mesh: {{{params}}}\n  decimate: {{ratio: 1.0}}\n  navmesh: {{}}\n"


def _outside_mesh(scratch: Scratch, folder: Path) -> list[Step]:
    outside = folder / "outside"
    outside.mkdir()
    (outside / "room.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    workspace = scratch.workspace(folder / "ws", {"m.yaml": _import_mesh_recipe(str(outside / "room.obj"))})
    relative = os.path.relpath(outside / "room.obj", workspace / "recipes")
    (workspace / "recipes" / "r.yaml").write_text(_import_mesh_recipe(relative))
    return [
        Step(["validate", "recipe", "recipes/m.yaml"], (1,), r"outside|allow", cwd=workspace),
        Step(["validate", "recipe", "recipes/r.yaml"], (1,), r"outside|allow", cwd=workspace),
    ]


def _usda_fifo_sublayer(scratch: Scratch, folder: Path) -> list[Step]:
    workspace = scratch.workspace(folder)
    data = workspace / "data" / "raw"
    data.mkdir(parents=True)
    os.mkfifo(data / "pipe.usda")
    (data / "room.usda").write_text("#usda 1.0\n(\n    subLayers = [@./pipe.usda@]\n)\n")
    (workspace / "recipes" / "u.yaml").write_text(_import_mesh_recipe("../data/raw/room.usda"))
    return [
        Step(["validate", "recipe", "recipes/u.yaml"], (1,), r"pipe\.usda", timeout=60, cwd=workspace),
        Step(["build", "u", "--jobs", "1"], (1,), r"pipe\.usda", timeout=120, cwd=workspace),
    ]


def _nan_obj(scratch: Scratch, folder: Path) -> list[Step]:
    workspace = scratch.workspace(folder)
    data = workspace / "data" / "raw"
    data.mkdir(parents=True)
    obj = ["v 0 0 0", "v 10 0 0", "v 10 10 0", "v 0 10 0", "v nan 5 0", "f 1 2 3", "f 1 3 4", "f 1 2 5"]
    (data / "floor.obj").write_text("\n".join(obj) + "\n")
    (workspace / "recipes" / "n.yaml").write_text(_import_mesh_recipe("../data/raw/floor.obj"))
    return [Step(["build", "n", "--jobs", "1"], (1,), r"nan|finite", timeout=120, cwd=workspace)]


def _submission_case(
    name: str,
    breaks: str,
    what: str,
    write: Callable[[Scratch, Path], Path],
    *,
    codes_validate=(1,),
    codes_eval=(0, 1),
    expect="",
) -> Case:
    """A case that validates and scores one hostile submission."""

    def prepare(scratch: Scratch, folder: Path) -> list[Step]:
        path = write(scratch, folder)
        dataset = str(scratch.dataset)
        return [
            Step(["validate", "submission", str(path), "--dataset", dataset], codes_validate, expect),
            Step(
                ["eval", "--dataset", dataset, "--submission", str(path), "--out", str(folder / "out")],
                codes_eval,
                expect,
                timeout=300,
            ),
        ]

    return Case(name, breaks, what, prepare, needs_dataset=True)


def _far_record(distance: float) -> Callable[[Scratch, Path], Path]:
    def write(scratch: Scratch, folder: Path) -> Path:
        episode_id = scratch.split_episodes()[0]
        rows = [[0, 0, 0, 0, 0, 0, 0, 1], [1, distance, 0, 0, 0, 0, 0, 1]]
        path = folder / "far.jsonl"
        path.write_text(json.dumps({"episode_id": episode_id, "stop": True, "trajectory": rows}) + "\n")
        return path

    return write


def _gzip_bomb_lines(scratch: Scratch, folder: Path) -> Path:
    line = (scratch.valid_line() + "\n").encode()
    chunk = line * max(1, (4 << 20) // len(line))
    path = folder / "bomb.jsonl.gz"
    with gzip.open(path, "wb", compresslevel=1) as handle:
        for _ in range((1 << 30) // len(chunk) + 1):
            handle.write(chunk)
    return path


def _gzip_bomb_zeros(scratch: Scratch, folder: Path) -> Path:
    path = folder / "zeros.jsonl.gz"
    zeros = bytes(16 << 20)
    with gzip.open(path, "wb", compresslevel=9) as handle:
        for _ in range(128):  # 2 GiB of NUL bytes
            handle.write(zeros)
    return path


def _deep_json(scratch: Scratch, folder: Path) -> Path:
    episode_id = scratch.split_episodes()[0]
    path = folder / "deep.jsonl"
    path.write_text(
        f'{{"episode_id": "{episode_id}", "stop": true, "trajectory": '
        + "[" * 100_000
        + "]" * 100_000
        + "}\n"
    )
    return path


def _eval_out_cases(scratch: Scratch, folder: Path) -> list[Step]:
    submission = folder / "one.jsonl"
    submission.write_text(scratch.valid_line() + "\n")
    existing = folder / "a-file"
    existing.write_text("x")
    readonly = folder / "readonly"
    readonly.mkdir()
    readonly.chmod(0o555)
    base = ["eval", "--dataset", str(scratch.dataset), "--submission", str(submission), "--out"]
    steps = [
        Step([*base, str(existing)], (1,), r"a-file"),
        Step([*base, str(existing / "below")], (1,), r"a-file|not a (folder|directory)"),
    ]
    if os.geteuid() != 0:  # root writes into read-only folders
        steps.append(Step([*base, str(readonly / "out")], (1,), r"readonly|writ"))
    return steps


def _dataset_case(name: str, what: str, damage: Callable[[Path], str]) -> Case:
    """A case that damages a copy of the dataset; eval, run-agent and validate dataset must refuse it."""

    def prepare(scratch: Scratch, folder: Path) -> list[Step]:
        copy = scratch.tampered_copy(folder)
        named = re.escape(damage(copy))
        submission = folder / "one.jsonl"
        submission.write_text(scratch.valid_line() + "\n")
        return [
            Step(["validate", "dataset", str(copy)], (1,), named),
            Step(
                ["eval", "--dataset", str(copy), "--submission", str(submission), "--out", str(folder / "o")],
                (1,),
                named,
            ),
            Step(
                [
                    "run-agent",
                    "--dataset",
                    str(copy),
                    "--agent",
                    "random",
                    "--limit",
                    "1",
                    "--jobs",
                    "0",
                    "--out",
                    str(folder / "s.jsonl"),
                ],
                (1,),
                named,
            ),
        ]

    return Case(name, "5", what, prepare, needs_dataset=True)


def _rewrite_gz(path: Path, edit: Callable[[dict], None]) -> None:
    data = json.loads(gzip.decompress(path.read_bytes()))
    edit(data)
    path.write_bytes(gzip.compress(json.dumps(data).encode(), mtime=0))


def _move_goals(copy: Path) -> str:
    def edit(data: dict) -> None:
        for episode in data["episodes"]:
            for goal in episode["goals"]:
                goal["position"][0] += 3.0

    _rewrite_gz(copy / "eval" / "objnav.json.gz", edit)
    return "eval/objnav.json.gz"


def _delete_file(copy: Path) -> str:
    victim = sorted(p for p in (copy / "eval").glob("*.json.gz") if not p.name.endswith("rollouts.json.gz"))[
        -1
    ]
    victim.unlink()
    return f"eval/{victim.name}"


def _manifest_edit(edit: Callable[[dict], None]) -> Callable[[Path], str]:
    def damage(copy: Path) -> str:
        manifest = json.loads((copy / "manifest.json").read_text())
        edit(manifest)
        (copy / "manifest.json").write_text(json.dumps(manifest))
        return "manifest.json"

    return damage


def _escape_entry(manifest: dict) -> None:
    manifest["files"]["../../etc/hostname"] = "0" * 64


def _bump_counts(manifest: dict) -> None:
    counts = manifest["counts"]
    while isinstance(counts, dict):
        key = sorted(counts)[0]
        if isinstance(counts[key], int):
            counts[key] += 1
            return
        counts = counts[key]


def _sleepy_agent(scratch: Scratch, folder: Path) -> list[Step]:
    agent = folder / "sleepy.py"
    agent.write_text(
        "import time\n\n\nclass Sleepy:\n    action_mode = 'discrete'\n    privileged = False\n"
        "    sensors = ()\n\n    def reset(self, task):\n        pass\n\n"
        "    def act(self, observation, info):\n        time.sleep(100_000)\n"
    )
    out = folder / "sleepy.jsonl"
    argv = [
        "run-agent",
        "--dataset",
        str(scratch.dataset),
        "--agent",
        f"{agent}:Sleepy",
        "--limit",
        "2",
        "--jobs",
        "1",
    ]
    return [Step([*argv, "--step-timeout", "2", "--out", str(out)], (0,), r"timeout", timeout=240)]


def _truncated_cache(scratch: Scratch, folder: Path) -> list[Step]:
    workspace = scratch.built_box_room(folder)
    usdc = workspace / "data" / "built" / "targets" / "box-room" / "geometry" / "scene.usdc"
    with open(usdc, "r+b") as handle:
        handle.truncate(100)
    return [
        Step(["status", "--verify"], (0, 1), r"corrupt", cwd=workspace),
        Step(["build", "--jobs", "1"], (0,), r"corrupt", timeout=180, cwd=workspace),
        Step(["status", "--verify"], (0,), r"fresh", cwd=workspace),
        Step(["build", "--force", "box-room", "--jobs", "1"], (0,), r"2 built", timeout=180, cwd=workspace),
    ]


def _interrupt(signum: int, code: tuple[int, ...]) -> Callable[[Scratch, Path], list[Step]]:
    def prepare(scratch: Scratch, folder: Path) -> list[Step]:
        workspace = scratch.box_room(folder)
        return [
            Step(
                ["build", "--jobs", "2"],
                code,
                r"interrupt|resume",
                signal_when=(signum, RUNNING_STAGE_LOG),
                cwd=workspace,
            ),
            Step(["build", "--jobs", "2"], (0,), r"finished", timeout=180, cwd=workspace),
        ]

    return prepare


def _parent_killed(scratch: Scratch, folder: Path) -> list[Step]:
    workspace = scratch.box_room(folder)
    return [
        Step(
            ["build", "--jobs", "2"],
            (-signal.SIGKILL,),
            "",
            signal_when=(signal.SIGKILL, RUNNING_STAGE_LOG),
            cwd=workspace,
        ),
        Step(["build", "--jobs", "2"], (0,), r"finished", timeout=180, cwd=workspace),
    ]


def _concurrent_builds(scratch: Scratch, folder: Path) -> list[Step]:
    workspace = scratch.box_room(folder)
    return [
        Step(["build", "--jobs", "1"], (0,), r"wait", copies=2, timeout=240, cwd=workspace),
        Step(["status", "--verify"], (0,), r"fresh", cwd=workspace),
    ]


def _osm_recipe(name: str) -> str:
    return (
        "extends: outdoor-city\nstages:\n  osm_city:\n"
        f"    source: ../data/raw/{name}\n    center: [48.0, 11.0]\n    size_m: [200, 200]\n"
    )


def _osm_case(
    name: str,
    what: str,
    content: Callable[[], bytes],
    file: str,
    expect: str,
    codes: tuple[int, ...] = (1,),
) -> Case:
    """A case that builds a city from one hostile OSM file: by default exit 1, its message, nothing
    built; ``codes`` and ``expect`` say otherwise for a file that is read after all."""

    def prepare(scratch: Scratch, folder: Path) -> list[Step]:
        workspace = scratch.workspace(folder, {"city.yaml": _osm_recipe(file)})
        data = workspace / "data" / "raw"
        data.mkdir(parents=True, exist_ok=True)
        (data / file).write_bytes(content())
        return [
            Step(["validate", "recipe", "recipes/city.yaml"], (0, 1), "", timeout=120, cwd=workspace),
            Step(["build", "city", "--jobs", "1"], codes, expect, timeout=300, cwd=workspace),
        ]

    return Case(name, "osm", what, prepare)


def _billion_laughs() -> bytes:
    entities = ['<!ENTITY l0 "lol">'] + [f'<!ENTITY l{i} "{f"&l{i - 1};" * 10}">' for i in range(1, 10)]
    return (
        '<?xml version="1.0"?>\n<!DOCTYPE osm [' + "".join(entities) + "]>\n"
        '<osm version="0.6"><node id="1" lat="48" lon="11"><tag k="name" v="&l9;"/></node></osm>\n'
    ).encode()


def _osm_gzip_bomb() -> bytes:
    """512 MiB of an XML comment, gzipped (compressed piece by piece: this process stays small, so the
    commands it starts do not inherit a large peak)."""
    packed = io.BytesIO()
    spaces = b" " * (16 << 20)
    with gzip.GzipFile(fileobj=packed, mode="wb", compresslevel=9, mtime=0) as handle:
        handle.write(b'<?xml version="1.0"?>\n<osm version="0.6">\n<!-- ')
        for _ in range(32):
            handle.write(spaces)
    return packed.getvalue()


def _t_junction() -> bytes:
    return (PROJECT / "tests" / "navverse" / "city" / "data" / "t_junction.osm").read_bytes()


def _truncated_osm() -> bytes:
    data = _t_junction()
    return data[: len(data) // 2]


CASES: list[Case] = [
    _submission_case(
        "far-record-1e7",
        "1",
        "a record that jumps 1e7 m",
        _far_record(1e7),
        expect=r"from the origin|outside",
    ),
    _submission_case(
        "far-record-1e9",
        "1",
        "a record that jumps 1e9 m",
        _far_record(1e9),
        expect=r"from the origin|outside",
    ),
    _recipe_case("alias-bomb", "2", "nine nested YAML anchors (a billion nodes)", _alias_bomb(), r"alias"),
    _submission_case(
        "gzip-bomb-lines",
        "3",
        "1 GiB of valid lines in a small gzip",
        _gzip_bomb_lines,
        codes_eval=(1,),
        expect=r"at most 256 MiB",
    ),
    _submission_case(
        "gzip-bomb-zeros",
        "3",
        "2 GiB of NUL bytes in a small gzip",
        _gzip_bomb_zeros,
        codes_eval=(1,),
        expect=r"at most 256 MiB",
    ),
    Case(
        "truncated-cache", "4", "a committed scene.usdc truncated; build, status, --force", _truncated_cache
    ),
    _dataset_case("moved-goals", "goals of an episode file moved 3 m and re-gzipped", _move_goals),
    _dataset_case("deleted-file", "an episode file deleted", _delete_file),
    _dataset_case(
        "empty-files", "the manifest's files emptied", _manifest_edit(lambda m: m.__setitem__("files", {}))
    ),
    _dataset_case("escaping-entry", "a manifest entry ../../etc/hostname", _manifest_edit(_escape_entry)),
    _dataset_case("wrong-counts", "a manifest count changed", _manifest_edit(_bump_counts)),
    _recipe_case("tag-int", "6", "!!int abc", "seed: !!int abc\nstages: {navmesh: {}}\n"),
    _recipe_case("tag-binary", "6", "!!binary", "description: !!binary aGVsbG8=\nstages: {navmesh: {}}\n"),
    _recipe_case("tag-timestamp", "6", "!!timestamp", "description: 2024-01-01\nstages: {navmesh: {}}\n"),
    _recipe_case("merge-scalar", "6", "<<: 5", "<<: 5\nstages: {navmesh: {}}\n"),
    _recipe_case("utf16", "6", "UTF-16 text", "stages: {navmesh: {}}\n".encode("utf-16")),
    _recipe_case(
        "latin1", "6", "Latin-1 text", "description: caf\xe9\nstages: {navmesh: {}}\n".encode("latin-1")
    ),
    _recipe_case("nul-byte", "6", "a NUL byte", b"description: a\x00b\nstages: {navmesh: {}}\n"),
    _recipe_case("nan", "6", ".nan", "stages: {navmesh: {area_costs: {floor: .nan}}}\n", r"finite"),
    _recipe_case("inf", "6", ".inf", "stages: {navmesh: {area_costs: {floor: .inf}}}\n", r"finite"),
    _recipe_case("1e309", "6", "1e309", "stages: {navmesh: {area_costs: {floor: 1e309}}}\n", r"finite"),
    _recipe_case(
        "huge-int", "6", "a 5000-digit integer", "seed: " + "9" * 5000 + "\nstages: {navmesh: {}}\n"
    ),
    _recipe_case("deep-lists", "6", "5000-deep lists", _deep("list", 5000), r"deep|nest"),
    _recipe_case("deep-maps", "6", "3000-deep mappings", _deep("map", 3000), r"deep|nest"),
    _recipe_case("seed-yes", "6", "seed: yes", "seed: yes\nstages: {navmesh: {}}\n", r"seed"),
    _recipe_case(
        "huge-box",
        "6",
        "box: [1e308, 1, 1]",
        "stages:\n  blockout:\n    scene_type: indoor\n    surfaces:\n"
        "      - {name: f, terrain: floor, center: [0, 0, 0], box: [1e308, 1, 1]}\n",
        r"box",
    ),
    _recipe_case(
        "extends-outside",
        "6",
        "extends to an absolute path",
        "extends: /etc/hostname.yaml\nstages: {navmesh: {}}\n",
        r"extends",
    ),
    _recipe_case(
        "extends-cycle",
        "6",
        "an extends cycle",
        "extends: hostile.yaml\nstages: {navmesh: {}}\n",
        r"yaml:\d+:.*cycle",
    ),
    _special_file_case("directory-recipe", "a directory named x.yaml", lambda p: p.mkdir()),
    _special_file_case("symlink-loop", "a symlink loop named x.yaml", lambda p: p.symlink_to(p.name)),
    _special_file_case("symlink-dev-zero", "a symlink to /dev/zero", lambda p: p.symlink_to("/dev/zero")),
    _special_file_case("fifo-recipe", "a FIFO named x.yaml", lambda p: os.mkfifo(p)),
    Case("sleepy-agent", "7", "an agent whose act never returns", _sleepy_agent, needs_dataset=True),
    Case(
        "mesh-outside", "8", "import_mesh from an absolute and a ../ path outside the project", _outside_mesh
    ),
    Case("usda-fifo-sublayer", "8", "a .usda whose sublayer is a FIFO", _usda_fifo_sublayer),
    _submission_case(
        "deep-json", "9", "a 100k-deep JSON trajectory", _deep_json, codes_eval=(0, 1), expect=r"deep|nest"
    ),
    Case(
        "eval-out",
        "9",
        "eval --out an existing file, below a file, a read-only folder",
        _eval_out_cases,
        needs_dataset=True,
    ),
    Case("ctrl-c-build", "9", "Ctrl-C of a build", _interrupt(signal.SIGINT, (130,))),
    Case("sigterm-build", "9", "SIGTERM of a build", _interrupt(signal.SIGTERM, (143,))),
    Case("parent-killed", "10", "the build's parent SIGKILLed: nothing left running", _parent_killed),
    Case("concurrent-builds", "10", "two builds at once in one workspace", _concurrent_builds),
    Case("nan-vertex", "10", "an .obj with a NaN vertex", _nan_obj),
    _osm_case(
        "osm-billion-laughs",
        "an OSM file declaring nested entities",
        _billion_laughs,
        "laughs.osm",
        r"DOCTYPE",
    ),
    _osm_case(
        "osm-gzip-bomb",
        "512 MiB of XML in a small .osm.gz",
        _osm_gzip_bomb,
        "bomb.osm.gz",
        r"bomb|ratio|large",
    ),
    _osm_case("osm-truncated", "an .osm file cut in half", _truncated_osm, "cut.osm", r"truncated"),
    _osm_case(
        "osm-pbf-holding-xml",
        "OSM XML named .osm.pbf: read by its content, the city built",
        _t_junction,
        "x.osm.pbf",
        r"finished.*5 built",
        codes=(0,),
    ),
]
"""Every case, in the order of the breaks they reproduce."""


# ------------------------------------------------------------------------------------------ main


def _default_dataset() -> Path | None:
    versions = sorted((PROJECT / "episodes" / "navverse-mini").glob("v*/manifest.json"))
    return versions[-1].parent if versions else None


def _dataset_store(dataset: Path) -> list[Path]:
    """The build store of the workspace a dataset version is in (``<workspace>/episodes/<name>/v<x>``),
    if there is one: where its scenes were built."""
    store = dataset.resolve().parents[2] / "data" / "built"
    return [store] if (store / "targets").is_dir() else []


def main(argv: Sequence[str] | None = None) -> int:
    """Run the chosen cases and print one row per step; the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--dataset", type=Path, default=None, help="dataset version (default: newest navverse-mini)"
    )
    parser.add_argument(
        "--scenes",
        type=Path,
        action="append",
        default=None,
        metavar="DIR",
        help="where the dataset's scenes are, a scene pack or a build store (repeatable; default: "
        "$NAVVERSE_SCENES, else the build store of the dataset's workspace)",
    )
    parser.add_argument("--cap-mb", type=float, default=1024.0, help="peak RSS allowed per command (MB)")
    parser.add_argument("--only", nargs="+", default=None, metavar="CASE", help="run only these cases")
    parser.add_argument("--list", action="store_true", help="list the cases and exit")
    args = parser.parse_args(argv)
    console = Console()
    if args.list:
        for case in CASES:
            console.print(f"{case.name:22} break {case.breaks:3} {case.what}", highlight=False)
        return 0
    known = {case.name for case in CASES}
    unknown = sorted(set(args.only or ()) - known)
    if unknown:
        console.print(f"unknown cases: {', '.join(unknown)} (see --list)")
        return 1
    dataset = args.dataset or _default_dataset()
    if dataset is not None and not (dataset / "manifest.json").is_file():
        console.print(f"{dataset} is not a dataset version (no manifest.json)")
        return 1
    scenes = args.scenes or ([] if os.environ.get(SCENES_ENV) or dataset is None else _dataset_store(dataset))
    if scenes:  # the commands run inherit it
        os.environ[SCENES_ENV] = os.pathsep.join(str(folder.resolve()) for folder in scenes)
    chosen = [case for case in CASES if args.only is None or case.name in args.only]
    table = Table(title=f"hostile inputs (cap {args.cap_mb:.0f} MB per command)")
    for column in ("case", "break", "command", "exit", "peak tree MB", "peak own MB", "s", "verdict"):
        table.add_column(
            column, justify="right" if column in ("exit", "peak tree MB", "peak own MB", "s") else "left"
        )
    failed = 0
    with tempfile.TemporaryDirectory(prefix="navverse-adversarial-") as tmp:
        scratch = Scratch(Path(tmp), dataset.resolve() if dataset else None)
        for case in chosen:
            if case.needs_dataset and scratch.dataset is None:
                table.add_row(
                    case.name, case.breaks, "", "", "", "", "", "not run: no dataset (make episodes)"
                )
                continue
            folder = Path(tmp) / case.name
            folder.mkdir()
            console.print(f"[dim]{case.name}: {case.what}[/dim]")
            for step in case.prepare(scratch, folder):
                outcome = run_step(step, cwd=PROJECT, cap_bytes=int(args.cap_mb * 2**20))
                faults = judge(step, outcome, cap_mb=args.cap_mb)
                failed += bool(faults)
                verdict = "[green]ok[/green]" if not faults else "[red]FAIL[/red]"
                if faults:
                    console.print(
                        f"FAIL {case.name}: navverse {' '.join(step.argv)}\n  " + "\n  ".join(faults),
                        style="red",
                        highlight=False,
                        markup=False,
                    )
                    console.print(outcome.output[-1500:], style="dim", highlight=False, markup=False)
                table.add_row(
                    case.name,
                    case.breaks,
                    " ".join(step.argv[:2]) + (f" ×{step.copies}" if step.copies > 1 else ""),
                    ",".join(map(str, outcome.codes)),
                    f"{outcome.peak_tree_mb:.0f}",
                    f"{outcome.peak_own_mb:.0f}",
                    f"{outcome.seconds:.1f}",
                    verdict,
                )
            for path in folder.rglob("*"):  # read-only folders made by a case
                if path.is_dir() and not path.is_symlink():
                    path.chmod(0o755)
    console.print(table)
    console.print(f"{failed} failed step(s)" if failed else "every case passed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
