"""Throughput of a build and an evaluation: old and new paths on the same inputs, as ratios.

Run in a workspace where ``make`` has built the scenes and navverse-mini (default: this checkout)::

    python bench/throughput.py                    # every part
    python bench/throughput.py --parts navmesh    # one part (navmesh, verifier, eval, projection)

Parts, each on the workspace's own built scenes and dataset:

1. **navmesh** -- per pair of a city and an indoor-to-outdoor scene built on it: the city's navmesh
   with the outdoor preset as the paper's table has it (``detail_sample_max_error`` 0, the old path)
   and as shipped (1 cell height), from scratch, one thread each (CPU seconds); the difference of the
   two in navigable area and in geodesic distance over seeded pairs of navigable points; then the i2o
   scene from scratch and incrementally (its city's tiles in a fresh tile store first), which must
   give the same bytes.
2. **verifier** -- :mod:`bench._verifier`: navverse-mini's candidates verified scene by scene in
   child processes by the older verifier (``--before CHECKOUT``, or this checkout with the settings
   of the old path) and by this one, CPU seconds per candidate by scene type (world load included),
   and the verdict agreement with every disagreement.
3. **eval** -- ``navverse eval`` of a one-line submission (peak memory of the process tree; the
   first time, with the caches of the scene's fields and geometry to fill, and again; with
   ``--before``, also that checkout's ``navverse``), of
   every eval-split episode's verified rollout as a submission, and of 10 000 trajectories: the
   split's episodes repeated under new ids (the same scenes, goals and rollouts) as a release of their
   own, with its manifest, and its rollouts as the submission. Time and peak memory of each; the time
   per trajectory between the split and the 10 000 (both over ``--pictures``, so both draw as many
   episode cards: the cards are a fixed cost).
4. **projection** -- navverse-full in CPU-hours: the scene stages' CPU per scene (the workspace's
   manifests, navmeshes as measured in part 1), verification per candidate (part 2, or the
   manifests), sampling and instructions per candidate (manifests), times the scenes and candidates
   of the ``navverse-full`` recipes' header.

Timings are measurements of this run on this machine (the load average is printed), never assertions.
"""

from __future__ import annotations

import argparse
import gzip
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import psutil
from rich.console import Console
from rich.table import Table

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from navverse.nav import NavMeshSettings, PathFinder  # noqa: E402
from navverse.nav.scene_navmesh import build_scene_navmesh, scene_settings  # noqa: E402
from navverse.nav.tiles import TileStore  # noqa: E402
from navverse.scene.directory import read_scene  # noqa: E402
from navverse.scene_types import scene_profile  # noqa: E402

PAIRS = ("synthetic-grid-s0:cafe-synthetic-grid", "west-oakland:apartment-west-oakland")
PAPER_DETAIL_ERROR = {"detail_sample_max_error": 0.0}
PARTS = ("navmesh", "verifier", "eval", "projection")
# navverse-full (recipes/datasets/navverse-full.yaml's header): scenes and candidates per scene type.
FULL_SCENES = {"indoor": 100, "outdoor": 50, "i2o": 50}
FULL_CANDIDATES = {"indoor": 6200, "outdoor": 8600, "i2o": 6800}
SCENE_STAGES = {
    "indoor_layout", "import_mesh", "decimate", "blockout", "synthetic_city", "osm_city", "city_geometry",
    "populate", "storefronts", "assemble_i2o", "generate_i2o", "navmesh",
}  # fmt: skip
PER_CANDIDATE_STAGES = {"sample_episodes", "instructions"}
# The parts of navverse-mini, by the scene type they hold (their candidates measure per-candidate costs).
MINI_PARTS = {"navverse-mini-indoor": "indoor", "navverse-outdoor": "outdoor", "navverse-i2o": "i2o"}


# -- navmesh ---------------------------------------------------------------------------------------


def _timed_build(
    scene_dir: Path, overrides: dict, store: TileStore | None
) -> tuple[PathFinder, float, float]:
    """Build one scene's navmesh on one thread: (finder, CPU s, wall s); the scene is read untimed."""
    scene = read_scene(scene_dir)
    annotations = scene.annotations
    preset = scene_profile(annotations.scene_type).navmesh_preset
    settings = scene_settings(NavMeshSettings.preset(preset).with_overrides(overrides), annotations)
    cpu, wall = time.process_time(), time.perf_counter()
    finder = build_scene_navmesh(scene, settings, jobs=1, tile_store=store)
    return finder, time.process_time() - cpu, time.perf_counter() - wall


def _distance_changes(old: PathFinder, new: PathFinder, *, pairs: int, seed: int) -> np.ndarray:
    """Relative change of the geodesic distance between seeded pairs of old-navmesh points (> 2 m apart)."""
    rng = np.random.default_rng(seed)
    changes = []
    while len(changes) < pairs:
        a, b = old.get_random_navigable_point(rng), old.get_random_navigable_point(rng)
        d_old, d_new = old.geodesic_distance(a, b), new.geodesic_distance(a, b)
        if np.isfinite(d_old) and np.isfinite(d_new) and d_old > 2.0:
            changes.append(abs(d_new - d_old) / d_old)
    return np.array(changes)


def navmesh_part(built: Path, pairs: Sequence[str], *, distance_pairs: int, console: Console) -> list[dict]:
    """Per city/i2o pair: the city's build before and after, the i2o scene full and incremental."""
    rows = []
    for pair in pairs:
        city, i2o = pair.split(":")
        city_dir, i2o_dir = (built / "targets" / name / "geometry" for name in (city, i2o))
        if not city_dir.is_dir() or not i2o_dir.is_dir():
            console.print(f"[yellow]navmesh: {pair} skipped: {built}/targets has no geometry of both[/]")
            continue
        old, old_cpu, _ = _timed_build(city_dir, PAPER_DETAIL_ERROR, None)
        new, new_cpu, _ = _timed_build(city_dir, {}, None)
        changes = _distance_changes(old, new, pairs=distance_pairs, seed=0)
        with tempfile.TemporaryDirectory() as folder:
            store = TileStore(folder)
            _timed_build(city_dir, {}, store)
            full, full_cpu, _ = _timed_build(i2o_dir, {}, None)
            incremental, inc_cpu, _ = _timed_build(i2o_dir, {}, store)
            use = store.last_use
        rows.append({
            "city": city, "i2o": i2o,
            "city_old_cpu_s": old_cpu, "city_new_cpu_s": new_cpu,
            "area_change_pct": 100 * (new.navigable_area / old.navigable_area - 1),
            "distance_change_pct": {q: 100 * float(np.quantile(changes, p))
                                    for q, p in (("median", 0.5), ("p99", 0.99), ("max", 1.0))},
            "i2o_full_cpu_s": full_cpu, "i2o_incremental_cpu_s": inc_cpu,
            "tiles": use.tiles, "tiles_reused": use.reused, "tiles_built": use.built,
            "identical": full.to_bytes() == incremental.to_bytes(),
        })  # fmt: skip
    return rows


def navmesh_table(rows: list[dict]) -> Table:
    table = Table(title="navmesh: old and new paths (CPU s, one thread)")
    for column in ("city", "old", "new", "ratio", "area", "distance median/p99/max", "i2o", "full",
                   "incremental", "ratio", "tiles reused", "same bytes"):  # fmt: skip
        table.add_column(column, justify="right")
    for r in rows:
        d = r["distance_change_pct"]
        table.add_row(
            r["city"], f"{r['city_old_cpu_s']:.1f}", f"{r['city_new_cpu_s']:.1f}",
            f"{r['city_old_cpu_s'] / r['city_new_cpu_s']:.1f}x", f"{r['area_change_pct']:+.2f} %",
            f"{d['median']:.3f}/{d['p99']:.2f}/{d['max']:.2f} %", r["i2o"], f"{r['i2o_full_cpu_s']:.2f}",
            f"{r['i2o_incremental_cpu_s']:.2f}", f"{r['i2o_full_cpu_s'] / r['i2o_incremental_cpu_s']:.1f}x",
            f"{r['tiles_reused']}/{r['tiles']}", "yes" if r["identical"] else "NO",
        )  # fmt: skip
    return table


# -- eval ------------------------------------------------------------------------------------------


def _peak_tree_mb(argv: list[str], *, cwd: Path, env: dict[str, str]) -> tuple[int, float, float]:
    """Run ``argv``: (exit code, wall s, peak RSS of its process tree in MB, sampled every 20 ms)."""
    started = time.perf_counter()
    process = subprocess.Popen(argv, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    root, peak = psutil.Process(process.pid), 0
    while process.poll() is None:
        try:
            tree = [root, *root.children(recursive=True)]
            peak = max(peak, sum(p.memory_info().rss for p in tree if p.is_running()))
        except psutil.Error:
            pass
        time.sleep(0.02)
    return process.returncode, time.perf_counter() - started, peak / 2**20


def _rollout_submission(release: Path, split: str, path: Path, *, limit: int | None = None) -> int:
    """Write the split's verified rollouts as a submission (stopping at the end); returns the lines."""
    lines = 0
    with path.open("w", encoding="utf-8") as out:
        for rollouts in sorted((release / split).glob("*.rollouts.json.gz")):
            for episode_id, trajectory in json.loads(gzip.decompress(rollouts.read_bytes())).items():
                out.write(
                    json.dumps({"episode_id": episode_id, "trajectory": trajectory, "stop": True}) + "\n"
                )
                lines += 1
                if limit is not None and lines >= limit:
                    return lines
    return lines


def _scaled_release(release: Path, split: str, count: int, folder: Path) -> Path:
    """A release of `count` episodes: the split's, repeated in turn under new ids (``<scene>-<task>-NNNN``
    numbered on), with the same scenes, goals, reference paths and rollouts; one split, its manifest's
    counts and checksums its own. Returns its version directory."""
    from navverse.dataset import file_sha256, read_json_gz, write_json_gz

    manifest = json.loads((release / "manifest.json").read_text(encoding="utf-8"))
    name = f"{manifest['name']}-x{count}"
    root = folder / name / f"v{manifest['version']}"
    (root / split).mkdir(parents=True)
    tasks = sorted(p.name.removesuffix(".json.gz") for p in (release / split).glob("*.json.gz")
                   if not p.name.endswith(".rollouts.json.gz"))  # fmt: skip
    files = {t: read_json_gz(release / split / f"{t}.json.gz") for t in tasks}
    rollouts = {t: read_json_gz(release / split / f"{t}.rollouts.json.gz") for t in tasks}
    episodes: dict[str, list[dict]] = {t: [] for t in tasks}
    trajectories: dict[str, dict[str, list]] = {t: {} for t in tasks}
    numbers: dict[tuple[str, str], int] = defaultdict(int)
    made = 0
    while made < count and any(files[t]["episodes"] for t in tasks):
        for task in tasks:
            for episode in files[task]["episodes"][: count - made]:
                key = (episode["scene_id"], task)
                episode_id = f"{key[0]}-{task}-{numbers[key]:04d}"
                numbers[key] += 1
                episodes[task].append({**episode, "episode_id": episode_id})
                trajectories[task][episode_id] = rollouts[task][episode["episode_id"]]
                made += 1
    counts: dict[str, dict[str, int]] = {}
    for task in tasks:
        write_json_gz({**files[task], "episodes": episodes[task]}, root / split / f"{task}.json.gz")
        write_json_gz(trajectories[task], root / split / f"{task}.rollouts.json.gz")
        for episode in episodes[task]:
            counts.setdefault(task, {}).setdefault(episode["scene_type"], 0)
            counts[task][episode["scene_type"]] += 1
    manifest.pop("quota", None)  # the quotas of the release it repeats
    names = [f"{split}/{task}{kind}" for task in tasks for kind in (".json.gz", ".rollouts.json.gz")]
    manifest.update(
        name=name,
        splits={split: manifest["splits"][split]},
        counts={split: counts},
        files={n: file_sha256(root / n) for n in names},
    )
    text = json.dumps(manifest, indent=2, sort_keys=True) + "\n"
    (root / "manifest.json").write_text(text, encoding="utf-8")
    return root


SCALED = 10_000
"""Trajectories of the eval part's largest submission."""


def eval_part(workspace: Path, dataset: str, split: str, console: Console, *, before: Path | None) -> dict:
    """``navverse eval``: peak memory of a one-line submission, the first time on this machine (cold
    caches: a fresh ``$NAVVERSE_CACHE_DIR``) and again (warm), and with the ``before`` checkout's
    ``navverse`` (warm); time and peak memory of the split's rollouts (cold, then warm) and of
    :data:`SCALED` trajectories (a release of the split's episodes repeated, warm), and the time per
    trajectory between the two warm runs."""
    releases = sorted((workspace / "episodes" / dataset).glob("v*/manifest.json"))
    if not releases:
        console.print(f"[yellow]eval: skipped: {workspace}/episodes/{dataset} has no release[/]")
        return {}
    release = releases[-1].parent
    navverse = str(Path(sys.executable).with_name("navverse"))
    old = str(before / ".venv" / "bin" / "navverse") if before is not None else None
    result: dict[str, Any] = {"release": str(release)}
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        scaled = _scaled_release(release, split, SCALED, folder / "scaled")
        now = (navverse, folder / "cache")  # a fresh cache: the first run fills it
        runs = [
            ("one_line_cold", *now, release, 1), ("one_line", *now, release, 1),
            ("split_cold", *now, release, None),  # fills the caches of the split's other scenes
            ("split", *now, release, None), ("scaled", *now, scaled, None),
        ]  # fmt: skip
        if old is not None:  # with caches of its own
            was = (old, folder / "cache-before")
            runs += [("one_line_before_cold", *was, release, 1), ("one_line_before", *was, release, 1)]
        for name, command, cache, version, limit in runs:
            submission = folder / f"{name}.jsonl"
            lines = _rollout_submission(version, split, submission, limit=limit)
            out = folder / f"out-{name}"
            argv = [command, "eval", "--dataset", str(version), "--submission", str(submission),
                    "--split", split, "--out", str(out), "--episodes", "submitted"]  # fmt: skip
            env = {**os.environ, "NAVVERSE_ROOT": str(workspace), "NAVVERSE_CACHE_DIR": str(cache)}
            code, wall, peak = _peak_tree_mb(argv, cwd=workspace, env=env)
            result[name] = {"lines": lines, "exit": code, "wall_s": wall, "peak_mb": peak}
    split_run, big = result["split"], result["scaled"]
    per_trajectory = max(0.0, big["wall_s"] - split_run["wall_s"]) / max(1, big["lines"] - split_run["lines"])
    result["s_per_trajectory"] = per_trajectory
    result["fixed_s"] = split_run["wall_s"] - split_run["lines"] * per_trajectory
    result["projected_10000_s"] = result["fixed_s"] + 10_000 * per_trajectory
    return result


# -- projection ------------------------------------------------------------------------------------


def _manifests(built: Path) -> list[dict]:
    return [json.loads(p.read_text()) for p in sorted((built / "artifacts").glob("*/*/manifest.json"))]


def projection_part(built: Path, navmesh_rows: list[dict], verifier: dict | None) -> dict:
    """navverse-full's CPU-hours from this workspace's measured per-scene and per-candidate costs."""
    manifests = _manifests(built)
    types: dict[str, str] = {}
    for m in manifests:  # a scene's type, from its navmesh stage's scene.json
        if m["stage"] == "navmesh":
            scene_json = built / "targets" / m["target"] / "scene" / "scene.json"
            if scene_json.is_file():
                types[m["target"]] = json.loads(scene_json.read_text())["scene_type"]
    per_scene: dict[str, dict[str, float]] = defaultdict(lambda: defaultdict(float))
    for m in manifests:
        kind = types.get(m["target"])
        if kind and m["stage"] in SCENE_STAGES:
            per_scene[kind][m["target"]] += m.get("run", {}).get("cpu_s", 0.0)
    scene_cpu = {kind: float(np.mean(list(cpu.values()))) for kind, cpu in per_scene.items()}
    # Navmeshes as measured now (one thread, from scratch; i2o incremental on its city's tiles).
    if navmesh_rows:
        navmesh_now = {
            m["target"]: m.get("run", {}).get("cpu_s", 0.0) for m in manifests if m["stage"] == "navmesh"
        }
        for kind, key in (("outdoor", "city"), ("i2o", "i2o")):
            measured = [r for r in navmesh_rows if r[key] in navmesh_now]
            if measured and kind in scene_cpu:
                new = "city_new_cpu_s" if kind == "outdoor" else "i2o_incremental_cpu_s"
                delta = np.mean([r[new] - navmesh_now[r[key]] for r in measured])
                scene_cpu[kind] = max(0.0, scene_cpu[kind] + float(min(0.0, delta)))
    candidates: dict[str, int] = defaultdict(int)
    verify_cpu: dict[str, float] = defaultdict(float)
    other_cpu: dict[str, float] = defaultdict(float)
    for m in manifests:
        kind = MINI_PARTS.get(m["target"])
        if kind is None:
            continue
        cpu = m.get("run", {}).get("cpu_s", 0.0)
        if m["stage"] == "verify_episodes":
            candidates[kind] += int(m.get("stats", {}).get("candidates", 0))
            verify_cpu[kind] += cpu
        elif m["stage"] in PER_CANDIDATE_STAGES:
            other_cpu[kind] += cpu
    measured = (verifier or {}).get("cpu_per_candidate_new", {})
    verify_per_candidate = {
        k: measured.get(k, verify_cpu[k] / candidates[k] if candidates[k] else 0.0) for k in FULL_CANDIDATES
    }
    other_per_candidate = {k: other_cpu[k] / candidates[k] if candidates[k] else 0.0 for k in FULL_CANDIDATES}
    hours = {
        "scenes": sum(FULL_SCENES[k] * scene_cpu.get(k, 0.0) for k in FULL_SCENES) / 3600,
        "verification": sum(FULL_CANDIDATES[k] * verify_per_candidate.get(k, 0.0) for k in FULL_CANDIDATES)
        / 3600,
        "sampling_and_instructions": sum(FULL_CANDIDATES[k] * other_per_candidate[k] for k in FULL_CANDIDATES)
        / 3600,
    }
    hours["total"] = sum(hours.values())
    return {"scene_cpu_s": scene_cpu, "verify_cpu_per_candidate_s": verify_per_candidate,
            "other_cpu_per_candidate_s": other_per_candidate, "cpu_hours": hours}  # fmt: skip


# -- main ------------------------------------------------------------------------------------------


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--workspace", type=Path, default=ROOT, help="a workspace after `make` (this checkout)"
    )
    parser.add_argument("--parts", nargs="+", choices=PARTS, default=list(PARTS), help="parts to run (all)")
    parser.add_argument("--pairs", nargs="+", default=list(PAIRS), metavar="CITY:I2O",
                        help=f"city and i2o scenes of the navmesh part ({' '.join(PAIRS)})")  # fmt: skip
    parser.add_argument("--distance-pairs", type=int, default=300, help="geodesic pairs compared (300)")
    parser.add_argument("--dataset", default="navverse-mini", help="dataset of the eval part (navverse-mini)")
    parser.add_argument("--split", default="eval", help="split of the eval part (eval)")
    parser.add_argument("--candidates", type=int, default=0,
                        help="verifier part: candidates per scene type (0: all)")  # fmt: skip
    parser.add_argument("--before", type=Path, default=None, metavar="CHECKOUT",
                        help="verifier part: a checkout of the older verifier, with its .venv "
                             "(default: this checkout's old-path settings)")  # fmt: skip
    parser.add_argument("--json", type=Path, default=None, metavar="PATH", help="also write the results here")
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    args = parse_args(argv)
    console = Console(width=None if sys.stdout.isatty() else 200)
    workspace = args.workspace.resolve()
    built = workspace / "data" / "built"
    console.print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs; workspace {workspace}")
    results: dict[str, Any] = {}
    if "navmesh" in args.parts:
        results["navmesh"] = navmesh_part(
            built, args.pairs, distance_pairs=args.distance_pairs, console=console
        )
        console.print(navmesh_table(results["navmesh"]))
    if "verifier" in args.parts:
        from bench import _verifier

        results["verifier"] = _verifier.compare(
            workspace, per_type=args.candidates or None, before=args.before, console=console
        )
    if "eval" in args.parts:
        results["eval"] = ev = eval_part(workspace, args.dataset, args.split, console, before=args.before)
        if ev:
            one, cold, split, big = ev["one_line"], ev["one_line_cold"], ev["split"], ev["scaled"]
            first = ev["split_cold"]
            if "one_line_before" in ev:
                was = ev["one_line_before"]
                console.print(
                    f"eval: one line before {was['peak_mb']:.0f} MB peak (exit {was['exit']}), now "
                    f"{one['peak_mb']:.0f} MB: {was['peak_mb'] / one['peak_mb']:.1f}x less"
                )
            console.print(
                f"eval: one line {one['peak_mb']:.0f} MB peak, {one['wall_s']:.1f} s (the first time on this "
                f"machine, cold caches: {cold['peak_mb']:.0f} MB, {cold['wall_s']:.1f} s); "
                f"{first['lines']} trajectories with cold caches {first['wall_s']:.1f} s, "
                f"{first['peak_mb']:.0f} MB peak; warm: "
                f"{split['lines']} trajectories {split['wall_s']:.1f} s, {split['peak_mb']:.0f} MB peak; "
                f"{big['lines']} trajectories {big['wall_s']:.1f} s, {big['peak_mb']:.0f} MB peak; "
                f"{ev['fixed_s']:.1f} s + {1000 * ev['s_per_trajectory']:.2f} ms per trajectory: 10 000 in "
                f"{ev['projected_10000_s']:.0f} s (exit codes {one['exit']}, {split['exit']}, {big['exit']})"
            )
    if "projection" in args.parts:
        results["projection"] = p = projection_part(
            built, results.get("navmesh", []), results.get("verifier")
        )
        h = p["cpu_hours"]
        console.print(
            f"navverse-full projected: scenes {h['scenes']:.1f} h, verification {h['verification']:.1f} h, "
            f"sampling and instructions {h['sampling_and_instructions']:.1f} h: {h['total']:.1f} CPU-hours"
        )
    if args.json:
        args.json.write_text(json.dumps(results, indent=2, default=str) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
