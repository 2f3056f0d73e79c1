"""Pictures of built city scenes for the docs: the BEV, a street-level view and an oblique aerial view.

Usage::

    python scripts/city_views.py west-oakland synthetic-s0 [--out docs/img]

For each target (built with ``navverse build <target>``) it writes ``city_<target>_bev.png`` (the
scene's ``bev.png``: terrain classes, buildings, crosswalks, the navmesh drawn in),
``city_<target>_street.png`` (a 1280 x 720 ray-cast view from 1.6 m above a sidewalk near the
window's centre, looking along the street) and ``city_<target>_aerial.png`` (from 45 degrees above
the south-west, looking at the centre).
"""

from __future__ import annotations

import argparse
import math
import shutil
import sys
from pathlib import Path

import numpy as np
from PIL import Image
from shapely.geometry import LineString, Point

from navverse.city.map import CityMap, Road, read_city_map
from navverse.errors import NavverseError
from navverse.scene.directory import read_scene
from navverse.sim.camera import CameraIntrinsics, look_at
from navverse.sim.render import SceneRenderer, Shading

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"
EYE_HEIGHT = 1.6
OUTDOOR = Shading(fog=0.25, fog_distance=400.0)


def street_pose(city: CityMap) -> np.ndarray:
    """A camera on a sidewalk of the road nearest the window's centre, looking along the road."""
    x0, y0, x1, y1 = city.window
    centre = Point((x0 + x1) / 2.0, (y0 + y1) / 2.0)
    candidates: list[Road] = [r for r in city.roads if r.sidewalk_left or r.sidewalk_right]
    if not candidates:
        candidates = list(city.roads)
    road = min(candidates, key=lambda r: LineString(r.centerline.points).distance(centre))
    line = LineString(road.centerline.points)
    along = line.project(centre)
    here = line.interpolate(along)
    ahead = line.interpolate(min(line.length, along + 1.0))
    if ahead.distance(here) < 0.5:
        ahead, here = here, line.interpolate(max(0.0, along - 1.0))
    direction = np.array([ahead.x - here.x, ahead.y - here.y])
    direction /= np.linalg.norm(direction)
    left = np.array([-direction[1], direction[0]])
    side, sign = (road.sidewalk_left, 1.0) if road.sidewalk_left else (road.sidewalk_right, -1.0)
    offset = road.width / 2.0 + (side or 1.0) / 2.0
    eye = np.array([here.x, here.y]) + sign * left * offset
    target = eye + direction * 30.0
    return look_at([*eye, EYE_HEIGHT], [*target, 1.0])


def aerial_pose(city: CityMap) -> np.ndarray:
    """A camera 45 degrees above the south-west of the centre, far enough to see about 300 m."""
    x0, y0, x1, y1 = city.window
    cx, cy = (x0 + x1) / 2.0, (y0 + y1) / 2.0
    reach = min(150.0, 0.5 * max(x1 - x0, y1 - y0))
    distance = reach * 1.2
    horizontal = distance / math.sqrt(2.0)
    eye = [cx - horizontal / math.sqrt(2.0), cy - horizontal / math.sqrt(2.0), horizontal]
    return look_at(eye, [cx, cy, 0.0])


def render(target: str, out: Path) -> list[Path]:
    """Write the three pictures of one built target; returns their paths."""
    scene_dir = TARGETS / target / "scene"
    city_file = TARGETS / target / "city_map" / "city_map.json"
    if not scene_dir.is_dir() or not city_file.is_file():
        raise NavverseError(f"{target} is not a built city: run `navverse build {target}` first")
    scene = read_scene(scene_dir)
    city = read_city_map(city_file)
    out.mkdir(parents=True, exist_ok=True)
    written = [out / f"city_{target}_bev.png"]
    shutil.copyfile(scene_dir / "bev.png", written[0])
    intrinsics = CameraIntrinsics.from_hfov(1280, 720, 80.0)
    renderer = SceneRenderer(scene, intrinsics=intrinsics, depth_range=(0.1, 3000.0), shading=OUTDOOR)
    for name, pose in (("street", street_pose(city)), ("aerial", aerial_pose(city))):
        path = out / f"city_{target}_{name}.png"
        Image.fromarray(renderer.render(pose).rgb).save(path, optimize=True)
        written.append(path)
    return written


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("targets", nargs="+", help="built city targets, e.g. west-oakland synthetic-s0")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "img", help="output folder")
    args = parser.parse_args(argv)
    try:
        for target in args.targets:
            for path in render(target, args.out):
                print(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path)
    except NavverseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
