"""A table of built indoor-to-outdoor scenes: how each building was joined to its city.

Usage::

    python scripts/i2o_report.py [targets...]     # default: every built i2o target

For each target it prints the city facade chosen, the exit (opening) width, the floor-to-ground step
at the exit, the navmesh islands, whether the rooms and the street outside the exit are one island,
and the share of the building's navigable floor (2000 points drawn over it by area) reachable from the
street, as a Markdown table.
"""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon

from navverse.nav.scene_navmesh import load_scene_navmesh, read_navmesh_info
from navverse.scene.directory import read_annotations
from navverse.scene_types import scene_profile

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"
SAMPLES = 2000


def row(target: str) -> str:
    """One Markdown row for a built i2o target."""
    scene_dir = TARGETS / target / "scene"
    record = json.loads((Path(os.path.realpath(TARGETS / target / "geometry")) / "manifest.json").read_text())
    stats = record["stats"]
    ann = read_annotations(scene_dir)
    (building,) = [b for b in ann.buildings if b.indoor]
    exit_ = building.exits[0]
    finder = load_scene_navmesh(scene_dir)
    normal = np.array([math.cos(exit_.facing), math.sin(exit_.facing)])
    street = (*(np.asarray(exit_.center[:2]) + normal * 3.0), exit_.center[2])
    street_island = int(finder.island_of(street))
    footprint = Polygon(building.footprint)
    radius = float(np.max(np.linalg.norm(np.asarray(building.footprint) - exit_.center[:2], axis=1)))
    rng = np.random.default_rng(0)
    points = []
    for _ in range(SAMPLES * 20):
        p = finder.get_random_navigable_point_near(exit_.center, radius, rng)
        if (
            np.isfinite(p).all()
            and shapely.contains_xy(footprint, p[0], p[1])
            and p[2] < exit_.center[2] + 1.0
        ):
            points.append(p)
            if len(points) == SAMPLES:
                break
    islands = finder.island_of(np.array(points))
    rooms = [
        int(finder.island_of((*Polygon(r.polygon).representative_point().coords[0], exit_.center[2])))
        for r in building.rooms
    ]
    one = all(i == street_island for i in rooms) and street_island >= 0
    reachable = float(np.mean(islands == street_island)) if len(points) else 0.0
    info = read_navmesh_info(scene_dir / "navmesh.json")
    return (
        f"| {target} | {stats['city']} facade {stats['facade']} (replaces {stats['replaced']['map_id']}) "
        f"| {stats['exit_width']:.2f} m | {stats['step']:+.3f} m | {info.islands} "
        f"| {'yes' if one else 'no'} | {100 * reachable:.1f} % of {len(points)} |"
    )


def main(argv: list[str]) -> int:
    targets = argv or sorted(
        p.name
        for p in TARGETS.iterdir()
        if (p / "scene" / "scene.json").is_file()
        and scene_profile(read_annotations(p / "scene").scene_type).transition_metrics  # joined to a city
    )
    print(
        "| target | facade | opening | floor step | navmesh islands | rooms and street one island "
        "| indoor navmesh reachable from the street |"
    )
    print("|---|---|---|---|---|---|---|")
    for target in targets:
        print(row(target))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
