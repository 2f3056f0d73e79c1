"""Pictures of an assembled indoor-to-outdoor scene for the docs: its bird's-eye view around the exit,
and the robot camera's view at the doorway looking out and from the sidewalk looking in.

Usage::

    python scripts/i2o_views.py cafe-west-oakland [--out docs/img]

For a built i2o target it writes ``i2o_<target>_bev.png`` (the 60 m square around the exit: rooms,
furniture, the street and its objects; the exit's doorway marked in red, pointing out) and
``i2o_<target>_doorway.png`` (two 640 x 480 frames from Spot's camera, 0.6 m above the floor: 2.5 m
inside the exit looking out, and 5 m outside it looking in).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from navverse.errors import NavverseError
from navverse.scene.annotations import ExitAnnotation
from navverse.scene.bev import bev_window
from navverse.scene.directory import read_scene
from navverse.scene.geometry import Scene
from navverse.sim.camera import CameraIntrinsics, look_at
from navverse.sim.render import SceneRenderer

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"
CAMERA_HEIGHT = 0.6
SIDE = 60.0


def indoor_exit(scene: Scene) -> ExitAnnotation:
    """The exit of the scene's indoor building (the one joined to the street)."""
    indoor = [b for b in scene.annotations.buildings if b.indoor]
    if len(indoor) != 1 or not indoor[0].exits:
        raise NavverseError(
            f"{scene.scene_id} is not an assembled i2o scene (no indoor building with an exit)"
        )
    return indoor[0].exits[0]


def bev(scene: Scene, exit_: ExitAnnotation, out: Path, *, pixels: int = 900) -> Path:
    """The BEV of the square around the exit, the doorway marked with an arrow pointing out."""
    centre = np.asarray(exit_.center[:2])
    window = bev_window(scene, centre, SIDE, pixels=pixels)
    image = Image.fromarray(window.image)
    draw = ImageDraw.Draw(image)
    pixel = window.pixel

    normal = np.array([math.cos(exit_.facing), math.sin(exit_.facing)])
    along = np.array([-normal[1], normal[0]])
    half = exit_.width / 2
    draw.line([pixel(centre - along * half), pixel(centre + along * half)], fill=(220, 30, 30), width=6)
    tip = centre + normal * 3.0
    draw.line([pixel(centre), pixel(tip)], fill=(220, 30, 30), width=4)
    for side in (-1, 1):
        draw.line([pixel(tip), pixel(tip - normal * 1.0 + along * side * 0.7)], fill=(220, 30, 30), width=4)
    x, y = pixel(tip + normal * 1.5)
    draw.text((x - 14, y - 6), "exit", fill=(0, 0, 0), stroke_width=2, stroke_fill=(255, 255, 255))
    image.save(out, optimize=True)
    return out


def doorway(scene: Scene, exit_: ExitAnnotation, out: Path) -> Path:
    """Two camera frames side by side: inside looking out, outside looking in."""
    renderer = SceneRenderer(scene, intrinsics=CameraIntrinsics.from_hfov(640, 480, 90.0))
    normal = np.array([math.cos(exit_.facing), math.sin(exit_.facing)])
    centre = np.asarray(exit_.center[:2])
    floor = exit_.center[2]
    inside = np.array([*(centre - normal * 2.5), floor + CAMERA_HEIGHT])
    outside = np.array([*(centre + normal * 5.0), floor + CAMERA_HEIGHT])
    frames = [
        renderer.render(look_at(inside, [*(centre + normal * 10.0), floor + 1.0])).rgb,
        renderer.render(look_at(outside, [*(centre - normal * 5.0), floor + 1.0])).rgb,
    ]
    sheet = Image.new("RGB", (1288, 480), (255, 255, 255))
    for k, frame in enumerate(frames):
        sheet.paste(Image.fromarray(frame), (k * 648, 0))
    sheet.save(out, optimize=True)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("target", help="a built i2o target, e.g. cafe-west-oakland")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "img")
    args = parser.parse_args(argv)
    scene_dir = TARGETS / args.target / "scene"
    try:
        if not (scene_dir / "scene.json").is_file():
            raise NavverseError(f"{args.target} is not built: run `navverse build {args.target}` first")
        scene = read_scene(scene_dir)
        exit_ = indoor_exit(scene)
        args.out.mkdir(parents=True, exist_ok=True)
        print(bev(scene, exit_, args.out / f"i2o_{args.target}_bev.png"))
        print(doorway(scene, exit_, args.out / f"i2o_{args.target}_doorway.png"))
    except NavverseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
