"""Whether street objects keep a city's sidewalks passable: the bare and the populated navmesh compared.

:func:`sidewalk_passability` lays a grid of points over the plan's sidewalks and crosswalks, stands
them on the bare scene's surface, and asks both navmeshes which island each point lies over (a point
not over a navmesh polygon is off it). Objects
take sidewalk away (points under them leave the mesh) but must not cut it: the points of one bare
island must stay on one populated island, and every crosswalk must still be on the mesh, on the
island its sidewalks were on.

A piece cut off by an object is a **cut** when it holds at least ``min_piece`` points (with the
default 1.5 m grid, ~11 m² of sidewalk); smaller pieces are **pockets** (the corner between a bench
and a wall), counted apart. Islands are counted over the sidewalk points only, so a walkable car
roof or bench seat, an island of its own that no sidewalk point lies on, does not count.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from navverse.city.geometry.street_plan import StreetPlan
from navverse.nav import PathFinder

__all__ = ["Passability", "sidewalk_passability"]


@dataclass(frozen=True)
class Passability:
    """What population did to the sidewalk network.

    Attributes
    ----------
    points : int
        Sidewalk and crosswalk grid points on the bare navmesh.
    covered : int
        Of them, points off the populated navmesh (under or too close to an object).
    islands_before, islands_after : int
        Islands holding sidewalk points, on the bare and on the populated navmesh (pockets left out
        of the latter).
    cuts : int
        Pieces of at least ``min_piece`` points cut off their bare island by objects.
    pocket_points : int
        Points on pieces smaller than that.
    crosswalks : int
        Crosswalks of the plan.
    crosswalks_cut : int
        Crosswalks with no point left on the populated navmesh's island of their bare island.
    """

    points: int
    covered: int
    islands_before: int
    islands_after: int
    cuts: int
    pocket_points: int
    crosswalks: int
    crosswalks_cut: int

    @property
    def passable(self) -> bool:
        """No cut, no crosswalk cut off, as many islands as before."""
        return self.cuts == 0 and self.crosswalks_cut == 0 and self.islands_after == self.islands_before


def _grid(area: BaseGeometry, spacing: float) -> np.ndarray:
    """Points of a ``spacing`` grid inside ``area`` (cell centres), shape (N, 2)."""
    if area.is_empty:
        return np.zeros((0, 2))
    x0, y0, x1, y1 = area.bounds
    xs = np.arange(x0 + spacing / 2.0, x1, spacing)
    ys = np.arange(y0 + spacing / 2.0, y1, spacing)
    gx, gy = (g.ravel() for g in np.meshgrid(xs, ys))
    shapely.prepare(area)
    inside = shapely.contains_xy(area, gx, gy)
    return np.column_stack([gx[inside], gy[inside]])


def _islands(finder: PathFinder, xyz: np.ndarray, reach: float) -> np.ndarray:
    """The island under each point (-1 where the point is off the navmesh or over no surface)."""
    found = np.full(len(xyz), -1)
    ok = np.isfinite(xyz[:, 2])
    if ok.any():
        on = np.zeros(len(xyz), dtype=bool)
        on[ok] = finder.is_navigable(xyz[ok], max_y_delta=0.5)
        found[on] = finder.island_of(xyz[on], max_horizontal=reach, max_vertical=0.5)
    return found


def sidewalk_passability(
    bare: PathFinder,
    populated: PathFinder,
    plan: StreetPlan,
    heights: Callable[[np.ndarray], np.ndarray],
    *,
    spacing: float = 1.5,
    min_piece: int = 5,
    reach: float = 0.1,
) -> Passability:
    """Compare the sidewalk islands of a city's bare and populated navmeshes.

    Parameters
    ----------
    bare, populated : PathFinder
        Navmeshes of the scene before and after population, built with the same settings.
    plan : StreetPlan
        The city's ground plan (``street_plan.json``).
    heights : callable
        ``heights(xy) -> z``: the bare scene's surface height under each point (NaN where none).
    spacing : float
        Grid spacing (m).
    min_piece : int
        Fewest points of a cut-off piece that counts as a cut.
    reach : float
        How far (m, horizontally) a point over the navmesh may snap to it to find its island.

    Returns
    -------
    Passability
    """
    crosswalk_parts = [
        part
        for part in getattr(plan.classes["crosswalk"], "geoms", [plan.classes["crosswalk"]])
        if part.area > 0
    ]
    walk = _grid(shapely.union_all([plan.classes["sidewalk"], plan.classes["crosswalk"]]), spacing)
    points = [walk] + [_grid(part, min(spacing, 0.5)) for part in crosswalk_parts]
    owners = np.concatenate([np.full(len(p), k - 1) for k, p in enumerate(points)])  # -1: sidewalk grid
    xy = np.concatenate(points) if points else np.zeros((0, 2))
    z = np.asarray(heights(xy), dtype=np.float64)
    xyz = np.column_stack([xy, z + 0.05])
    before, after = (_islands(finder, xyz, reach) for finder in (bare, populated))
    on_bare = before >= 0
    grid = on_bare & (owners < 0)

    # Pieces: (bare island, populated island) pairs of the still-navigable sidewalk points.
    kept = grid & (after >= 0)
    pieces = Counter(zip(before[kept].tolist(), after[kept].tolist(), strict=True))
    by_bare: dict[int, list[tuple[int, int]]] = defaultdict(list)
    for (b, a), n in pieces.items():
        by_bare[b].append((n, a))
    cuts = pocket_points = 0
    main_of: dict[int, int] = {}
    big_after: set[int] = set()
    for b, found in by_bare.items():
        found.sort(reverse=True)
        main_of[b] = found[0][1]
        big_after.add(found[0][1])
        for n, a in found[1:]:
            if n >= min_piece:
                cuts += 1
                big_after.add(a)
            else:
                pocket_points += n

    crosswalks_cut = 0
    for k in range(len(crosswalk_parts)):
        mine = (owners == k) & on_bare
        if not mine.any():
            continue  # not on the bare navmesh either (a crosswalk cut by the window)
        home = {main_of.get(int(b)) for b in before[mine]}
        if not any(int(a) in home for a in after[mine] if a >= 0):
            crosswalks_cut += 1
    return Passability(
        points=int(grid.sum()),
        covered=int((grid & (after < 0)).sum()),
        islands_before=len(set(before[grid].tolist())),
        islands_after=len(big_after),
        cuts=cuts,
        pocket_points=pocket_points,
        crosswalks=len(crosswalk_parts),
        crosswalks_cut=crosswalks_cut,
    )
