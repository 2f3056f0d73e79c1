"""Shortest paths on an occupancy grid: traversal costs with clearance, Dijkstra, path tracing.

The planning half of :mod:`navverse.eval.agents.frontier`: :func:`traversal_costs` makes occupied cells
(grown by the robot's half width) impassable, cells near them costly and unknown cells dearer than
free ones; :func:`grid_dijkstra` runs :func:`scipy.sparse.csgraph.dijkstra` over the 8-connected
grid; :func:`trace_path` follows the predecessors back to the start.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage, sparse
from scipy.sparse import csgraph

__all__ = ["grid_dijkstra", "trace_path", "traversal_costs"]


def traversal_costs(
    occupied: np.ndarray,
    unknown: np.ndarray,
    *,
    cell_size: float,
    body_radius: float,
    margin: float,
    unknown_cost: float = 2.0,
    margin_cost: float = 8.0,
) -> np.ndarray:
    """Per-cell cost of crossing a cell; ``inf`` where the robot's body would touch an obstacle.

    Parameters
    ----------
    occupied, unknown : ndarray of bool, shape (rows, cols)
        Occupied and never-observed cells.
    cell_size : float
        Cell edge (m).
    body_radius : float
        Cells closer than this to an occupied cell's centre are impassable (m).
    margin : float
        Beyond ``body_radius``, cells closer than ``body_radius + margin`` cost up to ``margin_cost`` more.
    unknown_cost : float
        Cost of an unknown cell (a free cell costs 1).
    margin_cost : float
        Extra cost right at ``body_radius``, falling linearly to 0 at ``body_radius + margin``.

    Returns
    -------
    ndarray of float64, shape (rows, cols)
    """
    clearance = ndimage.distance_transform_edt(~occupied) * cell_size if occupied.any() else None
    costs = np.where(unknown, unknown_cost, 1.0)
    if clearance is not None:
        costs = costs + margin_cost * np.clip((body_radius + margin - clearance) / margin, 0.0, 1.0)
        costs[clearance < body_radius] = np.inf
    return costs


def grid_dijkstra(costs: np.ndarray, start: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Shortest 8-connected paths from ``start`` over a cost grid.

    A step between neighbouring cells costs its length (1 or sqrt 2 cells) times the mean of the two
    cells' costs; cells of infinite cost are never entered.

    Returns
    -------
    distance : ndarray, shape (rows, cols)
        Path cost to each cell (``inf`` where unreachable).
    predecessors : ndarray of int, shape (rows * cols,)
        Flat index of the previous cell on the path (negative at the start and unreachable cells).
    """
    rows, cols = costs.shape
    index = np.arange(rows * cols).reshape(rows, cols)
    sources, targets, weights = [], [], []
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        a = (slice(0, rows - dr), slice(max(0, -dc), cols - max(0, dc)))
        b = (slice(dr, rows), slice(max(0, dc), cols - max(0, -dc)))
        w = 0.5 * math.hypot(dr, dc) * (costs[a] + costs[b])
        ok = np.isfinite(w)
        sources.append(index[a][ok])
        targets.append(index[b][ok])
        weights.append(w[ok])
    graph = sparse.coo_matrix(
        (np.concatenate(weights), (np.concatenate(sources), np.concatenate(targets))),
        shape=(rows * cols, rows * cols),
    ).tocsr()
    distance, predecessors = csgraph.dijkstra(
        graph, directed=False, indices=start[0] * cols + start[1], return_predecessors=True
    )
    return distance.reshape(rows, cols), predecessors


def trace_path(predecessors: np.ndarray, target: tuple[int, int], cols: int) -> np.ndarray:
    """Cells ``(row, col)`` from the start to ``target`` along Dijkstra's predecessors."""
    node = target[0] * cols + target[1]
    path = [node]
    while predecessors[node] >= 0:
        node = int(predecessors[node])
        path.append(node)
    path = np.array(path[::-1], dtype=np.int64)
    return np.stack([path // cols, path % cols], -1)
