"""How well each robot follows navmesh paths under full physics, with the waypoint interface.

Usage::

    python scripts/path_following.py [--scene office-s1] [--paths 100] [--seed 0]
                                     [--embodiments spot turtlebot] [--picture docs/img/path_following.png]
                                     [--out-of-building]

For a built scene (``data/built/targets/<scene>/scene``) it draws seeded start and end points on
the navmesh's largest island whose shortest path is 5-50 m long, spawns each robot at the start facing
the first corner, and has it follow the path's corners through the shared waypoint follower
(:func:`navverse.sim.rollout.follow_path`; fall, stuck and a 300 s timeout end a rollout). It prints,
per robot, the share of paths whose rollout ends within 1.0 + r_robot of the path's end (1.6 m for
spot, the paper's success tolerance; 1.2 m for turtlebot), how many arrived within the follower's
own 3 cm, the terminations, the final distances, the speed and the collisions, and draws the
executed trajectories over the scene's bird's-eye view.

With ``--out-of-building`` (indoor-to-outdoor scenes) every path starts at a seeded navigable point
inside the building and ends on the sidewalk in front of its exit (0.8 m into the first sidewalk the
exit's outward direction meets), so each rollout walks out of a room, through the exit, to the street.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.progress import track
from rich.table import Table

from navverse.errors import NavverseError
from navverse.nav.sampling import sample_paths
from navverse.nav.scene_navmesh import load_scene_navmesh
from navverse.scene.bev import BevOverlay, render_bev
from navverse.sim.embodiments import make_embodiment
from navverse.sim.rollout import PathRollout, follow_path
from navverse.sim.simulator import Simulator
from navverse.sim.world import World

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"
MIN_LENGTH, MAX_LENGTH = 5.0, 50.0
COLORS = {"spot": "tab:blue", "turtlebot": "tab:orange"}


@dataclass(frozen=True)
class Trial:
    """One path and how a robot followed it."""

    path: np.ndarray
    length: float
    rollout: PathRollout


def draw_paths(scene_dir: Path, count: int, seed: int) -> list[tuple[np.ndarray, float]]:
    """``count`` seeded navmesh paths of 5-50 m on the largest island: (corners, geodesic length)."""
    paths = sample_paths(
        load_scene_navmesh(scene_dir), seed, count, min_length=MIN_LENGTH, max_length=MAX_LENGTH
    )
    return [(path.points, path.geodesic_distance) for path in paths]


def exit_paths(scene_dir: Path, count: int, seed: int) -> list[tuple[np.ndarray, float]]:
    """``count`` seeded paths from inside an i2o scene's building to the sidewalk outside its exit."""
    from shapely import contains_xy
    from shapely.geometry import Polygon

    from navverse.episodes.instructions.roads import RoadFollowing
    from navverse.scene.directory import read_scene

    scene = read_scene(scene_dir)
    indoor = [b for b in scene.annotations.buildings if b.indoor]
    if len(indoor) != 1 or not indoor[0].exits:
        raise NavverseError(f"{scene_dir} has no indoor building with an exit (an i2o scene is needed)")
    building, exit_ = indoor[0], indoor[0].exits[0]
    normal = np.array([math.cos(exit_.facing), math.sin(exit_.facing)])
    classes = RoadFollowing(scene).classes
    steps = np.asarray(exit_.center[:2]) + np.outer(np.arange(0.5, 12.0, 0.25), normal)
    on_sidewalk = np.flatnonzero(classes(steps) == "sidewalk")
    if not len(on_sidewalk):
        raise NavverseError(f"no sidewalk within 12 m in front of the exit of {scene_dir}")
    finder = load_scene_navmesh(scene_dir)
    end = finder.snap_point((*(steps[on_sidewalk[0]] + normal * 0.8), exit_.center[2]))
    footprint = Polygon(building.footprint)
    radius = float(np.max(np.linalg.norm(np.asarray(building.footprint) - exit_.center[:2], axis=1)))
    rng = np.random.default_rng(seed)
    paths: list[tuple[np.ndarray, float]] = []
    for _ in range(count * 50):
        start = finder.get_random_navigable_point_near(exit_.center, radius, rng)
        if not np.isfinite(start).all() or not contains_xy(footprint, start[0], start[1]):
            continue
        path = finder.find_path(start, end)
        if path.found and path.geodesic_distance >= 2.0:
            paths.append((path.points, path.geodesic_distance))
            if len(paths) == count:
                break
    return paths


def run(world: World, embodiment: str, paths: list[tuple[np.ndarray, float]]) -> list[Trial]:
    """Follow every path with a fresh spawn of the robot."""
    sim = Simulator(world, make_embodiment(embodiment))
    trials = []
    for points, length in track(paths, description=f"{embodiment:>9}", transient=True):
        heading = points[1, :2] - points[0, :2]
        sim.spawn(points[0], math.atan2(heading[1], heading[0]))
        trials.append(Trial(points, length, follow_path(sim, points)))
    sim.robot.remove()
    return trials


def report(console: Console, results: dict[str, list[Trial]], scene: str, seconds: dict[str, float]) -> None:
    count = len(next(iter(results.values())))
    table = Table(title=f"{scene}: {count} navmesh paths, waypoint interface")
    for column in (
        "robot",
        "ends within 1 + r",
        "arrived (3 cm)",
        "terminations",
        "final distance med / p95 / max",
        "speed",
        "paths w/ collision",
        "sim / wall time",
    ):
        table.add_column(column, justify="right")
    for name, trials in results.items():
        tolerance = 1.0 + make_embodiment(name).radius
        final = np.array([t.rollout.final_distance for t in trials])
        within = float(np.mean(final <= tolerance))
        terminations = Counter(t.rollout.termination for t in trials if t.rollout.termination)
        speed = sum(t.rollout.traveled for t in trials) / sum(t.rollout.duration for t in trials)
        collided = sum(t.rollout.collisions > 0 for t in trials)
        sim_time = sum(t.rollout.duration for t in trials)
        table.add_row(
            name,
            f"{100 * within:.1f}% (<= {tolerance:.1f} m)",
            f"{sum(t.rollout.arrived for t in trials)}",
            ", ".join(f"{k} {v}" for k, v in sorted(terminations.items())) or "none",
            f"{np.median(final):.3f} / {np.percentile(final, 95):.3f} / {final.max():.2f} m",
            f"{speed:.2f} m/s",
            f"{collided}",
            f"{sim_time:.0f} s / {seconds[name]:.1f} s",
        )
    console.print(table)


def picture(scene_dir: Path, results: dict[str, list[Trial]], out: Path) -> None:
    """The executed trajectories over the scene's bird's-eye view, one colour per robot."""
    from navverse.scene.directory import read_scene

    overlays = []
    for name, trials in results.items():
        segments = [
            np.stack([t.rollout.trajectory[:-1, 1:3], t.rollout.trajectory[1:, 1:3]], axis=1) for t in trials
        ]
        color = COLORS.get(name, "k")
        overlays.append(
            BevOverlay(f"{name} trajectories", np.concatenate(segments), color=color, linewidth=0.6)
        )
        ends = [t.path[-1, :2] for t in trials if not t.rollout.arrived]
        if ends:
            cross = np.array([[[x - 0.3, y - 0.3], [x + 0.3, y + 0.3]] for x, y in ends]
                             + [[[x - 0.3, y + 0.3], [x + 0.3, y - 0.3]] for x, y in ends])  # fmt: skip
            overlays.append(BevOverlay(f"{name}: ends not reached", cross, color="red", linewidth=1.2))
    out.parent.mkdir(parents=True, exist_ok=True)
    render_bev(read_scene(scene_dir), out, overlays=overlays)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default="office-s1", help="a built indoor scene id (default office-s1)")
    parser.add_argument("--paths", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--embodiments", nargs="+", default=["spot", "turtlebot"])
    parser.add_argument("--picture", type=Path, help="write the trajectories over the BEV to this PNG")
    parser.add_argument(
        "--out-of-building",
        action="store_true",
        help="paths from inside an i2o scene's building to the street",
    )
    args = parser.parse_args(argv)
    console = Console(width=max(Console().width, 150))
    scene_dir = TARGETS / args.scene / "scene"
    try:
        if not (scene_dir / "scene.json").is_file():
            raise NavverseError(
                f"{scene_dir} is not built; run `navverse build {args.scene}` (or `make scenes`)"
            )
        draw = exit_paths if args.out_of_building else draw_paths
        paths = draw(scene_dir, args.paths, args.seed)
        results: dict[str, list[Trial]] = {}
        seconds: dict[str, float] = {}
        with World(scene_dir) as world:
            for name in args.embodiments:
                began = time.perf_counter()
                results[name] = run(world, name, paths)
                seconds[name] = time.perf_counter() - began
    except NavverseError as exc:
        console.print(f"[red]error:[/red] {exc}")
        return 1
    lengths = np.array([length for _, length in paths])
    console.print(f"paths: {len(paths)}, geodesic length {lengths.min():.1f}-{lengths.max():.1f} m "
                  f"(median {np.median(lengths):.1f} m), seed {args.seed}")  # fmt: skip
    report(console, results, args.scene, seconds)
    if args.picture:
        picture(scene_dir, results, args.picture)
        console.print(f"wrote {args.picture}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
