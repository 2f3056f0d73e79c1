"""The streets of a built scene for traffic: the roads cars drive and the crossings where people cross.

The roads are those of the city map the scene was made from, as its look keeps them (``look.json``
``map.roads``: centerline, width, lanes, one-way, highway class; :func:`navverse.look.files.read_look`).
The crossings are where people actually cross: the navmesh's crosswalk polygons, joined where they
touch, each group's area-weighted centre (a mapped crossing and the junction crosswalks the geometry
adds alike). A scene without a map (an indoor building) has no roads; one without crosswalk polygons
has no crossings.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from navverse.dynamics.traffic import RoadSpec
from navverse.look.files import find_look, read_look
from navverse.nav.pathfinder import PathFinder

__all__ = ["Streets", "crossings_of", "scene_streets"]

CROSSWALK = "crosswalk"
_TOUCH = 0.05  # m: polygons whose vertices come this close belong to one crossing


@dataclass(frozen=True)
class Streets:
    """Roads and crossings of a scene.

    Attributes
    ----------
    roads : list of RoadSpec
    crossings : ndarray, shape (K, 2)
        Centre of each crossing (m).
    """

    roads: list[RoadSpec]
    crossings: np.ndarray


def crossings_of(finder: PathFinder) -> np.ndarray:
    """Centres ``(K, 2)`` of the groups of touching crosswalk polygons of a navmesh (its areas named)."""
    area = finder.area_names.get(CROSSWALK)
    if area is None:
        return np.zeros((0, 2))
    polygons = [
        p for p, kind in zip(finder.polygons(), finder.polygon_area_types(), strict=True) if kind == area
    ]
    if not polygons:
        return np.zeros((0, 2))
    parent = list(range(len(polygons)))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    owner = np.concatenate([np.full(len(p), i) for i, p in enumerate(polygons)])
    keys = np.round(np.concatenate([p[:, :2] for p in polygons]) / _TOUCH).astype(np.int64)
    order = np.lexsort((keys[:, 1], keys[:, 0]))
    same = np.all(keys[order][1:] == keys[order][:-1], axis=1)
    for a, b in zip(owner[order][:-1][same], owner[order][1:][same], strict=True):
        ra, rb = root(int(a)), root(int(b))
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    sums: dict[int, np.ndarray] = {}
    for i, polygon in enumerate(polygons):
        xy = polygon[:, :2]
        cross = xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1]
        area_m2 = 0.5 * cross.sum()
        if abs(area_m2) < 1e-9:
            continue
        centre = ((xy + np.roll(xy, -1, axis=0)) * cross[:, None]).sum(axis=0) / (6.0 * area_m2)
        total = sums.setdefault(root(i), np.zeros(3))
        total += (abs(area_m2) * centre[0], abs(area_m2) * centre[1], abs(area_m2))
    return np.array([[t[0] / t[2], t[1] / t[2]] for _, t in sorted(sums.items())]).reshape(-1, 2)


def scene_streets(scene_dir: str | Path, finder: PathFinder) -> Streets:
    """The street plan of a built scene (its look's roads, its navmesh's crossings).

    Raises
    ------
    SceneError
        If the scene's look exists but cannot be read.
    """
    roads: list[RoadSpec] = []
    look = find_look(Path(scene_dir))
    if look is not None:
        _, details = read_look(look)
        for road in details.roads if details is not None else []:
            roads.append(
                RoadSpec(
                    centerline=np.asarray(road.centerline, dtype=float),
                    width=float(road.width),
                    highway=road.highway,
                    lanes=road.lanes,
                    oneway=road.oneway,
                )
            )
    return Streets(roads=roads, crossings=crossings_of(finder))
