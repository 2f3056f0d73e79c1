"""Pictures of a populated city for the docs: a robot's camera on a busy sidewalk, and the zones of its block.

Usage::

    python scripts/street_life_views.py synthetic-grid-s0 [--out docs/img] [--size 90]

For a built city target (``navverse build <target>``; its ``populate`` stage on) it writes:

- ``street_<target>_camera.png``: RGB and semantic images (objects by instance with their category,
  terrain by class) from a robot camera 0.6 m above the walkway, placed where the most objects stand
  within 25 m ahead along the street;
- ``street_<target>_zones.png``: a bird's-eye view of ``--size`` meters around that camera: the
  street plan's classes, the sidewalk zones (furniture, walkway, frontage, verge) and parking bands
  (``navverse/city/street_life/zones.py``), every object's footprint coloured by what placed it (mapped
  furniture, the zone grammar, parking, contextual groups), and the camera.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Patch, PathPatch
from matplotlib.patches import Polygon as PolygonPatch
from matplotlib.path import Path as MplPath
from PIL import Image
from render_frames import panel, rgb_image, semantic_image
from shapely.geometry import LineString, Point, box

from navverse.city.geometry.street_plan import STREET_PLAN_FILE, load_street_plan
from navverse.city.map import read_city_map
from navverse.city.street_life.objects import footprint
from navverse.city.street_life.zones import street_zones
from navverse.errors import NavverseError
from navverse.scene.directory import read_scene
from navverse.sim.camera import look_at
from navverse.sim.render import SceneRenderer

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"
EYE = 0.6
PLAN_COLOURS = {
    "road": "#5b5e66",
    "crosswalk": "#e8dc8c",
    "lowered_curb": "#e8dc8c",
    "curb": "#9aa0aa",
    "shared": "#7d7f86",
    "building": "#a08a7c",
    "green": "#a8cf8c",
    "ground": "#d9cdb4",
    "plaza": "#d9b8a8",
    "parking": "#8a8d99",
    "water": "#8ab4e0",
}
ZONE_COLOURS = {
    "furniture": "#4f9a4f",
    "walkway": "#f2f2f2",
    "frontage": "#b98ad9",
    "verge": "#c2c77a",
    "parking": "#6f95d6",
    "curbside": "#9bb6e6",
}
SOURCE_COLOURS = {
    "map": "#1f4fa8",
    "osm": "#1f4fa8",
    "grammar": "#127a3a",
    "parking": "#c0392b",
    "group": "#e67e22",
}


def _polygons(geometry):
    return [g for g in getattr(geometry, "geoms", [geometry]) if g.geom_type == "Polygon" and not g.is_empty]


def _patch(polygon, **style) -> PathPatch:
    """A matplotlib patch of a polygon with its holes."""
    rings = [np.asarray(polygon.exterior.coords), *(np.asarray(r.coords) for r in polygon.interiors)]
    codes = []
    for ring in rings:
        codes += [MplPath.MOVETO] + [MplPath.LINETO] * (len(ring) - 2) + [MplPath.CLOSEPOLY]
    return PathPatch(MplPath(np.concatenate(rings), codes), **style)


def camera_spot(city, zones, objects) -> tuple[np.ndarray, np.ndarray]:
    """The walkway point (eye) and look-at target with the most objects within 25 m ahead."""
    centres = np.array([o.annotation.center[:2] for o in objects]) if objects else np.zeros((0, 2))
    best, best_score = None, -1
    for road in city.roads:
        line = LineString(road.centerline.points)
        for sign, walk in ((1.0, road.sidewalk_left), (-1.0, road.sidewalk_right)):
            if walk is None or line.length < 30.0:
                continue
            offset = line.offset_curve(sign * (road.width / 2.0 + walk * 0.6))
            if offset.is_empty or offset.geom_type != "LineString":
                continue
            for along in np.arange(5.0, offset.length - 5.0, 10.0):
                here = offset.interpolate(along)
                if not zones.walkway.contains(here):
                    continue
                ahead = offset.interpolate(min(offset.length, along + 1.0))
                direction = np.array([ahead.x - here.x, ahead.y - here.y])
                norm = np.linalg.norm(direction)
                if norm == 0 or not len(centres):
                    continue
                direction /= norm
                rel = centres - (here.x, here.y)
                dist = np.linalg.norm(rel, axis=1)
                cos = (rel @ direction) / np.maximum(dist, 1e-9)
                score = int(((dist < 25.0) & (dist > 2.0) & (cos > math.cos(math.radians(35)))).sum())
                if score > best_score:
                    best_score = score
                    best = (np.array([here.x, here.y]), np.array([here.x, here.y]) + 20.0 * direction)
    if best is None:
        raise NavverseError("no walkway with objects in view: is the city populated?")
    return best


def zones_picture(path: Path, plan, zones, objects, eye, target, size: float) -> None:
    """The bird's-eye view of ``size`` meters around the camera."""
    half = size / 2.0
    window = box(eye[0] - half, eye[1] - half, eye[0] + half, eye[1] + half)
    fig, ax = plt.subplots(figsize=(9, 9))
    for cls, colour in PLAN_COLOURS.items():
        for polygon in _polygons(plan.classes[cls].intersection(window)):
            ax.add_patch(_patch(polygon, color=colour, lw=0))
    for name, colour in ZONE_COLOURS.items():
        for polygon in _polygons(getattr(zones, name).intersection(window)):
            ax.add_patch(_patch(polygon, color=colour, lw=0))
    for obj in objects:
        a = obj.annotation
        if not window.contains(Point(a.center[:2])):
            continue
        shape = footprint(a.category, a.size, a.center[0], a.center[1], a.yaw + math.pi / 2.0)
        colour = SOURCE_COLOURS.get((a.source or "").split(":")[0], "black")
        ax.add_patch(
            PolygonPatch(np.asarray(shape.exterior.coords), facecolor=colour, edgecolor="black", lw=0.4)
        )
    ax.annotate("", xy=target, xytext=eye, arrowprops={"arrowstyle": "->", "color": "red", "lw": 2})
    ax.plot(*eye, "o", color="red")
    ax.set_xlim(eye[0] - half, eye[0] + half)
    ax.set_ylim(eye[1] - half, eye[1] + half)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    legend = [Patch(color=c, label=f"zone: {n}") for n, c in ZONE_COLOURS.items()]
    legend += [Patch(color=c, label=f"object: {n}") for n, c in SOURCE_COLOURS.items() if n != "osm"]
    legend.append(Patch(color="red", label="camera"))
    ax.legend(handles=legend, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def render(target: str, out: Path, size: float) -> list[Path]:
    """Write the two pictures of one built, populated city."""
    scene_dir = TARGETS / target / "scene"
    geometry_dir = TARGETS / target / "geometry"
    city_file = TARGETS / target / "city_map" / "city_map.json"
    if not scene_dir.is_dir() or not city_file.is_file() or not (geometry_dir / STREET_PLAN_FILE).is_file():
        raise NavverseError(f"{target} is not a built, populated city: run `navverse build {target}` first")
    scene = read_scene(scene_dir)
    city = read_city_map(city_file)
    plan = load_street_plan(geometry_dir / STREET_PLAN_FILE)
    zones = street_zones(city, plan)
    objects = list(scene.objects)
    eye, target_xy = camera_spot(city, zones, objects)
    out.mkdir(parents=True, exist_ok=True)
    renderer = SceneRenderer(scene)
    frame = renderer.render(look_at([*eye, EYE], [*target_xy, EYE]))
    categories = {o.annotation.id: o.annotation.category for o in objects}
    images = [rgb_image(frame, "RGB"), semantic_image(frame, renderer.class_names, categories)]
    camera = out / f"street_{target}_camera.png"
    panel(images, ["RGB", "semantic (instances by category, terrain by class)"], scale=1.0).save(camera)
    zones_path = out / f"street_{target}_zones.png"
    zones_picture(zones_path, plan, zones, objects, eye, target_xy, size)
    return [camera, zones_path]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("targets", nargs="+", help="built city targets, e.g. synthetic-grid-s0")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "img", help="output folder")
    parser.add_argument("--size", type=float, default=90.0, help="side of the bird's-eye view (m)")
    args = parser.parse_args(argv)
    try:
        for target in args.targets:
            for path in render(target, args.out, args.size):
                Image.open(path).verify()
                print(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path)
    except NavverseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
