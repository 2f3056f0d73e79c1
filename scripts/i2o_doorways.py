"""Do an assembled scene's navmesh tiles resolve the building's doorways as the indoor preset does?

Usage::

    python scripts/i2o_doorways.py cafe-west-oakland:cafe-s0 office-synthetic-grid:office-s0 ...

For each pair (a built i2o target and the indoor target its building came from) it compares the two
navmeshes over the building: for every doorway between rooms and for the exit, whether a robot gets
from 0.8 m on one side to 0.8 m on the other (a path at most 1.5 times the straight line), and the
navigable floor inside the footprint (the area of the navmesh's polygons at floor height there).
Prints a Markdown table; exits 1 if a doorway passable in the indoor navmesh is not passable in the
assembled one.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon

from navverse.nav.scene_navmesh import load_scene_navmesh
from navverse.scene.directory import read_annotations

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"


def _building(scene_dir: Path):
    (building,) = [b for b in read_annotations(scene_dir).buildings if b.indoor]
    return building


def passable(finder, center, facing: float, floor: float) -> bool:
    """Whether the path across a doorway, 0.8 m each side, is at most 1.5 times its 1.6 m."""
    normal = np.array([math.cos(facing), math.sin(facing)])
    a = (*(np.asarray(center[:2]) - normal * 0.8), floor)
    b = (*(np.asarray(center[:2]) + normal * 0.8), floor)
    return bool(finder.geodesic_distance(a, b) <= 1.6 * 1.5)


def floor_area(finder, building) -> float:
    """The navigable area (m²) inside the building's footprint, at its floor: the navmesh polygons
    within 1 m of the floor height, clipped to the footprint."""
    footprint = Polygon(building.footprint)
    pieces = []
    for corners in finder.polygons():
        if len(corners) >= 3 and abs(float(np.mean(corners[:, 2])) - building.base_height) < 1.0:
            polygon = Polygon(corners[:, :2])
            if polygon.is_valid and polygon.intersects(footprint):
                pieces.append(polygon.intersection(footprint))
    return float(shapely.union_all(pieces).area) if pieces else 0.0


def compare(i2o: str, indoor: str) -> tuple[str, bool]:
    """One table row, and whether every doorway passable indoors is passable in the assembled scene."""
    results = {}
    for name in (indoor, i2o):
        scene_dir = TARGETS / name / "scene"
        finder = load_scene_navmesh(scene_dir)
        building = _building(scene_dir)
        floor = building.base_height
        doors = [passable(finder, d.center, d.facing, floor) for d in building.doors]
        exits = [passable(finder, e.center, e.facing, floor) for e in building.exits[:1]]
        results[name] = (doors, exits, floor_area(finder, building))
    (d0, e0, s0), (d1, e1, s1) = results[indoor], results[i2o]
    ok = all(b or not a for a, b in zip(d0 + e0, d1 + e1, strict=True))
    row = (
        f"| {i2o} | {indoor} | {sum(d0)}/{len(d0)} | {sum(d1)}/{len(d1)} | {sum(e0)}/{len(e0)} "
        f"| {sum(e1)}/{len(e1)} | {s0:.1f} m² | {s1:.1f} m² ({100 * s1 / s0:.1f} %) |"
    )
    return row, ok


def main(argv: list[str]) -> int:
    print(
        "| i2o scene | indoor scene | doorways passable (indoor preset) | (i2o) | exit (indoor) "
        "| exit (i2o) | navigable floor (indoor) | (i2o) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    good = True
    for pair in argv:
        i2o, _, indoor = pair.partition(":")
        row, ok = compare(i2o, indoor)
        print(row)
        good &= ok
    return 0 if good else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
