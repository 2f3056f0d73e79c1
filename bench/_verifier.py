"""Verifier before vs after: a workspace's candidates verified by two checkouts, in this run.

Used by ``bench/throughput.py`` (its ``verifier`` part); also runnable alone::

    python bench/_verifier.py --workspace DIR [--before CHECKOUT] [--candidates N]

For every ``verify_episodes`` artifact of the workspace (one per dataset: navverse-mini-indoor,
navverse-outdoor, navverse-i2o), the same candidates are verified scene by scene, each scene in a
fresh child process (world load included, as a build does), with the stage's recorded parameters:

* **after**: this checkout's verifier with its default settings;
* **before**: the verifier of ``--before`` (a checkout of the older code with its own ``.venv``) when
  given, else this checkout with every object loaded (``object_margin_m: null``): that measures the
  culling of far objects alone.

Each child reports its own CPU seconds. The verdicts (accepted, or the rejection reason) of both
runs are compared candidate by candidate; every disagreement is listed with both rollouts' duration
and distance. Timings are measurements on this machine, never assertions.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]

SCENE_TYPES = {"navverse-mini-indoor": "indoor", "navverse-outdoor": "outdoor", "navverse-i2o": "i2o"}
"""The navverse-mini part datasets and the scene type of their scenes."""
OLD_PATH = {"object_margin_m": None}
"""Settings that make this checkout's verifier load what the old one did."""


def _child(job_path: Path) -> None:
    """Verify one scene's candidates (the job file says which) and print the verdicts as JSON."""
    import time

    here = Path(__file__).resolve().parent  # bench/ is not a package root: keep its modules out of the way
    sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != here]
    job = json.loads(job_path.read_text())
    from navverse.dataset import Episode, read_json_gz
    from navverse.episodes.verification import VerificationSettings, verify_scene

    start = time.process_time()
    candidates = read_json_gz(job["candidates"])
    wanted = set(job["episodes"])
    episodes = [Episode.model_validate(e) for e in candidates["episodes"] if e["episode_id"] in wanted]
    settings = VerificationSettings.model_validate(job["settings"])
    results = verify_scene(job["scene_dir"], episodes, embodiment=candidates["embodiment"], settings=settings)
    verdicts = {
        r.episode_id: [r.reason or "accepted", r.verification.duration_s, r.verification.traveled_m]
        for r in results
    }
    print(json.dumps({"cpu_s": time.process_time() - start, "verdicts": verdicts}))


def _artifact_dir(artifacts: Path, key: str) -> Path:
    found = sorted(artifacts.glob(f"*/*-{key}"))
    if not found:
        raise SystemExit(f"artifact {key} is not in {artifacts}: build the workspace first")
    return found[0]


def _jobs(workspace: Path, per_type: int | None) -> list[dict[str, Any]]:
    """One job per (dataset, scene): the scene directory, its candidates and the stage's parameters."""
    artifacts = workspace / "data" / "built" / "artifacts"
    jobs = []
    for manifest_path in sorted((artifacts / "verify_episodes").glob("*/manifest.json")):
        manifest = json.loads(manifest_path.read_text())
        scene_type = SCENE_TYPES.get(manifest["target"])
        if scene_type is None:
            continue
        from navverse.dataset import read_json_gz

        candidates_file = _artifact_dir(artifacts, manifest["inputs"]["candidates"][0]) / "candidates.json.gz"
        scene_dirs = {}
        for key in manifest["inputs"]["scene"]:
            directory = _artifact_dir(artifacts, key)
            scene_dirs[json.loads((directory / "scene.json").read_text())["scene_id"]] = directory
        by_scene: dict[str, list[str]] = defaultdict(list)
        for episode in read_json_gz(candidates_file)["episodes"][:per_type]:
            by_scene[episode["scene_id"]].append(episode["episode_id"])
        params = {k: v for k, v in manifest["params"].items() if k != "keyframes"} | {"keyframes": 0}
        for scene_id, episode_ids in sorted(by_scene.items()):
            jobs.append(
                {
                    "dataset": manifest["target"],
                    "scene_type": scene_type,
                    "scene_id": scene_id,
                    "scene_dir": str(scene_dirs[scene_id]),
                    "candidates": str(candidates_file),
                    "episodes": episode_ids,
                    "params": params,
                }
            )
    if not jobs:
        raise SystemExit(f"no verify_episodes artifact of {', '.join(SCENE_TYPES)} in {workspace}")
    return jobs


def _run(job: dict[str, Any], *, python: str, checkout: Path, settings: dict[str, Any]) -> dict[str, Any]:
    """Run one job in a child process of ``checkout``'s code; its CPU seconds and verdicts."""
    with tempfile.TemporaryDirectory(prefix="navverse-bench-verifier-") as tmp:
        job_file = Path(tmp) / "job.json"
        job_file.write_text(json.dumps({**job, "settings": settings}))
        env = {**os.environ, "PYTHONPATH": str(checkout)}
        done = subprocess.run(
            [python, str(Path(__file__).resolve()), "--child", str(job_file)],
            cwd=checkout, env=env, capture_output=True, text=True, check=False,
        )  # fmt: skip
    if done.returncode != 0:
        raise SystemExit(f"verifying {job['scene_id']} failed in {checkout}:\n{done.stderr[-3000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def compare(
    workspace: Path, *, per_type: int | None = None, before: Path | None = None, console: Any = None
) -> dict[str, Any]:
    """Verify the workspace's candidates with the old and the new verifier; CPU and verdicts.

    Parameters
    ----------
    workspace : Path
        A checkout whose ``data/built`` holds navverse-mini's verify_episodes artifacts.
    per_type : int, optional
        Candidates per dataset (the first ones, scene by scene); None: all.
    before : Path, optional
        A checkout of the older verifier, with its ``.venv``; None: this checkout's old settings.
    console : rich.console.Console, optional
        Where the table and the disagreements are printed.

    Returns
    -------
    dict
        ``cpu_per_candidate_old`` / ``cpu_per_candidate_new`` and ``ratio`` by scene type,
        ``candidates`` by scene type, ``agreement`` (fraction) and ``disagreements`` (list).
    """
    from rich.console import Console
    from rich.progress import Progress
    from rich.table import Table

    console = console or Console()
    jobs = _jobs(workspace, per_type)
    new_python = sys.executable
    if before is not None:
        old_python, old_checkout, old_settings = str(before / ".venv" / "bin" / "python"), before, {}
    else:
        old_python, old_checkout, old_settings = new_python, ROOT, dict(OLD_PATH)
    cpu: dict[str, dict[str, float]] = {"old": defaultdict(float), "new": defaultdict(float)}
    candidates: dict[str, int] = defaultdict(int)
    scenes: dict[str, int] = defaultdict(int)
    disagreements = []
    compared = 0
    with Progress(console=console, transient=True) as progress:
        task = progress.add_task("verifier: scenes (old, new)", total=len(jobs))
        for job in jobs:
            old = _run(
                job, python=old_python, checkout=old_checkout, settings={**job["params"], **old_settings}
            )
            new = _run(job, python=new_python, checkout=ROOT, settings=job["params"])
            kind = job["scene_type"]
            cpu["old"][kind] += old["cpu_s"]
            cpu["new"][kind] += new["cpu_s"]
            candidates[kind] += len(job["episodes"])
            scenes[kind] += 1
            for episode_id in job["episodes"]:
                a, b = old["verdicts"][episode_id], new["verdicts"][episode_id]
                compared += 1
                if a[0] != b[0]:
                    disagreements.append(
                        {"episode_id": episode_id, "old": a[0], "new": b[0],
                         "old_duration_s": a[1], "new_duration_s": b[1],
                         "old_traveled_m": a[2], "new_traveled_m": b[2]}
                    )  # fmt: skip
            progress.advance(task)
    per_old = {k: cpu["old"][k] / candidates[k] for k in candidates}
    per_new = {k: cpu["new"][k] / candidates[k] for k in candidates}
    ratio = {k: per_old[k] / per_new[k] if per_new[k] > 0 else float("inf") for k in candidates}
    agreement = 1.0 - len(disagreements) / compared if compared else 1.0
    table = Table(
        title=f"verifier: {'--before ' + str(before) if before else 'old settings'} vs this checkout"
    )
    for column in ("scene type", "scenes", "candidates", "CPU s/candidate old", "new", "ratio"):
        table.add_column(column, justify="left" if column == "scene type" else "right")
    for kind in sorted(candidates):
        table.add_row(kind, str(scenes[kind]), str(candidates[kind]), f"{per_old[kind]:.2f}",
                      f"{per_new[kind]:.2f}", f"{ratio[kind]:.1f}x")  # fmt: skip
    console.print(table)
    console.print(
        f"verdict agreement: {compared - len(disagreements)} of {compared} ({100 * agreement:.2f} %)"
    )
    for d in disagreements:
        console.print(
            f"  {d['episode_id']}: {d['old']} -> {d['new']} (duration {d['old_duration_s']} -> "
            f"{d['new_duration_s']} s, traveled {d['old_traveled_m']} -> {d['new_traveled_m']} m)"
        )
    return {
        "cpu_per_candidate_old": per_old,
        "cpu_per_candidate_new": per_new,
        "ratio": ratio,
        "candidates": dict(candidates),
        "scenes": dict(scenes),
        "agreement": agreement,
        "disagreements": disagreements,
    }


def main(argv: list[str] | None = None) -> int:
    """Command line: ``--workspace DIR [--before CHECKOUT] [--candidates N]``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workspace", type=Path, default=ROOT, help="checkout with the built navverse-mini")
    parser.add_argument("--before", type=Path, help="checkout of the older verifier (with its .venv)")
    parser.add_argument("--candidates", type=int, default=0, help="candidates per dataset (0: all)")
    parser.add_argument("--json", type=Path, help="write the results here")
    parser.add_argument("--child", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child is not None:
        _child(args.child)
        return 0
    sys.path.insert(0, str(ROOT))
    results = compare(args.workspace.resolve(), per_type=args.candidates or None, before=args.before)
    if args.json is not None:
        args.json.write_text(json.dumps(results, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
