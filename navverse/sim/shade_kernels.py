"""Compiled per-pixel loops of the lit renderer: hit geometry, tile sampling, light, haze, sky, encoding.

Each loop visits every hit (or pixel) once and keeps its intermediate values in registers, where the
same arithmetic in numpy would make a pass over memory per operation. They are numba functions,
compiled on first use and cached beside this module, free of the GIL. The longest take a range
``[start, stop)`` of their hits or pixels, and :func:`split` runs one over contiguous pieces on
threads of a small pool (Python threads, not a numba threading layer: safe beside other threads and
across ``fork``). Every loop writes its elements into arrays its caller allocated, each from its own
inputs only, so results do not depend on how the work was split.
"""

from __future__ import annotations

import math
import os
import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
from numba import njit

__all__ = [
    "add_lamps",
    "add_sun",
    "checker_fill",
    "encode_pixels",
    "even_pixels",
    "gather_hits",
    "lamp_light",
    "lifted_rays",
    "log_average_luma",
    "open_air_light",
    "pixel_rays",
    "shade_hits",
    "sky_pixels",
    "split",
    "tile_albedo",
]

_JIT = {"cache": True, "nogil": True}
_SPLIT_BELOW = 64  # fewer elements (hits, pixels or rows) than this run in one piece
_pool_state: dict[str, Any] = {}
_pool_lock = threading.Lock()


def split(kernel: Callable[..., None], count: int, *args: Any, parts: int) -> None:
    """Run ``kernel(start, stop, *args)`` over ``[0, count)`` in up to `parts` contiguous pieces at once.

    The calling thread runs the first piece; the others go to a pool of threads shared by this
    process's renderers (made again after a ``fork``). `parts` of 0 uses one piece per core.
    """
    if parts <= 0:
        parts = os.cpu_count() or 1
    if parts <= 1 or count < _SPLIT_BELOW:
        kernel(0, count, *args)
        return
    bounds = [count * i // parts for i in range(parts + 1)]
    pool = _pool(parts - 1)
    pending = [pool.submit(kernel, bounds[i], bounds[i + 1], *args) for i in range(1, parts)]
    kernel(0, bounds[1], *args)
    for future in pending:
        future.result()


def _pool(workers: int) -> ThreadPoolExecutor:
    """This process's pool of at least `workers` threads."""
    with _pool_lock:
        pool = _pool_state.get("pool")
        if pool is None or _pool_state["pid"] != os.getpid() or _pool_state["workers"] < workers:
            pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="navverse-shade")
            _pool_state.update(pool=pool, pid=os.getpid(), workers=workers)
        return pool


_LUMA_R, _LUMA_G, _LUMA_B = 0.2126, 0.7152, 0.0722  # Rec. 709 weights


@njit(**_JIT)
def pixel_rays(
    start: int,
    stop: int,
    x: np.ndarray,
    y: np.ndarray,
    rotation: np.ndarray,
    eye: np.ndarray,
    near: float,
    rays: np.ndarray,
) -> None:
    """Rows `start` to `stop` of the rays ``(H, W, 6)`` of a pinhole camera: through pixel
    ``(row, col)`` the direction ``(y[row] R[:, 1] + R[:, 2]) + x[col] R[:, 0]`` (optical z 1), from
    the near plane along it (in float32, in this order of operations)."""
    near32 = np.float32(near)
    for row in range(start, stop):
        for col in range(x.shape[0]):
            for c in range(3):
                per_row = y[row] * rotation[c, 1] + rotation[c, 2]
                per_col = x[col] * rotation[c, 0]
                rays[row, col, 3 + c] = per_row + per_col
                rays[row, col, c] = (eye[c] + near32 * per_row) + near32 * per_col


@njit(**_JIT)
def gather_hits(
    start: int,
    stop: int,
    rays: np.ndarray,
    t_hit: np.ndarray,
    hits: np.ndarray,
    face: np.ndarray,
    face_normals: np.ndarray,
    face_albedo: np.ndarray,
    origin: np.ndarray,
    near: float,
    pixel_angle: float,
    points: np.ndarray,
    world: np.ndarray,
    normals: np.ndarray,
    depth: np.ndarray,
    footprint: np.ndarray,
    hit_face: np.ndarray,
    albedo: np.ndarray,
) -> None:
    """Per hit pixel ``hits[k]``: the hit point (local float32 and world float64), the face normal
    turned towards the camera, the z-depth, the width of the pixel on the surface (`pixel_angle` times
    the depth over the cosine between ray and normal, at most five times the depth's), the face and
    its albedo.

    `rays` is ``(P, 6)`` (origin on the near plane, direction with optical z 1), `t_hit` ``(P,)``,
    `face` ``(P,)``; `face_normals` ``(F + 1, 3)``, `face_albedo` ``(3, F + 1)``; outputs ``(K, 3)``
    (three), ``(K,)`` (three), ``(3, K)``.
    """
    for k in range(start, stop):
        p = hits[k]
        f = face[p]
        t = t_hit[p]
        dx, dy, dz = rays[p, 3], rays[p, 4], rays[p, 5]
        nx, ny, nz = face_normals[f, 0], face_normals[f, 1], face_normals[f, 2]
        along = nx * dx + ny * dy + nz * dz
        if along > 0.0:
            nx, ny, nz = -nx, -ny, -nz
        px = rays[p, 0] + t * dx
        py = rays[p, 1] + t * dy
        pz = rays[p, 2] + t * dz
        points[k, 0], points[k, 1], points[k, 2] = px, py, pz
        world[k, 0] = np.float64(px) + origin[0]
        world[k, 1] = np.float64(py) + origin[1]
        world[k, 2] = np.float64(pz) + origin[2]
        normals[k, 0], normals[k, 1], normals[k, 2] = nx, ny, nz
        depth[k] = t + np.float32(near)
        cosine = abs(along) / math.sqrt(dx * dx + dy * dy + dz * dz)
        footprint[k] = depth[k] * np.float32(pixel_angle) / max(cosine, np.float32(0.2))
        hit_face[k] = f
        for c in range(3):
            albedo[c, k] = face_albedo[c, f]


@njit(**_JIT)
def tile_albedo(
    start: int,
    stop: int,
    pool: np.ndarray,
    offset: np.ndarray,
    width: np.ndarray,
    levels: np.ndarray,
    sizes: np.ndarray,
    texel: np.ndarray,
    tile: np.ndarray,
    u: np.ndarray,
    v: np.ndarray,
    footprint: np.ndarray,
    shift: np.ndarray,
    tint: np.ndarray,
    modulate: np.ndarray,
    to_linear: np.ndarray,
    grain_base: np.ndarray,
    albedo: np.ndarray,
) -> None:
    """Sample the tile of every hit with one (``tile[k] >= 0``) into `albedo` ``(3, K)`` (linear).

    The tiles repeat, mip-mapped, packed in `pool` ``(N, 3)`` (sRGB bytes; each level padded by one
    wrapped row and column; `offset`, `width` ``(T, L)`` per level, sides powers of two): the level
    whose texels are about as wide as the hit's `footprint`, bilinear at ``(u, v)`` meters plus the
    material's `shift` ``(T, 2)``, to linear (`to_linear`, 256 entries) times its `tint` ``(T, 3)``;
    where `modulate` (objects), the hit's own colour times the sample over `grain_base` instead.
    """
    for k in range(start, stop):
        t = tile[k]
        if t < 0:
            continue
        ratio = footprint[k] / texel[t]
        level, limit, top = 0, 2.0, levels[t] - 1
        while ratio >= limit and level < top:  # level = floor(log2(ratio)), within the tile's levels
            level += 1
            limit *= 2.0
        w = width[t, level]
        scale = w / sizes[t]
        x = (u[k] + shift[t, 0]) * scale - 0.5
        y = (v[k] + shift[t, 1]) * scale - 0.5
        col = math.floor(x)
        row = math.floor(y)
        fx = np.float32(x - col)
        fy = np.float32(y - row)
        index = offset[t, level] + (row & (w - 1)) * (w + 1) + (col & (w - 1))  # w is a power of two
        below = index + w + 1
        w00 = (np.float32(1.0) - fx) * (np.float32(1.0) - fy)
        w01 = fx * (np.float32(1.0) - fy)
        w10 = (np.float32(1.0) - fx) * fy
        w11 = fx * fy
        for c in range(3):
            srgb = (
                np.float32(pool[index, c]) * w00
                + np.float32(pool[index + 1, c]) * w01
                + np.float32(pool[below, c]) * w10
                + np.float32(pool[below + 1, c]) * w11
            )
            value = to_linear[min(int(srgb + np.float32(0.5)), 255)] * tint[t, c]
            if modulate[k]:
                albedo[c, k] *= value / grain_base[c]
            else:
                albedo[c, k] = value


@njit(**_JIT)
def open_air_light(
    normals: np.ndarray,
    room: np.ndarray,
    sky_light: np.ndarray,
    ground_light: np.ndarray,
    sun: np.ndarray,
    sun_up: bool,
    light: np.ndarray,
    sun_cosine: np.ndarray,
) -> int:
    """Sky and ground light ``light`` ``(3, K)`` on hits in the open (``room < 0``; 0 indoors), blended by
    the normal's height; `sun_cosine` ``(K,)`` the cosine to the sun where positive in the open, else
    0. Returns the number of hits facing the sun."""
    facing = 0
    for k in range(normals.shape[0]):
        sun_cosine[k] = 0.0
        if room[k] >= 0:
            for c in range(3):
                light[c, k] = 0.0
            continue
        up = np.float32(0.5) + np.float32(0.5) * normals[k, 2]
        for c in range(3):
            light[c, k] = ground_light[c] + up * (sky_light[c] - ground_light[c])
        if sun_up:
            cosine = normals[k, 0] * sun[0] + normals[k, 1] * sun[1] + normals[k, 2] * sun[2]
            if cosine > 0.0:
                sun_cosine[k] = cosine
                facing += 1
    return facing


@njit(**_JIT)
def lifted_rays(
    points: np.ndarray, normals: np.ndarray, depth: np.ndarray, which: np.ndarray, directions: np.ndarray
) -> np.ndarray:
    """Rays ``(M, 6)`` from the hits `which` lifted off their surfaces (1 cm plus 0.04 % of the depth)
    along their `directions` (``(K, 3)``, one per hit, or ``(1, 3)``, one for all)."""
    rays = np.empty((which.shape[0], 6), dtype=np.float32)
    same = directions.shape[0] == 1
    for m in range(which.shape[0]):
        k = which[m]
        lift = np.float32(0.01) + np.float32(4e-4) * depth[k]
        d = 0 if same else k
        for c in range(3):
            rays[m, c] = points[k, c] + normals[k, c] * lift
            rays[m, 3 + c] = directions[d, c]
    return rays


@njit(**_JIT)
def even_pixels(pixels: np.ndarray, which: np.ndarray, width: int) -> np.ndarray:
    """Whether each hit `which` (indices into `pixels`, flat pixel indices of an image `width` wide)
    is on the even squares of a checkerboard (row + column even)."""
    even = np.empty(which.shape[0], dtype=np.bool_)
    for m in range(which.shape[0]):
        p = pixels[which[m]]
        even[m] = (p // width + p % width) % 2 == 0
    return even


@njit(**_JIT)
def checker_fill(
    pixels: np.ndarray,
    which: np.ndarray,
    key: np.ndarray,
    even: np.ndarray,
    even_blocked: np.ndarray,
    width: int,
    height: int,
) -> tuple[np.ndarray, np.ndarray]:
    """Shadows of the odd squares from the even ones: a hit `which[m]` on an odd square takes the
    shadow of its four neighbours (``(M,)`` results, 1 blocked) where all of them in the image are
    shadow hits with its `key` (face, room) that agree; the others are returned ``(U,)`` (indices into
    `which`) for their own shadow rays. `even_blocked` holds the even squares' results in order."""
    count = which.shape[0]
    slot = np.full(width * height, -1, dtype=np.int32)
    state = np.full(count, -1, dtype=np.int8)
    e = 0
    for m in range(count):
        slot[pixels[which[m]]] = m
        if even[m]:
            state[m] = 1 if even_blocked[e] else 0
            e += 1
    undecided = np.empty(count, dtype=np.int64)
    u = 0
    for m in range(count):
        if even[m]:
            continue
        p = pixels[which[m]]
        row, col = p // width, p % width
        agreed, seen = -1, 0
        for dr, dc in ((-1, 0), (1, 0), (0, -1), (0, 1)):
            r, c = row + dr, col + dc
            if r < 0 or r >= height or c < 0 or c >= width:
                continue
            q = slot[r * width + c]
            if q < 0 or key[which[q]] != key[which[m]] or (agreed >= 0 and state[q] != agreed):
                seen = 0
                break
            agreed = state[q]
            seen += 1
        if seen >= 2:
            state[m] = agreed
        else:
            undecided[u] = m
            u += 1
    return state, undecided[:u]


@njit(**_JIT)
def add_sun(
    light: np.ndarray, which: np.ndarray, blocked: np.ndarray, sun_cosine: np.ndarray, sun_color: np.ndarray
) -> None:
    """Add the sun's light to the hits `which` whose shadow ray is not `blocked`."""
    for m in range(which.shape[0]):
        if blocked[m]:
            continue
        k = which[m]
        for c in range(3):
            light[c, k] += sun_color[c] * sun_cosine[k]


@njit(**_JIT)
def lamp_light(
    points: np.ndarray,
    normals: np.ndarray,
    room: np.ndarray,
    lamps: np.ndarray,
    strength: float,
    reach: float,
    direct: np.ndarray,
    to_lamp: np.ndarray,
) -> None:
    """The direct light `direct` ``(K,)`` of each indoor hit's room lamp (cosine, full within `reach`
    meters, then falling off as the inverse square; 0 in the open or facing away) and the vector
    `to_lamp` ``(K, 3)`` from the hit to its lamp."""
    for k in range(points.shape[0]):
        r = room[k]
        direct[k] = 0.0
        if r < 0:
            continue
        dx = lamps[r, 0] - points[k, 0]
        dy = lamps[r, 1] - points[k, 1]
        dz = lamps[r, 2] - points[k, 2]
        to_lamp[k, 0], to_lamp[k, 1], to_lamp[k, 2] = dx, dy, dz
        distance2 = dx * dx + dy * dy + dz * dz
        cosine = (normals[k, 0] * dx + normals[k, 1] * dy + normals[k, 2] * dz) / math.sqrt(
            max(distance2, 1e-6)
        )
        if cosine > 0.0:
            direct[k] = strength * cosine * min(1.0, reach * reach / max(distance2, 1e-12))


@njit(**_JIT)
def add_lamps(
    light: np.ndarray,
    room: np.ndarray,
    direct: np.ndarray,
    shadowed: np.ndarray,
    blocked: np.ndarray,
    bounce: float,
    color: np.ndarray,
) -> None:
    """Add to `light` ``(3, K)`` each indoor hit's lamp light `direct`, but where its shadow ray (hit
    ``shadowed[m]``) is `blocked`, and the room's bounced light `bounce`, in the lamps' `color`."""
    for m in range(shadowed.shape[0]):
        if blocked[m]:
            direct[shadowed[m]] = 0.0
    for k in range(room.shape[0]):
        if room[k] < 0:
            continue
        total = direct[k] + bounce
        for c in range(3):
            light[c, k] += color[c] * total


@njit(**_JIT)
def shade_hits(
    start: int,
    stop: int,
    radiance: np.ndarray,
    hits: np.ndarray,
    albedo: np.ndarray,
    light: np.ndarray,
    depth: np.ndarray,
    reflect: np.ndarray,
    horizon: np.ndarray,
    haze_distance: float,
) -> None:
    """Radiance at pixels `hits` of ``radiance`` ``(3, P)``: albedo times light, plus the horizon's sky
    that a mirror mirrors (`reflect`), faded into the horizon over `haze_distance` (0: no haze; the
    fade ``1 - exp(-depth / haze_distance)`` linear in a table of 1/16-distance steps)."""
    steps = 16
    top = 8 * steps  # the fade is 1 - exp(-8) = 0.9997 at eight haze distances
    fade = np.empty(top + 2, dtype=np.float32)
    for i in range(top + 2):
        fade[i] = 1.0 - math.exp(-i / steps)
    scale = np.float32(steps / haze_distance) if haze_distance > 0.0 else np.float32(0.0)
    for k in range(start, stop):
        p = hits[k]
        where = min(depth[k] * scale, np.float32(top))
        i = int(where)
        haze = fade[i] + (where - np.float32(i)) * (fade[i + 1] - fade[i])
        for c in range(3):
            value = albedo[c, k] * light[c, k] + reflect[k] * horizon[c]
            radiance[c, p] = value + haze * (horizon[c] - value)


@njit(**_JIT)
def sky_pixels(
    start: int,
    stop: int,
    radiance: np.ndarray,
    pixels: np.ndarray,
    rays: np.ndarray,
    horizon: np.ndarray,
    zenith: np.ndarray,
    sun: np.ndarray,
    sun_color: np.ndarray,
    sun_up: bool,
) -> None:
    """The sky's radiance at `pixels` of ``radiance`` ``(3, P)`` by their rays' directions (``rays``
    ``(P, 6)``): from the horizon to the zenith by the elevation's sine to the power 0.6 (linear in a
    table of 1024 steps), a glow round the sun (the cosine to it to the power 48)."""
    steps = 1024
    height_of = np.empty(steps + 1, dtype=np.float32)
    for i in range(steps + 1):
        height_of[i] = (i / steps) ** 0.6
    for m in range(start, stop):
        p = pixels[m]
        dx, dy, dz = rays[p, 3], rays[p, 4], rays[p, 5]
        inverse = np.float32(1.0) / np.float32(math.sqrt(dx * dx + dy * dy + dz * dz))
        where = min(max(dz * inverse, np.float32(0.0)), np.float32(1.0)) * np.float32(steps)
        i = min(int(where), steps - 1)
        height = height_of[i] + (where - np.float32(i)) * (height_of[i + 1] - height_of[i])
        glow = np.float32(0.0)
        if sun_up:
            toward = max((dx * sun[0] + dy * sun[1] + dz * sun[2]) * inverse, np.float32(0.0))
            t2 = toward * toward
            t4 = t2 * t2
            t8 = t4 * t4
            t16 = t8 * t8
            glow = t16 * t16 * t16  # the 48th power
        for c in range(3):
            radiance[c, p] = (
                horizon[c] + height * (zenith[c] - horizon[c]) + np.float32(0.35) * sun_color[c] * glow
            )


@njit(**_JIT)
def log_average_luma(radiance: np.ndarray, measured: np.ndarray, stride: int) -> float:
    """The geometric mean of the luminance of every `stride`-th of the `measured` pixels ``(M,)`` of
    ``radiance`` ``(3, P)`` (luminances below 1e-4 count as 1e-4); NaN when none is measured."""
    total, count = 0.0, 0
    for m in range(0, measured.shape[0], stride):
        p = measured[m]
        luma = _LUMA_R * radiance[0, p] + _LUMA_G * radiance[1, p] + _LUMA_B * radiance[2, p]
        total += math.log(max(luma, 1e-4))
        count += 1
    if count == 0:
        return math.nan
    return math.exp(total / count)


@njit(**_JIT)
def encode_pixels(
    start: int, stop: int, radiance: np.ndarray, scale: float, table: np.ndarray, out: np.ndarray
) -> None:
    """sRGB bytes ``out`` ``(P, 3)`` of ``radiance`` ``(3, P)`` times `scale`, through the filmic curve
    (Narkowicz's fit of the ACES reference tone map) and `table` (bytes of ``k / (len(table) - 1)``)."""
    steps = np.float32(table.shape[0] - 1)
    gain = np.float32(scale)
    for p in range(start, stop):
        for c in range(3):
            x = radiance[c, p] * gain
            mapped = x * (np.float32(2.51) * x + np.float32(0.03))
            mapped /= x * (np.float32(2.43) * x + np.float32(0.59)) + np.float32(0.14)
            mapped = min(max(mapped, np.float32(0.0)), np.float32(1.0))
            out[p, c] = table[int(mapped * steps + np.float32(0.5))]
