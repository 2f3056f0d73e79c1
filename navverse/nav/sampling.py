"""Seeded random navmesh paths within a length range (test paths, benchmarks, episode candidates)."""

from __future__ import annotations

import numpy as np

from navverse.nav.errors import NavMeshError
from navverse.nav.pathfinder import PathFinder, ShortestPath

__all__ = ["sample_paths"]


def sample_paths(
    finder: PathFinder,
    rng: np.random.Generator | int,
    count: int,
    *,
    min_length: float = 5.0,
    max_length: float = 50.0,
    island: int | None = None,
    max_tries: int = 200,
) -> list[ShortestPath]:
    """Shortest paths between random navigable points whose geodesic length is in a range.

    Parameters
    ----------
    finder : PathFinder
        The navmesh.
    rng : numpy.random.Generator or int
        The randomness (a seed makes a new generator).
    count : int
        Paths wanted.
    min_length, max_length : float
        Accepted geodesic lengths (m), inclusive.
    island : int, optional
        Island both ends are drawn from (default: the largest).
    max_tries : int
        Pairs drawn per path wanted before giving up.

    Returns
    -------
    list of ShortestPath
        ``count`` paths, in the order drawn.

    Raises
    ------
    NavMeshError
        When fewer than ``count`` paths in the range were found in ``max_tries * count`` pairs.
    """
    rng = np.random.default_rng(rng)
    island = finder.largest_island if island is None else island
    paths: list[ShortestPath] = []
    for _ in range(max_tries * count):
        if len(paths) == count:
            return paths
        start = finder.get_random_navigable_point(rng, island=island)
        end = finder.get_random_navigable_point(rng, island=island)
        path = finder.find_path(start, end)
        if path.found and min_length <= path.geodesic_distance <= max_length:
            paths.append(path)
    if len(paths) == count:
        return paths
    raise NavMeshError(
        f"found only {len(paths)} of {count} paths of {min_length}-{max_length} m on island {island} "
        f"in {max_tries * count} tries; widen the length range or pick a larger island"
    )
