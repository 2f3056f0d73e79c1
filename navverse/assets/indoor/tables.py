"""Tables and desks: dining, coffee and cafe tables, desks, school desks, reception desks and lecterns.

The user's side (where the chair goes, where visitors stand at a reception desk) faces +y.
"""

from __future__ import annotations

import math

import numpy as np

from navverse.assets.fittings import FRONT_THICKNESS, HANDLE_DEPTH, corners, drawer_fronts, legs
from navverse.assets.materials import pick, shade
from navverse.assets.parts import Assembly, bar, cylinder, frustum, hull, rounded_prism
from navverse.assets.spec import Asset, Size, SupportArea, top_support

__all__ = ["ASSETS"]


def _dining_table(rng: np.random.Generator, size: Size) -> Assembly:
    """A top (square or rounded corners) on four legs joined by an apron."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wood = pick(rng, "wood")
    top_t = float(rng.uniform(0.028, 0.05))
    radius = float(rng.choice([0.005, 0.05, 0.12]))
    asm.add(rounded_prism((0.0, 0.0), w, d, radius, h - top_t, h), wood)
    leg_color = wood if rng.uniform() < 0.7 else pick(rng, "dark_metal")
    leg_t = float(rng.uniform(0.05, 0.08))
    inset = 0.06 + 0.5 * leg_t
    legs(
        asm,
        corners(w, d, inset),
        0.0,
        h - top_t,
        leg_t,
        leg_color,
        round_legs=rng.uniform() < 0.4,
        taper=0.65,
    )
    apron_z = h - top_t - 0.09
    xi, yi = hx - inset, hy - inset
    for y in (-yi, yi):
        asm.box((-xi, y - 0.01, apron_z), (xi, y + 0.01, h - top_t), shade(wood, 0.9))
    for x in (-xi, xi):
        asm.box((x - 0.01, -yi, apron_z), (x + 0.01, yi, h - top_t), shade(wood, 0.9))
    return asm


def _coffee_table(rng: np.random.Generator, size: Size) -> Assembly:
    """A low top on four legs with a shelf underneath; the top is wood or glass in a metal frame."""
    w, d, h = size
    asm = Assembly()
    glass = rng.uniform() < 0.3
    wood = pick(rng, "wood")
    frame = pick(rng, "dark_metal") if glass else wood
    top = pick(rng, "glass") if glass else wood
    asm.add(rounded_prism((0.0, 0.0), w, d, 0.03, h - 0.025, h), top)
    legs(asm, corners(w, d, 0.05), 0.0, h - 0.025, 0.045, frame)
    asm.add(rounded_prism((0.0, 0.0), w - 0.1, d - 0.1, 0.02, 0.09, 0.11), shade(wood, 0.92))
    return asm


def _cafe_table(rng: np.random.Generator, size: Size) -> Assembly:
    """A round (or square) top on a pedestal with a cross-foot or disc base."""
    w, d, h = size
    rx, ry = 0.5 * w, 0.5 * d
    asm = Assembly()
    top_color = pick(rng, "wood") if rng.uniform() < 0.6 else pick(rng, "stone")
    metal = pick(rng, "dark_metal") if rng.uniform() < 0.6 else pick(rng, "chrome")
    if rng.uniform() < 0.7:
        asm.add(frustum((0, 0, h - 0.03), (0, 0, h), (rx, ry), (rx, ry), sections=24), top_color)
    else:
        asm.add(rounded_prism((0.0, 0.0), w, d, 0.04, h - 0.03, h), top_color)
    asm.add(cylinder((0, 0, 0.03), (0, 0, h - 0.03), 0.035, sections=12), metal)
    asm.add(frustum((0, 0, h - 0.1), (0, 0, h - 0.03), 0.04, 0.12, sections=12), metal)
    if rng.uniform() < 0.5:
        asm.add(
            frustum((0, 0, 0), (0, 0, 0.03), (0.7 * rx, 0.7 * ry), (0.6 * rx, 0.6 * ry), sections=20), metal
        )
    else:
        for k in range(4):
            a = 0.25 * math.pi + 0.5 * math.pi * k
            asm.add(bar((0, 0, 0.02), (0.68 * rx * math.cos(a), 0.68 * ry * math.sin(a), 0.02), 0.04), metal)
    return asm


def _desk(rng: np.random.Generator, size: Size) -> Assembly:
    """A desk top on legs or side panels, a modesty panel and often a drawer pedestal."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    top = pick(rng, "wood") if rng.uniform() < 0.6 else pick(rng, "painted")
    frame = pick(rng, "metal") if rng.uniform() < 0.5 else shade(top, 0.9)
    top_t = 0.03
    asm.box((-hx, -hy, h - top_t), (hx, hy, h), top)
    panels = rng.uniform() < 0.5
    if panels:
        for x in (-hx + 0.02, hx - 0.02):
            asm.box((x - 0.01, -hy + 0.02, 0.02), (x + 0.01, hy - 0.04, h - top_t), frame)
            asm.box((x - 0.02, -hy + 0.02, 0.0), (x + 0.02, hy - 0.04, 0.02), shade(frame, 0.7))
    else:
        legs(asm, corners(w, d, 0.04), 0.0, h - top_t, 0.045, frame)
    asm.box((-hx + 0.06, -hy + 0.03, 0.3), (hx - 0.06, -hy + 0.045, h - top_t), frame)
    if w >= 1.1 and rng.uniform() < 0.7:
        side = 1.0 if rng.uniform() < 0.5 else -1.0
        px0, px1 = sorted((side * (hx - 0.05), side * (hx - 0.47)))
        face = hy - 0.06 - FRONT_THICKNESS - HANDLE_DEPTH
        body = shade(top, 0.95)
        asm.box((px0, -hy + 0.06, 0.03), (px1, face, h - top_t), body)
        drawer_fronts(
            asm,
            px0,
            px1,
            0.05,
            h - top_t - 0.01,
            face,
            rows=3,
            cols=1,
            color=body,
            handle_color=pick(rng, "chrome"),
        )
    return asm


def _school_desk(rng: np.random.Generator, size: Size) -> Assembly:
    """A laminate top on a tubular steel frame with a book tray under the top."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    top = pick(rng, "light_wood")
    frame = pick(rng, "accent") if rng.uniform() < 0.4 else pick(rng, "metal")
    asm.add(rounded_prism((0.0, 0.0), w, d, 0.02, h - 0.025, h), top)
    legs(asm, corners(w, d, 0.04), 0.0, h - 0.025, 0.03, frame, round_legs=True)
    for x in (-hx + 0.04, hx - 0.04):
        asm.box((x - 0.012, -hy + 0.04, 0.12), (x + 0.012, hy - 0.04, 0.145), frame)
    tray = shade(frame, 0.8)
    tz = h - 0.16
    asm.box((-hx + 0.06, -hy + 0.04, tz), (hx - 0.06, hy - 0.12, tz + 0.01), tray)
    asm.box((-hx + 0.06, -hy + 0.04, tz), (hx - 0.06, -hy + 0.05, h - 0.025), tray)
    for x in (-hx + 0.06, hx - 0.07):
        asm.box((x, -hy + 0.04, tz), (x + 0.01, hy - 0.12, h - 0.025), tray)
    return asm


def _reception_desk(rng: np.random.Generator, size: Size) -> Assembly:
    """A high visitor counter (+y) with a transaction ledge in front of a low work surface."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = pick(rng, "painted") if rng.uniform() < 0.5 else pick(rng, "wood")
    ledge = pick(rng, "stone") if rng.uniform() < 0.5 else pick(rng, "wood")
    accent = pick(rng, "accent")
    work_z = 0.75
    front_y0, front_y1 = hy - 0.08, hy - 0.02
    asm.box((-hx, front_y0, 0.04), (hx, front_y1, h - 0.03), body)
    asm.box((-hx + 0.02, front_y0 + 0.01, 0.0), (hx - 0.02, front_y1 - 0.01, 0.04), shade(body, 0.5))
    asm.box((-hx, front_y1, h - 0.35), (hx, front_y1 + 0.006, h - 0.27), accent)
    asm.box((-hx, hy - 0.3, h - 0.03), (hx, hy, h), ledge)
    asm.box((-hx + 0.03, -hy, work_z - 0.03), (hx - 0.03, front_y0, work_z), shade(body, 0.95))
    for x in (-hx + 0.015, hx - 0.015):
        asm.box((x - 0.015, -hy, 0.0), (x + 0.015, front_y0, work_z), body)
    asm.box((-hx + 0.03, front_y0 - 0.4, 0.05), (-hx + 0.45, front_y0, work_z - 0.03), shade(body, 0.9))
    return asm


def _reception_supports(size: Size) -> list[SupportArea]:
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    return [
        SupportArea(height=0.75, x_min=-hx + 0.06, x_max=hx - 0.06, y_min=-hy + 0.03, y_max=hy - 0.34),
        SupportArea(height=h, x_min=-hx + 0.03, x_max=hx - 0.03, y_min=hy - 0.27, y_max=hy - 0.02),
    ]


def _lectern(rng: np.random.Generator, size: Size) -> Assembly:
    """A sloped reading top (falling towards the speaker at +y) on a panel column and a base plate."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wood = pick(rng, "wood")
    asm.box((-hx, -hy, 0.0), (hx, hy, 0.04), shade(wood, 0.8))
    asm.box((-0.35 * w, -0.3 * d, 0.04), (0.35 * w, 0.2 * d, h - 0.2), wood)
    low, high = h - 0.12, h
    points = [
        (x, y, z)
        for x in (-hx, hx)
        for y, z in ((hy, low - 0.04), (hy, low), (-hy, high - 0.04), (-hy, high))
    ]
    asm.add(hull(points), wood)
    asm.box((-0.35 * w, -0.3 * d, h - 0.2), (0.35 * w, 0.2 * d, h - 0.08), wood)
    asm.box((-hx + 0.05, hy - 0.03, low), (hx - 0.05, hy, low + 0.03), shade(wood, 0.7))
    return asm


def _cafe_supports(size: Size) -> list[SupportArea]:
    w, d, h = size
    # the largest rectangle in the round top's ellipse, less a margin
    return [SupportArea(height=h, x_min=-0.33 * w, x_max=0.33 * w, y_min=-0.33 * d, y_max=0.33 * d)]


ASSETS: tuple[Asset, ...] = (
    Asset(
        "dining_table",
        (1.10, 0.75, 0.72),
        (2.20, 1.00, 0.78),
        "floor",
        None,
        0.7,
        "wood",
        _dining_table,
        supports=top_support(inset=0.05),
        contexts=("home", "office", "cafe"),
    ),
    Asset(
        "coffee_table",
        (0.80, 0.45, 0.35),
        (1.30, 0.75, 0.48),
        "floor",
        None,
        0.4,
        "wood",
        _coffee_table,
        supports=top_support(),
        contexts=("home", "office", "hospital"),
    ),
    Asset(
        "cafe_table",
        (0.60, 0.60, 0.72),
        (0.80, 0.80, 0.76),
        "floor",
        None,
        0.6,
        "wood",
        _cafe_table,
        supports=_cafe_supports,
        contexts=("cafe", "home", "retail"),
    ),
    Asset(
        "desk",
        (1.00, 0.60, 0.72),
        (1.80, 0.80, 0.77),
        "wall",
        None,
        0.8,
        "wood",
        _desk,
        supports=top_support(),
        contexts=("office", "home", "school", "hospital"),
    ),
    Asset(
        "school_desk",
        (0.60, 0.45, 0.68),
        (0.75, 0.55, 0.78),
        "floor",
        None,
        0.6,
        "wood",
        _school_desk,
        supports=top_support(inset=0.02),
        contexts=("school",),
    ),
    Asset(
        "reception_desk",
        (1.60, 0.75, 1.00),
        (2.80, 0.90, 1.15),
        "floor",
        None,
        1.0,
        "wood",
        _reception_desk,
        supports=_reception_supports,
        contexts=("office", "hospital", "retail"),
    ),
    Asset(
        "lectern",
        (0.50, 0.40, 1.10),
        (0.70, 0.55, 1.25),
        "floor",
        None,
        0.7,
        "wood",
        _lectern,
        contexts=("school", "office"),
    ),
)
