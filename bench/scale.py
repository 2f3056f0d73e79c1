"""Fan-out throughput: ``ctx.map`` items per second with 1 and 2 workers, on local processes and on Ray.

The work per item is a synthetic, CPU-bound stand-in for verifying one episode (not
``navverse.episodes.verification``, which needs a built scene): a seeded unicycle rollout of
:data:`STEPS` steps on a 2-D occupancy grid, in a Python loop with small numpy operations, about
as long per item as a short oracle rollout. Each configuration maps the same items through
:func:`pipeline.context.run_map`, as a stage's ``ctx.map`` does:

- ``in-process``: the stage's own process (what ``ctx.map`` does with a one-core share);
- ``processes xN``: a spawned pool of N processes (``LocalProcessExecutor``'s fan-out);
- ``ray xN``: Ray tasks on a local Ray instance started with N CPUs (``RayExecutor``'s fan-out).

Every configuration must return the same results (checked). Printed: wall time, items/s, the ratio
to in-process, and the 2-worker / 1-worker ratio per engine. Pool and Ray start-up are inside the
timing (a stage pays them on each ``ctx.map`` call for the pool; once per build for Ray).

Run ``python bench/scale.py`` (``--items N``, ``--steps N``, ``--json PATH``). Timings are
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
from functools import partial
from typing import Any

import numpy as np

from pipeline.context import FanOut, run_map

STEPS = 1500
"""Rollout steps per item by default."""

GRID = 128
"""Occupancy grid side (cells of 0.1 m)."""


def rollout(seed: int, *, steps: int = STEPS) -> float:
    """Length travelled by a seeded unicycle steering around a random occupancy grid (one 'episode').

    Parameters
    ----------
    seed : int
        The item's seed (grid and controls derive from it only).
    steps : int
        Integration steps.

    Returns
    -------
    float
        Metres travelled before the step budget ran out.
    """
    rng = np.random.default_rng(seed)
    grid = rng.random((GRID, GRID)) < 0.08
    grid[GRID // 2 - 2 : GRID // 2 + 3, GRID // 2 - 2 : GRID // 2 + 3] = False
    position = np.array([GRID / 20.0, GRID / 20.0])
    heading, travelled, dt = 0.0, 0.0, 0.05
    turns = rng.normal(0.0, 0.6, size=steps)
    for turn in turns:
        heading += float(turn) * dt
        step = 0.6 * dt * np.array([np.cos(heading), np.sin(heading)])
        cell = np.clip(((position + step) * 10.0).astype(int), 0, GRID - 1)
        if grid[cell[1], cell[0]]:
            heading += np.pi / 2
            continue
        position = np.clip(position + step, 0.0, GRID / 10.0 - 1e-6)
        travelled += float(np.hypot(*step))
    return travelled


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


def _timed(fn: Callable[[int], float], items: list[int], fanout: FanOut) -> tuple[float, list[float]]:
    started = time.perf_counter()
    results = run_map(fn, items, fanout=fanout)
    return time.perf_counter() - started, results


def measure(items: int, steps: int) -> tuple[list[Measurement], float]:
    """Run every configuration over the same items; returns the measurements and the Ray start-up time."""
    import ray

    fn = partial(rollout, steps=steps)
    seeds = list(range(items))
    wall, expected = _timed(fn, seeds, FanOut("inline", 1))
    runs = [Measurement("in-process", 1, items, wall)]
    for workers in (1, 2):
        wall, results = _timed(fn, seeds, FanOut("processes", workers))
        _same(results, expected, f"processes x{workers}")
        runs.append(Measurement("processes", workers, items, wall))
    startup = 0.0
    for workers in (1, 2):
        started = time.perf_counter()
        ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False, configure_logging=False)
        startup = time.perf_counter() - started
        try:
            _timed(fn, seeds[: 2 * workers], FanOut("ray", workers))  # start the workers once
            wall, results = _timed(fn, seeds, FanOut("ray", workers))
        finally:
            ray.shutdown()
        _same(results, expected, f"ray x{workers}")
        runs.append(Measurement("ray", workers, items, wall))
    return runs, startup


def _same(results: list[float], expected: list[float], name: str) -> None:
    if results != expected:
        raise SystemExit(f"{name}: results differ from in-process ones")


def report(runs: list[Measurement], items: int, steps: int) -> dict[str, Any]:
    """Print the table and the ratios; return them as JSON data."""
    base = runs[0].rate
    print(
        f"{items} items, {steps} rollout steps each, {os.cpu_count()} cores ({platform.processor() or '?'})"
    )
    print(f"{'engine':<12}{'workers':>8}{'wall s':>9}{'items/s':>10}{'vs in-process':>15}")
    for run in runs:
        print(f"{run.engine:<12}{run.workers:>8}{run.wall_s:>9.2f}{run.rate:>10.1f}{run.rate / base:>15.2f}")
    scaling = {}
    for engine in ("processes", "ray"):
        one, two = (next(r for r in runs if r.engine == engine and r.workers == n) for n in (1, 2))
        scaling[engine] = two.rate / one.rate
        print(f"{engine}: 2 workers / 1 worker = {scaling[engine]:.2f}")
    ray_two = next(r for r in runs if r.engine == "ray" and r.workers == 2)
    pool_two = next(r for r in runs if r.engine == "processes" and r.workers == 2)
    print(f"ray x2 / processes x2 = {ray_two.rate / pool_two.rate:.2f}")
    return {
        "items": items,
        "steps": steps,
        "runs": [asdict(r) | {"rate": r.rate} for r in runs],
        "scaling": scaling,
    }


def main() -> None:
    """Parse the options, measure, print."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--items", type=int, default=200, help="items (episodes) mapped per configuration")
    parser.add_argument("--steps", type=int, default=STEPS, help="rollout steps per item")
    parser.add_argument("--json", default=None, help="also write the results here")
    args = parser.parse_args()
    per_item = time.perf_counter()
    rollout(0, steps=args.steps)
    print(f"one item in-process: {1000 * (time.perf_counter() - per_item):.1f} ms")
    runs, startup = measure(args.items, args.steps)
    data = report(runs, args.items, args.steps)
    print(f"ray.init (local, not in the timings above): {startup:.1f} s")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump(data | {"ray_init_s": startup}, handle, indent=2)


if __name__ == "__main__":
    main()
