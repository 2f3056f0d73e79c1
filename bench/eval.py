"""Scoring benchmark: ``navverse.eval`` scoring against a plain-Python implementation of the same formulas.

On synthetic data (numpy only, deterministic from ``--seed``):

1. A 200 m x 200 m outdoor scene as :class:`navverse.scene.fields.SceneFields` at 0.1 m: a street
   grid (roads, sidewalks, crosswalks), blocks of grass with box buildings (a non-navigable class),
   box objects (cars, benches) on the navigable ground, a strip with no surface along the border; the
   obstacle raster and its Euclidean distance transform as ``scene_fields`` makes them.
2. ``--trajectories`` records of ``--seconds`` at ``--hz`` for the Spot-like robot (``[t, x, y, z, qx,
   qy, qz, qw]``, unit quaternions), each from its own generator: a smooth random walk (cruise speed
   log-uniform in 0.1-1.3 m/s, Ornstein-Uhlenbeck yaw rate and speed, mirrored at the scene's edges, z
   on gentle hills, a few degrees of roll and pitch). By ``index % 10``: two stand still near the goal
   for the rest of the record and stop (success), one stops far from it (wrong goal), one falls (the
   tilt ramps to 80° in a second and the rows go on), one passes the goal without stopping, four wander,
   one starts inside a large goal (d_0 = 0; with ``index % 20 == 9`` it never moves: L = P = 0). A
   seventh of the records run 2 s longer (cut at 300 s when ``--seconds`` is over 298); a third are
   VLN, whose reference path is the first (up to) 50 m the robot walked, half a meter off (nDTW). One
   to four goal instances; collisions are not reported, so CR is the footprint against the obstacle
   field.
3. Ours: :func:`navverse.eval.measures.measure` on batches of ``scoring.BATCH_ROWS`` rows (as
   ``navverse eval`` batches them), then :func:`~navverse.eval.metrics.compute_metrics` over every
   episode. The records are generated a batch at a time (10 000 x 15 001 rows would be 9.6 GB);
   generation is timed apart from scoring.
4. Peer, in the same run on the first ``--reference`` records: :func:`reference_scores`, the same
   definitions written from DESIGN.md §3 as a per-record, per-row loop in plain Python (``math``,
   lists, no numpy). Its values must agree with ours to 1e-6 (absolute or relative) for every metric
   and the same label, or the script exits 1.

Run ``python bench/eval.py`` (what ``make bench`` does). Timings are measurements, never assertions;
the printed load average shows whether other work shared the machine.
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import os
import platform
import resource
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table
from scipy import ndimage, signal

from navverse.eval.measures import MEASURES, EpisodeTarget, Robot, measure
from navverse.eval.metrics import compute_metrics
from navverse.eval.scoring import BATCH_ROWS, robot_for
from navverse.scene.fields import SceneFields

SCENE = "synthetic-city"
CLASSES = ("sidewalk", "road", "crosswalk", "green", "building")
SIDEWALK, ROAD, CROSSWALK, GREEN, BUILDING = range(len(CLASSES))
SCENE_PREFERRED = frozenset({"sidewalk", "crosswalk"})
"""The classes the synthetic scene marks ``preferred`` (the robot adds its ``extra_surfaces``)."""
CELL = 0.1
STANDING = 0.55
"""Base height above the ground (m)."""
KINDS = ("success", "success", "wrong_goal", "fall", "passes_goal", "wander", "wander", "wander", "wander",
         "at_goal")  # fmt: skip
"""The kind of record ``index % 10``."""
TASKS = ("objnav", "placenav", "vln")
"""The task of record ``index % 3``."""
OVERRUN = 2.0
"""Records with ``index % 7 == 5`` last this much longer than ``--seconds`` (s)."""
COMPARED = ("success", "spl", "soft_success", "soft_spl", "ne", "os", "ce", "cr", "ado", "nsr", "path_length",
            "speed", "ndtw", "sdtw")  # fmt: skip
TOLERANCE = 1e-6


@dataclass(frozen=True, eq=False)
class Record:
    """One synthetic submission record and the episode it answers."""

    rows: np.ndarray
    target: EpisodeTarget
    stop: bool


# ---------------------------------------------------------------------- synthetic data


def synthetic_fields(size: float, seed: int) -> SceneFields:
    """A ``size`` x ``size`` m street grid at 0.1 m, with the fields ``scene_fields`` would make of it."""
    rng = np.random.default_rng([seed, 1])
    n = max(20, round(size / CELL))
    terrain = np.full((n, n), GREEN, dtype=np.int16)
    objects = np.zeros((n, n), dtype=bool)
    pitch, road, walk = 40.0, 8.0, 3.0

    def cells(metres: float) -> int:
        return round(metres / CELL)

    streets = [cells(s) for s in np.arange(pitch / 2, size, pitch)]
    for c in streets:  # sidewalks, then roads over them, then crosswalks where roads cross
        half = cells(road / 2 + walk)
        terrain[:, max(0, c - half) : c + half] = SIDEWALK
        terrain[max(0, c - half) : c + half, :] = SIDEWALK
    for c in streets:
        half = cells(road / 2)
        terrain[:, max(0, c - half) : c + half] = ROAD
        terrain[max(0, c - half) : c + half, :] = ROAD
    for cy in streets:
        for cx in streets:
            half, band = cells(road / 2), cells(2.0)
            terrain[max(0, cy - half) : cy + half, max(0, cx - half - band) : cx - half] = CROSSWALK
            terrain[max(0, cy - half) : cy + half, cx + half : cx + half + band] = CROSSWALK
    green = np.argwhere(terrain == GREEN)
    for _ in range(round(0.4 * (size / pitch) ** 2)):  # box buildings on the grass
        r, c = green[rng.integers(len(green))]
        h, w = cells(rng.uniform(4.0, 14.0)), cells(rng.uniform(4.0, 14.0))
        block = terrain[r : r + h, c : c + w]
        block[block == GREEN] = BUILDING
    for _ in range(round(6 * (size / pitch) ** 2)):  # cars, benches, bins: obstacles on navigable ground
        r, c = rng.integers(0, n, size=2)
        objects[r : r + cells(rng.uniform(0.4, 4.5)), c : c + cells(rng.uniform(0.4, 2.0))] = True
    border = cells(1.0)
    terrain[:border, :] = terrain[-border:, :] = terrain[:, :border] = terrain[:, -border:] = -1
    obstacle = (terrain == BUILDING) | objects
    distance = ndimage.distance_transform_edt(~obstacle).astype(np.float32) * np.float32(CELL)
    return SceneFields((0.0, 0.0), CELL, terrain, obstacle, distance, CLASSES)


def preferred_flags(fields: SceneFields, robot: Robot) -> np.ndarray:
    """A bool per terrain class (and a last one for no surface), as ``navverse eval`` builds them."""
    names = fields.class_names
    return np.array([n in SCENE_PREFERRED or n in robot.extra_surfaces for n in names] + [False], dtype=bool)


def hills(x: np.ndarray | float, y: np.ndarray | float) -> np.ndarray:
    """Ground height (m)."""
    return 0.4 * np.sin(np.asarray(x) / 17.0) * np.cos(np.asarray(y) / 23.0)


def _ou(rng: np.random.Generator, n: int, dt: float, tau: float, sigma: float) -> np.ndarray:
    """An Ornstein-Uhlenbeck process (stationary standard deviation `sigma`, time constant `tau`)."""
    a = math.exp(-dt / tau)
    noise = rng.standard_normal(n) * sigma * math.sqrt(1.0 - a * a)
    noise[0] = rng.standard_normal() * sigma
    return signal.lfilter([1.0], [1.0, -a], noise)


def _fold(u: np.ndarray, lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    """`u` mirrored into [lo, hi], and where it runs mirrored."""
    span = hi - lo
    m = np.mod(u - lo, 2.0 * span)
    flipped = m > span
    return lo + np.where(flipped, 2.0 * span - m, m), flipped


def _quaternion(roll: np.ndarray, pitch: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """``[x, y, z, w]`` of the rotation yaw (z), then pitch (y), then roll (x)."""
    cr, sr = np.cos(roll / 2), np.sin(roll / 2)
    cp, sp = np.cos(pitch / 2), np.sin(pitch / 2)
    cy, sy = np.cos(yaw / 2), np.sin(yaw / 2)
    q = np.stack([sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
                  cr * cp * cy + sr * sp * sy], axis=1)  # fmt: skip
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _free_point(rng: np.random.Generator, fields: SceneFields, margin: float) -> np.ndarray:
    size = fields.terrain.shape[1] * fields.cell
    while True:
        p = rng.uniform(margin, size - margin, size=2)
        if fields.distance_at(p) > 1.0:
            return p


def _goal(rng: np.random.Generator, near: np.ndarray, gap: float) -> tuple[np.ndarray, float]:
    """A goal instance whose edge is `gap` m (horizontally) from `near`, and its radius."""
    radius = 0.5 * max(rng.uniform(0.4, 3.0), rng.uniform(0.4, 3.0))
    heading = rng.uniform(0.0, 2.0 * math.pi)
    xy = near[:2] + (radius + gap) * np.array([math.cos(heading), math.sin(heading)])
    return np.array([xy[0], xy[1], near[2] + rng.uniform(-0.2, 0.2)]), radius


def synthetic_record(index: int, *, seed: int, hz: float, seconds: float, fields: SceneFields) -> Record:
    """Record `index`, the same whatever the batch it is made in (its own generator)."""
    rng = np.random.default_rng([seed, 0, index])
    kind, task = KINDS[index % len(KINDS)], TASKS[index % len(TASKS)]
    duration = seconds + (OVERRUN if index % 7 == 5 else 0.0)
    n = math.floor(duration * hz + 1e-9) + 1
    dt = 1.0 / hz
    t = np.arange(n) / hz
    size = fields.terrain.shape[1] * fields.cell
    start = _free_point(rng, fields, margin=5.0)
    cruise = math.exp(rng.uniform(math.log(0.1), math.log(1.3)))  # m/s, log-uniform
    speed = cruise * np.clip(1.0 + _ou(rng, n, dt, tau=5.0, sigma=0.3), 0.0, 2.0)
    moving = np.ones(n)
    until = rng.uniform(0.4, 0.95) * duration
    if kind in ("success", "wrong_goal", "fall"):
        moving[t > until] = 0.0  # it stands still (and stops, or lies where it fell) for the rest
    if kind == "at_goal":
        speed *= 0.0 if index % 20 == 9 else 0.01
    yaw = rng.uniform(-math.pi, math.pi) + np.cumsum(_ou(rng, n, dt, tau=3.0, sigma=0.4)) * dt
    step = speed * moving * dt
    xy = start + np.concatenate([[[0.0, 0.0]], np.cumsum(step[1:, None] * np.stack(
        [np.cos(yaw[1:]), np.sin(yaw[1:])], axis=1), axis=0)])  # fmt: skip
    x, flip_x = _fold(xy[:, 0], 2.0, size - 2.0)
    y, flip_y = _fold(xy[:, 1], 2.0, size - 2.0)
    heading = np.arctan2(np.where(flip_y, -1.0, 1.0) * np.sin(yaw), np.where(flip_x, -1.0, 1.0) * np.cos(yaw))
    z = hills(x, y) + STANDING
    phase = rng.uniform(0.0, 2.0 * math.pi, size=2)
    roll = np.radians(3.0) * np.sin(0.7 * t + phase[0])
    pitch = np.radians(2.0) * np.sin(1.1 * t + phase[1])
    if kind == "fall":
        roll = roll + np.radians(80.0) * np.clip(t - until, 0.0, 1.0)  # over in a second
    rows = np.column_stack([t, x, y, z, _quaternion(roll, pitch, heading)])
    xyz = rows[:, 1:4]
    end = xyz[np.searchsorted(t, min(duration, 300.0), side="right") - 1]
    if kind == "success":
        primary = _goal(rng, end, rng.uniform(0.0, 1.4))
    elif kind == "passes_goal":
        primary = _goal(rng, xyz[rng.integers(n // 4, n // 2)], rng.uniform(0.0, 1.0))
    elif kind == "at_goal":
        primary = (xyz[0] + np.array([0.0, 0.0, 0.1]), rng.uniform(2.0, 3.0))
    else:
        far = np.append(_free_point(rng, fields, margin=5.0), 0.0)
        primary = _goal(rng, far + np.array([0.0, 0.0, hills(*far[:2]) + STANDING]), 0.0)
    goals = [primary]
    for _ in range(index % 4 if task != "vln" else 0):  # other instances of the category
        other = _free_point(rng, fields, margin=5.0)
        goals.append(_goal(rng, np.array([*other, float(hills(*other)) + STANDING]), 0.0))
    centers = np.array([g[0] for g in goals])
    radii = np.array([g[1] for g in goals])
    gap = np.linalg.norm(centers[:, :2] - xyz[0, :2], axis=1) - radii - 1.6
    geodesic = float(max(0.0, gap.min()) * rng.uniform(1.0, 1.3)) if kind != "at_goal" else 0.0
    reference = np.zeros((0, 3))
    if task == "vln":  # what the robot walked first, up to 50 m, half a meter off
        scored = np.searchsorted(t, min(duration, 300.0), side="right")
        along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xyz[:scored, :2], axis=0), axis=1))])
        last = max(1, int(np.searchsorted(along, rng.uniform(0.3, 1.0) * min(along[-1], 50.0))))
        k = int(np.clip(along[min(last, scored - 1)] / 2.0, 2, 40))
        reference = xyz[np.linspace(0, min(last, scored - 1), k).round().astype(int)].copy()
        reference[1:-1, :2] += rng.normal(0.0, 0.5, size=(k - 2, 2))
    target = EpisodeTarget(
        episode_id=f"{SCENE}-{task}-{index:05d}",
        scene_id=SCENE,
        task=task,
        goal_centers=centers,
        goal_radii=radii,
        geodesic=geodesic,
        reference_path=reference,
        scene_type="indoor",
    )
    return Record(rows=rows, target=target, stop=kind in ("success", "wrong_goal", "at_goal"))


# ---------------------------------------------------------------------- the plain-Python reference

# The definitions of DESIGN.md §3 "Metrics", written out again rather than imported from the code under test.
REF_TIMEOUT = 300.0
REF_FALL_DEG = 45.0
REF_CELL = 1.0
REF_EPSILON = 1.0
REF_DENSIFY = 0.25
REF_DTW_SPACING = 0.5


@dataclass(frozen=True)
class PlainGrid:
    """The scene fields as flat Python lists (row-major, row 0 at the minimum y)."""

    x0: float
    y0: float
    cell: float
    rows: int
    cols: int
    distance: list[float]
    terrain: list[int]
    preferred: dict[int, bool]

    @classmethod
    def of(cls, fields: SceneFields, preferred_classes: set[str] | frozenset[str]) -> PlainGrid:
        flags = {i: name in preferred_classes for i, name in enumerate(fields.class_names)}
        flags[-1] = False
        return cls(float(fields.origin[0]), float(fields.origin[1]), float(fields.cell),
                   fields.terrain.shape[0], fields.terrain.shape[1], fields.distance.ravel().tolist(),
                   fields.terrain.ravel().tolist(), flags)  # fmt: skip

    def index(self, x: float, y: float) -> int:
        col = min(max(math.floor((x - self.x0) / self.cell), 0), self.cols - 1)
        row = min(max(math.floor((y - self.y0) / self.cell), 0), self.rows - 1)
        return row * self.cols + col


def _resample_plain(points: Points, spacing: float) -> Points:
    if len(points) < 2:
        return list(points)
    along = [0.0]
    for (x0, y0), (x1, y1) in itertools.pairwise(points):
        along.append(along[-1] + math.sqrt((x1 - x0) ** 2 + (y1 - y0) ** 2))
    total = along[-1]
    if total <= 0.0:
        return points[:1]
    out, j, i = [], 0, 0
    while i * spacing < total:
        s = i * spacing
        while along[j + 1] <= s:  # the segment with along[j] <= s < along[j + 1]
            j += 1
        f = (s - along[j]) / (along[j + 1] - along[j])
        (x0, y0), (x1, y1) = points[j], points[j + 1]
        out.append((x0 + f * (x1 - x0), y0 + f * (y1 - y0)))
        i += 1
    out.append(points[-1])
    return out


Points = list[tuple[float, float]]


def _ndtw_plain(path: Points, reference: Points, threshold: float) -> float:
    q = _resample_plain(path, REF_DTW_SPACING)
    r = _resample_plain(reference, REF_DTW_SPACING)
    previous = [0.0] + [math.inf] * len(r)  # D[i - 1, j - 1] at index j, with D[-1, -1] = 0
    for qx, qy in q:
        current = [math.inf]
        for j, (rx, ry) in enumerate(r):
            cost = math.sqrt((qx - rx) ** 2 + (qy - ry) ** 2)
            current.append(cost + min(previous[j + 1], current[j], previous[j]))
        previous = current
    return math.exp(-previous[-1] / (len(r) * threshold))


def reference_scores(record: Record, robot: Robot, grid: PlainGrid) -> dict[str, Any]:
    """Every metric and the label of one record: a loop over its rows in plain Python."""
    rows = record.rows.tolist()
    target = record.target
    goals = [(*c, r) for c, r in zip(target.goal_centers.tolist(), target.goal_radii.tolist(), strict=True)]
    tolerance = 1.0 + robot.radius
    half = robot.width / 2.0
    reach = max(robot.length / 2.0 - half, 0.0)
    touch_below = half - grid.cell / 2.0  # a footprint point this close to an obstacle cell touches it

    kept, fell = [], False
    for i, row in enumerate(rows):
        if i > 0 and row[0] > REF_TIMEOUT:
            break  # timed out here
        kept.append(row)
        qx, qy = row[4], row[5]
        cos_tilt = 1.0 - 2.0 * (qx * qx + qy * qy)  # z of the base's z axis
        if math.degrees(math.acos(max(-1.0, min(1.0, cos_tilt)))) > REF_FALL_DEG:
            fell = True
            break  # fell here

    def goal_distance(x: float, y: float, z: float) -> float:
        edge = min(math.sqrt((x - gx) ** 2 + (y - gy) ** 2 + (z - gz) ** 2) - r for gx, gy, gz, r in goals)
        return max(0.0, edge)

    d_start = goal_distance(*kept[0][1:4])
    d_min = math.inf
    path = clearance = on_preferred = 0.0
    collided = False
    cells = set()
    previous = None
    for _, x, y, z, qx, qy, qz, qw in kept:
        d = goal_distance(x, y, z)
        d_min = min(d_min, d)
        if previous is not None:
            px, py, pz = previous
            path += math.sqrt((x - px) ** 2 + (y - py) ** 2 + (z - pz) ** 2)
            dx, dy = x - px, y - py
            parts = max(1, math.ceil(math.sqrt(dx * dx + dy * dy) / REF_DENSIFY))
            for j in range(parts):  # the segment from the previous row, its end left to the next
                f = j / parts
                cells.add((math.floor((px + dx * f) / REF_CELL), math.floor((py + dy * f) / REF_CELL)))
        previous = (x, y, z)
        at = grid.index(x, y)
        clearance += grid.distance[at]
        on_preferred += grid.preferred[grid.terrain[at]]
        if not collided:
            yaw = math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
            ax, ay = math.cos(yaw), math.sin(yaw)
            for k in (-1.0, -0.5, 0.0, 0.5, 1.0):  # points along the capsule's axis
                if grid.distance[grid.index(x + k * reach * ax, y + k * reach * ay)] < touch_below:
                    collided = True
                    break
    cells.add((math.floor(previous[0] / REF_CELL), math.floor(previous[1] / REF_CELL)))
    d_end = goal_distance(*previous)
    duration = kept[-1][0] - kept[0][0]

    if fell:
        label = "fall"
    elif d_end <= tolerance:
        label = "success"
    elif record.stop:
        label = "wrong_goal"
    else:
        label = "timeout"
    success = 1.0 if label == "success" else 0.0
    geodesic = target.geodesic
    efficiency = 1.0 if max(geodesic, path) == 0 else geodesic / max(geodesic, path)
    soft = max(0.0, 1.0 - d_end / d_start) if d_start > 0 else (1.0 if d_end == 0 else 0.0)
    ndtw = math.nan
    if target.task == "vln" and len(target.reference_path) >= 2:
        walked = [(row[1], row[2]) for row in kept]
        ndtw = _ndtw_plain(walked, [(p[0], p[1]) for p in target.reference_path.tolist()], tolerance)
    return {
        "label": label,
        "success": success,
        "spl": success * efficiency,
        "soft_success": soft,
        "soft_spl": soft * efficiency,
        "ne": d_end,
        "os": 1.0 if d_min <= tolerance else 0.0,
        "ce": len(cells) / max(path, REF_EPSILON),
        "cr": 1.0 if collided else 0.0,
        "ado": clearance / len(kept),
        "nsr": on_preferred / len(kept),
        "path_length": path,
        "speed": path / duration if duration > 0 else 0.0,
        "ndtw": ndtw,
        "sdtw": success * ndtw,
    }


# ---------------------------------------------------------------------- the run


def agreement(ours: dict[str, np.ndarray], reference: list[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Per metric: the largest absolute difference and the records beyond the tolerance (and the label)."""
    out: dict[str, dict[str, Any]] = {}
    for name in COMPARED:
        worst, bad = 0.0, []
        for i, ref in enumerate(reference):
            a, b = float(ours[name][i]), float(ref[name])
            if math.isnan(a) and math.isnan(b):
                continue
            diff = abs(a - b) if not (math.isnan(a) or math.isnan(b)) else math.inf
            worst = max(worst, diff)
            if not math.isclose(a, b, rel_tol=TOLERANCE, abs_tol=TOLERANCE):
                bad.append({"record": i, "ours": a, "reference": b})
        out[name] = {"max_abs_diff": worst, "disagree": bad}
    labels = [
        {"record": i, "ours": str(ours["label"][i]), "reference": ref["label"]}
        for i, ref in enumerate(reference)
        if str(ours["label"][i]) != ref["label"]
    ]
    out["label"] = {"max_abs_diff": float(len(labels)), "disagree": labels}
    return out


def peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def run(args: argparse.Namespace, console: Console) -> dict[str, Any]:
    """Generate, score, run the reference; returns every figure."""
    robot = robot_for("spot")
    w0 = time.perf_counter()
    fields = synthetic_fields(args.scene_size, args.seed)
    preferred = preferred_flags(fields, robot)
    fields_s = time.perf_counter() - w0
    count = args.trajectories
    rows_each = math.floor(args.seconds * args.hz + 1e-9) + 1
    per_batch = args.batch or max(1, BATCH_ROWS // rows_each)
    measures = {name: np.full(count, np.nan) for name in MEASURES}
    geodesic = np.zeros(count)
    sample: list[Record] = []
    generate_s = measure_s = measure_cpu = 0.0
    rows_total = 0
    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn())
    with Progress(*columns, console=console, transient=True) as progress:
        task = progress.add_task("generate + score", total=count)
        for first in range(0, count, per_batch):
            w0 = time.perf_counter()
            records = [
                synthetic_record(i, seed=args.seed, hz=args.hz, seconds=args.seconds, fields=fields)
                for i in range(first, min(count, first + per_batch))
            ]
            generate_s += time.perf_counter() - w0
            w0, c0 = time.perf_counter(), time.process_time()
            values = measure(
                [r.rows for r in records],
                [r.target for r in records],
                robot=robot,
                stops=[r.stop for r in records],
                collisions=[None] * len(records),
                fields={SCENE: fields},
                preferred={SCENE: preferred},
            )
            measure_s += time.perf_counter() - w0
            measure_cpu += time.process_time() - c0
            chosen = slice(first, first + len(records))
            for name, array in values.items():
                measures[name][chosen] = array
            geodesic[chosen] = [r.target.geodesic for r in records]
            rows_total += sum(len(r.rows) for r in records)
            sample.extend(records[: max(0, args.reference - len(sample))])
            progress.advance(task, len(records))
            del records, values
    reach = np.full(count, robot.success_distance("indoor"))
    inputs = {**measures, "geodesic": geodesic, "success_distance": reach, "valid": np.ones(count)}
    w0, c0 = time.perf_counter(), time.process_time()
    metrics = compute_metrics(inputs)
    compute_s, compute_cpu = time.perf_counter() - w0, time.process_time() - c0
    peak_scoring = peak_rss_mb()

    w0 = time.perf_counter()
    grid = PlainGrid.of(fields, set(SCENE_PREFERRED) | set(robot.extra_surfaces))
    grid_s = time.perf_counter() - w0
    reference: list[dict[str, Any]] = []
    w0, c0 = time.perf_counter(), time.process_time()
    for record in sample:
        reference.append(reference_scores(record, robot, grid))
    reference_s, reference_cpu = time.perf_counter() - w0, time.process_time() - c0
    sample_rows = sum(len(r.rows) for r in sample)
    labels, counts = np.unique(metrics["label"].astype(str), return_counts=True)
    ours_each = (measure_s + compute_s) / count
    ref_each = reference_s / len(sample) if sample else math.nan
    return {
        "trajectories": count,
        "rows": rows_total,
        "rows_per_trajectory": rows_each,
        "batch_trajectories": per_batch,
        "fields": {
            "shape": list(fields.terrain.shape),
            "cell": fields.cell,
            "seconds": fields_s,
            "obstacle_share": float(fields.obstacle.mean()),
        },
        "generate_s": generate_s,
        "measure_s": measure_s,
        "measure_cpu_s": measure_cpu,
        "compute_metrics_s": compute_s,
        "compute_metrics_cpu_s": compute_cpu,
        "scoring_s": measure_s + compute_s,
        "rows_per_s": rows_total / (measure_s + compute_s),
        "peak_rss_mb_after_scoring": peak_scoring,
        "reference": {
            "trajectories": len(sample),
            "rows": sample_rows,
            "grid_to_lists_s": grid_s,
            "seconds": reference_s,
            "cpu_s": reference_cpu,
            "per_trajectory_s": ref_each,
            "extrapolated_s": ref_each * count,
        },
        "ours_per_trajectory_s": ours_each,
        "ratio": ref_each / ours_each,
        "ratio_cpu": (reference_cpu / len(sample) if sample else math.nan)
        / ((measure_cpu + compute_cpu) / count),
        "labels": {str(k): int(v) for k, v in zip(labels, counts, strict=True)},
        "means": {n: float(np.nanmean(metrics[n])) for n in COMPARED if np.isfinite(metrics[n]).any()},
        "agreement": agreement({k: v[: len(sample)] for k, v in metrics.items()}, reference),
        "peak_rss_mb": peak_rss_mb(),
    }


def speed_table(r: dict[str, Any]) -> Table:
    count = r["trajectories"]
    table = Table(
        title=f"scoring {count:,} records of {r['rows_per_trajectory']:,} rows ({r['rows']:,} rows)"
    )
    for column in ("", "records", "rows", "wall s", "CPU s", "ms / record", "rows / s", f"× {count:,}"):
        table.add_column(column, justify="right")
    ref = r["reference"]
    table.add_row(
        "ours: measure", f"{r['trajectories']:,}", f"{r['rows']:,}", f"{r['measure_s']:.2f}",
        f"{r['measure_cpu_s']:.2f}", "", f"{r['rows'] / r['measure_s']:,.0f}", "",
    )  # fmt: skip
    table.add_row(
        "ours: compute_metrics", f"{r['trajectories']:,}", "", f"{r['compute_metrics_s']:.3f}",
        f"{r['compute_metrics_cpu_s']:.3f}", "", "", "",
    )  # fmt: skip
    table.add_row(
        "ours: scoring", f"{r['trajectories']:,}", f"{r['rows']:,}", f"{r['scoring_s']:.2f}",
        f"{r['measure_cpu_s'] + r['compute_metrics_cpu_s']:.2f}", f"{1000 * r['ours_per_trajectory_s']:.2f}",
        f"{r['rows_per_s']:,.0f}", f"{r['scoring_s']:.1f} s",
    )  # fmt: skip
    if ref["trajectories"]:
        table.add_row(
            "plain Python", f"{ref['trajectories']:,}", f"{ref['rows']:,}", f"{ref['seconds']:.2f}",
            f"{ref['cpu_s']:.2f}", f"{1000 * ref['per_trajectory_s']:.1f}",
            f"{ref['rows'] / ref['seconds']:,.0f}", f"{ref['extrapolated_s'] / 60:.1f} min (extrapolated)",
        )  # fmt: skip
    return table


def agreement_table(r: dict[str, Any]) -> Table:
    table = Table(
        title=f"agreement with the plain-Python reference on {r['reference']['trajectories']} records "
        f"(tolerance {TOLERANCE:g} absolute or relative)"
    )
    for column in ("metric", "mean (all records)", "max |Δ|", "records beyond tolerance"):
        table.add_column(column, justify="right")
    for name, entry in r["agreement"].items():
        mean = r["means"].get(name)
        diff = entry["max_abs_diff"]
        table.add_row(
            name,
            "" if mean is None else f"{mean:.4f}",
            f"{int(diff)} labels differ" if name == "label" else f"{diff:.2e}",
            str(len(entry["disagree"])),
            style="red" if entry["disagree"] else None,
        )
    return table


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    """Command-line flags."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trajectories", type=int, default=10_000, help="records scored (default 10000)")
    parser.add_argument("--hz", type=float, default=50.0, help="rows per second (default 50)")
    parser.add_argument("--seconds", type=float, default=300.0, help="record length, s (default 300)")
    parser.add_argument("--reference", type=int, default=20, help="records the plain-Python peer scores (20)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the scene and the records (default 0)")
    parser.add_argument("--scene-size", type=float, default=200.0, help="side of the square scene, m (200)")
    parser.add_argument("--batch", type=int, default=0, help="records per measure() (default: BATCH_ROWS)")
    parser.add_argument("--json", type=Path, default=None, metavar="PATH", help="also write the results here")
    args = parser.parse_args(argv)
    if args.trajectories < 1 or args.hz <= 0 or args.seconds <= 0 or args.scene_size < 20:
        parser.error("--trajectories, --hz and --seconds must be positive, --scene-size at least 20 m")
    args.reference = max(0, min(args.reference, args.trajectories))
    return args


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark; returns the exit code (1 if ours and the reference disagree)."""
    args = parse_args(argv)
    console = Console(width=None if sys.stdout.isatty() else 150)
    console.print(
        f"eval benchmark: {os.cpu_count()} CPUs, {platform.python_implementation()} "
        f"{platform.python_version()}, numpy {np.__version__}; {args.trajectories} records of "
        f"{args.seconds:g} s at {args.hz:g} Hz, reference on {args.reference}, seed {args.seed}; "
        f"load average {os.getloadavg()[0]:.2f}",
        highlight=False,
    )
    r = run(args, console)
    console.print(speed_table(r))
    ref, fields = r["reference"], r["fields"]
    labels = ", ".join(f"{k} {v}" for k, v in r["labels"].items())
    console.print(
        f"ours: navverse.eval.measures.measure on batches of {r['batch_trajectories']} records "
        f"(scoring.BATCH_ROWS = {BATCH_ROWS:,} rows), then compute_metrics over all; not included: "
        f"generating the records ({r['generate_s']:.1f} s) and the scene fields ({fields['seconds']:.1f} s, "
        f"{fields['shape'][0]} x {fields['shape'][1]} cells). Plain Python: bench/eval.py reference_scores, "
        f"a record at a time (not included: its grid as lists, {ref['grid_to_lists_s']:.1f} s). "
        + (
            f"plain Python / ours per record: {r['ratio']:,.0f}× (wall), {r['ratio_cpu']:,.0f}× (CPU). "
            if ref["trajectories"]
            else "No reference run (--reference 0). "
        )
        + f"Peak RSS {r['peak_rss_mb']:,.0f} MB. Labels: {labels}. Load average {os.getloadavg()[0]:.2f}",
        highlight=False,
    )
    failed = any(entry["disagree"] for entry in r["agreement"].values())
    if ref["trajectories"]:
        console.print(agreement_table(r))
        for name, entry in r["agreement"].items():
            for bad in entry["disagree"][:5]:
                console.print(
                    f"[red]{name}[/red] of record {bad['record']}: ours {bad['ours']}, "
                    f"reference {bad['reference']}",
                    highlight=False,
                )
    if args.json is not None:
        report = {"benchmark": "eval", "args": {k: str(v) for k, v in vars(args).items()}, **r}
        args.json.write_text(json.dumps(report, indent=1, default=float))
        console.print(f"wrote {args.json}", highlight=False)
    if failed:
        console.print("[red]ours and the plain-Python reference disagree[/red]")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
