"""Small items people carry and set down outdoors: briefcase, backpack, suitcase, umbrella, coffee cup,
notebook, shopping bag, handbag, water bottle, takeaway box and newspaper.

Most of them stand on bench seats, cafe tables and ledges (placement ``surface``); the rolling suitcase
and the paper shopping bag stand on the ground (``floor``).

Frame conventions
-----------------
- Bags and cases stand upright: x is their width, y their thickness, z their height. The front panel
  (briefcase flap, backpack pocket, suitcase front shell, bag logo) faces +y; the backpack's shoulder
  straps and the suitcase's trolley handle are at the back (-y).
- The closed umbrella lies on its side along x: the ferrule tip at +x, the crook handle at -x with its
  hook lying flat and curling towards +y or -y.
- The coffee cup and the water bottle are upright solids of revolution, slightly elliptic when their x
  and y sizes differ.
- Notebook, newspaper and takeaway box lie flat: the notebook's spine or spiral is at -x, the
  newspaper's fold at -y (its masthead near +y), the clamshell takeaway box's closing tab at +y.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np

from navverse.assets.materials import RGB, pick, shade
from navverse.assets.parts import (
    Assembly,
    Solid,
    bar,
    box,
    cylinder,
    difference,
    ellipsoid,
    extrude,
    frustum,
    hull,
    revolve,
    rotate,
    rounded_prism,
    rounded_rectangle,
    torus,
    translate,
)
from navverse.assets.spec import Asset, Size

__all__ = ["ASSETS"]

# local palettes (sRGB)
_KRAFT: tuple[RGB, ...] = ((196, 160, 118), (178, 140, 98), (208, 176, 134))
_LUGGAGE: tuple[RGB, ...] = (
    (32, 32, 36),
    (38, 58, 104),
    (150, 32, 42),
    (196, 198, 202),
    (56, 106, 98),
    (222, 178, 58),
    (232, 232, 228),
    (112, 78, 146),
    (86, 88, 94),
    (214, 120, 140),
)
_ATTACHE: tuple[RGB, ...] = ((186, 190, 196), (34, 34, 38), (72, 50, 36), (40, 48, 72))
_HANDBAG: tuple[RGB, ...] = (
    (36, 32, 30),
    (100, 62, 40),
    (160, 108, 64),
    (98, 34, 34),
    (206, 180, 150),
    (230, 222, 210),
    (60, 76, 110),
    (150, 150, 146),
    (180, 60, 70),
)
_CANOPY: tuple[RGB, ...] = (
    (24, 24, 28),
    (30, 40, 80),
    (150, 30, 36),
    (40, 80, 60),
    (120, 110, 100),
    (60, 90, 160),
    (200, 170, 60),
)
_CUP: tuple[RGB, ...] = ((250, 250, 248), (244, 242, 236), (196, 160, 118), (34, 34, 38), (196, 36, 44))
_PET: tuple[RGB, ...] = ((200, 224, 236), (214, 230, 238), (190, 216, 228))
_FLASK: tuple[RGB, ...] = (
    (196, 200, 204),
    (36, 36, 40),
    (40, 110, 170),
    (196, 60, 60),
    (60, 150, 110),
    (236, 196, 60),
    (226, 140, 168),
    (240, 240, 236),
)
_NEWSPRINT: tuple[RGB, ...] = ((234, 230, 218), (226, 224, 216), (240, 236, 226), (242, 214, 196))
_INK: RGB = (36, 36, 40)
_TEXT: RGB = (150, 150, 152)
_RUBBER: RGB = (30, 30, 32)


def _scaled(solid: Solid, sx: float = 1.0, sy: float = 1.0, sz: float = 1.0) -> Solid:
    """A solid scaled about the origin (positive factors keep it closed and outward)."""
    return solid[0] * np.array([sx, sy, sz]), solid[1]


def _plate_y(cx: float, cz: float, width: float, height: float, radius: float, y0: float, y1: float) -> Solid:
    """A plate from `y0` to `y1` whose front (x-z) outline is a rectangle with rounded corners."""
    outline = rounded_rectangle(width, height, radius) + np.array([cx, cz])
    return rotate(extrude(outline, -y1, -y0), "x", 0.5 * math.pi)


def _sweep(path: np.ndarray, radii: tuple[float, float], normal: Sequence[float], sections: int = 8) -> Solid:
    """A tube along a plane curve, capped at both ends.

    Parameters
    ----------
    path : ndarray, shape (K, 3)
        Centre line, lying in a plane with normal `normal`.
    radii : (float, float)
        Half thickness along `normal` and half width in the plane of the curve.
    sections : int
        Vertices per cross-section (a multiple of 4 reaches both radii exactly).
    """
    pts = np.asarray(path, dtype=np.float64)
    up = np.asarray(normal, dtype=np.float64)
    up = up / np.linalg.norm(up)
    tangent = np.gradient(pts, axis=0)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    side = np.cross(up, tangent)
    side /= np.linalg.norm(side, axis=1, keepdims=True)
    angles = 2.0 * np.pi * np.arange(sections) / sections
    ring = (
        pts[:, None, :]
        + radii[0] * np.cos(angles)[None, :, None] * up
        + radii[1] * np.sin(angles)[None, :, None] * side[:, None, :]
    )
    n, s = len(pts), sections
    vertices = np.concatenate([ring.reshape(-1, 3), pts[:1], pts[-1:]])
    k = np.arange(s)
    k1 = (k + 1) % s
    faces = []
    for i in range(n - 1):
        a, b, c, d = i * s + k, i * s + k1, (i + 1) * s + k1, (i + 1) * s + k
        faces += [np.stack([a, b, c], axis=1), np.stack([a, c, d], axis=1)]
    faces.append(np.stack([np.full(s, n * s), k1, k], axis=1))
    faces.append(np.stack([np.full(s, n * s + 1), (n - 1) * s + k, (n - 1) * s + k1], axis=1))
    tri = np.concatenate(faces).astype(np.int64)
    corner = vertices[tri]
    volume = np.einsum("ij,ij->i", corner[:, 0], np.cross(corner[:, 1], corner[:, 2])).sum()
    return vertices, (tri if volume > 0 else tri[:, ::-1].copy())


def _arch(
    cx: float,
    y: float,
    z_base: float,
    half_span: float,
    rise: float,
    *,
    square: float = 1.0,
    leg: float = 0.0,
) -> np.ndarray:
    """Centre line of a handle arching over x in the plane ``y = const``: a half ellipse from
    ``cx - half_span`` to ``cx + half_span`` rising `rise` above `z_base` (``square < 1`` flattens its
    top into a rounded box shape), with straight legs of length `leg` below both ends."""
    theta = np.linspace(math.pi, 0.0, 17)
    c, s = np.cos(theta), np.sin(theta)
    x = cx + half_span * np.sign(c) * np.abs(c) ** square
    z = z_base + rise * np.abs(s) ** square
    points = np.stack([x, np.full_like(x, y), z], axis=1)
    if leg > 0:
        start = [[cx - half_span, y, z_base - leg]]
        end = [[cx + half_span, y, z_base - leg]]
        points = np.concatenate([start, points, end])
    return points


def _briefcase(rng: np.random.Generator, size: Size) -> Assembly:
    """A briefcase standing on its long edge: a hard attaché case (shell, metal seam frame, latches) or a
    soft leather brief (tapered body, front flap, clasp), with a top carry handle and feet."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    metal = pick(rng, "chrome") if rng.uniform() < 0.6 else pick(rng, "brass")
    grip = 0.008
    top = h - float(np.clip(0.1 * h, 0.03, 0.045))
    foot = 0.006
    if rng.uniform() < 0.5:  # hard attaché case, the lid seam at y = 0
        shell = pick(rng, _ATTACHE)
        zc = 0.5 * (foot + top)
        asm.add(_plate_y(0.0, zc, w - 0.004, top - foot - 0.004, 0.02, -hy, hy), shell)
        asm.add(_plate_y(0.0, zc, w, top - foot, 0.022, -0.004, 0.004), metal)
        for sx in (-1.0, 1.0):
            x = sx * 0.3 * w
            asm.box((x - 0.022, -0.012, top - 0.004), (x + 0.022, 0.012, top + 0.008), metal)
            asm.box((x - 0.01, 0.012, top - 0.03), (x + 0.01, 0.016, top - 0.01), shade(metal, 0.7))
        y_handle, body_color = 0.0, shell
    else:  # soft leather brief: tapered towards the top, flap over the front
        leather = pick(rng, "leather") if rng.uniform() < 0.7 else pick(rng, _HANDBAG)
        yc, depth = -0.0025, d - 0.005
        y_top = 0.225 * d
        points = [(x, y + yc, z) for x, y in rounded_rectangle(w, depth, 0.015) for z in (foot, 0.6 * top)]
        points += [(x, y + yc, top) for x, y in rounded_rectangle(w - 0.012, 0.45 * d, 0.01)]
        asm.add(hull(points), leather)
        fx = hx - 0.012
        flap = [
            (sx * fx, y, z)
            for sx in (-1.0, 1.0)
            for y, z in (
                (hy - 0.002, 0.42 * top),
                (hy - 0.008, 0.42 * top),
                (hy - 0.002, 0.6 * top),
                (hy - 0.008, 0.6 * top),
                (y_top + yc + 0.003, top + 0.002),
                (y_top + yc - 0.004, top - 0.002),
            )
        ]
        asm.add(hull(flap), shade(leather, 0.85))
        asm.box((-0.02, hy - 0.004, 0.42 * top - 0.006), (0.02, hy, 0.42 * top + 0.024), metal)
        asm.box(
            (-0.005, hy - 0.012, 0.42 * top + 0.024), (0.005, hy - 0.002, 0.55 * top), shade(leather, 0.6)
        )
        y_handle, body_color = yc, leather
    half = float(np.clip(0.15 * w, 0.05, 0.07))
    path = _arch(0.0, y_handle, top - 0.004, half, h - grip - (top - 0.004), square=0.5)
    asm.add(_sweep(path, (0.01, grip), (0.0, 1.0, 0.0)), shade(body_color, 0.7))
    for sx in (-1.0, 1.0):
        x = sx * half
        asm.box((x - 0.01, y_handle - 0.009, top - 0.004), (x + 0.01, y_handle + 0.009, top + 0.01), metal)
    for x in (-hx + 0.04, hx - 0.04):
        for y in (-hy + 0.02, hy - 0.02):
            asm.add(cylinder((x, y, 0.0), (x, y, foot + 0.003), 0.006, sections=8), _RUBBER)
    return asm


def _backpack(rng: np.random.Generator, size: Size) -> Assembly:
    """A daypack standing upright: rounded body, zipped front pocket (+y), padded back panel and two
    shoulder straps (-y), a grab loop on top and, on some, mesh side pockets."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    cloth = pick(rng, "fabric") if rng.uniform() < 0.6 else pick(rng, "accent")
    dark = shade(cloth, 0.45) if rng.uniform() < 0.5 else (38, 38, 42)
    pocket_color = cloth if rng.uniform() < 0.5 else pick(rng, "fabric")
    strap_t = float(np.clip(0.1 * d, 0.018, 0.026))
    pocket_t = float(np.clip(0.16 * d, 0.025, 0.04))
    side_t = 0.022 if rng.uniform() < 0.5 else 0.0
    y0, y1 = -hy + strap_t, hy - pocket_t
    bd, bcy = y1 - y0, 0.5 * (y0 + y1)
    bw = w - 2.0 * side_t
    loop_r = 0.005
    bh = h - 0.04
    shoulder = 0.62 * bh
    lower = rounded_prism((0.0, bcy), bw, bd, 0.2 * min(bw, bd), 0.0, shoulder)[0]
    dome = ellipsoid((0.0, bcy, shoulder), (0.5 * bw, 0.5 * bd, bh - shoulder), segments=16, rings=8)[0]
    asm.add(hull(np.concatenate([lower, dome])), cloth)
    asm.add(_plate_y(0.0, 0.27 * bh, 0.74 * bw, 0.44 * bh, 0.05, y1 - 0.01, hy - 0.002), pocket_color)
    asm.add(_plate_y(0.0, 0.47 * bh, 0.6 * bw, 0.008, 0.003, y1 - 0.005, hy), dark)  # zip
    asm.box((0.2 * bw, hy - 0.008, 0.44 * bh), (0.2 * bw + 0.012, hy, 0.47 * bh), (200, 200, 204))
    asm.add(_plate_y(0.0, 0.44 * bh, 0.8 * bw, 0.74 * bh, 0.05, y0 - 0.008, y0 + 0.012), dark)
    strap_y = -hy + 0.006
    for s in (-1.0, 1.0):
        points = [
            (s * 0.05, y0 - 0.006, 0.78 * bh),
            (s * 0.1, strap_y, 0.62 * bh),
            (s * 0.28 * bw, strap_y, 0.27 * bh),
            (s * 0.36 * bw, y0 - 0.004, 0.07 * bh),
        ]
        for a, b in itertools.pairwise(points):
            asm.add(bar(a, b, (0.055, 0.012, 0.012)), dark)
        x = s * 0.36 * bw
        asm.box((x - 0.02, y0 - 0.012, 0.02 * bh), (x + 0.02, y0 + 0.01, 0.1 * bh), (30, 30, 32))
    rise = h - loop_r - (bh - 0.012)
    asm.add(_sweep(_arch(0.0, bcy, bh - 0.012, 0.035, rise), (0.006, loop_r), (0.0, 1.0, 0.0)), dark)
    if side_t > 0:
        mesh = shade(dark, 1.3)
        for s in (-1.0, 1.0):
            xa, xb = sorted((s * hx, s * (hx - side_t - 0.012)))
            asm.box((xa, bcy - 0.3 * bd, 0.02 * bh), (xb, bcy + 0.3 * bd, 0.36 * bh), mesh)
    return asm


def _suitcase(rng: np.random.Generator, size: Size) -> Assembly:
    """A rolling suitcase: hard ribbed shell or soft case with a front pocket, zip band, trolley handle at
    the back (extended on tall sizes), top carry handle, four spinner wheels or two wheels and feet."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    hard = rng.uniform() < 0.6
    shell = pick(rng, _LUGGAGE) if hard else pick(rng, "fabric")
    trim = pick(rng, "dark_plastic")
    r = float(np.clip(0.065 * w, 0.024, 0.032))
    z_b = 2.0 * r + 0.012
    extended = h > 0.84
    if extended:  # bodies are about 1.5 times as tall as wide; the handle reaches 28-50 cm above
        top = float(np.clip(1.5 * w * rng.uniform(0.95, 1.05), max(0.5, h - 0.5), min(0.8, h - 0.28)))
    else:
        top = h - 0.035
    body_h, zc = top - z_b, 0.5 * (top + z_b)
    corner = float(np.clip(0.1 * w, 0.035, 0.05))
    y_seam = -0.1 * d
    asm.add(_plate_y(0.0, zc, w, body_h, corner, y_seam - 0.006, y_seam + 0.006), trim)
    if hard:
        asm.add(_plate_y(0.0, zc, w - 0.006, body_h - 0.006, corner - 0.003, -hy, hy - 0.005), shell)
        ribs = int(rng.integers(2, 6))
        for x in np.linspace(-0.5 * w, 0.5 * w, ribs + 2)[1:-1]:
            rib = _plate_y(float(x), zc, 0.014, body_h - 0.12, 0.006, hy - 0.008, hy)
            asm.add(rib, shade(shell, 0.88))
    else:
        asm.add(_plate_y(0.0, zc, w - 0.006, body_h - 0.006, corner - 0.003, -hy, hy - 0.025), shell)
        pocket_h = 0.62 * body_h
        pocket_z = z_b + 0.05 + 0.5 * pocket_h
        asm.add(_plate_y(0.0, pocket_z, w - 0.07, pocket_h, 0.03, hy - 0.03, hy - 0.002), shade(shell, 0.9))
        z_zip = pocket_z + 0.5 * pocket_h - 0.02
        asm.add(_plate_y(0.0, z_zip, w - 0.1, 0.008, 0.003, hy - 0.006, hy), trim)
    hs = 0.5 * min(0.6 * w, 0.28)
    y_t = -hy + 0.028
    asm.box((-hs - 0.025, -hy + 0.008, top - 0.006), (hs + 0.025, -hy + 0.048, top + 0.012), trim)
    if extended:
        mid = 0.5 * (top + h)
        for s in (-1.0, 1.0):
            x = s * hs
            asm.box((x - 0.011, y_t - 0.007, top), (x + 0.011, y_t + 0.007, mid), pick(rng, "metal"))
            asm.box((x - 0.009, y_t - 0.006, mid - 0.01), (x + 0.009, y_t + 0.006, h - 0.02), (186, 190, 194))
    asm.add(_plate_y(0.0, h - 0.015, 2.0 * hs + 0.04, 0.03, 0.012, y_t - 0.016, y_t + 0.016), trim)
    half = float(np.clip(0.22 * w, 0.06, 0.08))
    carry = _arch(0.0, 0.12 * d, top - 0.006, half, 0.027, square=0.6)
    asm.add(_sweep(carry, (0.012, 0.007), (0.0, 1.0, 0.0)), trim)
    if rng.uniform() < 0.65:  # four double spinner wheels
        for sx in (-1.0, 1.0):
            for sy in (-1.0, 1.0):
                x, y = sx * (hx - 0.035), sy * (hy - 0.035)
                asm.box((x - 0.022, y - 0.022, 2.0 * r - 0.006), (x + 0.022, y + 0.022, z_b + 0.004), trim)
                for dx in (-0.013, 0.003):
                    wheel = cylinder((x + dx, y, r), (x + dx + 0.01, y, r), r, sections=12)
                    asm.add(wheel, _RUBBER)
    else:  # two inline wheels at the back, two feet at the front
        for sx in (-1.0, 1.0):
            x, y = sx * (hx - 0.03), -hy + r + 0.004
            asm.box((x - 0.02, -hy + 0.002, r), (x + 0.02, y + r + 0.01, z_b + 0.004), trim)
            asm.add(cylinder((x - 0.012, y, r), (x + 0.012, y, r), r, sections=12), _RUBBER)
            fx = sx * (hx - 0.05)
            asm.box((fx - 0.02, hy - 0.05, 0.0), (fx + 0.02, hy - 0.015, z_b + 0.004), trim)
    return asm


def _umbrella(rng: np.random.Generator, size: Size) -> Assembly:
    """A closed stick umbrella lying along x: metal ferrule tip (+x), furled pleated canopy with a closing
    strap, shaft, and a crook handle (-x) lying flat."""
    length, d, h = size
    hx = 0.5 * length
    asm = Assembly()
    canopy = pick(rng, _CANOPY)
    handle = pick(rng, "wood") if rng.uniform() < 0.5 else pick(rng, ((30, 30, 32), (70, 44, 30), canopy))
    metal = pick(rng, "chrome") if rng.uniform() < 0.6 else (40, 40, 44)
    rc = 0.5 * h
    zc = rc
    rt = min(0.012, 0.45 * rc)
    hook = 1.0 if rng.uniform() < 0.5 else -1.0
    bend = 0.5 * (d - rc - rt)
    tip = float(rng.uniform(0.07, 0.09)) * length / 0.9
    canopy_len = 0.6 * length
    x_c1 = hx - tip
    x_c0 = x_c1 - canopy_len
    # ferrule, top cap
    asm.add(frustum((x_c1 - 0.01, 0.0, zc), (hx, 0.0, zc), 0.0055, 0.003, sections=8), metal)
    asm.add(frustum((x_c1 - 0.02, 0.0, zc), (x_c1 + 0.012, 0.0, zc), 0.3 * rc, 0.008, sections=8), handle)
    # pleated canopy: widest a quarter of the way up, tapering to the tip
    pleats = 8
    angles = 2.0 * np.pi * np.arange(2 * pleats) / (2 * pleats)
    radius = np.where(np.arange(2 * pleats) % 2 == 0, 1.0, 0.8)
    star = np.stack([radius * np.cos(angles), radius * np.sin(angles)], axis=1)
    x_wide = x_c0 + 0.25 * canopy_len

    def pleated(x0: float, x1: float, r0: float, r1: float) -> Solid:
        solid = extrude(star * r0, 0.0, x1 - x0, scale_top=(r1 / r0, r1 / r0))
        return translate(rotate(solid, "y", 0.5 * math.pi), (x0, 0.0, zc))

    asm.add(pleated(x_c0, x_wide, 0.75 * rc, rc), canopy)
    asm.add(pleated(x_wide, x_c1, rc, 0.22 * rc), canopy)
    asm.add(frustum((x_c0 - 0.035, 0.0, zc), (x_c0 + 0.002, 0.0, zc), 0.006, 0.7 * rc, sections=8), canopy)
    # closing strap with a press stud
    xs = x_wide + 0.35 * (x_c1 - x_wide)
    rs = rc * (1.0 - 0.78 * 0.35) + 0.001
    asm.add(cylinder((xs - 0.012, 0.0, zc), (xs + 0.012, 0.0, zc), rs, sections=16), shade(canopy, 0.75))
    asm.add(cylinder((xs, 0.0, zc + rs - 0.002), (xs, 0.0, zc + rs + 0.002), 0.006, sections=8), metal)
    # shaft and crook handle
    x_bend = -hx + bend + rt
    x_grip = x_bend + float(rng.uniform(0.09, 0.12))
    asm.add(cylinder((x_grip - 0.01, 0.0, zc), (x_c0 - 0.03, 0.0, zc), 0.005, sections=8), metal)
    asm.add(cylinder((x_grip - 0.004, 0.0, zc), (x_grip + 0.006, 0.0, zc), rt + 0.002, sections=12), metal)
    phi = np.linspace(0.0, math.pi, 13)[1:]
    path = np.concatenate(
        [
            np.stack([np.linspace(x_grip, x_bend, 5), np.zeros(5), np.full(5, zc)], axis=1),
            np.stack([x_bend - bend * np.sin(phi), hook * bend * (1 - np.cos(phi)), np.full(12, zc)], axis=1),
            [[x_bend + 0.2 * bend, 2.0 * hook * bend, zc], [x_bend + 0.35 * bend, 2.0 * hook * bend, zc]],
        ]
    )
    asm.add(_sweep(path, (rt, rt), (0.0, 0.0, 1.0)), handle)
    return asm


def _coffee_cup(rng: np.random.Generator, size: Size) -> Assembly:
    """A takeaway coffee cup: tapered paper cup, a cardboard sleeve or a printed band, and a sip lid."""
    w, d, h = size
    sy = d / w
    asm = Assembly()

    def add(solid: Solid, color: RGB) -> None:
        asm.add(_scaled(solid, 1.0, sy, 1.0), color)

    cup = pick(rng, _CUP, variation=0.03)
    lid = pick(rng, ((248, 248, 246), (30, 30, 32), (120, 84, 60)), variation=0.03)
    rl = 0.5 * w
    lid_h = float(np.clip(0.12 * h, 0.012, 0.02))
    z0 = h - lid_h
    cup_top = z0 + 0.004
    rt = rl - 0.0025
    rb = 0.72 * rt
    add(frustum((0.0, 0.0, 0.0), (0.0, 0.0, cup_top), rb, rt, sections=16), cup)

    def radius(z: float) -> float:
        return rb + (rt - rb) * z / cup_top

    if rng.uniform() < 0.75:  # corrugated cardboard sleeve
        s0 = float(rng.uniform(0.25, 0.33)) * cup_top
        s1 = s0 + min(0.055, 0.42 * cup_top)
        sleeve = pick(rng, (*_KRAFT, (34, 34, 38), (0, 112, 74), (250, 250, 248)), variation=0.03)
        add(frustum((0.0, 0.0, s0), (0.0, 0.0, s1), radius(s0) + 0.0018, radius(s1) + 0.0018), sleeve)
    else:  # printed logo band
        s0 = 0.45 * cup_top
        s1 = s0 + 0.2 * cup_top
        band = pick(rng, "brand")
        add(frustum((0.0, 0.0, s0), (0.0, 0.0, s1), radius(s0) + 0.0008, radius(s1) + 0.0008), band)
    profile = [
        (0.0, z0 + 0.002),
        (rl - 0.001, z0),
        (rl, z0 + 0.5 * lid_h),
        (rl - 0.004, z0 + 0.62 * lid_h),
        (rl - 0.005, h - 0.002),
        (rl - 0.012, h - 0.002),
        (rl - 0.016, z0 + 0.55 * lid_h),
        (0.0, z0 + 0.55 * lid_h),
    ]
    add(revolve(profile, sections=16), lid)
    spout = ellipsoid((0.0, rl - 0.0085, h - 0.004), (0.009, 0.0045, 0.004), segments=12, rings=4)
    add(spout, shade(lid, 0.85))
    return asm


def _notebook(rng: np.random.Generator, size: Size) -> Assembly:
    """A closed notebook lying flat: spiral-bound with wire rings at -x, hardbound with a rounded spine and
    an elastic band, or a soft-cover exercise book with a label."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    cover = pick(rng, "book") if rng.uniform() < 0.7 else pick(rng, "accent")
    pages = (244, 240, 226) if rng.uniform() < 0.6 else (250, 250, 248)
    style = int(rng.integers(3))
    if style == 0:  # spiral bound
        t = min(0.0015, 0.12 * h)
        ro = 0.5 * h
        cx = -hx + ro
        x0 = cx - 0.3 * ro
        asm.box((x0, -hy, 0.0), (hx, hy, t), shade(cover, 0.8))
        asm.box((x0 + 0.001, -hy + 0.002, t), (hx - 0.002, hy - 0.002, h - t), pages)
        asm.box((x0, -hy, h - t), (hx, hy, h), cover)
        wire = pick(rng, "chrome") if rng.uniform() < 0.6 else (30, 30, 32)
        minor = min(0.0007, 0.2 * ro)
        pitch = float(rng.uniform(0.009, 0.014))
        count = int((d - 0.02) / pitch) + 1
        for y in np.linspace(-hy + 0.01, hy - 0.01, count):
            asm.add(torus((cx, float(y), 0.5 * h), ro - minor, minor, sections=8, tube=4, axis="y"), wire)
    elif style == 1:  # hardbound with a rounded spine and an elastic band
        t = min(0.0022, 0.15 * h)
        rx = min(0.004, 0.04 * w)
        asm.add(
            frustum((-hx + rx, -hy, 0.5 * h), (-hx + rx, hy, 0.5 * h), (rx, 0.5 * h), (rx, 0.5 * h)), cover
        )
        band_t = 0.0008
        asm.add(rounded_prism((rx * 0.5, 0.0), w - rx, d - 2 * band_t, 0.005, 0.0, t), cover)
        asm.add(
            rounded_prism((rx * 0.5, 0.0), w - rx, d - 2 * band_t, 0.005, h - t - band_t, h - band_t), cover
        )
        asm.box((-hx + rx, -hy + 0.003, t), (hx - 0.003, hy - 0.003, h - t - band_t), pages)
        band = (30, 30, 32) if rng.uniform() < 0.6 else shade(cover, 0.6)
        bx = hx - 0.025
        asm.box((bx - 0.0035, -hy + band_t, h - band_t), (bx + 0.0035, hy - band_t, h), band)
        for s in (-1.0, 1.0):
            ya, yb = sorted((s * hy, s * (hy - band_t)))
            asm.box((bx - 0.0035, ya, 0.0), (bx + 0.0035, yb, h), band)
    else:  # soft-cover exercise book with a label
        t = min(0.0006, 0.1 * h)
        label_t = 0.0004
        asm.box((-hx, -hy, 0.0), (hx, hy, t), cover)
        asm.box((-hx + 0.001, -hy + 0.001, t), (hx - 0.001, hy - 0.001, h - t - label_t), pages)
        asm.box((-hx, -hy, h - t - label_t), (hx, hy, h - label_t), cover)
        lw, ld = 0.55 * w, 0.16 * d
        ly = 0.12 * d
        asm.box(
            (-0.5 * lw, ly - 0.5 * ld, h - label_t), (0.5 * lw, ly + 0.5 * ld, h - 0.0001), (248, 248, 244)
        )
        for k in range(3):
            yl = ly - 0.3 * ld + k * 0.3 * ld
            asm.box((-0.42 * lw, yl - 0.0006, h - label_t), (0.42 * lw, yl + 0.0006, h), _TEXT)
    return asm


def _shopping_bag(rng: np.random.Generator, size: Size) -> Assembly:
    """A paper carrier bag with an open top, folded-in hem, printed logo panels, twisted-cord or flat paper
    handles on the front and back walls, and sometimes groceries sticking out."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    paper = (
        pick(rng, _KRAFT) if rng.uniform() < 0.5 else pick(rng, "brand" if rng.uniform() < 0.5 else "paper")
    )
    wall = 0.0025
    rise = float(np.clip(0.22 * h, 0.07, 0.12))
    top = h - rise
    yw = hy - 0.001
    inner = box((-hx + wall, -yw + wall, 0.004), (hx - wall, yw - wall, top + 0.01))
    asm.add(difference(box((-hx, -yw, 0.0), (hx, yw, top)), inner), paper)
    hem = box((-hx + 2 * wall, -yw + 2 * wall, top - 0.04), (hx - 2 * wall, yw - 2 * wall, top + 0.01))
    asm.add(
        difference(box((-hx + wall, -yw + wall, top - 0.035), (hx - wall, yw - wall, top)), hem),
        shade(paper, 0.85),
    )
    logo = pick(rng, "brand") if paper not in _KRAFT else _INK
    if logo == paper:
        logo = shade(paper, 0.5)
    lw, lh = 0.5 * w, 0.3 * top
    lz = 0.55 * top
    for s in (-1.0, 1.0):
        ya, yb = sorted((s * hy, s * (yw - 0.001)))
        if rng.uniform() < 0.5:
            asm.box((-0.5 * lw, ya, lz - 0.5 * lh), (0.5 * lw, yb, lz + 0.5 * lh), logo)
        else:
            disc = frustum((0.0, ya, lz), (0.0, yb, lz), 0.5 * lh, 0.5 * lh, sections=16)
            asm.add(disc, logo)
    cord = rng.uniform() < 0.6
    radii = (0.0035, 0.0035) if cord else (0.0012, 0.01)
    handle = paper if rng.uniform() < 0.5 else pick(rng, ((248, 248, 244), (30, 30, 32), *_KRAFT))
    half = float(np.clip(0.22 * w, 0.045, 0.07))
    z_base = top - 0.03
    for s in (-1.0, 1.0):
        y = s * (yw - wall - radii[0] - 0.0005)
        path = _arch(0.0, y, z_base, half, h - radii[1] - z_base)
        asm.add(_sweep(path, radii, (0.0, 1.0, 0.0)), handle)
    if rng.uniform() < 0.5:  # groceries
        room = min(rise - 0.015, 0.09)
        x = -hx + wall + 0.01
        while x < hx - wall - 0.05:
            iw = min(float(rng.uniform(0.04, 0.1)), hx - wall - 0.005 - x)
            item_top = top + float(rng.uniform(-0.05, room))
            idy = min(float(rng.uniform(0.04, 0.12)), 2 * (yw - wall) - 0.01)
            iy = float(rng.uniform(-(yw - wall - 0.005 - 0.5 * idy), yw - wall - 0.005 - 0.5 * idy))
            if rng.uniform() < 0.4:  # a baguette or a leek
                color = (206, 160, 96) if rng.uniform() < 0.5 else (90, 150, 70)
                rad = min(0.5 * iw, 0.5 * idy, 0.03)
                asm.add(
                    cylinder((x + 0.5 * iw, iy, 0.004), (x + 0.5 * iw, iy, item_top), rad, sections=8), color
                )
            else:
                asm.box(
                    (x, iy - 0.5 * idy, 0.004), (x + iw, iy + 0.5 * idy, item_top), pick(rng, "packaging")
                )
            x += iw + 0.005
    return asm


def _handbag(rng: np.random.Generator, size: Size) -> Assembly:
    """A handbag standing upright: a tote (tapered body, zip, two handles with metal tabs) or a satchel
    (rounded body, front flap with a clasp, one top handle)."""
    w, d, h = size
    hy = 0.5 * d
    asm = Assembly()
    leather = pick(rng, _HANDBAG)
    trim = shade(leather, 0.7) if rng.uniform() < 0.6 else pick(rng, _HANDBAG)
    metal = pick(rng, "brass") if rng.uniform() < 0.5 else pick(rng, "chrome")
    r = 0.006
    if rng.uniform() < 0.5:  # tote
        top = h - float(np.clip(0.38 * h, 0.08, 0.14))
        yt = 0.3 * d
        points = [(x, y, 0.0) for x, y in rounded_rectangle(0.84 * w, d, 0.02)]
        points += [(x, y, top) for x, y in rounded_rectangle(w, 2.0 * yt, 0.01)]
        asm.add(hull(points), leather)
        base_w = 0.84 * w + 0.16 * w * 0.02 / top + 0.003
        asm.add(rounded_prism((0.0, 0.0), base_w, d, 0.02, 0.0, 0.02), trim)
        asm.box((-0.4 * w, -0.004, top - 0.001), (0.4 * w, 0.004, top + 0.003), shade(leather, 0.5))
        half = float(np.clip(0.22 * w, 0.05, 0.08))
        z_base = top - 0.03
        for s in (-1.0, 1.0):
            y = s * (yt + 0.0085)
            path = _arch(0.0, y, z_base, half, h - r - z_base, square=0.85)
            asm.add(_sweep(path, (0.004, r), (0.0, 1.0, 0.0)), trim)
            for sx in (-1.0, 1.0):
                ya, yb = sorted((s * (yt + 0.003), s * (yt + 0.0135)))
                x = sx * half
                asm.box((x - 0.009, ya, z_base - 0.025), (x + 0.009, yb, z_base + 0.005), metal)
    else:  # satchel: tapered body, flap over the top and the front with rounded corners, turn clasp
        top = h - float(np.clip(0.25 * h, 0.05, 0.09))
        yc, yb = -0.002, hy - 0.002
        levels = ((0.0, 1.0, 1.0), (0.03, 1.0, 1.0), (0.6 * top, 0.95, 0.9), (top, 0.8, 0.5))
        points = [
            (x, y + yc, z)
            for z, fw, fd in levels
            for x, y in rounded_rectangle(fw * w, fd * 2.0 * yb, 0.02 if z < top else 0.012)
        ]
        asm.add(hull(points), leather)

        def front(z: float) -> tuple[float, float]:
            """Half width and front face y of the body at height z."""
            zs = [lv[0] for lv in levels]
            fw = float(np.interp(z, zs, [lv[1] for lv in levels]))
            fd = float(np.interp(z, zs, [lv[2] for lv in levels]))
            return 0.5 * fw * w, yc + fd * yb

        z_f = 0.42 * top
        rc = float(np.clip(0.25 * w, 0.03, 0.06))
        hw_top, yf_top = front(top)
        flap = []
        for sx in (-1.0, 1.0):
            x = sx * (hw_top - 0.008)
            for y in (yc + 0.012, yf_top - 0.002):
                flap += [(x, y, top - 0.004), (x, y, top + 0.003)]
            flap.append((x, yf_top + 0.002, top + 0.001))
            hw, yf = front(0.6 * top)
            flap += [(sx * (hw - 0.008), yf + 0.003, 0.6 * top), (sx * (hw - 0.008), yf - 0.004, 0.6 * top)]
            for phi in np.linspace(0.0, 0.5 * math.pi, 5):
                z = z_f + rc * (1.0 - math.cos(phi))
                hw, yf = front(z)
                x = sx * (hw - 0.008 - rc + rc * math.sin(phi))
                flap += [(x, yf + 0.003, z), (x, yf - 0.004, z)]
        asm.add(hull(flap), trim)
        yf = front(z_f)[1]
        asm.box((-0.014, yf, z_f - 0.004), (0.014, hy, z_f + 0.022), metal)
        half = float(np.clip(0.2 * w, 0.045, 0.07))
        z_base = top - 0.012
        path = _arch(0.0, yc, z_base, half, h - r - z_base, square=0.8)
        asm.add(_sweep(path, (0.005, r), (0.0, 1.0, 0.0)), trim)
        for sx in (-1.0, 1.0):
            x = sx * half
            asm.box((x - 0.008, yc - 0.008, top - 0.012), (x + 0.008, yc + 0.008, top + 0.01), metal)
    return asm


def _water_bottle(rng: np.random.Generator, size: Size) -> Assembly:
    """A water bottle: a disposable PET bottle (ribbed body, label, neck ring, screw cap) or a reusable
    flask (body, bumper, wide cap with a carry loop)."""
    w, d, h = size
    sy = d / w
    asm = Assembly()

    def add(solid: Solid, color: RGB) -> None:
        asm.add(_scaled(solid, 1.0, sy, 1.0), color)

    R = 0.5 * w - 0.0008
    if rng.uniform() < 0.5:  # PET bottle
        cap_r, cap_h = 0.0155, 0.02
        rn = 0.0125
        neck_top = h - cap_h + 0.008
        H = neck_top - 0.02
        shoulder = float(rng.uniform(0.62, 0.7)) * H
        profile = [
            (0.0, 0.0),
            (0.8 * R, 0.0),
            (R, 0.025 * H),
            (R, 0.3 * H),
            (0.95 * R, 0.33 * H),
            (R, 0.36 * H),
        ]
        profile += [(R, shoulder)]
        for f in np.linspace(0.0, 1.0, 6)[1:]:
            profile.append(
                (
                    rn + (R - rn) * math.cos(0.5 * math.pi * f),
                    shoulder + (H - shoulder) * math.sin(0.5 * math.pi * f),
                )
            )
        profile += [(rn, neck_top), (0.0, neck_top)]
        add(revolve(profile, sections=16), pick(rng, _PET, variation=0.02))
        add(
            cylinder((0.0, 0.0, H + 0.004), (0.0, 0.0, H + 0.006), rn + 0.004, sections=12),
            pick(rng, _PET, variation=0.02),
        )
        z0 = float(rng.uniform(0.4, 0.45)) * H
        add(
            cylinder((0.0, 0.0, z0), (0.0, 0.0, z0 + 0.22 * H), R + 0.0008, sections=16),
            pick(rng, "packaging"),
        )
        cap = pick(rng, ((40, 90, 170), (240, 240, 236), (196, 40, 44), (40, 140, 80), (30, 30, 32)))
        add(cylinder((0.0, 0.0, h - cap_h), (0.0, 0.0, h), cap_r, sections=16), cap)
    else:  # reusable flask
        body = pick(rng, _FLASK)
        cap = (30, 30, 32) if rng.uniform() < 0.5 else shade(body, 0.75)
        loop_h = 0.018
        cap_r = 0.62 * R
        cap_top = h - loop_h
        cap_h = float(np.clip(0.12 * h, 0.025, 0.035))
        zn = cap_top - cap_h + 0.003
        shoulder = zn - 0.55 * R
        profile = [(0.0, 0.0), (R - 0.004, 0.0), (R, 0.004), (R, shoulder)]
        for f in np.linspace(0.0, 1.0, 5)[1:]:
            profile.append(
                (
                    cap_r - 0.003 + (R - cap_r + 0.003) * math.cos(0.5 * math.pi * f),
                    shoulder + (zn - shoulder) * math.sin(0.5 * math.pi * f),
                )
            )
        profile += [(0.0, zn)]
        add(revolve(profile, sections=16), body)
        add(cylinder((0.0, 0.0, 0.0), (0.0, 0.0, 0.022), R + 0.0008, sections=16), cap)
        add(cylinder((0.0, 0.0, zn - 0.004), (0.0, 0.0, cap_top), cap_r, sections=16), cap)
        lr = 0.003
        loop = _arch(0.0, 0.0, cap_top - 0.004, 0.55 * cap_r, h - lr - (cap_top - 0.004))
        add(_sweep(loop, (0.004, lr), (0.0, 1.0, 0.0)), cap)
    return asm


def _takeaway_box(rng: np.random.Generator, size: Size) -> Assembly:
    """A takeaway food box: a hinged clamshell (tray, flange, domed lid, hinge, closing tab) or a kraft
    meal box with a window and a sticker, sometimes with chopsticks in a paper sleeve on top."""
    w, d, h = size
    hy = 0.5 * d
    asm = Assembly()
    if rng.uniform() < 0.5:  # clamshell
        color = pick(rng, ((242, 242, 238), *_KRAFT, (34, 34, 38)), variation=0.03)
        zf = float(rng.uniform(0.4, 0.5)) * h
        rad = float(np.clip(0.12 * min(w, d), 0.01, 0.025))
        bw, bd = w - 0.016, d - 0.016
        tray = rounded_rectangle(0.88 * bw, 0.88 * bd, rad)
        asm.add(extrude(tray, 0.0, zf, scale_top=(1.0 / 0.88, 1.0 / 0.88)), color)
        asm.add(rounded_prism((0.0, 0.0), w, d, rad + 0.006, zf, zf + 0.004), shade(color, 0.95))
        lid = rounded_rectangle(bw, bd, rad)
        asm.add(
            translate(extrude(lid, 0.0, h - zf - 0.004, scale_top=(0.84, 0.82)), (0.0, 0.0, zf + 0.004)),
            color,
        )
        asm.box((-0.015, hy - 0.006, zf - 0.012), (0.015, hy, zf + 0.008), shade(color, 0.9))
        hinge = cylinder(
            (-0.35 * w, -hy + 0.004, zf + 0.002), (0.35 * w, -hy + 0.004, zf + 0.002), 0.004, sections=8
        )
        asm.add(hinge, shade(color, 0.9))
    else:  # kraft meal box
        color = pick(rng, _KRAFT) if rng.uniform() < 0.7 else pick(rng, ((242, 242, 238), (34, 34, 38)))
        sticks = rng.uniform() < 0.5
        lid_top = h - (0.007 if sticks else 0.001)
        body = rounded_rectangle(0.9 * w, 0.9 * d, 0.006)
        asm.add(
            extrude(body, 0.0, lid_top - 0.003, scale_top=(1.0 / 0.9 - 0.004 / w, 1.0 / 0.9 - 0.004 / d)),
            color,
        )
        asm.add(rounded_prism((0.0, 0.0), w, d, 0.006, lid_top - 0.004, lid_top), shade(color, 1.05))
        window = pick(rng, "glass")
        asm.box((-0.25 * w, -0.25 * d, lid_top - 0.002), (0.25 * w, 0.15 * d, lid_top + 0.001), window)
        sticker = pick(rng, "brand")
        sr = 0.07 * min(w, d)
        sx, sy = 0.33 * w, 0.3 * d
        asm.add(cylinder((sx, sy, lid_top - 0.002), (sx, sy, lid_top + 0.001), sr, sections=16), sticker)
        if sticks:
            sl = 0.85 * w
            yc = -0.35 * d
            asm.box((-0.5 * sl, yc - 0.012, lid_top), (0.3 * sl, yc + 0.012, h - 0.0005), (248, 246, 240))
            asm.box((-0.1 * sl, yc - 0.0121, lid_top + 0.001), (0.05 * sl, yc + 0.0121, h), sticker)
            for dy in (-0.005, 0.005):
                asm.add(
                    bar(
                        (0.3 * sl - 0.01, yc + dy, lid_top + 0.0025),
                        (0.5 * sl, yc + dy, lid_top + 0.0025),
                        0.005,
                    ),
                    (214, 182, 130),
                )
    return asm


def _newspaper(rng: np.random.Generator, size: Size) -> Assembly:
    """A folded newspaper lying flat: page block with a rounded fold at -y, an inner section peeking out,
    and a printed front page (masthead, headline, photo, text columns)."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    paper = pick(rng, _NEWSPRINT, variation=0.02)
    ink = 0.0006
    hp = h - ink
    rf = 0.5 * hp
    asm.add(cylinder((-hx, -hy + rf, rf), (hx, -hy + rf, rf), rf, sections=12), shade(paper, 0.96))
    step = float(rng.uniform(0.003, 0.008))
    asm.box((-hx, -hy + rf, 0.0), (hx, hy - step, hp), paper)
    asm.box((-hx + 0.004, -hy + rf, 0.2 * hp), (hx - 0.006, hy, 0.8 * hp), shade(paper, 0.93))
    # front page print
    m = 0.015
    x0, x1 = -hx + m, hx - m
    y_top = hy - step - m
    mast = pick(rng, "brand") if rng.uniform() < 0.4 else _INK
    mast_w = float(rng.uniform(0.55, 0.9)) * (x1 - x0)
    asm.box((-0.5 * mast_w, y_top - 0.035, hp), (0.5 * mast_w, y_top, h), mast)
    asm.box((x0, y_top - 0.043, hp), (x1, y_top - 0.041, h), _INK)
    head_w = float(rng.uniform(0.6, 1.0)) * (x1 - x0)
    asm.box((x0, y_top - 0.07, hp), (x0 + head_w, y_top - 0.052, h), _INK)
    y_col = y_top - 0.08
    y_end = -hy + rf + m
    cols = int(rng.integers(3, 6))
    pitch = (x1 - x0) / cols
    photo = rng.uniform() < 0.75
    pc = int(rng.integers(cols)) if photo else -1
    pspan = min(2, cols - pc) if photo else 0
    for c in range(cols):
        cx0 = x0 + c * pitch + 0.003
        cx1 = cx0 + pitch - 0.006
        yb = y_end
        if pc <= c < pc + pspan:
            py0 = y_col - 0.5 * (y_col - y_end)
            if c == pc:
                px1 = x0 + (pc + pspan) * pitch - 0.003
                tone = pick(
                    rng, ((90, 120, 150), (120, 100, 80), (70, 110, 70), (140, 140, 140)), variation=0.1
                )
                asm.box((cx0, py0, hp), (px1, y_col, h), tone)
            yb_top = py0 - 0.006
            asm.box((cx0, yb, hp), (cx1, yb_top, h - 0.0003), _TEXT)
        else:
            asm.box((cx0, yb, hp), (cx1, y_col, h - 0.0003), _TEXT)
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "briefcase",
        # attaché cases 42-46 x 10-13 x 31-34 cm plus a 3-4.5 cm handle; slim briefs 38 x 8 x 28 cm
        (0.38, 0.08, 0.30),
        (0.46, 0.14, 0.40),
        "surface",
        None,
        0.0,
        "leather",
        _briefcase,
        contexts=("street", "transit", "plaza", "frontage"),
    ),
    Asset(
        "backpack",
        # 20-30 l daypacks: about 30 x 20 x 45 cm
        (0.28, 0.15, 0.40),
        (0.36, 0.26, 0.52),
        "surface",
        None,
        0.0,
        "fabric",
        _backpack,
        contexts=("street", "park", "plaza", "transit"),
    ),
    Asset(
        "suitcase",
        # cabin 40 x 20 x 55 cm to checked 52 x 31 x 80 cm with wheels; an extended handle adds 30-50 cm
        (0.35, 0.20, 0.58),
        (0.52, 0.31, 1.05),
        "floor",
        None,
        0.3,
        "plastic",
        _suitcase,
        contexts=("street", "transit", "plaza", "frontage"),
    ),
    Asset(
        "umbrella",
        # closed stick umbrellas are 82-98 cm long; furled canopy 4.5-7 cm across, crook 10-14 cm wide
        (0.82, 0.10, 0.045),
        (0.98, 0.14, 0.07),
        "surface",
        None,
        0.0,
        "fabric",
        _umbrella,
        contexts=("street", "transit", "plaza", "frontage"),
    ),
    Asset(
        "coffee_cup",
        # 8-16 oz takeaway cups: lid 80-95 mm across, 10-17 cm tall with the lid
        (0.080, 0.080, 0.100),
        (0.095, 0.095, 0.170),
        "surface",
        None,
        0.0,
        "paper",
        _coffee_cup,
        contexts=("street", "park", "plaza", "transit", "frontage"),
    ),
    Asset(
        "notebook",
        # A5 (148 x 210 mm) to A4 (210 x 297 mm), 7-25 mm thick
        (0.145, 0.205, 0.007),
        (0.215, 0.300, 0.025),
        "surface",
        None,
        0.0,
        "paper",
        _notebook,
        contexts=("park", "plaza", "transit", "street"),
    ),
    Asset(
        "shopping_bag",
        # paper carrier bags: 24-44 cm wide, 11-20 cm gusset, 25-44 cm body plus 7-12 cm handles
        (0.24, 0.11, 0.32),
        (0.44, 0.20, 0.56),
        "floor",
        None,
        0.0,
        "paper",
        _shopping_bag,
        contexts=("street", "plaza", "transit", "frontage"),
    ),
    Asset(
        "handbag",
        # totes and satchels: 24-40 cm wide, 9-16 cm deep, 20-36 cm tall with the handles
        (0.24, 0.09, 0.20),
        (0.40, 0.16, 0.36),
        "surface",
        None,
        0.0,
        "leather",
        _handbag,
        contexts=("street", "plaza", "transit", "frontage", "park"),
    ),
    Asset(
        "water_bottle",
        # 0.5 l PET bottle 65 x 205 mm; 0.5-0.75 l reusable flasks 70-78 mm x 22-28 cm
        (0.064, 0.064, 0.19),
        (0.078, 0.078, 0.28),
        "surface",
        None,
        0.0,
        "plastic",
        _water_bottle,
        contexts=("park", "street", "plaza", "transit", "sports"),
    ),
    Asset(
        "takeaway_box",
        # foam and kraft clamshells / meal boxes: 14-24 x 12-22 cm, 5-9 cm tall
        (0.14, 0.12, 0.05),
        (0.24, 0.22, 0.09),
        "surface",
        None,
        0.0,
        "paper",
        _takeaway_box,
        contexts=("park", "plaza", "street", "frontage"),
    ),
    Asset(
        "newspaper",
        # a broadsheet folded in half is about 38 x 29 cm, a folded tabloid 28 x 22 cm; 4-16 mm thick
        (0.28, 0.22, 0.004),
        (0.39, 0.31, 0.016),
        "surface",
        None,
        0.0,
        "paper",
        _newspaper,
        contexts=("transit", "park", "plaza", "street"),
    ),
)
