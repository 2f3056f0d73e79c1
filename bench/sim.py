"""Physics benchmark: the simulator with its controller against raw ``stepSimulation`` of the same world.

For an indoor scene (``office-s1``), an outdoor-like one (``curb-street``) and a populated 1 km² city
(``aguascalientes``, ``--city``), all already built under ``data/built/targets/<id>/scene/``, and for
each embodiment (the city: the same paths also in its bare street, ``street_geometry``, so that the
cost of its objects per physics step shows as a ratio):

1. Load the scene into a :class:`navverse.sim.world.World` (static terrain per class, objects as
   convex compounds) and draw seeded navmesh paths of 3-50 m on its largest island.
2. Ours: the robot follows each path with the whole stack, as episode verification does
   (:func:`navverse.sim.rollout.follow_path`: waypoint follower and PID at 50 Hz, the embodiment's
   actuation before every 200 Hz physics step, contact and collision bookkeeping, terminations).
   Reported: physics steps per wall second and per CPU second, and the real-time factor (simulated
   seconds per CPU second; PyBullet runs on one core, so this is per core).
3. Peer, in the same run on the same world with the robot standing in it: raw
   ``client.stepSimulation()`` in a loop with no controller, no actuation and no queries, as many
   steps as ours took. The ratio raw / ours is the overhead of our stack per physics step.

Run ``python bench/sim.py`` (what ``make bench`` does). Timings are measurements, never assertions;
the printed load average shows whether other work shared the machine.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from navverse.errors import NavverseError
from navverse.nav.sampling import sample_paths
from navverse.nav.scene_navmesh import load_scene_navmesh
from navverse.sim.embodiments import make_embodiment
from navverse.sim.rollout import follow_path
from navverse.sim.simulator import Simulator
from navverse.sim.world import PHYSICS_HZ, World

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"
SCENES = (("office-s1", "indoor"), ("curb-street", "outdoor"))
EMBODIMENTS = ("spot", "turtlebot")


@dataclass(frozen=True)
class Timing:
    """Steps and the wall and CPU seconds they took."""

    steps: int
    wall: float
    cpu: float

    @property
    def steps_per_wall_second(self) -> float:
        return self.steps / self.wall

    @property
    def steps_per_cpu_second(self) -> float:
        return self.steps / self.cpu

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per CPU second."""
        return self.steps / PHYSICS_HZ / self.cpu


def time_ours(world: World, embodiment: str, paths: list[np.ndarray]) -> tuple[Timing, float]:
    """Follow every path with the full stack; returns the timing and the simulated distance (m)."""
    sim = Simulator(world, make_embodiment(embodiment))
    steps = wall = cpu = 0.0
    distance = 0.0
    for points in paths:
        heading = points[1, :2] - points[0, :2]
        sim.spawn(points[0], math.atan2(heading[1], heading[0]))
        before = world.steps
        w0, c0 = time.perf_counter(), time.process_time()
        rollout = follow_path(sim, points, settle=0.0)
        wall += time.perf_counter() - w0
        cpu += time.process_time() - c0
        steps += world.steps - before
        distance += rollout.traveled
    sim.robot.remove()
    return Timing(int(steps), wall, cpu), distance


def time_raw(world: World, embodiment: str, start: np.ndarray, steps: int) -> Timing:
    """``stepSimulation`` alone, ``steps`` times, with the robot standing at ``start``."""
    robot = make_embodiment(embodiment)
    robot.spawn(world, start, 0.0)
    step = world.client.stepSimulation
    w0, c0 = time.perf_counter(), time.process_time()
    for _ in range(steps):
        step()
    timing = Timing(steps, time.perf_counter() - w0, time.process_time() - c0)
    robot.remove()
    return timing


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--paths", type=int, default=10, help="paths per scene (default 10)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--city", default="aguascalientes", help="built, populated city (default aguascalientes)"
    )
    args = parser.parse_args(argv)
    console = Console(width=max(Console().width, 150))
    console.print(
        f"sim benchmark: {os.cpu_count()} CPUs, "
        f"{platform.python_implementation()} {platform.python_version()}, "
        f"{args.paths} paths per scene, seed {args.seed}; load average {os.getloadavg()[0]:.2f}"
    )
    table = Table(title=f"physics at {PHYSICS_HZ} Hz with the control stack vs raw stepSimulation")
    for column in (
        "scene",
        "robot",
        "sim time",
        "ours steps/s (wall)",
        "ours steps/s (CPU)",
        "× real time (CPU)",
        "raw steps/s (CPU)",
        "raw × real time",
        "raw / ours",
    ):
        table.add_column(column, justify="right")
    runs = [
        (scene_id, kind, TARGETS / scene_id / "scene", TARGETS / scene_id / "scene")
        for scene_id, kind in SCENES
    ]
    runs += [
        (args.city, "populated city", TARGETS / args.city / "scene", TARGETS / args.city / "scene"),
        (args.city, "bare street", TARGETS / args.city / "street_geometry", TARGETS / args.city / "scene"),
    ]
    per_step: dict[tuple[str, str], float] = {}
    try:
        for scene_id, kind, scene_dir, navmesh_dir in runs:
            if not (scene_dir / "scene.json").is_file() or not (navmesh_dir / "navmesh.bin").is_file():
                raise NavverseError(
                    f"{scene_dir} is not built; run `navverse build {scene_id}` (or `make scenes`)"
                )
            paths = [
                p.points
                for p in sample_paths(load_scene_navmesh(navmesh_dir), args.seed, args.paths, min_length=3.0)
            ]
            with World(scene_dir) as world:
                bodies = f"{len(world.scene.surfaces)} surfaces, {len(world.objects)} objects"
                for embodiment in EMBODIMENTS:
                    ours, _ = time_ours(world, embodiment, paths)
                    raw = time_raw(world, embodiment, paths[0][0], ours.steps)
                    per_step[(kind, embodiment)] = 1.0 / ours.steps_per_cpu_second
                    table.add_row(
                        f"{scene_id} ({kind}; {bodies})",
                        embodiment,
                        f"{ours.steps / PHYSICS_HZ:.0f} s",
                        f"{ours.steps_per_wall_second:,.0f}",
                        f"{ours.steps_per_cpu_second:,.0f}",
                        f"{ours.real_time_factor:.0f}×",
                        f"{raw.steps_per_cpu_second:,.0f}",
                        f"{raw.real_time_factor:.0f}×",
                        f"{raw.steps_per_cpu_second / ours.steps_per_cpu_second:.2f}",
                    )
    except NavverseError as exc:
        console.print(f"[red]error:[/red] {exc}")
        return 1
    console.print(table)
    for embodiment in EMBODIMENTS:
        if ("populated city", embodiment) in per_step:
            ratio = per_step[("populated city", embodiment)] / per_step[("bare street", embodiment)]
            console.print(
                f"{args.city}, {embodiment}: CPU per physics step populated / bare street = {ratio:.2f}"
            )
    console.print(
        "ours: navverse.sim.rollout.follow_path (follower + PID at 50 Hz, embodiment actuation every step, "
        "contacts, terminations); raw: client.stepSimulation() alone on the same world with the robot in it. "
        f"× real time: simulated seconds per CPU second (one core). load average {os.getloadavg()[0]:.2f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
