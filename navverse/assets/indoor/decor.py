"""Decor: table and floor lamps, potted plants, rugs, curtains, vases, book stacks, wall clocks and pictures.

Wall-mounted items (curtain, clock, picture) have their backs at -y and face +y.
"""

from __future__ import annotations

import math

import numpy as np

from navverse.assets.materials import RGB, pick, shade
from navverse.assets.parts import (
    Assembly,
    Solid,
    bar,
    cylinder,
    difference,
    ellipsoid,
    frustum,
    hull,
    revolve,
    torus,
)
from navverse.assets.spec import Asset, Size

__all__ = ["ASSETS"]

_WARM_LIGHT: RGB = (252, 240, 200)


def _lampshade(rx: float, ry: float, z0: float, z1: float, color: RGB, asm: Assembly) -> None:
    """A hollow, open drum shade (outer frustum minus a longer inner one) with a bulb inside."""
    outer = frustum((0, 0, z0), (0, 0, z1), (rx, ry), (0.72 * rx, 0.72 * ry), sections=20)
    inner = frustum(
        (0, 0, z0 - 0.01),
        (0, 0, z1 + 0.01),
        (rx - 0.006, ry - 0.006),
        (0.72 * rx - 0.006, 0.72 * ry - 0.006),
        sections=20,
    )
    asm.add(difference(outer, inner), color)
    bulb_r = 0.25 * min(rx, ry)
    asm.add(
        ellipsoid((0, 0, z0 + 0.45 * (z1 - z0)), (bulb_r, bulb_r, 1.2 * bulb_r), segments=12, rings=6),
        _WARM_LIGHT,
    )


def _lamp(rng: np.random.Generator, size: Size) -> Assembly:
    """A table lamp: a turned or disc base, a stem and an open drum shade."""
    w, d, h = size
    rx, ry = 0.5 * w, 0.5 * d
    asm = Assembly()
    base_color = pick(rng, "ceramic" if rng.uniform() < 0.5 else "brass")
    shade_h = 0.4 * h
    stem_top = h - 0.5 * shade_h
    r = 0.5 * min(rx, ry)
    if rng.uniform() < 0.5:
        body_h = 0.45 * h
        profile = [(0.0, 0.0), (0.6 * r, 0.0), (r, 0.4 * body_h), (0.35 * r, body_h), (0.0, body_h)]
        asm.add(revolve(profile, sections=16), base_color)
    else:
        asm.add(frustum((0, 0, 0), (0, 0, 0.03), r, 0.85 * r, sections=16), base_color)
    asm.add(cylinder((0, 0, 0.02), (0, 0, stem_top), 0.01, sections=8), pick(rng, "chrome"))
    _lampshade(rx, ry, h - shade_h, h, pick(rng, "fabric" if rng.uniform() < 0.5 else "paper"), asm)
    return asm


def _floor_lamp(rng: np.random.Generator, size: Size) -> Assembly:
    """A floor lamp: heavy disc base, tall pole and a drum shade or an uplighter bowl."""
    w, d, h = size
    rx, ry = 0.5 * w, 0.5 * d
    asm = Assembly()
    metal = pick(rng, "dark_metal") if rng.uniform() < 0.5 else pick(rng, "brass")
    asm.add(
        frustum((0, 0, 0), (0, 0, 0.03), (0.65 * rx, 0.65 * ry), (0.6 * rx, 0.6 * ry), sections=20), metal
    )
    if rng.uniform() < 0.6:
        shade_h = float(np.clip(0.2 * h, 0.25, 0.4))
        asm.add(cylinder((0, 0, 0.02), (0, 0, h - 0.5 * shade_h), 0.013, sections=8), metal)
        _lampshade(rx, ry, h - shade_h, h, pick(rng, "fabric" if rng.uniform() < 0.5 else "paper"), asm)
    else:
        asm.add(cylinder((0, 0, 0.02), (0, 0, h - 0.12), 0.013, sections=8), metal)
        bowl = frustum((0, 0, h - 0.13), (0, 0, h), (0.25 * rx, 0.25 * ry), (rx, ry), sections=20)
        cavity = frustum(
            (0, 0, h - 0.08), (0, 0, h + 0.01), (0.3 * rx, 0.3 * ry), (rx - 0.01, ry - 0.01), sections=20
        )
        asm.add(difference(bowl, cavity), metal)
        asm.add(cylinder((0, 0, h - 0.085), (0, 0, h - 0.075), 0.32 * min(rx, ry), sections=12), _WARM_LIGHT)
    return asm


def _leaf(base: np.ndarray, tip: np.ndarray, width: float) -> Solid:
    """A thin lance-shaped leaf from `base` to `tip` (a convex hull of its outline, 8 mm thick)."""
    direction = (tip - base) / np.linalg.norm(tip - base)
    horizontal = np.array([-direction[1], direction[0], 0.0])
    if np.linalg.norm(horizontal) < 1e-6:
        horizontal = np.array([1.0, 0.0, 0.0])
    horizontal /= np.linalg.norm(horizontal)
    normal = np.cross(direction, horizontal)
    mid = base + 0.45 * (tip - base)
    points = []
    for t in (-0.004, 0.004):
        points += [
            base + 0.2 * width * horizontal + t * normal,
            base - 0.2 * width * horizontal + t * normal,
            mid + 0.5 * width * horizontal + t * normal,
            mid - 0.5 * width * horizontal + t * normal,
            tip + t * normal,
        ]
    return hull(points)


def _potted_plant(rng: np.random.Generator, size: Size) -> Assembly:
    """A pot with soil and a bushy, tree-like or spiky (leaf blades) plant."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    pot_color = pick(rng, "pot")
    greens = [pick(rng, "foliage") for _ in range(3)]
    r_top = min(0.22, 0.38 * min(w, d))
    pot_h = float(np.clip(0.3 * h, 0.18, 0.45))
    profile = [
        (0.0, 0.0),
        (0.75 * r_top, 0.0),
        (r_top, pot_h - 0.03),
        (r_top + 0.012, pot_h - 0.03),
        (r_top + 0.012, pot_h),
        (0.0, pot_h),
    ]
    pot = difference(
        revolve(profile, sections=20),
        cylinder((0, 0, pot_h - 0.04), (0, 0, pot_h + 0.01), r_top - 0.01, sections=20),
    )
    asm.add(pot, pot_color)
    asm.add(
        cylinder((0, 0, pot_h - 0.05), (0, 0, pot_h - 0.035), r_top - 0.005, sections=20), pick(rng, "soil")
    )
    style = int(rng.integers(3))
    if style == 2 and h < 0.5:
        style = 0
    if style == 0:  # bush: a crown ellipsoid and smaller clumps inside its box
        rz = 0.5 * (h - pot_h) + 0.04
        asm.add(ellipsoid((0, 0, h - rz), (hx, hy, rz), segments=12, rings=6), greens[0])
        for k in range(int(rng.integers(3, 7))):
            s = float(rng.uniform(0.4, 0.6))
            cx, cy = rng.uniform(-1.0, 1.0, 2) * (1.0 - s) * np.array([hx, hy])
            cz = h - rz + float(rng.uniform(-0.2, 0.6)) * rz * (1.0 - s)
            asm.add(ellipsoid((cx, cy, cz), (s * hx, s * hy, s * rz), segments=8, rings=4), greens[1 + k % 2])
    elif style == 1:  # tree: trunk and a crown
        crown = 0.28 * h
        asm.add(cylinder((0, 0, pot_h - 0.05), (0, 0, h - crown), 0.02, sections=8), pick(rng, "bark"))
        asm.add(ellipsoid((0, 0, h - crown), (hx, hy, crown), segments=12, rings=6), greens[0])
        for k in range(3):
            a = 2.0 * math.pi * k / 3 + float(rng.uniform(0, 1))
            c = (0.4 * hx * math.cos(a), 0.4 * hy * math.sin(a), h - crown - 0.2 * crown)
            asm.add(ellipsoid(c, (0.5 * hx, 0.5 * hy, 0.5 * crown), segments=8, rings=4), greens[1 + k % 2])
    else:  # leaf blades; four reach the sides and one the top, so the plant fills its box
        base_z = pot_h - 0.04
        ends = [
            (hx - 0.005, 0.0, 0.75),
            (0.0, hy - 0.005, 0.8),
            (-hx + 0.005, 0.0, 0.7),
            (0.0, -hy + 0.005, 0.85),
        ]
        for x, y, f in ends:
            tip = np.array([x, y, base_z + f * (h - base_z)])
            asm.add(_leaf(np.array([0.2 * x, 0.2 * y, base_z]), tip, 0.06), greens[0])
        asm.add(_leaf(np.array([0.0, 0.0, base_z]), np.array([0.0, 0.0, h]), 0.06), greens[1])
        for _ in range(int(rng.integers(4, 9))):
            a = float(rng.uniform(0, 2 * math.pi))
            f = float(rng.uniform(0.3, 0.8))
            tip = np.array(
                [
                    f * hx * math.cos(a),
                    f * hy * math.sin(a),
                    base_z + float(rng.uniform(0.5, 0.95)) * (h - base_z),
                ]
            )
            asm.add(
                _leaf(np.array([0.1 * tip[0], 0.1 * tip[1], base_z]), tip, 0.05), greens[int(rng.integers(3))]
            )
    return asm


def _rug(rng: np.random.Generator, size: Size) -> Assembly:
    """A flat rug: a field, a border band, a medallion or stripes, and fringes at both ends."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    field = pick(rng, "fabric")
    border = pick(rng, "accent") if rng.uniform() < 0.5 else shade(field, 0.6)
    fringe = 0.04
    x0, x1 = -hx + fringe, hx - fringe
    asm.box((x0, -hy, 0.0), (x1, hy, 0.85 * h), field)
    band = float(np.clip(0.07 * min(w, d), 0.05, 0.15))
    asm.box((x0, -hy, 0.0), (x1, -hy + band, h), border)
    asm.box((x0, hy - band, 0.0), (x1, hy, h), border)
    asm.box((x0, -hy + band, 0.0), (x0 + band, hy - band, h), border)
    asm.box((x1 - band, -hy + band, 0.0), (x1, hy - band, h), border)
    motif = pick(rng, "accent")
    if rng.uniform() < 0.5:
        asm.add(
            frustum((0, 0, 0.0), (0, 0, h), (0.22 * w, 0.22 * d), (0.22 * w, 0.22 * d), sections=24), motif
        )
    else:
        n = int(rng.integers(2, 5))
        for k in range(n):
            x = x0 + band + (k + 1) * (x1 - x0 - 2 * band) / (n + 1)
            asm.box((x - 0.03, -hy + 2 * band, 0.0), (x + 0.03, hy - 2 * band, h), motif)
    for x in (-hx, hx - fringe - 0.01):
        asm.box((x, -hy + 0.02, 0.0), (x + fringe + 0.01, hy - 0.02, 0.4 * h), (236, 228, 210))
    return asm


def _curtain(rng: np.random.Generator, size: Size) -> Assembly:
    """A curtain rod with finials and brackets, two pleated drapes drawn aside, sometimes a sheer between."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    fabric = pick(rng, "fabric")
    metal = pick(rng, "dark_metal") if rng.uniform() < 0.5 else pick(rng, "brass")
    rod_y = -hy + 0.04
    rod_z = h - 0.025
    asm.add(cylinder((-hx + 0.04, rod_y, rod_z), (hx - 0.04, rod_y, rod_z), 0.012, sections=12), metal)
    for sx in (-1.0, 1.0):
        asm.add(
            ellipsoid((sx * (hx - 0.025), rod_y, rod_z), (0.025, 0.025, 0.025), segments=8, rings=4), metal
        )
        asm.box(
            (sx * (hx - 0.12) - 0.01, -hy, rod_z - 0.03),
            (sx * (hx - 0.12) + 0.01, rod_y, rod_z + 0.01),
            metal,
        )
    if rng.uniform() < 0.5:
        asm.box((-hx + 0.1, rod_y + 0.02, 0.05), (hx - 0.1, rod_y + 0.026, h - 0.06), (244, 242, 236))
    panel_w = float(rng.uniform(0.22, 0.4)) * w
    folds = max(4, round(panel_w / 0.08))
    fold_w = panel_w / folds
    for sx in (-1.0, 1.0):
        for k in range(folds):
            x_out = sx * (hx - 0.03 - k * fold_w)
            xc = x_out - sx * 0.5 * fold_w
            yc = hy - 0.03 if k % 2 == 0 else hy - 0.055
            part = frustum(
                (xc, yc, 0.0),
                (xc, yc, h - 0.05),
                (0.5 * fold_w + 0.01, 0.03),
                (0.5 * fold_w + 0.01, 0.03),
                sections=8,
            )
            asm.add(part, shade(fabric, 1.0 if k % 2 == 0 else 0.9))
    return asm


def _vase(rng: np.random.Generator, size: Size) -> Assembly:
    """A turned vase with an opening, sometimes holding a few flowers."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    flowers = rng.uniform() < 0.5
    body_h = 0.6 * h if flowers else h
    belly = float(rng.uniform(0.3, 0.6))
    neck = float(rng.uniform(0.35, 0.6))
    profile = [
        (0.0, 0.0),
        (0.6, 0.0),
        (1.0, belly * body_h),
        (neck, 0.88 * body_h),
        (neck + 0.08, body_h),
        (0.0, body_h),
    ]
    scaled = [(r * min(hx, hy), z) for r, z in profile]
    body = revolve(scaled, sections=20)
    opening = cylinder((0, 0, 0.5 * body_h), (0, 0, body_h + 0.01), 0.7 * neck * min(hx, hy), sections=20)
    vertices, faces = difference(body, opening)
    vertices = vertices * np.array([hx / min(hx, hy), hy / min(hx, hy), 1.0])
    color = pick(rng, "pot") if rng.uniform() < 0.5 else pick(rng, "accent")
    asm.add((vertices, faces), color)
    base = frustum((0, 0, 0), (0, 0, 0.012), (0.62 * hx, 0.62 * hy), (0.6 * hx, 0.6 * hy), sections=20)
    asm.add(base, shade(color, 0.7))
    band_r = neck * min(hx, hy)
    band = torus((0, 0, 0.88 * body_h), band_r, min(0.006, 0.1 * band_r), sections=20, tube=4)
    asm.add((band[0] * np.array([hx / min(hx, hy), hy / min(hx, hy), 1.0]), band[1]), shade(color, 1.3))
    if flowers:
        stem = pick(rng, "foliage")
        bloom = pick(rng, "accent")
        r = min(0.03, 0.3 * min(hx, hy))
        count = int(rng.integers(3, 6))
        for k in range(count):
            a = 2.0 * math.pi * k / count
            f = 0.0 if k == 0 else float(rng.uniform(0.3, 0.7))
            x, y = f * (hx - r) * math.cos(a), f * (hy - r) * math.sin(a)
            top = h - r if k == 0 else float(rng.uniform(0.8, 0.95)) * h
            asm.add(bar((0.0, 0.0, 0.6 * body_h), (x, y, top), 0.006), stem)
            asm.add(ellipsoid((x, y, top), (r, r, r), segments=8, rings=4), bloom)
    return asm


def _book_stack(rng: np.random.Generator, size: Size) -> Assembly:
    """Two to eight books lying flat, each with boards, a spine and a cream page block."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    n = int(np.clip(round(h / 0.035), 2, 8))
    thickness = rng.uniform(0.7, 1.3, n)
    thickness = thickness / thickness.sum() * h
    z = 0.0
    for k in range(n):
        bw = w if k == 0 else w * float(rng.uniform(0.75, 1.0))
        bd = d if k == 0 else d * float(rng.uniform(0.75, 1.0))
        cx = float(rng.uniform(-hx + 0.5 * bw, hx - 0.5 * bw)) if k else 0.0
        cy = float(rng.uniform(-hy + 0.5 * bd, hy - 0.5 * bd)) if k else 0.0
        t = float(thickness[k])
        cover = pick(rng, "book")
        x0, x1, y0, y1 = cx - 0.5 * bw, cx + 0.5 * bw, cy - 0.5 * bd, cy + 0.5 * bd
        board = min(0.003, 0.2 * t)
        asm.box((x0, y0, z), (x1, y1, z + board), cover)
        asm.box((x0, y0, z + t - board), (x1, y1, z + t), cover)
        spine_left = rng.uniform() < 0.5
        sx0, sx1 = (x0, x0 + 0.006) if spine_left else (x1 - 0.006, x1)
        asm.box((sx0, y0, z + board), (sx1, y1, z + t - board), shade(cover, 0.85))
        px0, px1 = (x0 + 0.006, x1 - 0.004) if spine_left else (x0 + 0.004, x1 - 0.006)
        asm.box((px0, y0 + 0.004, z + board), (px1, y1 - 0.004, z + t - board), (240, 234, 214))
        z += t
    return asm


def _wall_clock(rng: np.random.Generator, size: Size) -> Assembly:
    """A round wall clock: rim with a recessed face, twelve hour marks, two hands and a centre cap."""
    w, d, h = size
    hx, hy, hz = 0.5 * w, 0.5 * d, 0.5 * h
    asm = Assembly()
    rim_color = pick(rng, "dark_plastic") if rng.uniform() < 0.5 else pick(rng, "wood")
    recess = frustum(
        (0, hy - 0.01, hz), (0, hy + 0.01, hz), (0.88 * hx, 0.88 * hz), (0.88 * hx, 0.88 * hz), sections=24
    )
    asm.add(difference(_elliptic_disc(hx, hz, -hy, hy, hz), recess), rim_color)
    face_y = hy - 0.009
    asm.add(
        frustum(
            (0, -hy + 0.005, hz), (0, face_y, hz), (0.88 * hx, 0.88 * hz), (0.88 * hx, 0.88 * hz), sections=24
        ),
        (248, 246, 240),
    )
    for k in range(12):
        a = 2.0 * math.pi * k / 12
        x, z = 0.75 * hx * math.sin(a), hz + 0.75 * hz * math.cos(a)
        size_mark = 0.012 if k % 3 == 0 else 0.007
        asm.box(
            (x - size_mark, face_y, z - size_mark),
            (x + size_mark, face_y + 0.002, z + size_mark),
            (30, 30, 32),
        )
    for length, angle in (
        (0.45, float(rng.uniform(0, 2 * math.pi))),
        (0.7, float(rng.uniform(0, 2 * math.pi))),
    ):
        tip = (length * hx * math.sin(angle), face_y + 0.004, hz + length * hz * math.cos(angle))
        asm.add(bar((0.0, face_y + 0.004, hz), tip, (0.01, 0.002, 0.01)), (20, 20, 22))
    asm.add(cylinder((0.0, face_y, hz), (0.0, face_y + 0.007, hz), 0.01, sections=8), (20, 20, 22))
    return asm


def _elliptic_disc(rx: float, rz: float, y0: float, y1: float, zc: float) -> Solid:
    """A disc with its axis along y, radius `rx` along x and `rz` along z."""
    return frustum((0.0, y0, zc), (0.0, y1, zc), (rx, rz), (rx, rz), sections=24)


def _picture_frame(rng: np.random.Generator, size: Size) -> Assembly:
    """A framed picture: moulding, optional mat, and an abstract or landscape image in coloured blocks."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    frame = pick(rng, "wood") if rng.uniform() < 0.6 else pick(rng, "dark_metal")
    b = float(np.clip(0.06 * min(w, h), 0.02, 0.06))
    asm.box((-hx, -hy, h - b), (hx, hy, h), frame)
    asm.box((-hx, -hy, 0.0), (hx, hy, b), frame)
    asm.box((-hx, -hy, b), (-hx + b, hy, h - b), frame)
    asm.box((hx - b, -hy, b), (hx, hy, h - b), frame)
    face = hy - 0.008
    asm.box((-hx + b, -hy, b), (hx - b, face, h - b), (244, 242, 236))
    m = b * (1.5 if rng.uniform() < 0.5 else 0.3)
    x0, x1, z0, z1 = -hx + b + m, hx - b - m, b + m, h - b - m
    art = face + 0.001
    if rng.uniform() < 0.5:  # landscape: sky, hills, sun
        horizon = z0 + float(rng.uniform(0.35, 0.6)) * (z1 - z0)
        asm.box((x0, face, horizon), (x1, art, z1), (150, 190, 230))
        asm.box((x0, face, z0), (x1, art, horizon), pick(rng, "foliage"))
        sun_r = 0.12 * min(x1 - x0, z1 - z0)
        sx, sz = x0 + 0.75 * (x1 - x0), horizon + 0.6 * (z1 - horizon)
        asm.add(cylinder((sx, art, sz), (sx, art + 0.001, sz), sun_r, sections=16), (250, 210, 80))
    else:  # abstract blocks
        asm.box((x0, face, z0), (x1, art, z1), pick(rng, "painted"))
        for _ in range(int(rng.integers(2, 5))):
            bx0 = float(rng.uniform(x0, x1 - 0.05))
            bz0 = float(rng.uniform(z0, z1 - 0.05))
            bx1 = float(rng.uniform(bx0 + 0.03, x1))
            bz1 = float(rng.uniform(bz0 + 0.03, z1))
            asm.box((bx0, art, bz0), (bx1, art + 0.001, bz1), pick(rng, "accent"))
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "lamp",
        (0.20, 0.20, 0.30),
        (0.45, 0.45, 0.70),
        "surface",
        None,
        0.0,
        "fabric",
        _lamp,
        contexts=("home", "office", "hospital", "cafe"),
    ),
    Asset(
        "floor_lamp",
        (0.30, 0.30, 1.40),
        (0.50, 0.50, 1.85),
        "floor",
        None,
        0.0,
        "metal",
        _floor_lamp,
        contexts=("home", "office", "cafe"),
    ),
    Asset(
        "potted_plant",
        (0.30, 0.30, 0.40),
        (0.80, 0.80, 1.80),
        "floor",
        None,
        0.0,
        "plant",
        _potted_plant,
        contexts=("home", "office", "school", "retail", "hospital", "cafe"),
    ),
    Asset(
        "rug",
        (1.20, 0.80, 0.008),
        (3.00, 2.20, 0.02),
        "floor",
        None,
        0.0,
        "fabric",
        _rug,
        contexts=("home", "office", "cafe"),
    ),
    Asset(
        "curtain",
        (1.20, 0.08, 1.50),
        (3.00, 0.16, 2.50),
        "wall_mounted",
        (0.02, 0.30),
        0.0,
        "fabric",
        _curtain,
        contexts=("home", "hospital", "office", "cafe"),
    ),
    Asset(
        "vase",
        (0.10, 0.10, 0.20),
        (0.30, 0.30, 0.60),
        "surface",
        None,
        0.0,
        "ceramic",
        _vase,
        contexts=("home", "office", "cafe", "hospital"),
    ),
    Asset(
        "book_stack",
        (0.15, 0.20, 0.05),
        (0.32, 0.42, 0.30),
        "surface",
        None,
        0.0,
        "paper",
        _book_stack,
        contexts=("home", "office", "school"),
    ),
    Asset(
        "wall_clock",
        (0.25, 0.04, 0.25),
        (0.45, 0.07, 0.45),
        "wall_mounted",
        (1.60, 2.00),
        0.0,
        "plastic",
        _wall_clock,
        contexts=("home", "office", "school", "hospital", "cafe", "retail"),
    ),
    Asset(
        "picture_frame",
        (0.30, 0.02, 0.30),
        (1.20, 0.05, 0.90),
        "wall_mounted",
        (1.20, 1.70),
        0.0,
        "wood",
        _picture_frame,
        contexts=("home", "office", "hospital", "cafe"),
    ),
)
