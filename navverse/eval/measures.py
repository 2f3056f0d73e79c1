"""Per-episode measures of trajectories, vectorised over every row of a batch of episodes.

:func:`measure` computes, with no Python loop over rows, the distance to goal at the start, end and
closest point, the 3-D path length, duration, visited 1 m cells, collision, mean obstacle distance,
share of rows on preferred surfaces, fall and timeout, nDTW for VLN, and the exit measures of
indoor-to-outdoor episodes. The metrics are computed from these measures by the registry of
:mod:`navverse.eval.metrics`, whose docstring defines every metric and edge case.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from navverse.scene.fields import SceneFields
from navverse.scene_types import PROFILES, scene_profile

__all__ = [
    "CELL",
    "EXIT_MEASURES",
    "FALL_TILT_DEG",
    "MEASURES",
    "OUTCOME_MEASURES",
    "TIMEOUT_S",
    "TRANSITION_SCENE_TYPES",
    "EpisodeTarget",
    "Robot",
    "measure",
    "ndtw",
    "ndtw_many",
    "outcome",
]

TIMEOUT_S = 300.0
FALL_TILT_DEG = 45.0
CELL = 1.0
"""Coverage grid cell (m)."""
DENSIFY = 0.25
"""Rows farther apart than this (m) are subdivided for coverage."""
COVERAGE_SAMPLES = 100_000
"""Most points an episode's path is sampled at for coverage: a path longer than 25 km (this many times
:data:`DENSIFY`) is sampled every P / COVERAGE_SAMPLES m instead, so no path costs more memory or time."""
DTW_SPACING = 0.5
DTW_POINTS = 10_000
"""Most points a path is resampled at for nDTW: a path longer than 5 km (this many times
:data:`DTW_SPACING`) is resampled every length / DTW_POINTS m instead."""
POSITION_LIMIT = 1e6
"""Positions are clamped to ±1000 km on every axis before measuring, so no sum or cell index overflows.
Validated records never reach it (:data:`navverse.eval.submission.MAX_ABS_COORD` is 100 km)."""
_CHUNK_SAMPLES = 2**18
"""Coverage is computed over groups of whole episodes of about this many points."""
_DTW_CELLS = 2**20
"""nDTW is computed for groups of episodes whose references, padded to the longest of the group, hold
at most this many points in all (one, when a single reference is longer), so memory stays bounded."""
_CELL_OFFSET = 1 << 20
"""Added to cell indices (within ±POSITION_LIMIT / CELL) to make them non-negative in 21 bits."""
TRANSITION_SCENE_TYPES = tuple(name for name, p in PROFILES.items() if p.transition_metrics)
"""Scene types whose episodes get the transition (exit) measures (their profiles say so)."""
EXIT_MEASURES = ("reached_outdoor", "pre_exit_cells", "pre_exit_traveled", "post_exit_cells",
                 "post_exit_traveled")  # fmt: skip
OUTCOME_MEASURES = ("dtg", "fell", "timed_out", "stopped")
"""The measures a termination label is made of (:func:`outcome`): none reads a scene's fields."""
MEASURES = ("dtg", "dtg_min", "dtg_start", "traveled", "duration", "cells", "collided", "clearance",
            "on_preferred", "fell", "timed_out", "stopped", "dtw_score", *EXIT_MEASURES)  # fmt: skip
"""Names of the per-episode measures :func:`measure` returns."""


@dataclass(frozen=True)
class Robot:
    """What scoring needs of an embodiment: r_robot, the body's footprint and preferred surfaces."""

    name: str
    radius: float
    length: float
    width: float
    extra_surfaces: frozenset[str] = frozenset()

    def success_distance(self, scene_type: str) -> float:
        """Largest goal distance that counts as success in a scene of ``scene_type`` (m)."""
        return scene_profile(scene_type).success_distance(self.radius)


@dataclass(frozen=True, eq=False)
class EpisodeTarget:
    """What scoring needs of a dataset episode."""

    episode_id: str
    scene_id: str
    task: str
    goal_centers: np.ndarray  # (G, 3)
    goal_radii: np.ndarray  # (G,)
    geodesic: float
    reference_path: np.ndarray  # (R, 3)
    scene_type: str  # indoor | outdoor | i2o: the success distance and the exit measures depend on it


@dataclass(eq=False)
class _Batch:
    """Scored rows of a batch of episodes, concatenated; ``seg`` is the episode of each row."""

    xyz: np.ndarray
    quat: np.ndarray
    t: np.ndarray
    seg: np.ndarray
    starts: np.ndarray
    ends: np.ndarray
    fell: np.ndarray
    timed_out: np.ndarray


def _cut(trajectories: Sequence[np.ndarray]) -> _Batch:
    """Concatenate trajectories, dropping rows after 300 s and after a fall."""
    lengths = np.array([len(t) for t in trajectories], dtype=np.int64)
    rows = np.concatenate(trajectories) if trajectories else np.zeros((0, 8))
    seg = np.repeat(np.arange(len(trajectories)), lengths)
    first = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    last_t = rows[first + lengths - 1, 0] if len(rows) else np.zeros(0)
    q = rows[:, 4:8]
    cos_tilt = 1.0 - 2.0 * (q[:, 0] ** 2 + q[:, 1] ** 2)
    within = rows[:, 0] <= TIMEOUT_S
    within[first] = True  # an episode always keeps its first row
    falls = within & (cos_tilt < math.cos(math.radians(FALL_TILT_DEG)))
    index = np.arange(len(rows))
    first_fall = np.full(len(trajectories), len(rows), dtype=np.int64)
    fall_rows = np.flatnonzero(falls)
    if len(fall_rows):
        episodes, at = np.unique(seg[fall_rows], return_index=True)
        first_fall[episodes] = fall_rows[at]
    keep = within & (index <= first_fall[seg])
    fell = first_fall < len(rows)
    if not keep.all():  # one copy of the kept rows (when every row is kept, none)
        rows, seg = rows[keep], seg[keep]
    kept = np.bincount(seg, minlength=len(trajectories))
    starts = np.concatenate([[0], np.cumsum(kept)[:-1]]).astype(np.int64)
    xyz = rows[:, 1:4]
    if len(xyz) and np.abs(xyz).max() > POSITION_LIMIT:
        xyz = np.clip(xyz, -POSITION_LIMIT, POSITION_LIMIT)
    return _Batch(
        xyz=xyz,
        quat=rows[:, 4:8],
        t=rows[:, 0],
        seg=seg,
        starts=starts,
        ends=starts + kept - 1,
        fell=fell,
        timed_out=last_t > TIMEOUT_S,
    )


def _goal_distance(
    batch: _Batch, targets: Sequence[EpisodeTarget], *, rows: np.ndarray | None = None
) -> np.ndarray:
    """``d_t`` of every scored row (or of the batch's `rows`, one per episode: the same values, computed
    for those rows only): 3-D, to the nearest goal's edge, at least 0."""
    most = max((len(t.goal_radii) for t in targets), default=1)
    centers = np.full((len(targets), most, 3), np.inf)
    radii = np.zeros((len(targets), most))
    for i, target in enumerate(targets):
        centers[i, : len(target.goal_radii)] = target.goal_centers
        radii[i, : len(target.goal_radii)] = target.goal_radii
    xyz = batch.xyz if rows is None else batch.xyz[rows]
    count = batch.ends - batch.starts + 1 if rows is None else np.ones(len(targets), dtype=np.int64)
    d = np.full(len(xyz), np.inf)
    x, y, z = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    for g in range(most):  # goals are few; rows are many
        # an episode's rows are contiguous: repeat, don't gather
        cx, cy, cz = (np.repeat(centers[:, g, k], count) for k in range(3))
        d = np.minimum(d, _norm3(x - cx, y - cy, z - cz) - np.repeat(radii[:, g], count))
    return np.maximum(d, 0.0)


def _norm3(dx: np.ndarray, dy: np.ndarray, dz: np.ndarray | None = None) -> np.ndarray:
    """``sqrt(dx² + dy² (+ dz²))``, in the order ``np.linalg.norm(axis=1)`` adds them."""
    total = dx * dx
    total += dy * dy
    if dz is not None:
        total += dz * dz
    return np.sqrt(total, out=total)


def _coverage(xy: np.ndarray, seg: np.ndarray, count: int) -> np.ndarray:
    """Unique 1 m cells visited per episode by rows `xy` of episodes `seg` (sorted), rows subdivided every
    :data:`DENSIFY` m (every P / :data:`COVERAGE_SAMPLES` m for a path P longer than that many samples).

    Whole episodes are sampled a group of about :data:`_CHUNK_SAMPLES` points at a time, so memory stays
    bounded whatever the path lengths.
    """
    cells = np.zeros(count)
    if not len(xy):
        return cells
    xy = np.clip(xy, -POSITION_LIMIT, POSITION_LIMIT)
    same = seg[1:] == seg[:-1]
    step = _norm3(np.diff(xy[:, 0]), np.diff(xy[:, 1])) * same  # 0 across episodes
    path = np.bincount(seg[1:], weights=step, minlength=count)
    spacing = np.maximum(DENSIFY, path / COVERAGE_SAMPLES)
    parts = np.ones(len(xy), dtype=np.int64)  # the points row i adds: itself and the way to row i + 1
    parts[:-1] = np.maximum(np.ceil(step / spacing[seg[1:]]), 1)
    runs = np.flatnonzero(np.concatenate([[True], ~same]))  # first row of each episode
    before = np.cumsum(parts) - parts  # points before each row
    group = before[runs] // _CHUNK_SAMPLES
    bounds = [*runs[np.flatnonzero(np.diff(group)) + 1], len(xy)]
    start = 0
    for end in bounds:
        episodes, inverse = np.unique(seg[start:end], return_inverse=True)
        cells[episodes] = _cells_visited(xy[start:end], inverse, parts[start:end], len(episodes))
        start = end
    return cells


def _cells_visited(xy: np.ndarray, episode: np.ndarray, parts: np.ndarray, count: int) -> np.ndarray:
    """Unique cells per episode (numbered 0..count-1) of whole episodes' rows, row i sampled at `parts[i]`
    points evenly from itself toward row i + 1 (an episode's last row has 1)."""
    k = np.repeat(np.arange(len(xy)), parts)
    frac = (np.arange(len(k)) - np.repeat(np.cumsum(parts) - parts, parts)) / parts[k]
    following = np.minimum(k + 1, len(xy) - 1)
    points = xy[k] + (xy[following] - xy[k]) * frac[:, None]
    index = np.floor(points / CELL).astype(np.int64) + _CELL_OFFSET
    keys = (episode[k].astype(np.int64) << 42) | (index[:, 0] << 21) | index[:, 1]
    return np.bincount(np.unique(keys) >> 42, minlength=count).astype(np.float64)


def _yaw(quat: np.ndarray) -> np.ndarray:
    x, y, z, w = quat.T
    return np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def _footprint_contact(
    batch: _Batch, fields: SceneFields, rows: np.ndarray, robot: Robot, centre: np.ndarray
) -> np.ndarray:
    """Rows whose footprint capsule (width ``robot.width`` along ``robot.length``) touches an obstacle.

    ``centre`` is the obstacle distance at each row's base. The distance field is 1-Lipschitz between
    cell centres and a point is at most half a cell diagonal from its cell's centre, so a capsule point
    ``reach`` away from the base is no closer than ``centre - reach - √2 cell``: rows farther than that
    from every obstacle cannot touch one and are not looked at.
    """
    half = robot.width / 2.0
    reach = max(robot.length / 2.0 - half, 0.0)
    touching = half - fields.cell / 2.0
    touched = np.zeros(len(centre), dtype=bool)
    near = np.flatnonzero(centre < touching + reach + math.sqrt(2.0) * fields.cell + 1e-3)
    if not len(near):
        return touched
    at = np.arange(len(batch.t))[rows][near]
    yaw = _yaw(batch.quat[at])
    axis = np.stack([np.cos(yaw), np.sin(yaw)], axis=1)
    xy = batch.xyz[at, :2]
    clearance = np.full(len(at), np.inf)
    for k in np.linspace(-1.0, 1.0, 5):
        clearance = np.minimum(clearance, fields.distance_at(xy + k * reach * axis))
    touched[near] = clearance < touching
    return touched


def _exit_measures(
    batch: _Batch,
    targets: Sequence[EpisodeTarget],
    fields: Mapping[str, SceneFields],
    step: np.ndarray,
) -> dict[str, np.ndarray]:
    """The :data:`EXIT_MEASURES` per episode: reached outdoors, and the cells and path length before and
    after the exit row; NaN for episodes outside :data:`TRANSITION_SCENE_TYPES` or without an indoor region.

    `step` is the length of the step from each row to the next (0 across episodes).
    """
    count = len(targets)
    transition = {t.scene_id for t in targets if t.scene_type in TRANSITION_SCENE_TYPES}
    scenes = sorted(scene for scene in transition if fields[scene].has_indoor)
    applies = np.array([t.scene_type in TRANSITION_SCENE_TYPES and t.scene_id in scenes for t in targets])
    if not scenes:
        return {name: np.full(count, np.nan) for name in EXIT_MEASURES}
    row_applies = applies[batch.seg]
    scene_of_row = np.array([t.scene_id for t in targets], dtype=object)[batch.seg]
    outside = np.zeros(len(batch.t), dtype=bool)
    for scene in scenes:
        rows = np.flatnonzero(row_applies & (scene_of_row == scene))
        outside[rows] = ~fields[scene].indoor_at(batch.xyz[rows, :2])
    exit_row = np.full(count, -1, dtype=np.int64)  # the first row outdoors, in the batch; -1: none
    out_rows = np.flatnonzero(outside)
    if len(out_rows):
        episodes, at = np.unique(batch.seg[out_rows], return_index=True)
        exit_row[episodes] = out_rows[at]
    reached = exit_row >= 0
    index = np.arange(len(batch.t))
    k = exit_row[batch.seg]
    parts = {
        "pre_exit": row_applies & ((k < 0) | (index <= k)),  # rows 0..k, or all if it never left
        "post_exit": row_applies & (k >= 0) & (index >= k),  # rows k..T
    }
    defined = {
        "pre_exit": applies & (exit_row != batch.starts),  # starting outdoors leaves nothing before
        "post_exit": reached,
    }
    out = {"reached_outdoor": np.where(applies, reached.astype(np.float64), np.nan)}
    for name, rows in parts.items():
        cells = _coverage(batch.xyz[rows, :2], batch.seg[rows], count)
        inside = rows[1:] & rows[:-1]  # a step is in a part when both its rows are
        traveled = np.bincount(batch.seg[1:], weights=step * inside, minlength=count)
        out[f"{name}_cells"] = np.where(defined[name], cells, np.nan)
        out[f"{name}_traveled"] = np.where(defined[name], traveled, np.nan)
    return out


def measure(
    trajectories: Sequence[np.ndarray],
    targets: Sequence[EpisodeTarget],
    *,
    robot: Robot,
    stops: Sequence[bool],
    collisions: Sequence[np.ndarray | None],
    fields: Mapping[str, SceneFields],
    preferred: Mapping[str, np.ndarray],
) -> dict[str, np.ndarray]:
    """Per-episode measures of a batch of valid trajectories.

    Parameters
    ----------
    trajectories : sequence of ndarray, each (K, 8)
        ``[t, x, y, z, qx, qy, qz, qw]`` rows (validated: finite, t increasing, unit quaternions).
    targets : sequence of EpisodeTarget
        The episodes, in the same order.
    robot : Robot
        The embodiment scored.
    stops, collisions : sequences
        Each record's stop flag and reported collision times (None: not reported).
    fields : mapping
        :class:`~navverse.scene.fields.SceneFields` by scene id.
    preferred : mapping
        By scene id, a bool per terrain class index (plus one last entry for "no surface") saying
        whether the class counts for NSR.

    Returns
    -------
    dict of ndarray
        ``dtg``, ``dtg_min``, ``dtg_start``, ``traveled``, ``duration``, ``cells``, ``collided``,
        ``clearance``, ``on_preferred``, ``fell``, ``timed_out``, ``stopped``, ``dtw_score`` (NaN unless
        VLN), ``reached_outdoor``, ``pre_exit_cells``, ``pre_exit_traveled``, ``post_exit_cells``,
        ``post_exit_traveled`` (NaN unless the episode's scene type is in :data:`TRANSITION_SCENE_TYPES`
        and its scene has an indoor region; the pre-exit ones also when it starts outdoors, the
        post-exit ones when it never leaves), each (E,).
    """
    count = len(trajectories)
    batch = _cut(trajectories)
    d = _goal_distance(batch, targets)
    step = _norm3(*(np.diff(batch.xyz[:, i]) for i in range(3)))
    step[batch.seg[1:] != batch.seg[:-1]] = 0.0
    path = np.bincount(batch.seg[1:], weights=step, minlength=count) if len(step) else np.zeros(count)
    clearance = np.full(len(batch.t), np.nan)
    on_preferred = np.zeros(len(batch.t))
    touching = np.zeros(len(batch.t), dtype=bool)
    scenes = sorted({t.scene_id for t in targets})
    scene_code = np.array([scenes.index(t.scene_id) for t in targets], dtype=np.int64)
    for code, scene in enumerate(scenes):
        rows = slice(None) if len(scenes) == 1 else np.flatnonzero(scene_code[batch.seg] == code)
        grid = fields[scene]
        row, col = grid.cells(batch.xyz[rows, :2])
        clearance[rows] = grid.distance[row, col]
        classes = grid.terrain[row, col]
        on_preferred[rows] = preferred[scene][np.where(classes >= 0, classes, len(preferred[scene]) - 1)]
        touching[rows] = _footprint_contact(batch, grid, rows, robot, clearance[rows])
    n_rows = np.bincount(batch.seg, minlength=count)
    end_time = batch.t[batch.ends]
    collided = np.zeros(count, dtype=bool)
    footprint_hits = np.bincount(batch.seg, weights=touching, minlength=count) > 0
    for i, times in enumerate(collisions):
        collided[i] = bool((times <= end_time[i] + 1e-9).any()) if times is not None else footprint_hits[i]
    ndtw_values = np.full(count, np.nan)
    vln = [i for i, t in enumerate(targets) if t.task == "vln" and len(t.reference_path) >= 2]
    if vln:
        ndtw_values[vln] = ndtw_many(
            [batch.xyz[batch.starts[i] : batch.ends[i] + 1] for i in vln],
            [targets[i].reference_path for i in vln],
            thresholds=[robot.success_distance(targets[i].scene_type) for i in vln],
        )
    exits = _exit_measures(batch, targets, fields, step)
    return {
        "dtg": d[batch.ends],
        "dtg_min": np.minimum.reduceat(d, batch.starts) if len(d) else np.zeros(count),
        "dtg_start": d[batch.starts],
        "traveled": path,
        "duration": end_time - batch.t[batch.starts],
        "cells": _coverage(batch.xyz[:, :2], batch.seg, count),
        "collided": collided.astype(np.float64),
        "clearance": np.bincount(batch.seg, weights=clearance, minlength=count) / n_rows,
        "on_preferred": np.bincount(batch.seg, weights=on_preferred, minlength=count) / n_rows,
        "fell": batch.fell.astype(np.float64),
        "timed_out": batch.timed_out.astype(np.float64),
        "stopped": np.asarray(stops, dtype=np.float64),
        "dtw_score": ndtw_values,
        **exits,
    }


def outcome(
    trajectories: Sequence[np.ndarray], targets: Sequence[EpisodeTarget], *, stops: Sequence[bool]
) -> dict[str, np.ndarray]:
    """The measures of :data:`OUTCOME_MEASURES` of a batch of valid trajectories, equal to those
    :func:`measure` gives, computed without a scene's fields (what the termination labels need).

    Parameters
    ----------
    trajectories : sequence of ndarray, each (K, 8)
        ``[t, x, y, z, qx, qy, qz, qw]`` rows (validated: finite, t increasing, unit quaternions).
    targets : sequence of EpisodeTarget
        The episodes, in the same order.
    stops : sequence of bool
        Each record's stop flag.

    Returns
    -------
    dict of ndarray
        ``dtg``, ``fell``, ``timed_out``, ``stopped``, each (E,).
    """
    batch = _cut(trajectories)
    return {
        "dtg": _goal_distance(batch, targets, rows=batch.ends),
        "fell": batch.fell.astype(np.float64),
        "timed_out": batch.timed_out.astype(np.float64),
        "stopped": np.asarray(stops, dtype=np.float64),
    }


def _resample(points: np.ndarray, spacing: float) -> np.ndarray:
    """Points every `spacing` meters along a horizontal polyline (its ends included), at most
    :data:`DTW_POINTS` + 1 of them (a longer polyline is resampled more coarsely)."""
    xy = np.clip(np.asarray(points, dtype=float)[:, :2], -POSITION_LIMIT, POSITION_LIMIT)
    if len(xy) < 2:
        return xy
    lengths = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])
    if lengths[-1] <= 0.0:
        return xy[:1]
    spacing = max(spacing, lengths[-1] / DTW_POINTS)
    at = np.append(np.arange(0.0, lengths[-1], spacing), lengths[-1])
    return np.stack([np.interp(at, lengths, xy[:, 0]), np.interp(at, lengths, xy[:, 1])], axis=1)


def ndtw(trajectory: np.ndarray, reference: np.ndarray, *, threshold: float) -> float:
    """Normalised dynamic time warping between a path and a reference (Ilharco et al., 2019).

    Both are resampled every 0.5 m in the horizontal plane (more coarsely beyond :data:`DTW_POINTS`
    points); ``exp(-DTW / (|R| * threshold))``, in [0, 1]. :func:`ndtw_many` of one pair.
    """
    return float(ndtw_many([trajectory], [reference], thresholds=[threshold])[0])


def ndtw_many(
    trajectories: Sequence[np.ndarray], references: Sequence[np.ndarray], *, thresholds: Sequence[float]
) -> np.ndarray:
    """:func:`ndtw` of each trajectory against its reference, the pairs' recurrences run side by side.

    The DTW table is filled a row (a point of the trajectory) at a time, the row in closed form:
    ``D[i, j] = c[i, j] + min(D[i-1, j], D[i, j-1], D[i-1, j-1])``, so ``D[i, :]`` is a running minimum
    of ``c[i, j] + min(D[i-1, j], D[i-1, j-1]) - C[i, j]`` plus ``C[i, j]``, C the running sum of the
    row's costs. Pairs are grouped by their references' lengths (a group's references padded to its
    longest, :data:`_DTW_CELLS` points in all), and row i of every pair of a group with an i-th point is
    one array operation. Each entry is computed by the same operations as one pair alone (the padding
    comes after a reference's end, and a row's sums and minima run from its start), so the values do not
    depend on the grouping.

    Parameters
    ----------
    trajectories, references : sequences of ndarray, each (K, 2+)
        The paths (x, y first), pair by pair; a reference has at least 2 points.
    thresholds : sequence of float
        Each pair's success distance (m).

    Returns
    -------
    ndarray
        nDTW of each pair, in [0, 1].
    """
    paths = [_resample(t, DTW_SPACING) for t in trajectories]
    refs = [_resample(r, DTW_SPACING) for r in references]
    out = np.empty(len(paths))
    order = sorted(range(len(paths)), key=lambda k: len(refs[k]))
    start = 0
    while start < len(order):  # groups of references of similar lengths, within _DTW_CELLS points
        end = start + 1
        while end < len(order) and (end + 1 - start) * len(refs[order[end]]) <= _DTW_CELLS:
            end += 1
        group = sorted(order[start:end], key=lambda k: -len(paths[k]))  # longest paths first
        start = end
        width = max(len(refs[k]) for k in group)
        ref = np.zeros((len(group), width, 2))
        for row, k in enumerate(group):
            ref[row, : len(refs[k])] = refs[k]
        lengths = np.array([len(paths[k]) for k in group])
        points = np.concatenate([paths[k] for k in group])
        first = np.cumsum(lengths) - lengths
        table = np.full((len(group), width + 1), np.inf)  # [D[i-1, -1], D[i-1, :]] of each pair
        table[:, 0] = 0.0
        for i in range(int(lengths[0])):
            n = int(np.count_nonzero(lengths > i))  # the pairs whose path has an i-th point: a prefix
            cost = np.linalg.norm(points[first[:n] + i][:, None, :] - ref[:n], axis=2)  # (n, width)
            above = np.minimum(table[:n, 1:], table[:n, :-1])  # from D[i-1, j] and D[i-1, j-1]
            through = np.cumsum(cost, axis=1)
            table[:n, 1:] = np.minimum.accumulate(cost + above - through, axis=1) + through
            table[:n, 0] = np.inf  # D[i, -1]: only the first row starts from D[-1, -1] = 0
        for row, k in enumerate(group):
            out[k] = math.exp(-table[row, len(refs[k])] / (len(refs[k]) * thresholds[k]))
    return out
