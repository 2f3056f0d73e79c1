"""Turn-and-move directives of a reference path, aligned to the times of its verification rollout.

The reference path is simplified (Douglas–Peucker, then segments shorter than ``min_segment`` are merged
and vertices without a real turn dropped) into :class:`Directive` s by :func:`plan_directives`: a start
(turn from the start heading, walk the first segment), one turn per remaining vertex (signed angle
classified by :func:`turn_class`), and an arrival. :func:`align_directives` matches each directive to
the rollout row at which the robot carried it out, its closest approach to the directive's vertex,
with rows kept in path order.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["Directive", "align_directives", "plan_directives", "turn_class", "wrap_angle"]

_TURNS = ((20.0, "straight"), (60.0, "slight"), (120.0, "turn"), (160.0, "sharp"))  # |angle| below, in deg


@dataclass(frozen=True)
class Directive:
    """One step of a template: turn by ``angle`` at ``position``, then walk ``length``.

    Attributes
    ----------
    kind : {"start", "turn", "arrive"}
        The first directive turns from the start heading; the last one is the arrival (no turn).
    turn : str
        :func:`turn_class` of `angle`: ``straight``, ``slight_left``, ``left``, ``sharp_left``,
        ``around`` (and the ``right`` ones).
    angle : float
        Signed turn (rad), positive to the left (counter-clockwise seen from above).
    length : float
        Horizontal length of the segment walked after the turn (m); 0 for the arrival.
    position : tuple of float
        The path vertex where the directive is carried out.
    """

    kind: Literal["start", "turn", "arrive"]
    turn: str
    angle: float
    length: float
    position: tuple[float, float, float]


def turn_class(angle: float) -> str:
    """Name a signed turn angle (rad, positive left): ``straight`` below 20°, ``slight_*`` below 60°,
    ``left``/``right`` below 120°, ``sharp_*`` below 160°, else ``around``."""
    degrees = abs(math.degrees(angle))
    side = "left" if angle > 0.0 else "right"
    for limit, name in _TURNS:
        if degrees < limit:
            return name if name == "straight" else side if name == "turn" else f"{name}_{side}"
    return "around"


def wrap_angle(angle: ArrayLike) -> np.ndarray:
    """Angles (rad) wrapped into ``[-pi, pi)``."""
    return (np.asarray(angle) + np.pi) % (2.0 * np.pi) - np.pi


def _douglas_peucker(points: np.ndarray, tolerance: float) -> np.ndarray:
    """Indices of the vertices kept by Douglas–Peucker on a 2-D polyline (iterative)."""
    keep = np.zeros(len(points), dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, len(points) - 1)]
    while stack:
        first, last = stack.pop()
        if last - first < 2:
            continue
        a, b = points[first], points[last]
        ab = b - a
        rel = points[first + 1 : last] - a
        length = float(np.hypot(*ab))
        if length < 1e-9:
            dist = np.hypot(rel[:, 0], rel[:, 1])
        else:
            dist = np.abs(ab[0] * rel[:, 1] - ab[1] * rel[:, 0]) / length
        worst = int(np.argmax(dist))
        if dist[worst] > tolerance:
            mid = first + 1 + worst
            keep[mid] = True
            stack.extend([(first, mid), (mid, last)])
    return np.flatnonzero(keep)


def _merge_short(points: list[np.ndarray], min_segment: float) -> list[np.ndarray]:
    """Merge segments shorter than `min_segment`: the start and the end vertex never move."""
    while len(points) > 2:
        lengths = [float(np.hypot(*(b[:2] - a[:2]))) for a, b in itertools.pairwise(points)]
        i = int(np.argmin(lengths))
        if lengths[i] >= min_segment:
            break
        if i == 0:
            del points[1]
        elif i == len(points) - 2:
            del points[i]
        else:
            points[i : i + 2] = [0.5 * (points[i] + points[i + 1])]
    return points


def plan_directives(
    reference_path: ArrayLike, start_yaw: float, *, tolerance: float = 0.5, min_segment: float = 0.75
) -> list[Directive]:
    """Turn-and-move directives of a reference path.

    Parameters
    ----------
    reference_path : array_like, shape (K, 3)
        Path corners from the start to the goal region (z up).
    start_yaw : float
        The robot's heading at the start (rad).
    tolerance : float
        Douglas–Peucker tolerance (m).
    min_segment : float
        Shorter segments are merged into their neighbours (m).

    Returns
    -------
    list of Directive
        A start, one turn per kept interior vertex, and an arrival; empty if the path has no length.
    """
    path = np.asarray(reference_path, dtype=float).reshape(-1, 3)
    if len(path):
        step = np.hypot(*np.diff(path[:, :2], axis=0).T)
        path = path[np.concatenate([[True], step > 1e-6])]
    if len(path) < 2:
        return []
    points = [path[i] for i in _douglas_peucker(path[:, :2], tolerance)]
    points = _merge_short(points, min_segment)
    while True:  # drop vertices whose turn is too small to mention
        headings = [math.atan2(*(b[1::-1] - a[1::-1])) for a, b in itertools.pairwise(points)]
        turns = [float(wrap_angle(h1 - h0)) for h0, h1 in itertools.pairwise(headings)]
        straight = [i + 1 for i, a in enumerate(turns) if turn_class(a) == "straight"]
        if not straight:
            break
        del points[min(straight, key=lambda i: abs(turns[i - 1]))]
    angles = [float(wrap_angle(headings[0] - start_yaw)), *turns]
    directives = [
        Directive(
            kind="start" if i == 0 else "turn",
            turn=turn_class(angle),
            angle=angle,
            length=float(np.hypot(*(points[i + 1][:2] - points[i][:2]))),
            position=tuple(float(v) for v in points[i]),
        )
        for i, angle in enumerate(angles)
    ]
    end = tuple(float(v) for v in points[-1])
    return [*directives, Directive(kind="arrive", turn="straight", angle=0.0, length=0.0, position=end)]


def align_directives(directives: Sequence[Directive], rollout: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Rollout rows at which the directives were carried out, in order, and how far off they were.

    Each directive is matched to a rollout pose near its vertex; the rows strictly increase (when the
    rollout has at least as many rows as directives) and minimise the sum of horizontal distances,
    found by dynamic programming, so a path that comes back near an earlier vertex is not misread.

    Parameters
    ----------
    directives : sequence of Directive
        The directives, in path order.
    rollout : array_like, shape (K, 8)
        ``[t, x, y, z, qx, qy, qz, qw]`` rows.

    Returns
    -------
    rows : ndarray of int, shape (N,)
        Row of each directive (non-decreasing; increasing when ``K >= N``).
    errors : ndarray of float, shape (N,)
        Horizontal distance from each vertex to its row's position (m).
    """
    poses = np.asarray(rollout, dtype=float)[:, 1:3]
    vertices = np.array([d.position[:2] for d in directives], dtype=float).reshape(-1, 2)
    dist = np.linalg.norm(vertices[:, None, :] - poses[None, :, :], axis=2)  # (N, K)
    n, k = dist.shape
    if n == 0:
        return np.zeros(0, dtype=int), np.zeros(0)
    strict = k >= n
    cost = dist.copy()
    back = np.zeros((n, k), dtype=int)
    for i in range(1, n):
        prev = cost[i - 1]
        best = np.minimum.accumulate(prev)
        arg = np.zeros(k, dtype=int)
        for j in range(1, k):  # index of the running minimum (first one on ties)
            arg[j] = arg[j - 1] if prev[arg[j - 1]] <= prev[j] else j
        if strict:
            cost[i, 0] = np.inf
            cost[i, 1:] += best[:-1]
            back[i, 1:] = arg[:-1]
        else:
            cost[i] += best
            back[i] = arg
    rows = np.zeros(n, dtype=int)
    rows[-1] = int(np.argmin(cost[-1]))
    for i in range(n - 1, 0, -1):
        rows[i - 1] = back[i, rows[i]]
    return rows, dist[np.arange(n), rows]
