"""Fixtures of offices, schools and public rooms: whiteboard, trash can, coat rack, water dispenser,
fire extinguisher.

Wall-mounted items have their backs (brackets, frames) at -y.
"""

from __future__ import annotations

import math

import numpy as np

from navverse.assets.materials import pick, shade
from navverse.assets.parts import (
    Assembly,
    bar,
    box,
    cylinder,
    difference,
    ellipsoid,
    extrude,
    frustum,
    hull,
    revolve,
    rounded_prism,
    rounded_rectangle,
    translate,
)
from navverse.assets.spec import Asset, Size

__all__ = ["ASSETS"]


def _whiteboard(rng: np.random.Generator, size: Size) -> Assembly:
    """A white board in an aluminium frame with a marker tray, markers, an eraser and a few strokes."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    frame = pick(rng, "chrome")
    face = -hy + 0.018
    asm.box((-hx + 0.02, -hy, 0.05), (hx - 0.02, face, h - 0.02), (250, 250, 250))
    asm.box((-hx, -hy, h - 0.025), (hx, -hy + 0.025, h), frame)
    asm.box((-hx, -hy, 0.03), (hx, -hy + 0.025, 0.055), frame)
    for x in (-hx, hx - 0.025):
        asm.box((x, -hy, 0.03), (x + 0.025, -hy + 0.025, h), frame)
    asm.box((-0.3 * w, -hy, 0.0), (0.3 * w, hy, 0.03), frame)
    asm.box((-0.3 * w, hy - 0.006, 0.03), (0.3 * w, hy, 0.045), frame)
    colors = [(30, 60, 170), (190, 30, 30), (20, 20, 20), (30, 130, 60)]
    y_tray = 0.5 * ((-hy + 0.025) + (hy - 0.006))
    for k in range(int(rng.integers(2, 5))):
        x = -0.25 * w + 0.06 * k
        asm.add(cylinder((x, y_tray, 0.038), (x + 0.12, y_tray, 0.038), 0.008, sections=8), colors[k])
    asm.box((0.1 * w, -hy + 0.026, 0.03), (0.1 * w + 0.12, hy - 0.007, 0.055), (40, 40, 44))
    for _ in range(int(rng.integers(3, 8))):
        color = colors[int(rng.integers(len(colors)))]
        x0 = float(rng.uniform(-hx + 0.1, hx - 0.5))
        z0 = float(rng.uniform(0.2, h - 0.15))
        x1 = x0 + float(rng.uniform(0.1, 0.4))
        z1 = float(np.clip(z0 + rng.uniform(-0.1, 0.1), 0.12, h - 0.1))
        asm.add(bar((x0, face + 0.0005, z0), (x1, face + 0.0005, z1), (0.008, 0.001, 0.008)), color)
    return asm


def _trash_can(rng: np.random.Generator, size: Size) -> Assembly:
    """An open round bin (cavity cut out), a pedal bin with a lid, or a square bin with a slotted lid."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    color = pick(rng, "plastic") if rng.uniform() < 0.6 else pick(rng, "metal")
    style = int(rng.integers(3))
    if style == 0:
        outer = frustum((0, 0, 0), (0, 0, h), (0.82 * hx, 0.82 * hy), (hx, hy), sections=20)
        inner = frustum(
            (0, 0, 0.015),
            (0, 0, h + 0.01),
            (0.82 * hx - 0.01, 0.82 * hy - 0.01),
            (hx - 0.008, hy - 0.008),
            sections=20,
        )
        asm.add(difference(outer, inner), color)
        asm.add(
            frustum((0, 0, 0.015), (0, 0, 0.6 * h), (0.8 * hx, 0.8 * hy), (0.9 * hx, 0.9 * hy), sections=20),
            (34, 34, 36),
        )
        for k in range(int(rng.integers(1, 4))):
            a = 2.1 * k
            asm.add(
                ellipsoid(
                    (0.4 * hx * math.cos(a), 0.4 * hy * math.sin(a), 0.6 * h + 0.02), (0.04, 0.035, 0.03)
                ),
                (246, 246, 240),
            )
    elif style == 1:
        ry = hy - 0.04
        yc = -0.04
        body = frustum((0, yc, 0), (0, yc, h - 0.05), (0.95 * hx, 0.95 * ry), (hx, ry), sections=20)
        asm.add(body, color)
        asm.add(
            frustum((0, yc, h - 0.05), (0, yc, h), (hx, ry), (0.8 * hx, 0.8 * ry), sections=20),
            shade(color, 0.85),
        )
        asm.box((-0.06, yc + 0.8 * ry, 0.02), (0.06, hy, 0.045), (40, 40, 44))
    else:
        outline = rounded_rectangle(w, d, 0.05)
        asm.add(extrude(outline, 0.0, 0.03), (40, 40, 44))
        asm.add(extrude(outline * 0.985, 0.03, h - 0.1), color)
        lid = extrude(outline, h - 0.1, h, scale_top=(0.8, 0.8))
        slot = box((-0.3 * w, 0.15 * d, h - 0.06), (0.3 * w, hy + 0.01, h + 0.01))
        dark_body = sum(color) < 240
        asm.add(difference(lid, slot), shade(color, 2.6) if dark_body else shade(color, 0.8))
    return asm


def _coat_rack(rng: np.random.Generator, size: Size) -> Assembly:
    """A pole on four feet with two rings of hooks, a top knob and sometimes a coat or two."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    color = pick(rng, "wood") if rng.uniform() < 0.5 else pick(rng, "dark_metal")
    asm.add(cylinder((0, 0, 0.0), (0, 0, h - 0.05), 0.02, sections=12), color)
    asm.add(ellipsoid((0, 0, h - 0.035), (0.035, 0.035, 0.035), segments=12, rings=6), color)
    for ex, ey in ((hx - 0.015, 0.0), (0.0, hy - 0.015), (-hx + 0.015, 0.0), (0.0, -hy + 0.015)):
        asm.add(bar((0, 0, 0.06), (ex, ey, 0.015), 0.03), color)
    hook_r = min(0.16, 0.8 * min(hx, hy))
    for z, phase in ((h - 0.2, 0.0), (h - 0.35, 0.25 * math.pi)):
        for k in range(4):
            a = phase + 0.5 * math.pi * k
            tip = (hook_r * math.cos(a), hook_r * math.sin(a), z + 0.08)
            asm.add(bar((0, 0, z), tip, 0.018), color)
            asm.add(ellipsoid(tip, (0.015, 0.015, 0.015), segments=8, rings=4), color)
    for sx in (-1.0, 1.0):  # coats hang from the hooks along x, shoulders along y
        if rng.uniform() < 0.4:
            x = sx * min(hook_r, hx - 0.08)
            half = min(0.17, hy - 0.02)
            top = h - 0.17
            points = [
                (x + dx, y, z)
                for y in (-half, half)
                for dx, z in ((-0.04, top), (0.04, top), (-0.07, 0.75), (0.07, 0.75))
            ]
            asm.add(hull(points), pick(rng, "fabric"))
    return asm


def _water_dispenser(rng: np.random.Generator, size: Size) -> Assembly:
    """A cabinet with a tap niche (boolean), hot and cold taps, a drip tray and an upturned water bottle."""
    w, d, h = size
    hy = 0.5 * d
    asm = Assembly()
    body = pick(rng, "white_plastic") if rng.uniform() < 0.7 else pick(rng, "metal")
    bottle_h = min(0.49, 0.36 * h)
    top = h - bottle_h
    cabinet = rounded_prism((0.0, 0.0), w, d, 0.02, 0.0, top)
    niche = box((-0.3 * w, hy - 0.09, top - 0.45), (0.3 * w, hy + 0.01, top - 0.15))
    asm.add(difference(cabinet, niche), body)
    asm.box((-0.28 * w, hy - 0.09, top - 0.45), (0.28 * w, hy - 0.005, top - 0.43), (60, 60, 64))
    for x, color in ((-0.1 * w, (200, 40, 40)), (0.1 * w, (40, 90, 200))):
        asm.box((x - 0.015, hy - 0.06, top - 0.2), (x + 0.015, hy - 0.03, top - 0.15), color)
    r = min(0.135, 0.45 * min(w, d))
    profile = [
        (0.0, top - 0.01),
        (0.028, top - 0.01),
        (0.028, top + 0.05),
        (r, top + 0.13),
        (r, h - 0.05),
        (r - 0.04, h),
        (0.0, h),
    ]
    asm.add(revolve(profile, sections=20), (150, 190, 225))
    return asm


def _fire_extinguisher(rng: np.random.Generator, size: Size) -> Assembly:
    """A red cylinder with a domed top, valve, lever, gauge and hose, on a wall bracket."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    red = shade((196, 30, 30), float(rng.uniform(0.9, 1.05)))
    dark = (30, 30, 32)
    r = min(0.5 * (w - 0.032), 0.5 * (d - 0.02))
    xc, yc = -hx + r, hy - r
    body_top = h - 0.12
    profile = [(0.0, 0.0), (r, 0.0), (r, body_top - 0.6 * r), (0.45 * r, body_top), (0.0, body_top)]
    asm.add(translate(revolve(profile, sections=20), (xc, yc, 0.0)), red)
    asm.add(cylinder((xc, yc, body_top - 0.01), (xc, yc, h - 0.05), 0.022, sections=12), (60, 60, 64))
    asm.add(bar((xc, yc, h - 0.045), (xc + 0.6 * r, yc, h - 0.01), (0.02, 0.02, 0.02)), dark)
    asm.add(bar((xc, yc, h - 0.07), (xc + 0.6 * r, yc, h - 0.075), (0.02, 0.02, 0.012)), dark)
    asm.add(
        cylinder((xc, yc + 0.02, h - 0.09), (xc, yc + 0.035, h - 0.09), 0.016, sections=12), (236, 236, 230)
    )
    asm.add(bar((xc + 0.02, yc, h - 0.07), (hx - 0.01, yc, 0.7 * body_top), 0.02), dark)
    asm.add(bar((hx - 0.01, yc, 0.7 * body_top), (hx - 0.01, yc, 0.3 * body_top), 0.02), dark)
    asm.box((xc - 0.03, -hy, 0.55 * body_top), (xc + 0.03, yc - r + 0.005, 0.65 * body_top), (60, 60, 64))
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "whiteboard",
        (1.20, 0.05, 0.90),
        (2.40, 0.10, 1.25),
        "wall_mounted",
        (0.80, 1.00),
        1.0,
        "plastic",
        _whiteboard,
        contexts=("school", "office", "hospital"),
    ),
    Asset(
        "trash_can",
        (0.25, 0.25, 0.30),
        (0.45, 0.45, 0.80),
        "floor",
        None,
        0.3,
        "plastic",
        _trash_can,
        contexts=("home", "office", "school", "retail", "hospital", "cafe"),
    ),
    Asset(
        "coat_rack",
        (0.40, 0.40, 1.65),
        (0.60, 0.60, 1.90),
        "floor",
        None,
        0.4,
        "wood",
        _coat_rack,
        contexts=("home", "office", "cafe", "hospital", "school"),
    ),
    Asset(
        "water_dispenser",
        (0.30, 0.30, 1.20),
        (0.36, 0.40, 1.45),
        "wall",
        None,
        0.6,
        "plastic",
        _water_dispenser,
        contexts=("office", "school", "hospital", "retail"),
    ),
    Asset(
        "fire_extinguisher",
        (0.18, 0.16, 0.45),
        (0.24, 0.22, 0.65),
        "wall_mounted",
        (0.80, 1.00),
        0.5,
        "metal",
        _fire_extinguisher,
        contexts=("office", "school", "retail", "hospital", "cafe"),
    ),
)
