"""Seating: chair, armchair, sofa, bench, bar stool, office chair and a row of waiting-room seats.

Every seat faces +y: the backrest is at -y, the sitter's legs point to +y.
"""

from __future__ import annotations

import math

import numpy as np

from navverse.assets.fittings import caster, corners, legs
from navverse.assets.materials import pick, shade
from navverse.assets.parts import (
    Assembly,
    align,
    bar,
    cylinder,
    frustum,
    rotate,
    rounded_prism,
    torus,
)
from navverse.assets.spec import Asset, Size

__all__ = ["ASSETS"]


def _chair(rng: np.random.Generator, size: Size) -> Assembly:
    """Four legs, a seat, two back posts and a slatted, railed or panelled backrest."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wood = pick(rng, "wood")
    leg = float(rng.uniform(0.032, 0.042))
    seat_top = float(np.clip(0.48 * h, 0.40, 0.48))
    seat_t = 0.03
    cushion = rng.uniform() < 0.4
    seat_wood_top = seat_top - (0.03 if cushion else 0.0)
    asm.box((-hx, -hy, seat_wood_top - seat_t), (hx, hy, seat_wood_top), wood)
    if cushion:
        asm.add(
            rounded_prism((0.0, 0.01), w - 0.04, d - 0.05, 0.03, seat_wood_top, seat_top), pick(rng, "fabric")
        )
    i = 0.5 * leg
    legs(asm, [(-hx + i, hy - i), (hx - i, hy - i)], 0.0, seat_wood_top - seat_t, leg, wood)
    legs(asm, [(-hx + i, -hy + i), (hx - i, -hy + i)], 0.0, h, leg, wood)
    for x in (-hx + i, hx - i):  # side stretchers
        asm.box((x - 0.01, -hy + leg, 0.14), (x + 0.01, hy - leg, 0.16), wood)
    inner = (-hx + leg, hx - leg)
    y0, y1 = -hy + 0.004, -hy + leg - 0.004
    back_bottom = seat_wood_top + 0.08
    style = int(rng.integers(3))
    asm.box((inner[0], y0, h - 0.09), (inner[1], y1, h - 0.01), wood)  # top rail
    if style == 0:  # vertical slats
        n = int(rng.integers(2, 5))
        xs = np.linspace(inner[0], inner[1], n + 2)[1:-1]
        for x in xs:
            asm.box((x - 0.018, y0, back_bottom), (x + 0.018, y1, h - 0.09), wood)
        asm.box((inner[0], y0, back_bottom - 0.04), (inner[1], y1, back_bottom), wood)
    elif style == 1:  # horizontal rails
        for z in np.linspace(back_bottom, h - 0.15, 2):
            asm.box((inner[0], y0, z), (inner[1], y1, z + 0.05), wood)
    else:  # upholstered panel
        asm.box((inner[0], y0 - 0.002, back_bottom), (inner[1], y1 + 0.01, h - 0.09), pick(rng, "fabric"))
    return asm


def _upholstered(rng: np.random.Generator, size: Size, seats: int) -> Assembly:
    """Armchair or sofa: base, arms (rolled or square), back, seat and back cushions, short legs."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    cover = pick(rng, "leather") if rng.uniform() < 0.25 else pick(rng, "fabric")
    cushion = shade(cover, 1.06)
    leg_h = float(rng.uniform(0.05, 0.12))
    base_top = leg_h + 0.2
    seat_top = float(np.clip(base_top + 0.15, 0.38, 0.48))
    arm_w = float(np.clip(0.12 * w / seats + 0.05, 0.1, 0.2))
    arm_top = min(seat_top + 0.2, h - 0.12)
    back_t = float(np.clip(0.2 * d, 0.14, 0.22))
    legs(asm, corners(w, d, 0.06), 0.0, leg_h, 0.045, pick(rng, "dark_wood"), round_legs=rng.uniform() < 0.5)
    asm.box((-hx, -hy, leg_h), (hx, hy, base_top), cover)
    asm.box((-hx, -hy, base_top - 0.01), (hx, -hy + back_t, h), cover)
    rolled = rng.uniform() < 0.5
    for sx in (-1.0, 1.0):
        x_out, x_in = sx * hx, sx * (hx - arm_w)
        lo_x, hi_x = min(x_out, x_in), max(x_out, x_in)
        if rolled:
            r = 0.5 * arm_w
            asm.box((lo_x, -hy, base_top - 0.01), (hi_x, hy, arm_top - r), cover)
            xc = 0.5 * (lo_x + hi_x)
            asm.add(cylinder((xc, -hy, arm_top - r), (xc, hy, arm_top - r), r, sections=12), cover)
        else:
            asm.box((lo_x, -hy, base_top - 0.01), (hi_x, hy, arm_top), cover)
    inner = w - 2.0 * arm_w
    pitch = inner / seats
    for k in range(seats):
        cx = -0.5 * inner + (k + 0.5) * pitch
        asm.add(
            rounded_prism((cx, 0.5 * back_t), pitch - 0.01, d - back_t - 0.01, 0.04, base_top, seat_top),
            cushion,
        )
        cushion_top = min(h - 0.04, seat_top + 0.75 * (h - seat_top))
        pillow = bar(
            (cx, -hy + back_t + 0.09, seat_top + 0.08),
            (cx, -hy + back_t + 0.05, cushion_top - 0.05),
            (pitch - 0.03, 0.1, 0.1),
        )
        asm.add(pillow, cushion)
    return asm


def _armchair(rng: np.random.Generator, size: Size) -> Assembly:
    return _upholstered(rng, size, 1)


def _sofa(rng: np.random.Generator, size: Size) -> Assembly:
    return _upholstered(rng, size, 2 if size[0] < 1.9 else 3)


def _bench(rng: np.random.Generator, size: Size) -> Assembly:
    """Seat slats on two trestles joined by a stretcher."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wood = pick(rng, "wood")
    frame = pick(rng, "dark_metal") if rng.uniform() < 0.5 else shade(wood, 0.8)
    slats = int(rng.integers(3, 6))
    gap = 0.012
    width = (d - (slats - 1) * gap) / slats
    for k in range(slats):
        y0 = -hy + k * (width + gap)
        asm.box((-hx, y0, h - 0.035), (hx, y0 + width, h), wood)
    for x in (-hx + 0.12, hx - 0.12):
        asm.box((x - 0.025, -hy + 0.03, h - 0.085), (x + 0.025, hy - 0.03, h - 0.035), frame)
        for y in (-hy + 0.05, hy - 0.05):
            asm.box((x - 0.025, y - 0.025, 0.0), (x + 0.025, y + 0.025, h - 0.085), frame)
        asm.box((x - 0.02, -hy + 0.05, 0.1), (x + 0.02, hy - 0.05, 0.14), frame)
    asm.box((-hx + 0.12, -0.02, 0.1), (hx - 0.12, 0.02, 0.14), frame)
    return asm


def _bar_stool(rng: np.random.Generator, size: Size) -> Assembly:
    """Round seat (sometimes with a low back) on a pole with a footrest ring and a round base."""
    w, d, h = size
    rx, ry = 0.5 * w, 0.5 * d
    asm = Assembly()
    metal = pick(rng, "chrome") if rng.uniform() < 0.5 else pick(rng, "dark_metal")
    seat_color = pick(rng, "leather") if rng.uniform() < 0.5 else pick(rng, "wood")
    with_back = h >= 0.86  # a counter-height seat with a low back; lower stools have none
    seat_top = h - 0.2 if with_back else h
    asm.add(
        frustum((0, 0, seat_top - 0.06), (0, 0, seat_top), (0.92 * rx, 0.92 * ry), (rx, ry), sections=20),
        seat_color,
    )
    asm.add(cylinder((0, 0, 0.02), (0, 0, seat_top - 0.06), 0.028, sections=12), metal)
    asm.add(
        frustum((0, 0, 0), (0, 0, 0.03), (0.78 * rx, 0.78 * ry), (0.7 * rx, 0.7 * ry), sections=20), metal
    )
    ring_r = 0.68 * min(rx, ry)
    ring_z = float(np.clip(0.42 * seat_top, 0.25, 0.35))
    asm.add(torus((0, 0, ring_z), ring_r, 0.012, sections=20, tube=6), metal)
    for k in range(3):
        a = 2.0 * math.pi * k / 3 + 0.5 * math.pi
        asm.add(bar((0, 0, ring_z), (ring_r * math.cos(a), ring_r * math.sin(a), ring_z), 0.016), metal)
    if with_back:
        for sx in (-1.0, 1.0):
            asm.add(
                bar(
                    (sx * 0.6 * rx, -0.75 * ry, seat_top - 0.02), (sx * 0.6 * rx, -0.85 * ry, h - 0.08), 0.02
                ),
                metal,
            )
        asm.add(bar((0, -0.86 * ry, h - 0.05), (0, -0.86 * ry, h - 0.05), (1.5 * rx, 0.03, 0.1)), seat_color)
    return asm


def _office_chair(rng: np.random.Generator, size: Size) -> Assembly:
    """Five-star base on casters, gas lift, padded seat, reclined backrest and (usually) armrests."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    shell = pick(rng, "dark_plastic")
    pad = pick(rng, "fabric") if rng.uniform() < 0.7 else pick(rng, "leather")
    metal = pick(rng, "chrome") if rng.uniform() < 0.4 else shell
    arms = rng.uniform() < 0.75
    seat_top = float(np.clip(0.44 * h, 0.44, 0.52))
    seat_w = w - 0.16 if arms else w
    # base: five arms, casters at their tips
    star = min(0.45 * min(w, d), 0.33)
    hub_z = 0.1
    for k in range(5):
        a = 0.5 * math.pi + 2.0 * math.pi * k / 5
        tip = (star * math.cos(a), star * math.sin(a))
        asm.add(bar((0, 0, hub_z), (tip[0], tip[1], hub_z - 0.02), (0.04, 0.04, 0.03)), metal)
        caster(asm, tip[0], tip[1], 0.025, shell, shell)
    asm.add(cylinder((0, 0, 0.06), (0, 0, 0.3), 0.035, sections=12), shell)
    asm.add(cylinder((0, 0, 0.3), (0, 0, seat_top - 0.09), 0.022, sections=12), pick(rng, "chrome"))
    asm.box((-0.12, -0.12, seat_top - 0.11), (0.12, 0.12, seat_top - 0.08), shell)
    seat_y0 = -hy + 0.1
    asm.add(
        rounded_prism((0.0, 0.5 * (seat_y0 + hy)), seat_w, hy - seat_y0, 0.06, seat_top - 0.08, seat_top), pad
    )
    # backrest: a padded panel tilted back, its back edge at y = -hy, its top at z = h
    back_w = min(seat_w - 0.04, 0.5)
    back_h = h - seat_top - 0.08
    panel = rotate(rounded_prism((0.0, 0.0), back_w, back_h, 0.08, 0.0, 0.06), "x", 0.5 * math.pi)
    panel = rotate(panel, "x", math.radians(10.0))
    panel = align(panel, y_min=-hy, z_max=h)
    asm.add(panel, pad)
    asm.add(
        bar((0, seat_y0 + 0.05, seat_top - 0.1), (0, -hy + 0.07, seat_top + 0.15), (0.06, 0.025, 0.025)),
        shell,
    )
    if arms:
        for sx in (-1.0, 1.0):
            x = sx * (hx - 0.035)
            asm.add(
                bar((sx * (0.5 * seat_w - 0.02), 0.0, seat_top - 0.06), (x, 0.0, seat_top + 0.18), 0.03),
                shell,
            )
            asm.box((x - 0.035, -0.14, seat_top + 0.18), (x + 0.035, 0.12, seat_top + 0.21), shell)
    return asm


def _seat_row(rng: np.random.Generator, size: Size) -> Assembly:
    """Waiting-room seating: two to four moulded seats on a beam with leg frames and armrests."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    frame = pick(rng, "metal")
    shell = pick(rng, "plastic") if rng.uniform() < 0.6 else pick(rng, "fabric")
    n = max(2, round(w / 0.6))
    pitch = (w - 0.05) / n
    beam_z = 0.32
    asm.box((-hx + 0.05, -0.03, beam_z - 0.06), (hx - 0.05, 0.03, beam_z), frame)
    for x in (-hx + 0.25, hx - 0.25):
        asm.box((x - 0.025, -0.025, 0.03), (x + 0.025, 0.025, beam_z), frame)
        asm.box((x - 0.03, -hy + 0.05, 0.0), (x + 0.03, hy - 0.05, 0.03), frame)
    seat_top = 0.45
    for k in range(n):
        cx = -hx + 0.025 + (k + 0.5) * pitch
        asm.add(rounded_prism((cx, 0.06), pitch - 0.07, d - 0.12, 0.05, seat_top - 0.04, seat_top), shell)
        back = bar(
            (cx, -hy + 0.09, seat_top + 0.05), (cx, -hy + 0.015, h - 0.035), (pitch - 0.09, 0.03, 0.07)
        )
        asm.add(back, shell)
        asm.box((cx - 0.03, -0.08, beam_z), (cx + 0.03, 0.08, seat_top - 0.04), frame)
    for k in range(n + 1):
        x = float(np.clip(-hx + 0.025 + k * pitch, -hx + 0.025, hx - 0.025))
        asm.box((x - 0.012, 0.0, beam_z), (x + 0.012, 0.03, 0.62), frame)
        asm.box((x - 0.025, -0.15, 0.62), (x + 0.025, 0.2, 0.65), shade(frame, 0.6))
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "chair",
        (0.40, 0.44, 0.78),
        (0.50, 0.56, 1.00),
        "floor",
        None,
        0.5,
        "wood",
        _chair,
        contexts=("home", "office", "school", "cafe"),
    ),
    Asset(
        "armchair",
        (0.70, 0.75, 0.75),
        (0.95, 0.95, 1.00),
        "floor",
        None,
        0.6,
        "fabric",
        _armchair,
        contexts=("home", "office", "hospital", "cafe"),
    ),
    Asset(
        "sofa",
        (1.50, 0.80, 0.75),
        (2.40, 1.00, 0.95),
        "wall",
        None,
        0.7,
        "fabric",
        _sofa,
        contexts=("home", "office"),
    ),
    Asset(
        "bench",
        (1.00, 0.34, 0.42),
        (1.80, 0.46, 0.48),
        "floor",
        None,
        0.5,
        "wood",
        _bench,
        contexts=("home", "school", "hospital", "retail"),
    ),
    Asset(
        "bar_stool",
        (0.34, 0.34, 0.62),
        (0.44, 0.44, 1.00),
        "floor",
        None,
        0.4,
        "metal",
        _bar_stool,
        contexts=("cafe", "home"),
    ),
    Asset(
        "office_chair",
        (0.58, 0.58, 0.90),
        (0.70, 0.70, 1.20),
        "floor",
        None,
        0.5,
        "fabric",
        _office_chair,
        contexts=("office", "school", "hospital"),
    ),
    Asset(
        "seat_row",
        (1.10, 0.55, 0.78),
        (2.50, 0.68, 0.86),
        "wall",
        None,
        0.7,
        "plastic",
        _seat_row,
        contexts=("hospital", "office", "retail", "school"),
    ),
)
