"""Pictures of a city's storefronts for the docs: robot-camera views from the sidewalk and a street's BEV.

Usage::

    python scripts/storefront_views.py synthetic-grid-s0 [--out docs/img] [--count 3]

For a built city target (``navverse build <target>``) it writes ``storefronts_<target>_views.png``:
``--count`` storefronts of different place categories, each as the robot's camera (Spot's: 0.6 m
above the ground, 90° field of view) sees it from the sidewalk, standing 4.5 m in front of the
storefront and a little to one side, and ``storefronts_<target>_bev.png``: the bird's-eye view of the
70 m around the street with the most storefronts, each outlined, its door marked and labelled with
its category.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from navverse.errors import NavverseError
from navverse.scene.annotations import StorefrontAnnotation
from navverse.scene.directory import read_scene
from navverse.scene.geometry import Scene
from navverse.scene.heights import SurfaceHeights
from navverse.sim.camera import CameraIntrinsics, look_at
from navverse.sim.render import SceneRenderer

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"
CAMERA_HEIGHT = 0.6
VIEW_DISTANCE = 4.5
SIDE_OFFSET = 1.0


def pick(scene: Scene, count: int) -> list[StorefrontAnnotation]:
    """`count` storefronts of different categories: the widest of each category (the widest signs),
    the widest first."""
    widest: dict[str, StorefrontAnnotation] = {}
    for store in sorted(scene.annotations.storefronts, key=lambda s: (-s.size[0], s.id)):
        widest.setdefault(store.place_category, store)
    return list(widest.values())[:count]


def camera_pose(store: StorefrontAnnotation, heights: SurfaceHeights) -> np.ndarray:
    """Camera-to-world of the robot's camera on the sidewalk in front of a storefront, looking at it."""
    normal = np.array([math.cos(store.facing), math.sin(store.facing)])
    along = np.array([-normal[1], normal[0]])
    eye = np.asarray(store.center[:2]) + normal * VIEW_DISTANCE + along * SIDE_OFFSET
    ground = heights(eye)[0]
    ground = store.entrance[2] if not np.isfinite(ground) else float(ground)
    target = [store.center[0], store.center[1], ground + 0.6 * store.size[2]]
    return look_at([eye[0], eye[1], ground + CAMERA_HEIGHT], target)


def views(scene: Scene, stores: list[StorefrontAnnotation]) -> Image.Image:
    """The camera views side by side, each captioned with the category and the sign's name."""
    intrinsics = CameraIntrinsics.from_hfov(640, 480, 90.0)
    renderer = SceneRenderer(scene, intrinsics=intrinsics, depth_range=(0.1, 1000.0))
    heights = SurfaceHeights(scene)
    tiles = []
    for store in stores:
        frame = Image.fromarray(renderer.render(camera_pose(store, heights)).rgb)
        caption = Image.new("RGB", (640, 28), (255, 255, 255))
        ImageDraw.Draw(caption).text((8, 8), f"{store.place_category}: {store.name}", fill=(0, 0, 0))
        tile = Image.new("RGB", (640, 508))
        tile.paste(frame, (0, 0))
        tile.paste(caption, (0, 480))
        tiles.append(tile)
    sheet = Image.new("RGB", (640 * len(tiles) + 8 * (len(tiles) - 1), 508), (255, 255, 255))
    for k, tile in enumerate(tiles):
        sheet.paste(tile, (k * 648, 0))
    return sheet


def street_bev(scene: Scene, out: Path, *, side: float = 70.0, pixels: int = 900) -> Path:
    """The BEV of the `side` m square around the densest group of storefronts, each one outlined in
    yellow with an arrow out of its door and labelled with its category."""
    from navverse.scene.bev import bev_window

    stores = scene.annotations.storefronts
    centres = np.array([s.center[:2] for s in stores])
    near = ((centres[:, None] - centres[None]) ** 2).sum(-1) < (side / 2) ** 2
    middle = centres[int(near.sum(1).argmax())]
    window = bev_window(scene, middle, side, pixels=pixels)
    crop = Image.fromarray(window.image)
    draw = ImageDraw.Draw(crop)
    pixel = window.pixel

    for store in stores:
        if np.abs(np.asarray(store.center[:2]) - middle).max() > side / 2:
            continue
        normal = np.array([math.cos(store.facing), math.sin(store.facing)])
        along = np.array([-normal[1], normal[0]])
        centre = np.asarray(store.center[:2])
        half_w, half_d = store.size[0] / 2, store.size[1] / 2
        corners = [
            centre + along * a * half_w + normal * b * half_d for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))
        ]
        draw.polygon([pixel(c) for c in corners], outline=(255, 200, 0), width=3)
        door = np.asarray(store.entrance[:2])
        draw.line([pixel(door - normal * 0.6), pixel(door + normal * 1.2)], fill=(220, 40, 40), width=3)
        x, y = pixel(centre + normal * 2.5)
        draw.text(
            (x - 20, y - 6), store.place_category, fill=(0, 0, 0), stroke_width=2, stroke_fill=(255, 255, 255)
        )
    crop.save(out, optimize=True)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("target", help="a built city target")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "img")
    parser.add_argument("--count", type=int, default=3)
    args = parser.parse_args(argv)
    scene_dir = TARGETS / args.target / "scene"
    try:
        if not scene_dir.is_dir():
            raise NavverseError(f"{args.target} is not built: run `navverse build {args.target}` first")
        scene = read_scene(scene_dir)
        if not scene.annotations.storefronts:
            raise NavverseError(f"{args.target} has no storefronts (is the storefronts stage skipped?)")
        args.out.mkdir(parents=True, exist_ok=True)
        sheet = args.out / f"storefronts_{args.target}_views.png"
        views(scene, pick(scene, args.count)).save(sheet, optimize=True)
        print(sheet)
        print(street_bev(scene, args.out / f"storefronts_{args.target}_bev.png"))
    except NavverseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
