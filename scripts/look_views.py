"""Before and after pictures of the robot camera: the flat frame beside the lit look, on six views.

Usage::

    python scripts/look_views.py [--city west-oakland] [--i2o office-west-oakland]
        [--apartment apartment-s0] [--office office-s1] [--out docs/img]

Each view is rendered by Spot's camera (640 x 480, 90 degrees horizontal field of view, 0.6 m above
the ground) twice: flat (``Shading``: one colour per face under fixed lights, the camera before
looks existed) and lit (the scene's built look: sun and shadows, sky, materials, facades, markings,
room lamps, exposure). The views: a street (on a sidewalk of the road nearest the city's centre,
looking along it), a crossing (the crossing nearest the centre, from the kerb, looking across the
road), a storefront row (the widest storefront, from the sidewalk, looking along its facade), the
i2o doorway from inside (2.5 m inside the exit, looking out), an apartment room (the largest living
room, corner to corner) and an office (the open office, corner to corner). It writes
``look_<view>.jpg`` for each (flat left, lit right) into ``--out``; every scene must be built with
its look (``navverse build <id>``).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np
from city_views import street_pose
from i2o_views import indoor_exit
from PIL import Image, ImageDraw
from render_frames import across_room
from shapely.geometry import LineString, Point
from storefront_views import pick

from navverse.city.geometry.crossings import junction_crossings
from navverse.city.geometry.surfaces import CROSSWALK_WIDTH
from navverse.city.map import CityMap, read_city_map
from navverse.errors import NavverseError
from navverse.look.files import find_look, load_scene_look
from navverse.scene.directory import read_scene
from navverse.scene.geometry import Scene
from navverse.scene.heights import SurfaceHeights
from navverse.scene_types import scene_profile
from navverse.sim.camera import CameraIntrinsics, look_at
from navverse.sim.render import SceneRenderer, Shading

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"
CAMERA_HEIGHT = 0.6
INTRINSICS = CameraIntrinsics.from_hfov(640, 480, 90.0)
CAPTION = 26  # pixels of caption under each frame

Pose = np.ndarray
Placer = Callable[[Scene, CityMap | None], Pose]


def _on_ground(scene: Scene, xy: np.ndarray) -> float:
    """The walkable surface's height under a plan point (0 where none is found)."""
    height = float(SurfaceHeights(scene)(np.asarray(xy, dtype=float))[0])
    return height if math.isfinite(height) else 0.0


def _robot_eye(scene: Scene, pose: Pose) -> Pose:
    """A pose moved down (or up) to the robot camera's height above the ground under it, looking level."""
    eye = pose[:3, 3]
    forward = pose[:3, 2].copy()
    forward[2] = 0.0
    forward /= max(float(np.linalg.norm(forward)), 1e-9)
    z = _on_ground(scene, eye[:2]) + CAMERA_HEIGHT
    return look_at([eye[0], eye[1], z], [eye[0] + 10.0 * forward[0], eye[1] + 10.0 * forward[1], z - 0.3])


def street(scene: Scene, city: CityMap | None) -> Pose:
    """On a sidewalk of the road nearest the centre, looking along the road."""
    if city is None:
        raise NavverseError("the street view needs a city built from a map")
    return _robot_eye(scene, street_pose(city))


def crossing(scene: Scene, city: CityMap | None) -> Pose:
    """At the kerb of the crossing nearest the city's centre (a mapped one, else one the geometry adds
    on a junction arm), looking across the road on it."""
    if city is None:
        raise NavverseError("the crossing view needs a city built from a map")
    crossings = city.crossings or junction_crossings(city, crosswalk_width=CROSSWALK_WIDTH)
    if not crossings:
        raise NavverseError("the city has no crossing to look across")
    x0, y0, x1, y1 = city.window
    centre = Point((x0 + x1) / 2.0, (y0 + y1) / 2.0)
    roads = {road.id: road for road in city.roads}
    chosen = min(crossings, key=lambda c: (Point(c.position).distance(centre), c.id))
    road = roads[chosen.road]
    line = LineString(road.centerline.points)
    at = line.project(Point(chosen.position))
    ahead = line.interpolate(min(line.length, at + 0.5))
    behind = line.interpolate(max(0.0, at - 0.5))
    direction = np.array([ahead.x - behind.x, ahead.y - behind.y])
    direction /= max(float(np.linalg.norm(direction)), 1e-9)
    left = np.array([-direction[1], direction[0]])
    here = np.asarray(chosen.position, dtype=float)
    eye = here + left * (road.width / 2.0 + 1.2) - direction * 0.8
    target = here - left * (road.width / 2.0 + 4.0)
    z = _on_ground(scene, eye) + CAMERA_HEIGHT
    return look_at([*eye, z], [*target, z - 1.0])


def storefront_row(scene: Scene, city: CityMap | None) -> Pose:
    """On the sidewalk before the widest storefront, looking along its facade."""
    stores = pick(scene, 1)
    if not stores:
        raise NavverseError(f"{scene.scene_id} has no storefront")
    store = stores[0]
    normal = np.array([math.cos(store.facing), math.sin(store.facing)])
    along = np.array([-normal[1], normal[0]])
    centre = np.asarray(store.center[:2], dtype=float)
    eye = centre + normal * 3.0 - along * 6.0
    target = centre + along * 6.0 + normal * 0.5
    z = _on_ground(scene, eye) + CAMERA_HEIGHT
    return look_at([*eye, z], [*target, z + 0.6])


def doorway(scene: Scene, city: CityMap | None) -> Pose:
    """2.5 m inside the i2o exit, looking out through it."""
    exit_ = indoor_exit(scene)
    normal = np.array([math.cos(exit_.facing), math.sin(exit_.facing)])
    centre = np.asarray(exit_.center[:2], dtype=float)
    floor = exit_.center[2]
    return look_at(
        [*(centre - normal * 2.5), floor + CAMERA_HEIGHT], [*(centre + normal * 10.0), floor + 1.0]
    )


def room(room_type: str, corner: tuple[int, int]) -> Placer:
    """Corner to corner across the largest room of a type."""

    def place(scene: Scene, city: CityMap | None) -> Pose:
        eye, target = across_room(room_type, corner=corner)(scene.annotations)
        return look_at(eye, target)

    return place


def renderers(target: str) -> tuple[Scene, CityMap | None, SceneRenderer, SceneRenderer]:
    """A built scene, its city map (if any) and its flat and lit renderers."""
    scene_dir = TARGETS / target / "scene"
    if not (scene_dir / "scene.json").is_file():
        raise NavverseError(f"{target} is not built: run `navverse build {target}` first")
    if find_look(scene_dir) is None:
        raise NavverseError(f"{target} has no built look: run `navverse build {target}`")
    scene = read_scene(scene_dir)
    city_file = TARGETS / target / "city_map" / "city_map.json"
    city = read_city_map(city_file) if city_file.is_file() else None
    sky = scene_profile(scene.annotations.scene_type).sky
    flat = SceneRenderer(scene, intrinsics=INTRINSICS, depth_range=(0.1, 1000.0), shading=Shading(sky=sky))
    lit = SceneRenderer(
        scene, intrinsics=INTRINSICS, depth_range=(0.1, 1000.0), look=load_scene_look(scene, scene_dir)
    )
    return scene, city, flat, lit


def side_by_side(flat: np.ndarray, lit: np.ndarray, captions: tuple[str, str]) -> Image.Image:
    """The two frames with a caption under each."""
    height, width = flat.shape[:2]
    sheet = Image.new("RGB", (2 * width + 8, height + CAPTION), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    for k, (frame, caption) in enumerate(zip((flat, lit), captions, strict=True)):
        sheet.paste(Image.fromarray(frame), (k * (width + 8), 0))
        draw.text((k * (width + 8) + 8, height + 7), caption, fill=(0, 0, 0))
    return sheet


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--city", default="west-oakland", help="built city with storefronts")
    parser.add_argument("--i2o", default="office-west-oakland", help="built indoor-to-outdoor scene")
    parser.add_argument("--apartment", default="apartment-s0", help="built apartment")
    parser.add_argument("--office", default="office-s1", help="built office")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "img")
    args = parser.parse_args(argv)
    views: list[tuple[str, str, Placer]] = [
        ("street", args.city, street),
        ("crossing", args.city, crossing),
        ("storefronts", args.city, storefront_row),
        ("i2o-doorway", args.i2o, doorway),
        ("apartment", args.apartment, room("living_room", (0, 0))),
        ("office", args.office, room("open_office", (0, 1))),
    ]
    args.out.mkdir(parents=True, exist_ok=True)
    loaded: dict[str, tuple[Scene, CityMap | None, SceneRenderer, SceneRenderer]] = {}
    try:
        for name, target, place in views:
            if target not in loaded:
                loaded[target] = renderers(target)
            scene, city, flat, lit = loaded[target]
            pose = place(scene, city)
            sheet = side_by_side(
                flat.render(pose).rgb,
                lit.render(pose).rgb,
                (f"{target}, {name}: flat (before looks)", f"{target}, {name}: lit (its look)"),
            )
            path = args.out / f"look_{name}.jpg"
            partial = path.with_name(path.name + ".partial")
            sheet.save(partial, format="JPEG", quality=88, optimize=True)
            os.replace(partial, path)
            print(path)
    except NavverseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
