"""Verification throughput: episodes per second with 1 and 2 workers, on local processes and on Ray.

The work is the dataset's own: :func:`navverse.episodes.verification.verify_scene` (a PyBullet world
loaded per scene, the oracle's rollout of each candidate under physics, the acceptance bounds) over
the first ``--per-scene`` candidates of each scene of a built dataset target (default
``navverse-mini-indoor``: ``make episodes`` builds it). Each configuration maps the same items, one
scene and its candidates per item as the ``verify_episodes`` stage does, through
:func:`pipeline.context.run_map`, as a stage's ``ctx.map`` does:

- ``in-process``: the stage's own process (what ``ctx.map`` does with a one-core share);
- ``processes xN``: a spawned pool of N processes (``LocalProcessExecutor``'s fan-out);
- ``ray xN``: Ray tasks on a local Ray instance started with N CPUs (``RayExecutor``'s fan-out).

Every configuration must give the same verdicts, durations and distances (checked). Printed: wall
time, episodes/s, the ratio to in-process, and the 2-worker / 1-worker ratio per engine. Pool and
Ray worker start-up are inside the timing (a stage pays them on each ``ctx.map`` call for the pool;
once per build for Ray).

Run ``python bench/scale.py`` (``--target NAME``, ``--per-scene N``, ``--json PATH``). Timings are
measurements, never assertions; other load on the machine lowers them.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from pipeline.context import FanOut, run_map
from pipeline.store import ArtifactStore
from pipeline.workspace import Workspace

Verdicts = list[tuple[str, str | None, float, float]]


def verify_item(item: tuple[str, list[dict], str]) -> Verdicts:
    """Verify one scene's candidates; (episode id, rejection or None, duration s, travelled m) each.

    Parameters
    ----------
    item : tuple
        The built scene directory, its candidates (episode dicts) and the robot.
    """
    from navverse.dataset import Episode
    from navverse.episodes.verification import VerificationSettings, verify_scene

    scene_dir, raw, embodiment = item
    episodes = [Episode.model_validate(e) for e in raw]
    results = verify_scene(Path(scene_dir), episodes, embodiment=embodiment, settings=VerificationSettings())
    return [(r.episode_id, r.reason, r.verification.duration_s, r.verification.traveled_m) for r in results]


def load_items(target: str, per_scene: int) -> tuple[list[tuple[str, list[dict], str]], int]:
    """One item per scene of `target`'s candidates: its first `per_scene` candidates; and their count."""
    from navverse.dataset import read_json_gz
    from navverse.episodes import files

    workspace = Workspace.find()
    store = ArtifactStore(workspace.built_dir)
    candidates_dir = store.target_output(target, "candidates")
    if candidates_dir is None:
        raise SystemExit(f"{target} has no built candidates here: run `make episodes` first")
    data = read_json_gz(candidates_dir / files.CANDIDATES)
    by_scene: dict[str, list[dict]] = {}
    for episode in data["episodes"]:
        by_scene.setdefault(episode["scene_id"], []).append(episode)
    items = []
    for scene_id, episodes in sorted(by_scene.items()):
        scene_dir = store.target_output(scene_id, "scene")
        if scene_dir is None:
            raise SystemExit(f"scene {scene_id} of {target} is not built here: run `make scenes` first")
        items.append((str(scene_dir), episodes[:per_scene], data["embodiment"]))
    return items, sum(len(item[1]) for item in items)


@dataclass
class Measurement:
    """One configuration's run."""

    engine: str
    workers: int
    items: int
    wall_s: float

    @property
    def rate(self) -> float:
        """Items per second."""
        return self.items / self.wall_s


def _timed(fn: Callable, items: list, fanout: FanOut) -> tuple[float, list]:
    started = time.perf_counter()
    results = run_map(fn, items, fanout=fanout, chunksize=1)
    return time.perf_counter() - started, results


def measure(items: list, episodes: int) -> tuple[list[Measurement], float]:
    """Run every configuration over the same items; returns the measurements and the Ray start-up time."""
    import ray

    wall, expected = _timed(verify_item, items, FanOut("inline", 1))
    runs = [Measurement("in-process", 1, episodes, wall)]
    for workers in (1, 2):
        wall, results = _timed(verify_item, items, FanOut("processes", workers))
        _same(results, expected, f"processes x{workers}")
        runs.append(Measurement("processes", workers, episodes, wall))
    startup = 0.0
    for workers in (1, 2):
        started = time.perf_counter()
        ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False, configure_logging=False)
        startup = time.perf_counter() - started
        try:
            wall, results = _timed(verify_item, items, FanOut("ray", workers))
        finally:
            ray.shutdown()
        _same(results, expected, f"ray x{workers}")
        runs.append(Measurement("ray", workers, episodes, wall))
    return runs, startup


def _same(results: list, expected: list, name: str) -> None:
    if results != expected:
        raise SystemExit(f"{name}: verdicts differ from the in-process ones")


def report(runs: list[Measurement], target: str, scenes: int) -> dict[str, Any]:
    """Print the table and the ratios; return them as JSON data."""
    base = runs[0].rate
    print(
        f"{runs[0].items} candidates of {target} in {scenes} scenes, {os.cpu_count()} cores "
        f"({platform.processor() or '?'})"
    )
    print(f"{'engine':<12}{'workers':>8}{'wall s':>9}{'episodes/s':>12}{'vs in-process':>15}")
    for run in runs:
        print(f"{run.engine:<12}{run.workers:>8}{run.wall_s:>9.2f}{run.rate:>12.2f}{run.rate / base:>15.2f}")
    scaling = {}
    for engine in ("processes", "ray"):
        one, two = (next(r for r in runs if r.engine == engine and r.workers == n) for n in (1, 2))
        scaling[engine] = two.rate / one.rate
        print(f"{engine}: 2 workers / 1 worker = {scaling[engine]:.2f}")
    ray_two = next(r for r in runs if r.engine == "ray" and r.workers == 2)
    pool_two = next(r for r in runs if r.engine == "processes" and r.workers == 2)
    print(f"ray x2 / processes x2 = {ray_two.rate / pool_two.rate:.2f}")
    return {
        "target": target,
        "scenes": scenes,
        "runs": [asdict(r) | {"rate": r.rate} for r in runs],
        "scaling": scaling,
    }


def main() -> None:
    """Parse the options, measure, print."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--target", default="navverse-mini-indoor", help="a built dataset target")
    parser.add_argument("--per-scene", type=int, default=4, help="candidates verified per scene (4)")
    parser.add_argument("--json", default=None, help="also write the results here")
    args = parser.parse_args()
    items, episodes = load_items(args.target, args.per_scene)
    runs, startup = measure(items, episodes)
    data = report(runs, args.target, len(items))
    print(f"ray.init (local, not in the timings above): {startup:.1f} s")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump(data | {"ray_init_s": startup}, handle, indent=2)


if __name__ == "__main__":
    main()
