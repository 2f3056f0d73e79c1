"""Screens and small machines: tv, wall tv, monitor, laptop, printer and espresso machine.

Screens, keyboards, paper trays and group heads face +y.
"""

from __future__ import annotations

import numpy as np

from navverse.assets.materials import RGB, pick, shade
from navverse.assets.parts import Assembly, bar, cylinder, frustum, hull, rounded_prism
from navverse.assets.spec import Asset, Size

__all__ = ["ASSETS"]

_DARK: RGB = (26, 28, 32)


def _screen(
    asm: Assembly, rng: np.random.Generator, w: float, y_back: float, thick: float, z0: float, z1: float
) -> RGB:
    """A flat panel between heights `z0` and `z1` with its back at `y_back`; returns the bezel colour."""
    hx = 0.5 * w
    bezel = pick(rng, "dark_plastic") if rng.uniform() < 0.75 else pick(rng, "metal")
    asm.box((-hx, y_back, z0), (hx, y_back + thick, z1), bezel)
    border = min(0.02, 0.04 * (z1 - z0))
    asm.box(
        (-hx + border, y_back + thick, z0 + border),
        (hx - border, y_back + thick + 0.002, z1 - border),
        pick(rng, "screen"),
    )
    return bezel


def _display(rng: np.random.Generator, size: Size, *, panel_thickness: float, pedestal: bool) -> Assembly:
    w, d, h = size
    hy = 0.5 * d
    asm = Assembly()
    panel_h = min(0.6 * w, h - 0.04)
    z0 = h - panel_h
    y_back = -0.5 * panel_thickness - 0.01
    bezel = _screen(asm, rng, w, y_back, panel_thickness, z0, h)
    stand = shade(bezel, 1.2)
    if pedestal:
        foot_w = min(0.6 * w, 0.28)
        asm.add(rounded_prism((0.0, 0.0), foot_w, d, 0.04, 0.0, 0.015), stand)
        # the neck holds the panel by its lower edge
        asm.box((-0.03, y_back - 0.03, 0.01), (0.03, y_back + 0.005, z0 + 0.015), stand)
    else:
        for sx in (-1.0, 1.0):
            x = sx * 0.36 * w
            points = [
                (x + dx, y, z) for dx in (-0.02, 0.02) for y, z in ((-hy, 0.0), (hy, 0.0), (0.0, z0 + 0.05))
            ]
            asm.add(hull(points + [(x + dx, 0.0, 0.015) for dx in (-0.02, 0.02)]), stand)
    return asm


def _tv(rng: np.random.Generator, size: Size) -> Assembly:
    """A flat-screen tv on two feet or a centre pedestal."""
    return _display(rng, size, panel_thickness=float(rng.uniform(0.03, 0.06)), pedestal=rng.uniform() < 0.4)


def _monitor(rng: np.random.Generator, size: Size) -> Assembly:
    """A computer monitor on a neck and a flat foot."""
    return _display(rng, size, panel_thickness=float(rng.uniform(0.02, 0.035)), pedestal=True)


def _wall_tv(rng: np.random.Generator, size: Size) -> Assembly:
    """A flat-screen tv hanging on the wall (its slim housing hides the bracket), with a logo on the bezel."""
    w, d, h = size
    hy = 0.5 * d
    asm = Assembly()
    bezel = _screen(asm, rng, w, -hy, d - 0.002, 0.0, h)
    asm.box((-0.03, hy - 0.002, 0.004), (0.03, hy, 0.012), shade(bezel, 2.5))
    return asm


def _laptop(rng: np.random.Generator, size: Size) -> Assembly:
    """An open laptop: base with keyboard and touchpad, lid leaning back with its screen facing +y."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    shell = pick(rng, "metal") if rng.uniform() < 0.6 else pick(rng, "dark_plastic")
    base_t = 0.018
    lean = 0.27 * (h - base_t)
    y_hinge = -hy + lean
    asm.add(rounded_prism((0.0, 0.5 * (y_hinge + hy)), w, hy - y_hinge, 0.01, 0.0, base_t), shell)
    t = 0.007
    bottom = np.array([0.0, y_hinge - 0.5 * t, base_t - 0.5 * t])
    top = np.array([0.0, -hy + 0.5 * t, h - 0.5 * t])
    asm.add(bar(bottom, top, (w, t, t)), shell)
    u = (top - bottom) / np.linalg.norm(top - bottom)
    normal = np.array([0.0, u[2], -u[1]])
    asm.add(
        bar(
            bottom + 0.7 * t * normal + 0.02 * u, top + 0.7 * t * normal - 0.01 * u, (w - 0.02, 0.003, 0.003)
        ),
        pick(rng, "screen"),
    )
    depth = hy - y_hinge
    asm.box((-hx + 0.02, y_hinge + 0.02, base_t), (hx - 0.02, y_hinge + 0.55 * depth, base_t + 0.002), _DARK)
    asm.box(
        (-0.18 * w, y_hinge + 0.62 * depth, base_t), (0.18 * w, hy - 0.02, base_t + 0.001), shade(shell, 0.85)
    )
    return asm


def _printer(rng: np.random.Generator, size: Size) -> Assembly:
    """An office printer: body, scanner lid, paper cassette, output tray with a sheet, control panel."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = pick(rng, "white_plastic") if rng.uniform() < 0.6 else pick(rng, "dark_plastic")
    front = hy - 0.04
    split = 0.7 * h
    asm.box((-hx, -hy, 0.0), (hx, front, split), body)
    asm.box((-hx, -hy, split), (hx, front - 0.02, h), shade(body, 1.05 if body[0] < 128 else 0.96))
    asm.box((-hx + 0.03, front, 0.02), (hx - 0.03, front + 0.01, 0.28 * h), shade(body, 0.92))
    asm.box((-hx + 0.04, front, 0.36 * h), (hx - 0.04, front + 0.003, 0.56 * h), _DARK)
    asm.box((-0.3 * w, front, 0.34 * h), (0.3 * w, hy, 0.34 * h + 0.01), shade(body, 0.85))
    asm.box(
        (-0.26 * w, front - 0.1, 0.34 * h + 0.01), (0.26 * w, hy - 0.01, 0.34 * h + 0.014), (250, 250, 248)
    )
    asm.box(
        (hx - 0.16, front - 0.09, split - 0.02), (hx - 0.02, front + 0.005, split + 0.005), shade(body, 0.8)
    )
    asm.box((hx - 0.14, front - 0.07, split + 0.005), (hx - 0.07, front - 0.01, split + 0.008), (40, 70, 90))
    return asm


def _espresso_machine(rng: np.random.Generator, size: Size) -> Assembly:
    """A cafe espresso machine: body, one to three group heads with portafilters, drip tray, cups on top."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    skin = pick(rng, "stainless") if rng.uniform() < 0.5 else pick(rng, "brand")
    chrome = pick(rng, "chrome")
    body_front = hy - 0.13
    top = h - 0.07
    asm.box((-hx, -hy, 0.0), (hx, body_front, top), skin)
    asm.box((-hx + 0.02, body_front, 0.0), (hx - 0.02, hy, 0.04), _DARK)
    asm.box((-hx, body_front, top - 0.1), (hx, body_front + 0.03, top), shade(skin, 0.9))
    groups = 1 if w < 0.55 else (2 if w < 0.72 else 3)
    xs = np.linspace(-hx, hx, groups + 2)[1:-1]
    for x in xs:
        x = float(x)
        asm.box((x - 0.05, body_front, 0.24), (x + 0.05, body_front + 0.06, 0.3), chrome)
        asm.add(
            cylinder((x, body_front + 0.05, 0.2), (x, body_front + 0.05, 0.24), 0.04, sections=16), chrome
        )
        asm.add(bar((x, body_front + 0.06, 0.215), (x, hy - 0.01, 0.2), 0.022), _DARK)
        asm.add(
            frustum((x, body_front + 0.05, 0.04), (x, body_front + 0.05, 0.1), 0.028, 0.035, sections=12),
            (246, 246, 242),
        )
    asm.add(
        cylinder(
            (0.0, body_front + 0.03, top - 0.06), (0.0, body_front + 0.04, top - 0.06), 0.03, sections=16
        ),
        (240, 240, 236),
    )
    wand_x = hx - 0.04
    asm.add(bar((wand_x, body_front + 0.02, 0.33), (wand_x, body_front + 0.06, 0.12), 0.012), chrome)
    for k in range(3):
        x = -hx + 0.08 + k * 0.09
        asm.add(frustum((x, -0.05, top), (x, -0.05, h), 0.03, 0.036, sections=12), (246, 246, 242))
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "tv",
        (0.70, 0.18, 0.45),
        (1.65, 0.35, 1.00),
        "surface",
        None,
        1.5,
        "plastic",
        _tv,
        contexts=("home", "office", "hospital", "cafe"),
    ),
    Asset(
        "wall_tv",
        (0.80, 0.04, 0.45),
        (1.65, 0.08, 0.95),
        "wall_mounted",
        (1.0, 1.5),
        1.5,
        "plastic",
        _wall_tv,
        contexts=("home", "office", "hospital", "cafe", "retail", "school"),
    ),
    Asset(
        "monitor",
        (0.45, 0.16, 0.35),
        (0.72, 0.25, 0.55),
        "surface",
        None,
        0.5,
        "plastic",
        _monitor,
        contexts=("office", "school", "hospital", "home", "retail"),
    ),
    Asset(
        "laptop",
        (0.30, 0.28, 0.20),
        (0.40, 0.36, 0.26),
        "surface",
        None,
        0.4,
        "metal",
        _laptop,
        contexts=("office", "school", "home", "cafe"),
    ),
    Asset(
        "printer",
        (0.38, 0.35, 0.20),
        (0.55, 0.50, 0.40),
        "surface",
        None,
        0.5,
        "plastic",
        _printer,
        contexts=("office", "school", "hospital"),
    ),
    Asset(
        "espresso_machine",
        (0.45, 0.45, 0.40),
        (0.80, 0.56, 0.52),
        "surface",
        None,
        0.5,
        "metal",
        _espresso_machine,
        contexts=("cafe", "office"),
    ),
)
