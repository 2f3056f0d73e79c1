"""Camera benchmark: ``navverse.sim.render.SceneRenderer`` against PyBullet's TinyRenderer.

For an indoor scene (``office-s1``), an outdoor one (``curb-street``) and a populated 1 km² city
(``aguascalientes``: its street objects, parked cars and groups; ``--city``), all already built under
``data/built/targets/<id>/scene/``:

1. Draw camera poses: random navigable points of the scene's navmesh, the camera 0.6 m above them,
   looking in a random horizontal direction (seeded).
2. Ours: one ``SceneRenderer`` (Open3D/Embree ray casting, all cores) making flat images (``Shading``;
   ``bench/look.py`` times the lit ones), RGB + depth + instance ids (+ terrain classes) at
   640 x 480, 90 degrees horizontal field of view; frames/s over all poses.
3. Peer, in the same run, on the same triangles and poses: PyBullet's ``getCameraImage`` with
   ``ER_TINY_RENDERER`` in a ``DIRECT`` client (one thread), which also returns RGB, depth and a
   segmentation mask. Every terrain surface is one body and every object one body, with one visual
   mesh per face colour, coloured like ours. Its projection comes from the same vertical field of
   view, aspect, near and far; its view matrix from the same pose.
4. Agreement: the peer's depth buffer is linearised to z-depth and compared with ours over the pixels
   both hit (mean absolute difference), with the fractions of pixels where both agree on hit/miss and
   on the instance id. TinyRenderer samples pixel corners (its rays pass through ``(col, row + 1)``
   in our image coordinates), ours pixel centres; a second, untimed render of ours with the principal
   point shifted by that half pixel shows how closely the two cameras agree once that is removed.
5. Textures: on the city, every terrain surface gets a texture made here (one seeded 256 x 256 image
   per terrain class, mapped along each face's dominant axis, repeating every 2.5 m), and a handful of
   poses are rendered with and without them, alternately; the printed ratio of median frame times is
   the cost of texture sampling (target <= 1.30).

Run ``python bench/render.py`` (what ``make bench`` does). Timings are measurements, never
assertions; the printed load average shows whether other work shared the machine.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import re
import resource
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.table import Table

from navverse.errors import NavverseError
from navverse.nav.scene_navmesh import load_scene_navmesh
from navverse.scene.colors import default_color
from navverse.scene.directory import read_scene
from navverse.scene.geometry import MeshData, Scene, Surface, Texture
from navverse.scene_types import scene_profile
from navverse.sim.bullet import pybullet as pb
from navverse.sim.camera import CameraIntrinsics, look_at
from navverse.sim.render import Frame, SceneRenderer, Shading

ROOT = Path(__file__).resolve().parent.parent
TARGETS = ROOT / "data" / "built" / "targets"
CAMERA_HEIGHT = 0.6
NEAR, FAR = 0.1, 100.0
TEXTURE_TILE_M = 2.5  # world size of one repeat of a bench texture
TEXTURE_PIXELS = 256


@dataclass(frozen=True)
class PeerFrame:
    """What TinyRenderer returns, decoded: z-depth (0 where nothing was hit) and instance ids."""

    depth: np.ndarray
    semantic: np.ndarray


# ---------------------------------------------------------------------- inputs


def scene_dir(scene_id: str) -> Path:
    """The built scene directory of `scene_id`; exits with a build hint if it is missing."""
    path = TARGETS / scene_id / "scene"
    if not (path / "scene.json").is_file() or not (path / "navmesh.bin").is_file():
        recipe = re.sub(r"-s\d+$", "", scene_id)
        print(
            f"scene {scene_id!r} is not built ({path} is missing or has no navmesh); build it with\n"
            f"    cd {ROOT} && .venv/bin/navverse build {recipe}\n"
            "or pass another built scene with --indoor / --outdoor",
            file=sys.stderr,
        )
        raise SystemExit(1)
    return path


def camera_poses(path: Path, count: int, seed: int) -> list[np.ndarray]:
    """`count` camera poses at random navigable points, 0.6 m up, looking in random horizontal directions."""
    pathfinder = load_scene_navmesh(path)
    rng = np.random.default_rng(seed)
    poses = []
    while len(poses) < count:
        point = pathfinder.get_random_navigable_point(rng)
        if not np.isfinite(point).all():
            raise NavverseError(f"the navmesh of {path} is empty: no navigable point to place a camera")
        yaw = rng.uniform(0.0, 2.0 * math.pi)
        eye = point + np.array([0.0, 0.0, CAMERA_HEIGHT])
        poses.append(look_at(eye, eye + np.array([math.cos(yaw), math.sin(yaw), 0.0])))
    return poses


def flat_shading(scene: Scene) -> Shading:
    """The flat images the camera made before looks existed (the sky on in outdoor and i2o scenes)."""
    return Shading(sky=scene_profile(scene.annotations.scene_type).sky)


# ---------------------------------------------------------------------- the peer


def _flat_mesh(mesh: MeshData) -> tuple[list[list[float]], list[int], list[list[float]]]:
    """Unshared vertices, indices and per-vertex face normals (flat shading in TinyRenderer)."""
    tri = mesh.vertices[mesh.faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.divide(normals, length, out=np.zeros_like(normals), where=length > 0)
    vertices = tri.reshape(-1, 3)
    return vertices.tolist(), list(range(len(vertices))), np.repeat(normals, 3, axis=0).tolist()


def _visual(client: int, mesh: MeshData, color: np.ndarray) -> int:
    vertices, indices, normals = _flat_mesh(mesh)
    rgba = [*(np.asarray(color, dtype=float) / 255.0).tolist(), 1.0]
    return pb.createVisualShape(
        pb.GEOM_MESH,
        vertices=vertices,
        indices=indices,
        normals=normals,
        rgbaColor=rgba,
        physicsClientId=client,
    )


def _body(client: int, shapes: list[int]) -> int:
    """A static body whose base shows the first visual shape and fixed links the others."""
    links = len(shapes) - 1
    return pb.createMultiBody(
        baseMass=0.0, baseVisualShapeIndex=shapes[0], linkMasses=[0.0] * links,
        linkCollisionShapeIndices=[-1] * links, linkVisualShapeIndices=shapes[1:],
        linkPositions=[[0.0, 0.0, 0.0]] * links, linkOrientations=[[0.0, 0.0, 0.0, 1.0]] * links,
        linkInertialFramePositions=[[0.0, 0.0, 0.0]] * links,
        linkInertialFrameOrientations=[[0.0, 0.0, 0.0, 1.0]] * links, linkParentIndices=[0] * links,
        linkJointTypes=[pb.JOINT_FIXED] * links, linkJointAxis=[[0.0, 0.0, 1.0]] * links,
        physicsClientId=client,
    )  # fmt: skip


def _split(mesh: MeshData, colors: np.ndarray) -> list[tuple[MeshData, np.ndarray]]:
    """The mesh's faces grouped by colour."""
    unique, inverse = np.unique(colors, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    return [(MeshData(mesh.vertices, mesh.faces[inverse == k]), unique[k]) for k in range(len(unique))]


class TinyRendererPeer:
    """The scene's triangles in a PyBullet ``DIRECT`` client, rendered with ``ER_TINY_RENDERER``."""

    def __init__(self, scene: Scene, intrinsics: CameraIntrinsics, *, terrain_lighten: float) -> None:
        self.client = pb.connect(pb.DIRECT)
        self.intrinsics = intrinsics
        self.instance_of_body: dict[int, int] = {}
        classes = scene.annotations.terrain_classes
        for surface in scene.surfaces:
            color = np.asarray(classes[surface.terrain_class].color, dtype=float)
            luma = float(color @ (0.2126, 0.7152, 0.0722)) / 255.0
            color += (255.0 - color) * terrain_lighten * (1.0 - luma)  # as SceneRenderer does
            body = _body(self.client, [_visual(self.client, surface.mesh, color)])
            self.instance_of_body[body] = 0
        for obj in scene.objects:
            mesh = obj.world_mesh()
            colors = mesh.face_colors
            if colors is None:
                colors = np.tile(
                    np.array([default_color(obj.annotation.category)], np.uint8), (mesh.num_faces, 1)
                )
            shapes = [_visual(self.client, part, color) for part, color in _split(mesh, colors)]
            self.instance_of_body[_body(self.client, shapes)] = obj.annotation.id
        k = intrinsics
        self.projection = pb.computeProjectionMatrixFOV(k.vfov_deg, k.width / k.height, NEAR, FAR)
        lookup = np.zeros(max(self.instance_of_body) + 2, dtype=np.int32)
        for body, instance in self.instance_of_body.items():
            lookup[body] = instance
        self._lookup = lookup

    def render(self, camera_to_world: np.ndarray) -> tuple[Any, ...]:
        """One ``getCameraImage`` call (what is timed); returns PyBullet's raw result."""
        # OpenGL's camera frame is the optical frame turned half a turn about x (y up, looking along -z).
        gl_to_world = camera_to_world @ np.diag([1.0, -1.0, -1.0, 1.0])
        view = np.linalg.inv(gl_to_world).T.reshape(-1).tolist()  # column-major
        k = self.intrinsics
        return pb.getCameraImage(
            k.width,
            k.height,
            view,
            self.projection,
            renderer=pb.ER_TINY_RENDERER,
            physicsClientId=self.client,
        )

    def decode(self, raw: tuple[Any, ...]) -> PeerFrame:
        """Linearise the depth buffer to z-depth and map segmentation bodies to instance ids."""
        width, height, _, depth_buffer, segmentation = raw
        seg = np.reshape(np.asarray(segmentation, dtype=np.int64), (height, width))
        hit = seg >= 0  # TinyRenderer leaves no reliable depth where nothing was drawn; the mask is -1
        buffer = np.reshape(np.asarray(depth_buffer, dtype=np.float64), (height, width))
        depth = np.where(hit, FAR * NEAR / (FAR - (FAR - NEAR) * buffer), 0.0)
        body = np.where(hit, seg & ((1 << 24) - 1), len(self._lookup) - 1)
        return PeerFrame(depth=depth, semantic=self._lookup[body])

    def close(self) -> None:
        """Disconnect the client."""
        pb.disconnect(physicsClientId=self.client)


# ---------------------------------------------------------------------- measuring


def _cpu_seconds() -> float:
    """User plus system CPU time of this process, all threads (s)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _agreement(ours: Sequence[Frame], peer: Sequence[PeerFrame]) -> dict[str, float]:
    diffs, hit_agree, sem_agree, both_total = [], 0, 0, 0
    for a, b in zip(ours, peer, strict=True):
        both = (a.depth > 0) & (b.depth > 0)
        diffs.append(np.abs(a.depth[both] - b.depth[both]))
        hit_agree += int(((a.depth > 0) == (b.depth > 0)).sum())
        sem_agree += int((a.semantic == b.semantic).sum())
        both_total += a.depth.size
    diff = np.concatenate(diffs)
    return {
        "depth_mad_m": float(diff.mean()) if diff.size else math.nan,
        "depth_median_m": float(np.median(diff)) if diff.size else math.nan,
        "hit_agree": hit_agree / both_total,
        "semantic_agree": sem_agree / both_total,
    }


def bench_scene(scene_id: str, args: argparse.Namespace, console: Console) -> dict[str, Any]:
    """Time both renderers on one scene and compare their images."""
    path = scene_dir(scene_id)
    scene = read_scene(path)
    poses = camera_poses(path, args.frames, args.seed)
    intrinsics = CameraIntrinsics.from_hfov(args.width, args.height, args.hfov)
    faces = sum(s.mesh.num_faces for s in scene.surfaces) + sum(o.mesh.num_faces for o in scene.objects)
    console.print(
        f"[bold]{scene_id}[/bold] ({scene.annotations.scene_type}): {faces} triangles, "
        f"{len(scene.objects)} objects, {len(poses)} poses",
        highlight=False,
    )

    started = time.perf_counter()
    renderer = SceneRenderer(
        scene, intrinsics=intrinsics, depth_range=(NEAR, FAR), shading=flat_shading(scene)
    )
    ours_setup = time.perf_counter() - started
    renderer.render(poses[0])  # warm-up
    ours_times, ours_frames = [], []
    cpu0 = _cpu_seconds()
    for pose in poses:
        t0 = time.perf_counter()
        frame = renderer.render(pose)
        ours_times.append(time.perf_counter() - t0)
        ours_frames.append(frame)
    ours_cpu = _cpu_seconds() - cpu0

    started = time.perf_counter()
    peer = TinyRendererPeer(scene, intrinsics, terrain_lighten=Shading().terrain_lighten)
    peer_setup = time.perf_counter() - started
    try:
        peer.render(poses[0])  # warm-up
        peer_times, raws = [], []
        cpu0 = _cpu_seconds()
        for pose in poses:
            t0 = time.perf_counter()
            raws.append(peer.render(pose))
            peer_times.append(time.perf_counter() - t0)
        peer_cpu = _cpu_seconds() - cpu0
        peer_frames = [peer.decode(raw) for raw in raws]
    finally:
        peer.close()

    # Untimed: ours through TinyRenderer's sampling points (pixel corners, see the module docstring).
    shifted = replace(intrinsics, cx=intrinsics.cx + 0.5, cy=intrinsics.cy - 0.5)
    aligned = SceneRenderer(
        scene, intrinsics=shifted, depth_range=(NEAR, FAR), shading=flat_shading(scene)
    ).render_batch(poses)
    return {
        "scene_type": scene.annotations.scene_type,
        "triangles": faces,
        "frames": len(poses),
        "ours_setup_s": ours_setup,
        "peer_setup_s": peer_setup,
        "ours_fps": len(poses) / sum(ours_times),
        "peer_fps": len(poses) / sum(peer_times),
        "ours_median_ms": 1000 * float(np.median(ours_times)),
        "peer_median_ms": 1000 * float(np.median(peer_times)),
        "ours_cpu_ms": 1000 * ours_cpu / len(poses),
        "peer_cpu_ms": 1000 * peer_cpu / len(poses),
        "same_camera": _agreement(ours_frames, peer_frames),
        "aligned_sampling": _agreement(aligned, peer_frames),
    }


# ---------------------------------------------------------------------- textures


def bench_texture(name: str, rng: np.random.Generator) -> Texture:
    """A noisy brick-like pattern of random hue: rows of offset bricks with darker mortar."""
    rows, cols = np.mgrid[0:TEXTURE_PIXELS, 0:TEXTURE_PIXELS]
    brick_h, brick_w = TEXTURE_PIXELS // 8, TEXTURE_PIXELS // 4
    shifted = cols + (rows // brick_h % 2) * (brick_w // 2)
    mortar = (rows % brick_h < 3) | (shifted % brick_w < 3)
    base = rng.uniform(60.0, 220.0, size=3)
    image = base + rng.normal(0.0, 14.0, size=(TEXTURE_PIXELS, TEXTURE_PIXELS, 1))
    image[mortar] *= 0.55
    return Texture(name, np.clip(image, 0, 255).astype(np.uint8))


def planar_uvs(mesh: MeshData) -> np.ndarray:
    """(M, 3, 2) UVs of each face's corners: world coordinates along the two axes other than the face
    normal's dominant one, per `TEXTURE_TILE_M`."""
    corners = mesh.vertices[mesh.faces]  # (M, 3, 3)
    normal = np.abs(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]))
    dominant = normal.argmax(axis=1)
    axes = np.array([[1, 2], [0, 2], [0, 1]])[dominant]  # (M, 2): facades get (horizontal, z)
    uvs = np.take_along_axis(corners, np.broadcast_to(axes[:, None, :], (len(axes), 3, 2)), axis=2)
    return (uvs / TEXTURE_TILE_M).astype(np.float32)


def textured_scene(scene: Scene, seed: int) -> Scene:
    """The scene with a texture on every terrain surface (one per terrain class)."""
    rng = np.random.default_rng(seed)
    textures = {name: bench_texture(name, rng) for name in scene.annotations.terrain_classes}
    surfaces = []
    for surface in scene.surfaces:
        mesh = surface.mesh
        textured = MeshData(
            mesh.vertices, mesh.faces, mesh.face_colors, planar_uvs(mesh),
            np.zeros(mesh.num_faces, np.int16), (textures[surface.terrain_class],),
        )  # fmt: skip
        surfaces.append(Surface(surface.name, surface.terrain_class, textured))
    return replace(scene, surfaces=tuple(surfaces))


def bench_textured(scene_id: str, args: argparse.Namespace, console: Console) -> dict[str, Any]:
    """Frame times of the scene with textured terrain against the same views untextured."""
    path = scene_dir(scene_id)
    scene = read_scene(path)
    poses = camera_poses(path, args.texture_frames, args.seed)
    intrinsics = CameraIntrinsics.from_hfov(args.width, args.height, args.hfov)
    shading = flat_shading(scene)
    plain = SceneRenderer(scene, intrinsics=intrinsics, depth_range=(NEAR, FAR), shading=shading)
    textured = SceneRenderer(
        textured_scene(scene, args.seed), intrinsics=intrinsics, depth_range=(NEAR, FAR), shading=shading
    )
    times: dict[str, list[float]] = {"plain": [], "textured": []}
    share = []
    for pose in [poses[0], *poses]:  # the first pose warms both up
        for name, renderer in (("plain", plain), ("textured", textured)):  # alternate: same load
            t0 = time.perf_counter()
            frame = renderer.render(pose)
            times[name].append(time.perf_counter() - t0)
        share.append(float((frame.terrain >= 0).mean()))
    plain_ms = 1000 * float(np.median(times["plain"][1:]))
    textured_ms = 1000 * float(np.median(times["textured"][1:]))
    result = {
        "frames": len(poses),
        "textured_pixels": float(np.mean(share[1:])),
        "plain_median_ms": plain_ms,
        "textured_median_ms": textured_ms,
        "ratio": textured_ms / plain_ms,
    }
    console.print(
        f"[bold]{scene_id}[/bold] textured terrain ({result['textured_pixels']:.0%} of pixels textured, "
        f"{len(poses)} poses): {plain_ms:.1f} ms untextured, {textured_ms:.1f} ms textured (median), "
        f"ratio {result['ratio']:.2f} (target <= 1.30)",
        highlight=False,
    )
    return result


def speed_table(results: dict[str, dict[str, Any]], args: argparse.Namespace) -> Table:
    """One row per scene: frames/s, median wall time and CPU time per frame of both, and their ratio."""
    table = Table(title=f"{args.width}x{args.height}, hfov {args.hfov:g} deg: RGB + depth + instance ids")
    for column in (
        "scene", "triangles", "ours fps", "ours ms (median)", "ours CPU ms", "TinyRenderer fps",
        "Tiny ms (median)", "Tiny CPU ms", "fps ratio", "CPU ratio",
    ):  # fmt: skip
        table.add_column(column, justify="right")
    for name, r in results.items():
        table.add_row(
            name, str(r["triangles"]), f"{r['ours_fps']:.1f}", f"{r['ours_median_ms']:.1f}",
            f"{r['ours_cpu_ms']:.1f}", f"{r['peer_fps']:.1f}", f"{r['peer_median_ms']:.1f}",
            f"{r['peer_cpu_ms']:.1f}", f"{r['ours_fps'] / r['peer_fps']:.2f}",
            f"{r['peer_cpu_ms'] / r['ours_cpu_ms']:.2f}",
        )  # fmt: skip
    return table


def agreement_table(results: dict[str, dict[str, Any]]) -> Table:
    """One row per scene: how closely the two renderers' depth and instance images agree."""
    table = Table(title="agreement with TinyRenderer on the same frames")
    for column in (
        "scene", "|Δdepth| mean", "|Δdepth| median", "hit/miss agree", "id agree",
        "aligned |Δdepth| mean", "aligned hit/miss agree", "aligned id agree",
    ):  # fmt: skip
        table.add_column(column, justify="right")
    for name, r in results.items():
        same, aligned = r["same_camera"], r["aligned_sampling"]
        table.add_row(
            name, f"{100 * same['depth_mad_m']:.2f} cm", f"{100 * same['depth_median_m']:.2f} cm",
            f"{100 * same['hit_agree']:.2f}%", f"{100 * same['semantic_agree']:.2f}%",
            f"{1000 * aligned['depth_mad_m']:.3f} mm", f"{100 * aligned['hit_agree']:.2f}%",
            f"{100 * aligned['semantic_agree']:.2f}%",
        )  # fmt: skip
    return table


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    """Command-line flags."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--indoor", default="office-s1", help="built indoor scene id (default office-s1)")
    parser.add_argument(
        "--outdoor", default="curb-street", help="built outdoor scene id (default curb-street)"
    )
    parser.add_argument(
        "--city", default="aguascalientes", help="built, populated city scene id (default aguascalientes)"
    )
    parser.add_argument("--frames", type=int, default=50, help="camera poses per scene (default 50)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the camera poses")
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--hfov", type=float, default=90.0, help="horizontal field of view, degrees")
    parser.add_argument(
        "--texture-frames", type=int, default=8, help="poses of the textured measurement (default 8)"
    )
    parser.add_argument(
        "--textures-only", action="store_true", help="run only the textured measurement (step 5)"
    )
    parser.add_argument("--json", type=Path, help="also write the results to this file")
    args = parser.parse_args(argv)
    if args.frames < 1 or args.texture_frames < 1:
        parser.error("--frames and --texture-frames must be >= 1")
    return args


def main(argv: Sequence[str] | None = None) -> int:
    """Run the benchmark; returns the exit code."""
    args = parse_args(argv)
    console = Console(width=None if sys.stdout.isatty() else 170)
    load_start = os.getloadavg()[0]
    console.print(
        f"render benchmark: {os.cpu_count()} CPUs, {platform.python_implementation()} "
        f"{platform.python_version()}, {args.frames} poses per scene at {CAMERA_HEIGHT} m, seed {args.seed}; "
        f"load average {load_start:.2f}",
        highlight=False,
    )
    scenes = (args.city,) if args.textures_only else (args.indoor, args.outdoor, args.city)
    for scene_id in scenes:  # fail before any timing if a scene is missing
        scene_dir(scene_id)
    results: dict[str, dict[str, Any]] = {}
    try:
        for scene_id in () if args.textures_only else scenes:
            results[scene_id] = bench_scene(scene_id, args, console)
        texture_result = bench_textured(args.city, args, console)
    except NavverseError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    if args.textures_only:
        console.print(f"load average {os.getloadavg()[0]:.2f}", highlight=False)
        return 0
    console.print(speed_table(results, args))
    console.print(
        "ours: Open3D RaycastingScene (Embree) on all cores; TinyRenderer: PyBullet getCameraImage "
        "(ER_TINY_RENDERER, DIRECT client), one thread. CPU ms: process CPU time per frame, all threads. "
        "fps ratio: ours / TinyRenderer; CPU ratio: TinyRenderer CPU / ours.",
        highlight=False,
    )
    console.print(agreement_table(results))
    console.print(
        "|Δdepth|: z-depth difference over the pixels both hit; hit/miss agree: pixels both hit or both "
        "miss; id agree: pixels with the same instance id (0 = terrain or nothing). TinyRenderer samples "
        "pixel corners, ours pixel centres; aligned: ours re-rendered (untimed) through its sampling "
        "points, half a pixel off.",
        highlight=False,
    )
    console.print(f"load average {os.getloadavg()[0]:.2f}", highlight=False)
    if args.json is not None:
        report = {
            "benchmark": "render",
            "args": {k: str(v) for k, v in vars(args).items()},
            "scenes": results,
            "textured": {args.city: texture_result},
        }
        args.json.write_text(json.dumps(report, indent=1))
        console.print(f"wrote {args.json}", highlight=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
