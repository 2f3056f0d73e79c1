"""Kitchen and bathroom: counter, fridge, oven, microwave, sink, toilet, bathtub, shower, washing machine.

Basins (sink, toilet bowl, bathtub, shower tray) are boolean cavities cut into one watertight shell.
Fronts (doors, controls, portholes) face +y; backs go against the wall at -y.
"""

from __future__ import annotations

import numpy as np

from navverse.assets.fittings import (
    FRONT_THICKNESS,
    HANDLE_DEPTH,
    bar_handle,
    door_fronts,
    drawer_fronts,
    knob,
)
from navverse.assets.materials import RGB, pick, shade
from navverse.assets.parts import (
    Assembly,
    bar,
    box,
    cylinder,
    difference,
    ellipsoid,
    extrude,
    frustum,
    rounded_prism,
    rounded_rectangle,
    translate,
)
from navverse.assets.spec import Asset, Size, top_support

__all__ = ["ASSETS"]

_FRONT = FRONT_THICKNESS + HANDLE_DEPTH
_SPLASH = 0.06
"""Backsplash height above a kitchen worktop, m."""
_DARK: RGB = (26, 28, 32)


def _kitchen_counter(rng: np.random.Generator, size: Size) -> Assembly:
    """Base cabinets (doors and drawer stacks) on a recessed plinth under a worktop with a backsplash."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    fronts = pick(rng, "painted") if rng.uniform() < 0.6 else pick(rng, "wood")
    worktop = pick(rng, "stone") if rng.uniform() < 0.6 else pick(rng, "wood")
    handles = pick(rng, "chrome")
    top = h - _SPLASH
    face = hy - 0.02 - _FRONT
    asm.box((-hx, -hy, top - 0.035), (hx, hy, top), worktop)
    asm.box((-hx, -hy, top), (hx, -hy + 0.015, h), worktop)
    asm.box((-hx + 0.005, -hy, 0.1), (hx - 0.005, face, top - 0.035), shade(fronts, 0.9))
    asm.box((-hx + 0.005, -hy, 0.0), (hx - 0.005, face - 0.05, 0.1), shade(fronts, 0.45))
    units = max(1, round(w / 0.6))
    unit_w = (w - 0.01) / units
    for u in range(units):
        x0, x1 = -hx + 0.005 + u * unit_w, -hx + 0.005 + (u + 1) * unit_w
        kind = int(rng.integers(3))
        if kind == 0:
            drawer_fronts(
                asm, x0, x1, 0.1, top - 0.035, face, rows=3, cols=1, color=fronts, handle_color=handles
            )
        elif kind == 1:
            door_fronts(
                asm,
                x0,
                x1,
                0.1,
                top - 0.035,
                face,
                count=1,
                color=fronts,
                handle_color=handles,
                handle_z=top - 0.15,
            )
        else:
            drawer_fronts(
                asm, x0, x1, top - 0.2, top - 0.035, face, rows=1, cols=1, color=fronts, handle_color=handles
            )
            door_fronts(
                asm,
                x0,
                x1,
                0.1,
                top - 0.2,
                face,
                count=1,
                color=fronts,
                handle_color=handles,
                handle_z=top - 0.3,
            )
    if w >= 1.2 and rng.uniform() < 0.5:  # a built-in hob
        hob_x = float(rng.uniform(-hx + 0.35, hx - 0.35))
        asm.box((hob_x - 0.29, -hy + 0.06, top), (hob_x + 0.29, hy - 0.06, top + 0.006), _DARK)
        for dx in (-0.14, 0.14):
            for dy in (-0.1, 0.1):
                ring = cylinder(
                    (hob_x + dx, dy, top + 0.006), (hob_x + dx, dy, top + 0.008), 0.08, sections=16
                )
                asm.add(ring, (70, 70, 76))
    return asm


def _fridge(rng: np.random.Generator, size: Size) -> Assembly:
    """A tall cabinet with fridge and freezer doors (or side-by-side doors), long handles, a base grille."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    skin = pick(rng, "stainless") if rng.uniform() < 0.5 else pick(rng, "white_plastic")
    if rng.uniform() < 0.15:
        skin = pick(rng, "dark_metal")
    handles = shade(skin, 0.75)
    door_t = 0.045
    face = hy - door_t - HANDLE_DEPTH
    asm.add(rounded_prism((0.0, 0.5 * (face - hy)), w, face + hy, 0.02, 0.0, h), skin)
    asm.box((-hx + 0.02, face, 0.0), (hx - 0.02, face + 0.01, 0.08), _DARK)
    front = face + door_t
    layout = int(rng.integers(3)) if w > 0.8 else int(rng.integers(2))
    if layout == 2:  # side by side
        for x0, x1, hx_handle in ((-hx, -0.003, -0.05), (0.003, hx, 0.05)):
            asm.box((x0, face, 0.08), (x1, front, h - 0.005), shade(skin, 1.03))
            bar_handle(asm, hx_handle, 0.55 * h, front, 0.6, handles, vertical=True)
    else:
        split = 0.08 + (0.3 if layout == 0 else 0.7) * (h - 0.08)
        asm.box((-hx, face, 0.08), (hx, front, split - 0.004), shade(skin, 1.03))
        asm.box((-hx, face, split + 0.004), (hx, front, h - 0.005), shade(skin, 1.03))
        lower = min(0.3, 0.6 * (split - 0.08))
        upper = min(0.6, 0.6 * (h - split))
        bar_handle(asm, hx - 0.06, split - 0.5 * lower - 0.03, front, lower, handles, vertical=True)
        bar_handle(asm, hx - 0.06, split + 0.5 * upper + 0.03, front, upper, handles, vertical=True)
    return asm


def _oven(rng: np.random.Generator, size: Size) -> Assembly:
    """A freestanding range: oven door with window and handle, knobs, burners on the cooktop, backguard."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    skin = pick(rng, "stainless") if rng.uniform() < 0.6 else pick(rng, "white_plastic")
    top = h - 0.08
    face = hy - 0.025 - HANDLE_DEPTH
    asm.box((-hx, -hy, 0.0), (hx, face, top - 0.01), skin)
    asm.box((-hx, -hy, top - 0.01), (hx, face, top), _DARK)
    asm.box((-hx, -hy, top), (hx, -hy + 0.04, h), skin)
    door_front = face + 0.025
    asm.box((-hx + 0.01, face, 0.12), (hx - 0.01, door_front, top - 0.12), shade(skin, 1.04))
    asm.box((-hx + 0.08, door_front, 0.22), (hx - 0.08, door_front + 0.003, top - 0.22), _DARK)
    bar_handle(asm, 0.0, top - 0.16, door_front, w - 0.16, shade(skin, 0.7))
    asm.box((-hx + 0.01, face, 0.02), (hx - 0.01, door_front, 0.11), shade(skin, 0.95))
    n_knobs = 4 if w < 0.75 else 6
    for x in np.linspace(-hx + 0.08, hx - 0.08, n_knobs):
        knob(asm, float(x), top - 0.06, face, (40, 40, 44), radius=0.018)
    burners = [(-0.25 * w, -0.22 * d), (0.25 * w, -0.22 * d), (-0.25 * w, 0.12 * d), (0.25 * w, 0.12 * d)]
    if w >= 0.75:
        burners.append((0.0, -0.05 * d))
    for k, (x, y) in enumerate(burners):
        r = 0.07 if k % 3 == 0 else 0.055
        asm.add(cylinder((x, y, top), (x, y, top + 0.015), r, sections=16), (60, 60, 64))
        asm.add(cylinder((x, y, top + 0.015), (x, y, top + 0.025), 0.6 * r, sections=12), (20, 20, 22))
    return asm


def _microwave(rng: np.random.Generator, size: Size) -> Assembly:
    """A box with a windowed door, a handle, a control panel with display and buttons, and feet."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    skin = (
        pick(rng, "stainless")
        if rng.uniform() < 0.4
        else pick(rng, "white_plastic" if rng.uniform() < 0.5 else "dark_plastic")
    )
    face = hy - 0.015 - HANDLE_DEPTH
    asm.box((-hx, -hy, 0.012), (hx, face, h), skin)
    for x in (-hx + 0.04, hx - 0.04):
        for y in (-hy + 0.04, face - 0.04):
            asm.box((x - 0.015, y - 0.015, 0.0), (x + 0.015, y + 0.015, 0.012), _DARK)
    door_x1 = -hx + 0.72 * w
    front = face + 0.015
    asm.box((-hx + 0.005, face, 0.02), (door_x1, front, h - 0.01), shade(skin, 1.05))
    asm.box((-hx + 0.05, front, 0.06), (door_x1 - 0.07, front + 0.003, h - 0.05), _DARK)
    bar_handle(asm, door_x1 - 0.03, 0.5 * h, front, 0.6 * h, shade(skin, 0.7), vertical=True)
    panel = shade(skin, 0.8)
    asm.box((door_x1 + 0.005, face, 0.02), (hx - 0.005, front, h - 0.01), panel)
    px0, px1 = door_x1 + 0.025, hx - 0.025
    asm.box((px0, front, h - 0.07), (px1, front + 0.003, h - 0.035), (40, 70, 60))
    for r in range(4):
        for c in range(3):
            bx = px0 + (c + 0.5) * (px1 - px0) / 3
            bz = h - 0.1 - r * 0.03
            asm.box(
                (bx - 0.008, front, bz - 0.008), (bx + 0.008, front + 0.004, bz + 0.008), shade(panel, 1.3)
            )
    return asm


def _sink(rng: np.random.Generator, size: Size) -> Assembly:
    """A bathroom sink: a basin cut into a ceramic top over a vanity (or on a pedestal), with a faucet."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    ceramic = pick(rng, "ceramic")
    chrome = pick(rng, "chrome")
    counter = float(np.clip(h - 0.2, 0.78, 0.9))
    block = rounded_prism((0.0, 0.0), w, d, 0.03, counter - 0.12, counter)
    bowl = ellipsoid((0.0, 0.04, counter), (min(0.26, 0.36 * w), 0.3 * d, 0.1), segments=16, rings=8)
    asm.add(difference(block, bowl), ceramic)
    asm.add(cylinder((0.0, 0.04, counter - 0.105), (0.0, 0.04, counter - 0.095), 0.02, sections=12), chrome)
    if w < 0.65 and rng.uniform() < 0.6:  # pedestal sink
        asm.add(
            frustum((0.0, -0.1 * d, 0.0), (0.0, -0.1 * d, counter - 0.12), (0.1, 0.09), (0.13, 0.11)), ceramic
        )
    else:
        wood = pick(rng, "wood") if rng.uniform() < 0.5 else pick(rng, "painted")
        face = hy - 0.01 - _FRONT
        asm.box((-hx + 0.01, -hy, 0.1), (hx - 0.01, face, counter - 0.12), wood)
        asm.box((-hx + 0.03, -hy, 0.0), (hx - 0.03, face - 0.04, 0.1), shade(wood, 0.5))
        door_fronts(
            asm,
            -hx + 0.01,
            hx - 0.01,
            0.1,
            counter - 0.125,
            face,
            count=1 if w < 0.7 else 2,
            color=shade(wood, 1.05),
            handle_color=chrome,
            handle_z=counter - 0.25,
        )
    y_tap = -hy + 0.06
    asm.add(cylinder((0.0, y_tap, counter), (0.0, y_tap, h - 0.02), 0.018, sections=12), chrome)
    asm.add(bar((0.0, y_tap, h - 0.02), (0.0, y_tap + 0.13, h - 0.04), 0.02), chrome)
    asm.add(bar((0.0, y_tap - 0.01, h - 0.012), (0.0, y_tap - 0.05, h - 0.012), (0.015, 0.02, 0.024)), chrome)
    return asm


def _toilet(rng: np.random.Generator, size: Size) -> Assembly:
    """Cistern, pedestal, bowl (boolean cavity), seat ring and a closed or raised lid."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    ceramic = pick(rng, "ceramic")
    seat = ceramic if rng.uniform() < 0.7 else pick(rng, "wood" if rng.uniform() < 0.5 else "dark_plastic")
    tank_y1 = -hy + 0.17
    asm.add(rounded_prism((0.0, -hy + 0.085), w, 0.17, 0.025, 0.36, h - 0.015), ceramic)
    asm.add(
        rounded_prism((0.0, -hy + 0.09), w - 0.01, 0.18, 0.025, h - 0.015, h - 0.006), shade(ceramic, 0.97)
    )
    asm.add(
        cylinder((0.0, -hy + 0.09, h - 0.006), (0.0, -hy + 0.09, h), 0.025, sections=12), pick(rng, "chrome")
    )
    rx, ry = 0.92 * hx, 0.5 * (d - 0.14)
    yc = hy - ry
    rim = 0.39
    outer = frustum((0.0, yc, 0.18), (0.0, yc, rim), (0.72 * rx, 0.72 * ry), (rx, ry), sections=24)
    cavity = ellipsoid((0.0, yc + 0.01, rim), (rx - 0.035, ry - 0.04, 0.17), segments=16, rings=8)
    asm.add(difference(outer, cavity), ceramic)
    asm.add(
        frustum((0.0, yc - 0.04, 0.0), (0.0, yc - 0.04, 0.2), (0.5 * rx, 0.55 * ry), (0.45 * rx, 0.5 * ry)),
        ceramic,
    )
    asm.box((-0.45 * rx, tank_y1 - 0.05, 0.2), (0.45 * rx, yc, rim - 0.02), ceramic)
    ring = difference(
        frustum((0.0, yc, rim), (0.0, yc, rim + 0.022), (rx, ry), (rx, ry), sections=24),
        frustum(
            (0.0, yc + 0.01, rim - 0.01),
            (0.0, yc + 0.01, rim + 0.04),
            (rx - 0.06, ry - 0.07),
            (rx - 0.06, ry - 0.07),
            sections=24,
        ),
    )
    asm.add(ring, seat)
    if rng.uniform() < 0.5:
        asm.add(
            frustum(
                (0.0, yc, rim + 0.022),
                (0.0, yc, rim + 0.04),
                (rx - 0.005, ry - 0.005),
                (rx - 0.01, ry - 0.01),
                sections=24,
            ),
            seat,
        )
    else:
        rz = min(ry - 0.01, 0.5 * (h - rim - 0.06))
        lid = frustum(
            (0.0, tank_y1, rim + 0.03 + rz),
            (0.0, tank_y1 + 0.02, rim + 0.03 + rz),
            (rx - 0.01, rz),
            (rx - 0.01, rz),
            sections=24,
        )
        asm.add(lid, seat)
    return asm


def _bathtub(rng: np.random.Generator, size: Size) -> Assembly:
    """A rounded shell with a sloped-wall basin (boolean), a drain and a deck-mounted faucet at one end."""
    w, d, h = size
    hx = 0.5 * w
    asm = Assembly()
    ceramic = pick(rng, "ceramic")
    chrome = pick(rng, "chrome")
    rim = h - 0.1
    shell = rounded_prism((0.0, 0.0), w, d, 0.06, 0.0, rim)
    inner_w, inner_d = w - 0.3, d - 0.18
    cavity = extrude(rounded_rectangle(inner_w, inner_d, 0.2), 0.0, rim - 0.05, scale_top=(1.06, 1.1))
    cavity = translate(cavity, (0.05, 0.0, 0.06))
    asm.add(difference(shell, cavity), ceramic)
    asm.add(
        cylinder((-0.5 * inner_w + 0.17, 0.0, 0.06), (-0.5 * inner_w + 0.17, 0.0, 0.066), 0.03, sections=12),
        chrome,
    )
    x_tap = -hx + 0.07
    asm.add(cylinder((x_tap, 0.0, rim), (x_tap, 0.0, h - 0.011), 0.02, sections=12), chrome)
    asm.add(bar((x_tap, 0.0, h - 0.011), (x_tap + 0.14, 0.0, h - 0.03), 0.022), chrome)
    for y in (-0.08, 0.08):
        asm.add(cylinder((x_tap, y, rim), (x_tap, y, h - 0.04), 0.018, sections=12), chrome)
    return asm


def _shower(rng: np.random.Generator, size: Size) -> Assembly:
    """A shower tray (boolean), tiled back wall, glass side panels, half-width front screen, rain head."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    ceramic = pick(rng, "ceramic")
    glass = pick(rng, "glass")
    frame = pick(rng, "chrome")
    tile = pick(rng, "stone") if rng.uniform() < 0.6 else pick(rng, "accent")
    tray = difference(
        box((-hx, -hy, 0.0), (hx, hy, 0.08)),
        box((-hx + 0.04, -hy + 0.04, 0.045), (hx - 0.04, hy - 0.04, 0.1)),
    )
    asm.add(tray, ceramic)
    asm.add(cylinder((0.0, 0.0, 0.045), (0.0, 0.0, 0.05), 0.04, sections=12), frame)
    asm.box((-hx, -hy, 0.08), (hx, -hy + 0.02, h), tile)
    for x in (-hx, hx - 0.008):
        asm.box((x, -hy + 0.02, 0.08), (x + 0.008, hy - 0.02, h - 0.03), glass)
    for x in (-hx, hx - 0.03):
        asm.box((x, hy - 0.03, 0.08), (x + 0.03, hy, h), frame)
    side = 1.0 if rng.uniform() < 0.5 else -1.0
    x0, x1 = sorted((0.0, side * (hx - 0.01)))
    asm.box((x0, hy - 0.025, 0.08), (x1, hy - 0.017, h - 0.03), glass)
    asm.box((-hx, hy - 0.03, h - 0.03), (hx, hy, h), frame)
    for x in (-hx, hx - 0.03):
        asm.box((x, -hy + 0.02, h - 0.03), (x + 0.03, hy - 0.03, h), frame)
    xs = -0.25 * w * side
    asm.add(cylinder((xs, -hy + 0.04, 1.0), (xs, -hy + 0.04, h - 0.12), 0.012, sections=12), frame)
    asm.box((xs - 0.06, -hy + 0.02, 1.0), (xs + 0.06, -hy + 0.07, 1.1), frame)
    asm.add(bar((xs, -hy + 0.04, h - 0.12), (xs, -hy + 0.25, h - 0.12), 0.02), frame)
    asm.add(cylinder((xs, -hy + 0.25, h - 0.14), (xs, -hy + 0.25, h - 0.125), 0.1, sections=20), frame)
    return asm


def _washing_machine(rng: np.random.Generator, size: Size) -> Assembly:
    """A front loader: cabinet, control strip (drawer, display, knob) and a round porthole door."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    skin = pick(rng, "white_plastic") if rng.uniform() < 0.75 else pick(rng, "stainless")
    face = hy - 0.05
    asm.box((-hx, -hy, 0.015), (hx, face, h), skin)
    for x in (-hx + 0.05, hx - 0.05):
        for y in (-hy + 0.05, face - 0.05):
            asm.box((x - 0.02, y - 0.02, 0.0), (x + 0.02, y + 0.02, 0.015), _DARK)
    strip = shade(skin, 0.93)
    asm.box((-hx, face, h - 0.12), (hx, face + 0.005, h - 0.005), strip)
    asm.box((-hx + 0.03, face, h - 0.1), (-hx + 0.03 + 0.3 * w, face + 0.012, h - 0.03), shade(skin, 1.02))
    asm.box((-0.02, face + 0.005, h - 0.09), (0.14, face + 0.008, h - 0.04), (30, 50, 60))
    asm.add(
        cylinder(
            (hx - 0.09, face + 0.005, h - 0.065), (hx - 0.09, face + 0.03, h - 0.065), 0.03, sections=16
        ),
        shade(skin, 0.8),
    )
    radius = min(0.23, 0.38 * w)
    zc = 0.5 * (h - 0.12) + 0.03
    asm.add(cylinder((0.0, face, zc), (0.0, face + 0.035, zc), radius, sections=24), shade(skin, 0.75))
    asm.add(cylinder((0.0, face + 0.035, zc), (0.0, hy, zc), 0.72 * radius, sections=24), (40, 60, 80))
    asm.box((-hx + 0.02, face, 0.02), (hx - 0.02, face + 0.004, 0.06), shade(skin, 0.85))
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "kitchen_counter",
        (0.60, 0.58, 0.92),
        (2.40, 0.66, 1.00),
        "wall",
        None,
        0.9,
        "wood",
        _kitchen_counter,
        supports=top_support(top_drop=_SPLASH, back_margin=0.015, front_margin=0.0),
        contexts=("home", "cafe", "office"),
    ),
    Asset(
        "fridge",
        (0.55, 0.60, 1.50),
        (0.91, 0.78, 1.95),
        "wall",
        None,
        0.9,
        "metal",
        _fridge,
        contexts=("home", "office", "cafe"),
    ),
    Asset(
        "oven",
        (0.50, 0.58, 0.92),
        (0.90, 0.66, 1.00),
        "wall",
        None,
        0.9,
        "metal",
        _oven,
        contexts=("home", "cafe"),
    ),
    Asset(
        "microwave",
        (0.44, 0.32, 0.25),
        (0.60, 0.45, 0.34),
        "surface",
        None,
        0.4,
        "metal",
        _microwave,
        contexts=("home", "office", "cafe", "hospital"),
    ),
    Asset(
        "sink",
        (0.50, 0.45, 0.95),
        (1.20, 0.58, 1.10),
        "wall",
        None,
        0.6,
        "ceramic",
        _sink,
        contexts=("home", "office", "hospital", "school", "cafe"),
    ),
    Asset(
        "toilet",
        (0.36, 0.60, 0.70),
        (0.45, 0.75, 0.85),
        "wall",
        None,
        0.6,
        "ceramic",
        _toilet,
        contexts=("home", "office", "hospital", "school", "cafe"),
    ),
    Asset(
        "bathtub",
        (1.50, 0.70, 0.55),
        (1.80, 0.85, 0.70),
        "wall",
        None,
        0.6,
        "ceramic",
        _bathtub,
        contexts=("home", "hospital"),
    ),
    Asset(
        "shower",
        (0.80, 0.80, 1.95),
        (1.20, 1.00, 2.15),
        "wall",
        None,
        0.6,
        "glass",
        _shower,
        contexts=("home", "hospital"),
    ),
    Asset(
        "washing_machine",
        (0.58, 0.55, 0.82),
        (0.62, 0.65, 0.88),
        "wall",
        None,
        0.8,
        "plastic",
        _washing_machine,
        supports=top_support(inset=0.02, front_margin=0.05),
        contexts=("home",),
    ),
)
