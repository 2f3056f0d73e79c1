"""Navmesh benchmark: ``navverse.nav`` builds on large scenes, and its path queries against a grid planner.

For each synthetic scene (``bench/_synthetic_scenes.py``: a ~2 M-triangle furnished building built
with ``nav.INDOOR``, and a 1 km x 1 km city built with ``nav.OUTDOOR``):

1. Build the navmesh in a fresh child process (``spawn``), with as many threads as CPUs: wall and
   CPU time, resident memory before the build and the peak after it, tiles, polygons, navigable
   area, islands. The child saves the navmesh; this process loads it.
2. Sample start/end pairs on the largest island whose geodesic distance is 5-50 m and time
   ``PathFinder.find_path`` on each (the minimum over a few repetitions).
3. Peer, on the same free space: scikit-image's ``MCP_Geometric`` (Dijkstra on a grid) on the
   navmesh's own top-down view at the navmesh cell size, cropped per query to the pair's bounding
   box plus a margin, 8-, 16- and 32-connected (moves up to (3, 2) cells). Reported: query times,
   the time ratio to the navmesh, and how much longer the grid path is than the navmesh path, both
   measured horizontally (the grid is 2-D; the geodesic also counts the rise over curbs and ramps).
4. Resolutions: a smaller city built three ways, each in a fresh child process: ``nav.OUTDOOR``
   (10 cm), ``nav.I2O`` with a ``fine_region`` over its central part (the tiles meeting it at 5 cm,
   the rest at 10 cm) and ``nav.INDOOR`` (5 cm everywhere); build times, memory, polygons and the
   ratios to the outdoor build.

Run ``python bench/navmesh.py`` (what ``make bench`` does); ``--quick`` builds small scenes,
``--json PATH`` also writes the results. Timings are measurements, never assertions.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing
import os
import platform
import resource
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import skimage
from _synthetic_scenes import Scene, indoor_building, outdoor_city
from rich.console import Console
from rich.table import Table
from skimage.graph import MCP, MCP_Geometric

from navverse import nav
from navverse.nav import PathFinder, TopDownView

MIN_GEODESIC = 5.0
MAX_GEODESIC = 50.0
KNIGHT_MOVES = [(-2, -1), (-2, 1), (-1, -2), (-1, 2), (1, -2), (1, 2), (2, -1), (2, 1)]
KING_MOVES = [(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)]
LONG_MOVES = [(a * i, b * j) for a, b in ((3, 1), (1, 3), (3, 2), (2, 3)) for i in (-1, 1) for j in (-1, 1)]
GRID_VARIANTS: dict[str, list[tuple[int, int]] | None] = {
    "grid 8-conn": None,  # MCP's default, fully connected neighbourhood
    "grid 16-conn": KING_MOVES + KNIGHT_MOVES,
    "grid 32-conn": KING_MOVES + KNIGHT_MOVES + LONG_MOVES,
}


@dataclass(frozen=True)
class SceneSpec:
    """How to make one benchmark scene.

    Attributes
    ----------
    preset : str
        Navmesh settings preset (``"indoor"`` or ``"outdoor"``).
    full, quick : callable
        Scene generators taking the seed: the full-size scene and a small one for ``--quick``.
    """

    preset: str
    full: Callable[[int], Scene]
    quick: Callable[[int], Scene]


SCENES: dict[str, SceneSpec] = {
    "indoor": SceneSpec(
        preset="indoor",
        full=partial(indoor_building, width=60.0, depth=40.0, target_triangles=2_000_000),
        quick=partial(indoor_building, width=30.0, depth=20.0, target_triangles=300_000),
    ),
    "outdoor": SceneSpec(
        preset="outdoor",
        full=partial(outdoor_city, size=1000.0),
        quick=partial(outdoor_city, size=200.0, block_range=(40.0, 70.0)),
    ),
}
RESOLUTION_CITY: dict[str, Callable[[int], Scene]] = {
    "full": partial(outdoor_city, size=300.0, block_range=(40.0, 70.0)),
    "quick": partial(outdoor_city, size=120.0, block_range=(40.0, 70.0)),
}
"""The city of the resolution comparison (step 4), full-size and for ``--quick``."""
FINE_REGION_SIDE = 0.3
"""Side of the comparison's ``fine_region``, a centred square, as a fraction of the city's side."""


@dataclass(frozen=True)
class QueryPair:
    """A start and an end point on the navmesh and the navmesh geodesic distance between them (m)."""

    start: np.ndarray
    end: np.ndarray
    geodesic: float


# ---------------------------------------------------------------------- memory and the build child


def _peak_rss_mib() -> float:
    """Peak resident set size of this process so far (MiB)."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 2**20 if sys.platform == "darwin" else peak / 2**10  # bytes on macOS, KiB elsewhere


def _current_rss_mib() -> float:
    """Current resident set size of this process (MiB); the peak where /proc is missing."""
    try:
        resident_pages = int(Path("/proc/self/statm").read_text().split()[1])
    except (OSError, IndexError, ValueError):
        return _peak_rss_mib()
    return resident_pages * os.sysconf("SC_PAGE_SIZE") / 2**20


def _cpu_seconds() -> float:
    """User plus system CPU time of this process, all threads (s)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def build_in_child(
    mesh_file: str, settings: dict[str, Any], jobs: int, navmesh_file: str
) -> dict[str, float]:
    """Build a navmesh from a saved mesh and save it; runs in a fresh process.

    Parameters
    ----------
    mesh_file : str
        ``.npz`` with ``vertices``, ``faces`` and ``area_types``.
    settings : dict
        ``NavMeshSettings`` fields.
    jobs : int
        Build threads.
    navmesh_file : str
        Where to save the navmesh.

    Returns
    -------
    dict of str to float
        ``build_s`` (wall), ``cpu_s``, ``rss_before_mib`` (resident, mesh loaded), ``peak_before_mib``
        and ``peak_after_mib`` (the process's high-water mark before and after the build).
    """
    with np.load(mesh_file) as data:
        vertices, faces, areas = data["vertices"], data["faces"], data["area_types"]
    rss_before, peak_before = _current_rss_mib(), _peak_rss_mib()
    cpu_start, start = _cpu_seconds(), time.perf_counter()
    finder = nav.build(
        vertices, faces, nav.NavMeshSettings.model_validate(settings), area_types=areas, jobs=jobs
    )
    build_s, cpu_s = time.perf_counter() - start, _cpu_seconds() - cpu_start
    peak_after = _peak_rss_mib()
    finder.save(navmesh_file)
    return {
        "build_s": build_s,
        "cpu_s": cpu_s,
        "rss_before_mib": rss_before,
        "peak_before_mib": peak_before,
        "peak_after_mib": peak_after,
    }


def build_in_fresh_process(
    scene: Scene, settings: nav.NavMeshSettings, jobs: int, workdir: Path, *, label: str = ""
) -> tuple[dict[str, float], Path]:
    """Save the scene, build its navmesh in a new ``spawn`` process, and return its stats and file.

    ``label`` tells apart the files of several builds of one scene.
    """
    name = f"{scene.name}-{label}" if label else scene.name
    mesh_file = workdir / f"{name}-mesh.npz"
    navmesh_file = workdir / f"{name}.navmesh"
    np.savez(mesh_file, vertices=scene.vertices, faces=scene.faces, area_types=scene.area_types)
    with ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn")) as pool:
        task = pool.submit(build_in_child, str(mesh_file), settings.model_dump(), jobs, str(navmesh_file))
        stats = task.result()
    mesh_file.unlink()
    return stats, navmesh_file


# ---------------------------------------------------------------------- queries


def sample_pairs(finder: PathFinder, count: int, rng: np.random.Generator) -> list[QueryPair]:
    """Start/end pairs on the largest island, ``MIN_GEODESIC`` to ``MAX_GEODESIC`` apart (geodesic).

    Raises
    ------
    RuntimeError
        If ``count`` pairs are not found in ``100 * count`` tries.
    """
    island = finder.largest_island
    pairs: list[QueryPair] = []
    for _ in range(100 * count):
        if len(pairs) == count:
            return pairs
        start = finder.get_random_navigable_point(rng, island=island)
        end = finder.get_random_navigable_point_near(start, MAX_GEODESIC, rng)
        if not np.isfinite(end).all():
            continue
        geodesic = finder.geodesic_distance(start, end)
        if MIN_GEODESIC <= geodesic <= MAX_GEODESIC:
            pairs.append(QueryPair(start, end, geodesic))
    if len(pairs) == count:
        return pairs
    raise RuntimeError(
        f"found only {len(pairs)} of {count} query pairs {MIN_GEODESIC}-{MAX_GEODESIC} m apart"
    )


def time_navmesh(
    finder: PathFinder, pairs: Sequence[QueryPair], repeats: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-query minimum time (µs) of ``find_path`` over ``repeats`` rounds, the geodesic distances
    (m, along the surface) and the horizontal lengths of the paths (m, for the 2-D grid).

    Each round runs every query once, so repetitions of a query are not back to back.
    """
    best_ns = np.full(len(pairs), np.iinfo(np.int64).max, dtype=np.int64)
    lengths = np.empty(len(pairs))
    horizontal = np.empty(len(pairs))
    for _ in range(repeats):
        for i, pair in enumerate(pairs):
            start = time.perf_counter_ns()
            path = finder.find_path(pair.start, pair.end)
            best_ns[i] = min(best_ns[i], time.perf_counter_ns() - start)
            lengths[i] = path.geodesic_distance
            horizontal[i] = float(np.linalg.norm(np.diff(path.points[:, :2], axis=0), axis=1).sum())
    return best_ns / 1e3, lengths, horizontal


def geometric_mcp(costs: np.ndarray, offsets: list[tuple[int, int]] | None) -> MCP_Geometric:
    """An ``MCP_Geometric`` (step cost = step length x mean cell cost) over ``offsets``.

    ``MCP_Geometric`` refuses offsets longer than one cell per axis, because for them its cost
    model (half the step in each end cell) skips the cells in between. With cost 1 on every free
    cell the model is exact (a step costs its length), so for such offsets this sets the object up
    through the base class ``MCP.__init__``, which accepts any offsets; the step costs are still
    ``MCP_Geometric``'s. (Cumulative costs then include the start cell's cost, 1, which changes no
    path; lengths are measured on the traceback.) A knight move may cross the corner of a blocked
    cell between its end cells.
    """
    if offsets is None:
        return MCP_Geometric(costs)
    if max(abs(component) for offset in offsets for component in offset) <= 1:
        return MCP_Geometric(costs, offsets=offsets)
    mcp = MCP_Geometric.__new__(MCP_Geometric)
    MCP.__init__(mcp, costs, offsets=offsets)
    return mcp


def grid_path_length(
    view: TopDownView,
    start: np.ndarray,
    end: np.ndarray,
    offsets: list[tuple[int, int]] | None,
    margin: float,
) -> float:
    """Length (m) of the grid shortest path between two points, NaN if unreachable.

    The grid is ``view.image`` (True = free) cropped to the points' bounding box plus ``margin``
    meters; free cells cost 1 per unit length and blocked ones are impassable. The path runs
    between the centers of the start and end cells.
    """
    cell = view.meters_per_pixel
    (r_start, c_start), (r_end, c_end) = view.world_to_pixel(np.stack([start[:2], end[:2]]))
    pad = math.ceil(margin / cell)
    rows, cols = view.image.shape
    r0, c0 = max(0, min(r_start, r_end) - pad), max(0, min(c_start, c_end) - pad)
    r1, c1 = min(rows, max(r_start, r_end) + pad + 1), min(cols, max(c_start, c_end) + pad + 1)
    costs = np.where(view.image[r0:r1, c0:c1], 1.0, np.inf)
    mcp = geometric_mcp(costs, offsets)
    source, target = (r_start - r0, c_start - c0), (r_end - r0, c_end - c0)
    cumulative, _ = mcp.find_costs([source], [target])
    if not np.isfinite(cumulative[target]):
        return math.nan
    steps = np.diff(np.asarray(mcp.traceback(target)), axis=0)
    return float(np.hypot(steps[:, 0], steps[:, 1]).sum() * cell)


def cell_is_free(view: TopDownView, point: np.ndarray) -> bool:
    """Whether the grid cell under ``point`` exists and is free."""
    row, col = view.world_to_pixel(point[:2])
    rows, cols = view.image.shape
    return bool(0 <= row < rows and 0 <= col < cols and view.image[row, col])


def time_grid(
    view: TopDownView,
    pairs: Sequence[QueryPair],
    offsets: list[tuple[int, int]] | None,
    margin: float,
    repeats: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-query minimum time (µs) and length (m) of the grid planner, and which pairs it could run.

    Pairs whose start or end cell is blocked are skipped (time and length NaN, not runnable).
    """
    times = np.full(len(pairs), np.nan)
    lengths = np.full(len(pairs), np.nan)
    runnable = np.array(
        [cell_is_free(view, p.start) and cell_is_free(view, p.end) for p in pairs], dtype=bool
    )
    for _ in range(repeats):
        for i in np.flatnonzero(runnable):
            start = time.perf_counter_ns()
            lengths[i] = grid_path_length(view, pairs[i].start, pairs[i].end, offsets, margin)
            elapsed = (time.perf_counter_ns() - start) / 1e3
            times[i] = elapsed if np.isnan(times[i]) else min(times[i], elapsed)
    return times, lengths, runnable


# ---------------------------------------------------------------------- statistics


def time_stats(times_us: np.ndarray) -> dict[str, float]:
    """Median and 90th percentile (µs)."""
    return {"median_us": float(np.median(times_us)), "p90_us": float(np.percentile(times_us, 90))}


def peer_stats(
    peer_us: np.ndarray, peer_m: np.ndarray, runnable: np.ndarray, nav_us: np.ndarray, nav_m: np.ndarray
) -> dict[str, float | int]:
    """Timing and path-length agreement of a peer against the navmesh, over the queries both solved."""
    solved = runnable & np.isfinite(peer_m)
    counts = {
        "queries": int(solved.sum()),
        "skipped_blocked_cell": int((~runnable).sum()),
        "unreached": int((runnable & ~np.isfinite(peer_m)).sum()),
    }
    if not solved.any():
        return counts
    ratios = peer_us[solved] / nav_us[solved]
    excess = 100.0 * (peer_m[solved] - nav_m[solved]) / nav_m[solved]
    return {
        **counts,
        **time_stats(peer_us[solved]),
        "ratio_median_of_ratios": float(np.median(ratios)),
        "ratio_of_medians": float(np.median(peer_us[solved]) / np.median(nav_us[solved])),
        "length_excess_median_pct": float(np.median(excess)),
        "length_excess_p90_pct": float(np.percentile(excess, 90)),
        "length_excess_max_pct": float(excess.max()),
        "length_excess_min_pct": float(excess.min()),
    }


# ---------------------------------------------------------------------- one scene


def bench_scene(name: str, args: argparse.Namespace, workdir: Path, console: Console) -> dict[str, Any]:
    """Generate, build, load and query one scene; returns its results."""
    spec = SCENES[name]
    settings = nav.PRESETS[spec.preset]
    console.print(f"[bold]{name}[/]: generating ...", highlight=False)
    start = time.perf_counter()
    scene = (spec.quick if args.quick else spec.full)(args.seed)
    generate_s = time.perf_counter() - start
    console.print(f"  {scene.description}; {scene.num_triangles:,} triangles; building ...", highlight=False)
    build, navmesh_file = build_in_fresh_process(scene, settings, args.jobs, workdir)
    scene_info = {
        "description": scene.description,
        "triangles": scene.num_triangles,
        "vertices": len(scene.vertices),
        "counts": scene.counts,
        "generate_s": generate_s,
        "preset": spec.preset,
        "cell_size": settings.cell_size,
    }
    del scene

    start = time.perf_counter()
    finder = nav.load(navmesh_file)
    load_s = time.perf_counter() - start
    navmesh_info = {
        "tiles": finder.num_tiles,
        "polygons": finder.num_polygons,
        "navigable_area_m2": finder.navigable_area,
        "islands": finder.num_islands,
        "largest_island_m2": float(finder.island_areas[0]),
        "file_mib": navmesh_file.stat().st_size / 2**20,
        "load_s": load_s,
    }

    console.print(
        f"  built in {build['build_s']:.1f} s; sampling {args.queries} queries ...", highlight=False
    )
    pairs = sample_pairs(finder, args.queries, np.random.default_rng((args.seed, 1)))
    nav_us, nav_m, nav_flat_m = time_navmesh(finder, pairs, args.repeats)
    start = time.perf_counter()
    view = finder.get_topdown_view(settings.cell_size)
    topdown_s = time.perf_counter() - start
    planners: dict[str, dict[str, Any]] = {
        "navmesh": {
            "queries": len(pairs),
            **time_stats(nav_us),
            "geodesic_median_m": float(np.median(nav_m)),
            "geodesic_min_m": float(nav_m.min()),
            "geodesic_max_m": float(nav_m.max()),
        },
    }
    per_query: dict[str, list[float]] = {"geodesic_m": nav_m.tolist(), "navmesh_us": nav_us.tolist()}
    for variant, offsets in GRID_VARIANTS.items():
        console.print(
            f"  {variant} on a {view.image.shape[0]} x {view.image.shape[1]} grid ...", highlight=False
        )
        peer_us, peer_m, runnable = time_grid(view, pairs, offsets, args.margin, args.peer_repeats)
        planners[variant] = peer_stats(peer_us, peer_m, runnable, nav_us, nav_flat_m)
        per_query[f"{variant} us"] = peer_us.tolist()
        per_query[f"{variant} m"] = peer_m.tolist()
    return {
        "scene": scene_info,
        "build": build,
        "navmesh": navmesh_info,
        "grid": {
            "shape": list(view.image.shape),
            "free_fraction": float(view.image.mean()),
            "topdown_s": topdown_s,
        },
        "planners": planners,
        "per_query": per_query,
    }


# ---------------------------------------------------------------------- resolutions


def resolution_settings(scene: Scene) -> dict[str, nav.NavMeshSettings]:
    """The builds compared: 10 cm, 10 cm with 5 cm tiles over the scene's centre, 5 cm."""
    lo, hi = scene.vertices[:, :2].min(axis=0), scene.vertices[:, :2].max(axis=0)
    center, half = (lo + hi) / 2, FINE_REGION_SIDE * (hi - lo) / 2
    region = (*(center - half).tolist(), *(center + half).tolist())
    return {
        "outdoor": nav.OUTDOOR,
        "i2o + region": nav.I2O.with_overrides({"fine_region": region}),
        "indoor": nav.INDOOR,
    }


def bench_resolutions(args: argparse.Namespace, workdir: Path, console: Console) -> dict[str, Any]:
    """Build one city at each of :func:`resolution_settings`; returns the builds' figures."""
    scene = RESOLUTION_CITY["quick" if args.quick else "full"](args.seed)
    console.print(
        f"[bold]resolutions[/]: {scene.description}; {scene.num_triangles:,} triangles", highlight=False
    )
    builds: dict[str, dict[str, Any]] = {}
    for label, settings in resolution_settings(scene).items():
        console.print(f"  building with {label} ...", highlight=False)
        build, navmesh_file = build_in_fresh_process(
            scene, settings, args.jobs, workdir, label=label.split()[0]
        )
        finder = nav.load(navmesh_file)
        builds[label] = {
            **build,
            "cell_size": settings.cell_size,
            "fine_region": settings.fine_region,
            "fine_factor": settings.fine_factor,
            "tiles": finder.num_tiles,
            "polygons": finder.num_polygons,
            "navigable_area_m2": finder.navigable_area,
            "islands": finder.num_islands,
            "file_mib": navmesh_file.stat().st_size / 2**20,
        }
        navmesh_file.unlink()
    return {"scene": scene.description, "region_area_share": FINE_REGION_SIDE**2, "builds": builds}


def resolution_table(result: dict[str, Any]) -> Table:
    """Build figures per resolution and their ratios to the outdoor (10 cm) build."""
    title = (
        f"resolutions: {result['scene']}; i2o region: the central {100 * result['region_area_share']:.0f} % "
        "of the area (the tiles meeting it cover more)"
    )
    table = Table(title=title, title_justify="left")
    table.add_column("settings", no_wrap=True)
    for header in (
        "wall s",
        "× outdoor",
        "CPU s",
        "build MiB",
        "× outdoor",
        "polygons",
        "× outdoor",
        "file MiB",
    ):
        table.add_column(header, justify="right", no_wrap=True)
    base = result["builds"]["outdoor"]
    base_mib = base["peak_after_mib"] - base["rss_before_mib"]
    for label, build in result["builds"].items():
        build_mib = build["peak_after_mib"] - build["rss_before_mib"]
        table.add_row(
            label,
            f"{build['build_s']:.2f}",
            f"{build['build_s'] / base['build_s']:.2f}",
            f"{build['cpu_s']:.2f}",
            f"{build_mib:.0f}",
            f"{build_mib / base_mib:.2f}" if base_mib > 0 else "",
            f"{build['polygons']:,}",
            f"{build['polygons'] / base['polygons']:.2f}",
            f"{build['file_mib']:.1f}",
        )
    return table


# ---------------------------------------------------------------------- report


def build_table(name: str, result: dict[str, Any]) -> Table:
    """Scene and navmesh build figures as a two-column table."""
    scene, build, mesh, grid = result["scene"], result["build"], result["navmesh"], result["grid"]
    table = Table(title=f"{name}: scene and navmesh build", show_header=False, title_justify="left")
    table.add_column(style="bold")
    table.add_column()
    busy = build["cpu_s"] / build["build_s"]
    build_mib = build["peak_after_mib"] - build["rss_before_mib"]
    largest_pct = 100 * mesh["largest_island_m2"] / mesh["navigable_area_m2"]
    rows = [
        ("scene", scene["description"]),
        ("mesh", f"{scene['triangles']:,} triangles, {scene['vertices']:,} vertices"),
        ("generated", f"{scene['generate_s']:.1f} s"),
        ("settings", f"nav.{scene['preset'].upper()} (cell {scene['cell_size']:g} m)"),
        ("build (wall)", f"{build['build_s']:.2f} s, CPU {build['cpu_s']:.2f} s ({busy:.2f} cores busy)"),
        (
            "memory (RSS)",
            f"{build['rss_before_mib']:.0f} MiB before, peak {build['peak_after_mib']:.0f} MiB: "
            f"build +{build_mib:.0f} MiB",
        ),
        ("navmesh", f"{mesh['tiles']:,} tiles, {mesh['polygons']:,} polygons"),
        ("navigable", f"{mesh['navigable_area_m2']:,.0f} m2"),
        ("islands", f"{mesh['islands']}, largest {mesh['largest_island_m2']:,.0f} m2 ({largest_pct:.1f} %)"),
        ("file", f"{mesh['file_mib']:.1f} MiB, loaded in {mesh['load_s']:.2f} s"),
        (
            "grid",
            f"{grid['shape'][0]:,} x {grid['shape'][1]:,} cells, {100 * grid['free_fraction']:.0f} % free "
            f"(top-down view in {grid['topdown_s']:.2f} s)",
        ),
    ]
    for key, value in rows:
        table.add_row(key, value)
    return table


def query_table(name: str, result: dict[str, Any], margin: float) -> Table:
    """Query timings and path-length agreement, one row per planner."""
    navmesh = result["planners"]["navmesh"]
    title = (
        f"{name}: find_path on {navmesh['queries']} pairs {MIN_GEODESIC:g}-{MAX_GEODESIC:g} m apart "
        f"(geodesic median {navmesh['geodesic_median_m']:.1f} m); grid cropped to the pair's bounding "
        f"box + {margin:g} m"
    )
    table = Table(title=title, title_justify="left")
    table.add_column("planner", no_wrap=True)
    for header in ("queries", "median µs", "p90 µs", "× nav", "× medians", "longer med %"):
        table.add_column(header, justify="right", no_wrap=True)
    for header in ("p90 %", "max %", "min %", "blocked", "unreached"):
        table.add_column(header, justify="right", no_wrap=True)
    for planner, stats in result["planners"].items():
        if not stats["queries"]:
            table.add_row(
                planner, "0", *[""] * 8, str(stats["skipped_blocked_cell"]), str(stats["unreached"])
            )
            continue
        row = [planner, str(stats["queries"]), f"{stats['median_us']:,.0f}", f"{stats['p90_us']:,.0f}"]
        if planner == "navmesh":
            row += ["1", "1", "", "", "", "", "", ""]
        else:
            row += [f"{stats['ratio_median_of_ratios']:,.0f}", f"{stats['ratio_of_medians']:,.0f}"]
            row += [f"{stats[f'length_excess_{key}_pct']:+.2f}" for key in ("median", "p90", "max", "min")]
            row += [str(stats["skipped_blocked_cell"]), str(stats["unreached"])]
        table.add_row(*row)
    return table


def load_average() -> float:
    """The 1-minute load average (NaN where unknown): other work on the machine skews timings."""
    try:
        return os.getloadavg()[0]
    except OSError:
        return math.nan


def machine_info() -> dict[str, Any]:
    """Where the benchmark ran."""
    return {
        "cpus": os.cpu_count(),
        "load_average_start": load_average(),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scikit-image": skimage.__version__,
    }


def json_safe(value: Any) -> Any:
    """``value`` with NaN and infinities replaced by None (JSON has no such numbers), recursively."""
    if isinstance(value, dict):
        return {key: json_safe(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(item) for item in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, Path):
        return str(value)
    return value


# ---------------------------------------------------------------------- command line


def parse_args(argv: Sequence[str] | None = None) -> argparse.Namespace:
    """Command-line flags."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--scenes", nargs="+", choices=list(SCENES), default=list(SCENES), help="scenes to run"
    )
    parser.add_argument("--queries", type=int, default=200, help="query pairs per scene (default 200)")
    parser.add_argument("--seed", type=int, default=0, help="seed of scenes and queries (default 0)")
    parser.add_argument("--json", type=Path, default=None, metavar="PATH", help="also write the results here")
    parser.add_argument(
        "--quick", action="store_true", help="small scenes (30 m x 20 m building, 200 m city)"
    )
    parser.add_argument("--repeats", type=int, default=5, help="navmesh repetitions per query (min taken)")
    parser.add_argument("--peer-repeats", type=int, default=2, help="grid repetitions per query (min taken)")
    parser.add_argument("--margin", type=float, default=15.0, help="grid crop margin around a pair (m)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="navmesh build threads")
    parser.add_argument(
        "--resolutions",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="compare build costs at 10 cm, 10 cm with a 5 cm region, and 5 cm (default: on)",
    )
    args = parser.parse_args(argv)
    for flag in ("queries", "repeats", "peer_repeats", "jobs"):
        if getattr(args, flag) < 1:
            parser.error(f"--{flag.replace('_', '-')} must be at least 1")
    if args.margin < 0:
        parser.error("--margin must not be negative")
    return args


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark; returns the exit code."""
    args = parse_args(argv)
    console = Console(width=None if sys.stdout.isatty() else 130)
    started = time.perf_counter()
    machine = machine_info()
    console.print(
        f"navmesh benchmark: {machine['cpus']} CPUs, build jobs {args.jobs}, seed {args.seed}, "
        f"{args.queries} queries{', quick scenes' if args.quick else ''}; "
        f"load average {machine['load_average_start']:.2f}",
        highlight=False,
    )
    results: dict[str, Any] = {}
    resolutions: dict[str, Any] | None = None
    with tempfile.TemporaryDirectory(prefix="navverse-bench-") as tmp:
        for name in args.scenes:
            results[name] = bench_scene(name, args, Path(tmp), console)
            console.print(build_table(name, results[name]))
            console.print(query_table(name, results[name], args.margin))
        if args.resolutions:
            resolutions = bench_resolutions(args, Path(tmp), console)
            console.print(resolution_table(resolutions))
    total_s = time.perf_counter() - started
    console.print(
        "× nav: median of the per-query time ratios grid / navmesh; × medians: ratio of the median times. "
        "longer %: (grid path length - navmesh path length) / navmesh path length, both horizontal, "
        "over the queries both solved. "
        "blocked: pairs skipped because the start or end cell is not free in the grid; "
        "unreached: the grid found no path inside its crop.",
        highlight=False,
    )
    if resolutions is not None:
        console.print(
            "resolutions: × outdoor is the ratio to the nav.OUTDOOR build (10 cm); i2o + region builds "
            "the tiles meeting the region at 5 cm; nav.INDOOR is 5 cm everywhere (and a 0.20 m climb). "
            "build MiB: peak RSS after the build less RSS before it.",
            highlight=False,
        )
    machine["load_average_end"] = load_average()
    console.print(f"total {total_s:.0f} s; load average {machine['load_average_end']:.2f}", highlight=False)
    if args.json is not None:
        report = {"benchmark": "navmesh", "args": vars(args), "machine": machine}
        report |= {"total_s": total_s, "scenes": results, "resolutions": resolutions}
        args.json.write_text(json.dumps(json_safe(report), indent=1, allow_nan=False))
        console.print(f"wrote {args.json}", highlight=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
