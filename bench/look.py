"""Look benchmark: the lit robot camera against today's flat one, and how much of each view shows a material.

1. Speed, on a populated 1 km² city (``aguascalientes``: its parked cars, street objects and groups;
   ``--city``) built with its look under ``data/built/targets/<id>/``: 50 seeded camera poses (random
   navigable points of its navmesh, 0.6 m up, random horizontal directions, as ``bench/render.py``
   draws them), 640 x 480, 90 degrees horizontal field of view, RGB + depth + instance ids + terrain
   classes per frame. Ours: ``SceneRenderer`` with the scene's built look (sun, shadow rays, sky,
   materials, exposure); the peer, in the same run on the same poses: the same renderer's flat frame
   (``Shading``: one colour per face under fixed lights, fog and outlines: the camera before looks
   existed). The two alternate pose by pose, ``--repeats`` rounds; printed: frames/s, the median
   wall time and the process CPU time per frame (all threads), and the ratio lit / flat of the
   medians (target: at least 20 frames/s lit, a ratio of at most 1.6). A lit frame without shadows
   is timed beside them, for information.
2. Materials, on ``--frames`` seeded views per scene type: the city (street views), a built indoor
   scene (``--indoor``, default ``office-s1``) and, when given, an indoor-to-outdoor one
   (``--i2o``): ``SceneRenderer.materials`` tells what each pixel shows; a hit pixel is textured when
   it shows a procedural material (or what is painted on it: windows, doors, markings) or an image
   texture (storefront signs), flat when its face shows only its own colour. Printed per scene: the
   textured share of all hit pixels, and its mean and minimum over views (target: at least 95 %).
3. The primary ray cast alone, on the city's poses: the camera's packet caster
   (:class:`~navverse.sim.raycast.TriangleCaster`, Embree, eight rays per traversal) against Open3D's
   ``RaycastingScene.cast_rays`` (Embree, one ray per traversal; the camera's caster before it) on the
   same rays and threads; printed: the median milliseconds of each, their ratio and the share of rays
   that hit the same face.
4. ``--figure PATH``: a picture of the first views of each scene, flat beside lit.

Run ``python bench/look.py``. Timings are measurements, never assertions; the printed load average
shows whether other work shared the machine.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import open3d as o3d
from PIL import Image
from render import CAMERA_HEIGHT, camera_poses, flat_shading, scene_dir
from rich.console import Console
from rich.table import Table

from navverse.errors import NavverseError
from navverse.look.files import find_look, load_scene_look
from navverse.scene.directory import read_scene
from navverse.sim.camera import CameraIntrinsics
from navverse.sim.raycast import TriangleCaster
from navverse.sim.render import FLAT_COLOR, NOTHING_HIT, SceneRenderer

FPS_TARGET = 20.0
RATIO_TARGET = 1.6
TEXTURED_TARGET = 0.95
FIGURE_VIEWS = 3  # views per scene in --figure


def _cpu_seconds() -> float:
    """CPU time of this process so far, all threads."""
    times = os.times()
    return times.user + times.system


def renderers(path: Path, intrinsics: CameraIntrinsics) -> dict[str, SceneRenderer]:
    """The flat, lit and lit-without-shadows renderers of a built scene (its built look)."""
    scene = read_scene(path)
    if find_look(path) is None:
        print(
            f"scene {scene.scene_id!r} has no built look (no look/ beside {path}); build it with\n"
            f"    .venv/bin/navverse build {scene.scene_id}",
            file=sys.stderr,
        )
        raise SystemExit(1)
    look = load_scene_look(scene, path)
    unshadowed = look.with_settings(look.settings.model_copy(update={"shadows": False}))
    return {
        "flat": SceneRenderer(scene, intrinsics=intrinsics, shading=flat_shading(scene)),
        "lit": SceneRenderer(scene, intrinsics=intrinsics, look=look),
        "lit, no shadows": SceneRenderer(scene, intrinsics=intrinsics, look=unshadowed),
    }


def bench_speed(scene_id: str, args: argparse.Namespace, console: Console) -> dict[str, Any]:
    """Time the flat and lit frames of one scene, alternating pose by pose."""
    path = scene_dir(scene_id)
    poses = camera_poses(path, args.frames, args.seed)
    intrinsics = CameraIntrinsics.from_hfov(args.width, args.height, args.hfov)
    cameras = renderers(path, intrinsics)
    for renderer in cameras.values():
        renderer.render(poses[0])  # warm-up (compiled loops, caches)
    times: dict[str, list[float]] = {name: [] for name in cameras}
    cpu = dict.fromkeys(cameras, 0.0)
    for _ in range(args.repeats):
        for pose in poses:
            for name, renderer in cameras.items():
                c0, t0 = _cpu_seconds(), time.perf_counter()
                renderer.render(pose)
                times[name].append(time.perf_counter() - t0)
                cpu[name] += _cpu_seconds() - c0
    result = {
        name: {
            "fps": len(values) / sum(values),
            "median_ms": 1000.0 * float(np.median(values)),
            "cpu_ms": 1000.0 * cpu[name] / len(values),
        }
        for name, values in times.items()
    }
    result["ratio"] = result["lit"]["median_ms"] / result["flat"]["median_ms"]
    console.print(
        f"[bold]{scene_id}[/bold]: {len(poses)} poses x {args.repeats} rounds, lit / flat "
        f"{result['ratio']:.2f} (target <= {RATIO_TARGET}), lit {result['lit']['fps']:.1f} frames/s "
        f"(target >= {FPS_TARGET:.0f})",
        highlight=False,
    )
    return result


def bench_cast(scene_id: str, args: argparse.Namespace, console: Console) -> dict[str, Any]:
    """Time the primary ray cast of the city's poses: packets (ours) against Open3D's per-ray cast."""
    path = scene_dir(scene_id)
    poses = camera_poses(path, args.frames, args.seed)
    intrinsics = CameraIntrinsics.from_hfov(args.width, args.height, args.hfov)
    mesh = read_scene(path).world_mesh(include_objects=True).mesh
    lo, hi = mesh.bounds()
    origin = np.round(0.5 * (lo + hi), 3)
    vertices = (mesh.vertices - origin).astype(np.float32)
    ours = TriangleCaster(vertices, mesh.faces)
    peer = o3d.t.geometry.RaycastingScene()
    peer.add_triangles(o3d.core.Tensor(vertices), o3d.core.Tensor(mesh.faces.astype(np.uint32)))
    directions = intrinsics.ray_directions().astype(np.float64)
    times: dict[str, list[float]] = {"packets": [], "open3d": []}
    same = total = 0
    for _ in range(args.repeats):
        for pose in poses:
            world = directions @ pose[:3, :3].T
            rays = np.concatenate([np.broadcast_to(pose[:3, 3] - origin, world.shape), world], axis=-1)
            rays = np.ascontiguousarray(rays, dtype=np.float32)
            t0 = time.perf_counter()
            face = ours.cast(rays).face
            t1 = time.perf_counter()
            theirs = peer.cast_rays(o3d.core.Tensor.from_numpy(rays))["primitive_ids"].numpy()
            t2 = time.perf_counter()
            times["packets"].append(t1 - t0)
            times["open3d"].append(t2 - t1)
            same += int((face == theirs).sum())
            total += face.size
    result = {name: 1000.0 * float(np.median(values)) for name, values in times.items()}
    result["ratio"] = result["open3d"] / result["packets"]
    result["same_face"] = same / max(total, 1)
    console.print(
        f"[bold]{scene_id}[/bold] primary cast: packets {result['packets']:.1f} ms, Open3D "
        f"{result['open3d']:.1f} ms per frame (median): {result['ratio']:.2f}x; "
        f"{100 * result['same_face']:.4f} % of rays hit the same face",
        highlight=False,
    )
    return result


def bench_materials(scene_id: str, args: argparse.Namespace, console: Console) -> dict[str, Any]:
    """The share of hit pixels that show a material, over seeded views of one scene."""
    path = scene_dir(scene_id)
    poses = camera_poses(path, args.frames, args.seed + 1)
    intrinsics = CameraIntrinsics.from_hfov(args.width, args.height, args.hfov)
    renderer = renderers(path, intrinsics)["lit"]
    shares, hit_total, textured_total = [], 0, 0
    for pose in poses:
        materials = renderer.materials(pose)
        hits = int((materials != NOTHING_HIT).sum())
        textured = hits - int((materials == FLAT_COLOR).sum())
        hit_total += hits
        textured_total += textured
        if hits:
            shares.append(textured / hits)
    scene_type = read_scene(path).annotations.scene_type
    result = {
        "scene_type": scene_type,
        "views": len(poses),
        "textured_share": textured_total / max(hit_total, 1),
        "mean_view_share": float(np.mean(shares)) if shares else 0.0,
        "min_view_share": float(np.min(shares)) if shares else 0.0,
    }
    console.print(
        f"[bold]{scene_id}[/bold] ({scene_type}): {100 * result['textured_share']:.2f} % of hit pixels "
        f"textured over {len(poses)} views",
        highlight=False,
    )
    return result


def speed_table(results: dict[str, dict[str, Any]]) -> Table:
    """Frames/s, median and CPU per frame of each camera, with the lit / flat ratio."""
    table = Table(title="lit against flat frames (640 x 480 RGB + depth + ids + classes)")
    for column in ("scene", "camera", "frames/s", "median ms", "CPU ms", "/ flat (median)"):
        table.add_column(column, justify="left" if column in ("scene", "camera") else "right")
    for scene_id, result in results.items():
        for name in ("flat", "lit", "lit, no shadows"):
            row = result[name]
            ratio = row["median_ms"] / result["flat"]["median_ms"]
            table.add_row(
                scene_id, name, f"{row['fps']:.1f}", f"{row['median_ms']:.1f}", f"{row['cpu_ms']:.1f}",
                f"{ratio:.2f}",
            )  # fmt: skip
    return table


def materials_table(results: dict[str, dict[str, Any]]) -> Table:
    """The textured share of each scene's views."""
    table = Table(title=f"pixels showing a material (target >= {100 * TEXTURED_TARGET:.0f} %)")
    for column in ("scene", "type", "views", "textured, all hits", "mean per view", "min per view"):
        table.add_column(column, justify="left" if column in ("scene", "type") else "right")
    for scene_id, r in results.items():
        table.add_row(
            scene_id, r["scene_type"], str(r["views"]), f"{100 * r['textured_share']:.2f} %",
            f"{100 * r['mean_view_share']:.2f} %", f"{100 * r['min_view_share']:.2f} %",
        )  # fmt: skip
    return table


def write_figure(scene_ids: Sequence[str], args: argparse.Namespace, target: Path) -> None:
    """A picture of the first views of each scene: flat on the left, lit on the right."""
    intrinsics = CameraIntrinsics.from_hfov(args.width // 2, args.height // 2, args.hfov)
    rows = []
    for scene_id in scene_ids:
        path = scene_dir(scene_id)
        cameras = renderers(path, intrinsics)
        for pose in camera_poses(path, FIGURE_VIEWS, args.seed + 1):
            rows.append(np.hstack([cameras["flat"].render(pose).rgb, cameras["lit"].render(pose).rgb]))
    target.parent.mkdir(parents=True, exist_ok=True)
    partial = target.with_name(target.name + ".partial")
    Image.fromarray(np.vstack(rows)).save(partial, format="PNG")
    os.replace(partial, target)


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    """Command-line flags."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--city", default="aguascalientes", help="built populated city (default aguascalientes)"
    )
    parser.add_argument("--indoor", default="office-s1", help="built indoor scene (default office-s1)")
    parser.add_argument("--i2o", help="a built indoor-to-outdoor scene, for its materials")
    parser.add_argument("--frames", type=int, default=50, help="camera poses per scene (default 50)")
    parser.add_argument("--repeats", type=int, default=2, help="timed rounds over the poses (default 2)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the camera poses")
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--hfov", type=float, default=90.0, help="horizontal field of view, degrees")
    parser.add_argument("--figure", type=Path, help="write flat / lit views of each scene to this PNG")
    parser.add_argument("--json", type=Path, help="also write the results to this file")
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark; returns the exit code."""
    args = parse_args(argv)
    console = Console(width=None if sys.stdout.isatty() else 150)
    console.print(
        f"look benchmark: {os.cpu_count()} CPUs, {platform.python_implementation()} "
        f"{platform.python_version()}, {args.frames} poses per scene at {CAMERA_HEIGHT} m, seed {args.seed}; "
        f"load average {os.getloadavg()[0]:.2f}",
        highlight=False,
    )
    material_scenes = [s for s in (args.city, args.indoor, args.i2o) if s]
    for scene_id in material_scenes:  # fail before any timing if a scene is missing
        scene_dir(scene_id)
    try:
        speed = {args.city: bench_speed(args.city, args, console)}
        cast = {args.city: bench_cast(args.city, args, console)}
        materials = {s: bench_materials(s, args, console) for s in material_scenes}
        if args.figure is not None:
            write_figure(material_scenes, args, args.figure)
            console.print(f"wrote {args.figure}", highlight=False)
    except NavverseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    console.print(speed_table(speed))
    console.print(
        "flat: the camera before looks (one colour per face, fixed lights, fog, outlines); lit: the "
        "scene's built look (sun, shadow rays, sky, materials, exposure). CPU ms: process CPU time per "
        "frame, all threads.",
        highlight=False,
    )
    console.print(materials_table(materials))
    console.print(f"load average {os.getloadavg()[0]:.2f}", highlight=False)
    if args.json is not None:
        report = {
            "benchmark": "look",
            "args": {k: str(v) for k, v in vars(args).items()},
            "speed": speed,
            "primary_cast": cast,
            "materials": materials,
        }
        args.json.write_text(json.dumps(report, indent=1))
        console.print(f"wrote {args.json}", highlight=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
