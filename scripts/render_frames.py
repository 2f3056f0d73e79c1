"""Render example robot camera frames of built indoor scenes into ``docs/img/frames/``.

Usage::

    python scripts/render_frames.py [--out docs/img/frames] [--only office-s1_corridor]

Each viewpoint is placed from the scene's annotations (rooms and doors in ``scene.json``), with the
camera 0.6 m above the floor and level, and gets a directory ``<scene>_<view>/`` with:

- ``rgb.png``: the shaded colour image of :class:`navverse.sim.render.SceneRenderer`;
- ``depth.png``: z-depth, near = bright (magma colour map), black where nothing was hit, with a
  scale bar in meters;
- ``semantic.png``: object instances in a categorical palette, labelled with their category;
  terrain in dark greys by class (floor, wall, ceiling), black where nothing was hit;
- ``panel.png``: the three side by side, at two thirds of the size.
"""

from __future__ import annotations

import argparse
import colorsys
import math
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib import colormaps
from PIL import Image, ImageDraw, ImageFont

from navverse.errors import NavverseError
from navverse.look.files import load_scene_look
from navverse.nav.scene_navmesh import load_scene_navmesh
from navverse.scene.annotations import RoomAnnotation, SceneAnnotations
from navverse.scene.directory import read_scene
from navverse.sim.camera import look_at
from navverse.sim.render import Frame, SceneRenderer

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"
CAMERA_HEIGHT = 0.6
STRIP = 34  # pixels of the legend strip under each image
TITLE = 26
TERRAIN_GREYS = {"floor": 70, "wall": 105, "ceiling": 45}
OTHER_TERRAIN_GREY = 85
MIN_LABEL_PIXELS = 1200

Pose = tuple[np.ndarray, np.ndarray]  # eye, target


@dataclass(frozen=True)
class Viewpoint:
    """A named camera placement in a built scene."""

    scene_id: str
    name: str
    place: Callable[[SceneAnnotations], Pose]

    @property
    def key(self) -> str:
        """Directory name of the viewpoint's images."""
        return f"{self.scene_id}_{self.name}"


def _room(annotations: SceneAnnotations, room_type: str) -> RoomAnnotation:
    rooms = [r for r in annotations.rooms if r.room_type == room_type]
    if not rooms:
        raise NavverseError(f"{annotations.scene_id} has no room of type {room_type!r}")
    return max(rooms, key=lambda r: _extent(r)[1].prod())


def _extent(room: RoomAnnotation) -> tuple[np.ndarray, np.ndarray]:
    polygon = np.asarray(room.polygon)
    lo, hi = polygon.min(axis=0), polygon.max(axis=0)
    return lo, hi - lo


def along_room(room_type: str, *, inset: float = 1.0) -> Callable[[SceneAnnotations], Pose]:
    """Stand `inset` meters inside one short end of the room, on its centre line, looking along it."""

    def place(annotations: SceneAnnotations) -> Pose:
        room = _room(annotations, room_type)
        lo, size = _extent(room)
        axis = int(np.argmax(size))
        center = lo + size / 2
        eye = center.copy()
        eye[axis] = lo[axis] + inset
        target = center.copy()
        target[axis] = lo[axis] + size[axis]
        z = room.floor_height + CAMERA_HEIGHT
        return np.append(eye, z), np.append(target, z)

    return place


def across_room(
    room_type: str, *, corner: tuple[int, int] = (0, 0), inset: float = 1.0
) -> Callable[[SceneAnnotations], Pose]:
    """Stand `inset` meters from a corner of the room's bounding box, looking at the opposite corner.

    `corner` picks the corner: per axis 0 for the minimum, 1 for the maximum.
    """

    def place(annotations: SceneAnnotations) -> Pose:
        room = _room(annotations, room_type)
        lo, size = _extent(room)
        hi = lo + size
        at_max = np.asarray(corner, dtype=bool)
        eye = np.where(at_max, hi - inset, lo + inset)
        target = np.where(at_max, lo + inset, hi - inset)
        z = room.floor_height + CAMERA_HEIGHT
        return np.append(eye, z), np.append(target, z)

    return place


VIEWPOINTS = (
    Viewpoint("office-s1", "corridor", along_room("corridor")),
    Viewpoint("office-s1", "open-office", across_room("open_office", corner=(0, 1))),
    Viewpoint("apartment-s0", "bedroom", across_room("bedroom")),
)


# ---------------------------------------------------------------------- pictures


def _font(size: int) -> ImageFont.ImageFont | ImageFont.FreeTypeFont:
    return ImageFont.load_default(size=size)


def _nice_ceiling(value: float) -> float:
    """The smallest of 1, 2, 2.5, 5 x 10^k at least `value`."""
    exponent = math.floor(math.log10(max(value, 1e-6)))
    for step in (1.0, 2.0, 2.5, 5.0, 10.0):
        if step * 10**exponent >= value:
            return step * 10**exponent
    return 10.0 ** (exponent + 1)


def _magma(values: np.ndarray) -> np.ndarray:
    return (colormaps["magma"](values)[..., :3] * 255).round().astype(np.uint8)


def depth_image(depth: np.ndarray, max_depth: float) -> Image.Image:
    """Depth as magma (near bright, far dark), black where nothing was hit, with a scale strip."""
    height, width = depth.shape
    shade = 1.0 - np.clip(depth / max_depth, 0.0, 1.0)
    rgb = _magma(0.12 + 0.88 * shade)
    rgb[depth <= 0] = 0
    canvas = Image.new("RGB", (width, height + STRIP), "white")
    canvas.paste(Image.fromarray(rgb), (0, 0))
    draw = ImageDraw.Draw(canvas)
    bar_left, bar_right, bar_top = 40, width - 150, height + 4
    ramp = np.linspace(0.0, 1.0, bar_right - bar_left)
    bar = _magma(0.12 + 0.88 * (1.0 - ramp))[None].repeat(10, axis=0)
    canvas.paste(Image.fromarray(bar), (bar_left, bar_top))
    font = _font(12)
    for tick in np.linspace(0.0, max_depth, 6):
        x = bar_left + (bar_right - bar_left - 1) * tick / max_depth
        draw.line([(x, bar_top + 10), (x, bar_top + 14)], fill="black")
        draw.text((x, bar_top + 15), f"{tick:g}", fill="black", font=font, anchor="mt")
    draw.text((bar_right + 8, bar_top + 8), "m z-depth", fill="black", font=font, anchor="lm")
    draw.rectangle([width - 62, bar_top, width - 52, bar_top + 10], fill="black")
    draw.text((width - 48, bar_top + 5), "no hit", fill="black", font=font, anchor="lm")
    return canvas


def instance_color(instance_id: int) -> tuple[int, int, int]:
    """A categorical colour per instance id: hues spread by the golden ratio, bright and saturated."""
    hue = (instance_id * 0.618033988749895) % 1.0
    saturation = 0.55 + 0.35 * ((instance_id * 7) % 3) / 2
    r, g, b = colorsys.hsv_to_rgb(hue, saturation, 0.95)
    return round(r * 255), round(g * 255), round(b * 255)


def semantic_image(frame: Frame, class_names: Sequence[str], categories: dict[int, str]) -> Image.Image:
    """Instances in palette colours with category labels; terrain in dark greys; black = no hit."""
    height, width = frame.semantic.shape
    rgb = np.zeros((height, width, 3), dtype=np.uint8)
    for index, name in enumerate(class_names):
        rgb[frame.terrain == index] = TERRAIN_GREYS.get(name, OTHER_TERRAIN_GREY)
    ids, counts = np.unique(frame.semantic[frame.semantic > 0], return_counts=True)
    for instance_id in ids:
        rgb[frame.semantic == instance_id] = instance_color(int(instance_id))
    canvas = Image.new("RGB", (width, height + STRIP), "white")
    canvas.paste(Image.fromarray(rgb), (0, 0))
    draw = ImageDraw.Draw(canvas)
    font = _font(13)
    rows, cols = np.indices(frame.semantic.shape)
    for instance_id, count in zip(ids, counts, strict=True):
        if count < MIN_LABEL_PIXELS:
            continue
        mask = frame.semantic == instance_id
        label = categories.get(int(instance_id), str(instance_id)).replace("_", " ")
        xy = (float(np.median(cols[mask])), float(np.median(rows[mask])))
        draw.text(xy, label, fill="white", font=font, anchor="mm", stroke_width=2, stroke_fill="black")
    font = _font(12)
    x, y = 8, height + STRIP // 2
    draw.text((x, y), f"{len(ids)} object instances; terrain:", fill="black", font=font, anchor="lm")
    x += round(draw.textlength(f"{len(ids)} object instances; terrain:", font=font)) + 8
    present = [n for i, n in enumerate(class_names) if (frame.terrain == i).any()]
    for name, grey in [(n, TERRAIN_GREYS.get(n, OTHER_TERRAIN_GREY)) for n in present] + [("no hit", 0)]:
        draw.rectangle([x, y - 6, x + 12, y + 6], fill=(grey, grey, grey), outline="black")
        draw.text((x + 16, y), name, fill="black", font=font, anchor="lm")
        x += 16 + round(draw.textlength(name, font=font)) + 12
    return canvas


def rgb_image(frame: Frame, caption: str) -> Image.Image:
    """The colour image with a caption strip."""
    height, width = frame.depth.shape
    canvas = Image.new("RGB", (width, height + STRIP), "white")
    canvas.paste(Image.fromarray(frame.rgb), (0, 0))
    ImageDraw.Draw(canvas).text((8, height + STRIP // 2), caption, fill="black", font=_font(12), anchor="lm")
    return canvas


def panel(images: Sequence[Image.Image], titles: Sequence[str], *, scale: float = 2 / 3) -> Image.Image:
    """Images side by side under titles, scaled by `scale`."""
    width = sum(im.width for im in images)
    height = max(im.height for im in images)
    canvas = Image.new("RGB", (width, height + TITLE), "white")
    draw = ImageDraw.Draw(canvas)
    x = 0
    for image, title in zip(images, titles, strict=True):
        canvas.paste(image, (x, TITLE))
        draw.text((x + image.width // 2, TITLE // 2), title, fill="black", font=_font(17), anchor="mm")
        x += image.width
    size = (round(canvas.width * scale), round(canvas.height * scale))
    return canvas.resize(size, Image.Resampling.LANCZOS)


def render_viewpoint(viewpoint: Viewpoint, out_dir: Path) -> list[Path]:
    """Render one viewpoint and write its four PNGs; returns their paths."""
    scene_dir = TARGETS / viewpoint.scene_id / "scene"
    scene = read_scene(scene_dir)
    eye, target = viewpoint.place(scene.annotations)
    pathfinder = load_scene_navmesh(scene_dir)
    snapped = pathfinder.snap_point(eye)
    if np.isfinite(snapped).all():  # stand where the robot can stand
        eye = snapped + np.array([0.0, 0.0, CAMERA_HEIGHT])
        target = np.array([target[0], target[1], eye[2]])
    renderer = SceneRenderer(scene, look=load_scene_look(scene, scene_dir))  # the scene's built look
    frame = renderer.render(look_at(eye, target))
    hit = frame.depth[frame.depth > 0]
    max_depth = _nice_ceiling(float(np.percentile(hit, 98))) if hit.size else 10.0
    categories = {o.annotation.id: o.annotation.category for o in scene.objects}
    caption = f"{viewpoint.key}: camera at ({eye[0]:.1f}, {eye[1]:.1f}) m, {CAMERA_HEIGHT} m above the floor"
    images = {
        "rgb": rgb_image(frame, caption),
        "depth": depth_image(frame.depth, max_depth),
        "semantic": semantic_image(frame, renderer.class_names, categories),
    }
    target_dir = out_dir / viewpoint.key
    target_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, image in images.items():
        paths.append(target_dir / f"{name}.png")
        image.save(paths[-1], optimize=True)
    combined = panel(list(images.values()), ["RGB", "depth", "instance ids"])
    paths.append(target_dir / "panel.png")
    combined.save(paths[-1], optimize=True)
    return paths


def main(argv: Sequence[str] | None = None) -> int:
    """Render every viewpoint (or those named by ``--only``)."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "img" / "frames")
    parser.add_argument("--only", nargs="*", help="viewpoint keys, e.g. office-s1_corridor")
    args = parser.parse_args(argv)
    selected = [v for v in VIEWPOINTS if not args.only or v.key in args.only]
    if not selected:
        parser.error(f"no viewpoint matches; choose from {', '.join(v.key for v in VIEWPOINTS)}")
    try:
        for viewpoint in selected:
            for path in render_viewpoint(viewpoint, args.out):
                shown = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
                print(f"{shown}: {path.stat().st_size // 1024} kB")
    except NavverseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
