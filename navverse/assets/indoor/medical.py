"""Hospital equipment: hospital bed, IV stand, medical cart, wheelchair and a folding privacy screen.

The hospital bed's headboard is at -y; the wheelchair's seat opens to +y (push handles at -y).
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from navverse.assets.fittings import FRONT_THICKNESS, HANDLE_DEPTH, caster, drawer_fronts
from navverse.assets.materials import pick, shade
from navverse.assets.parts import (
    Assembly,
    bar,
    box,
    cylinder,
    difference,
    ellipsoid,
    hull,
    rounded_prism,
    torus,
)
from navverse.assets.spec import Asset, Size, top_support

__all__ = ["ASSETS"]


def _hospital_bed(rng: np.random.Generator, size: Size) -> Assembly:
    """Casters, lift frame, platform, mattress with a raised back section, head/foot boards, side rails."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    frame = pick(rng, "metal")
    panel = pick(rng, "medical") if rng.uniform() < 0.6 else pick(rng, "light_wood")
    mattress = shade(pick(rng, "medical"), 0.85)
    for x in (-hx + 0.12, hx - 0.12):
        for y in (-hy + 0.15, hy - 0.15):
            caster(asm, x, y, 0.06, (40, 40, 42), frame)
    asm.box((-hx + 0.08, -hy + 0.12, 0.14), (hx - 0.08, hy - 0.12, 0.24), frame)
    for y in (-hy + 0.35, hy - 0.35):
        asm.box((-0.12, y - 0.06, 0.24), (0.12, y + 0.06, 0.5), shade(frame, 0.85))
    platform = 0.5
    asm.box((-hx + 0.05, -hy + 0.06, platform), (hx - 0.05, hy - 0.06, platform + 0.05), frame)
    top = platform + 0.05
    thick = 0.13
    knee = -hy + 0.85
    asm.add(
        rounded_prism((0.0, 0.5 * (knee + hy - 0.07)), w - 0.14, hy - 0.07 - knee, 0.04, top, top + thick),
        mattress,
    )
    length = 0.72
    angle = math.asin(
        float(
            np.clip((h - 0.08 - top - thick) / length, math.sin(math.radians(8)), math.sin(math.radians(35)))
        )
    )
    c, s = math.cos(angle), math.sin(angle)
    head_y, head_z = knee - length * c, top + length * s
    points = [
        (x, y + dy, z + dz)
        for x in (-hx + 0.07, hx - 0.07)
        for y, z in ((knee, top), (head_y, head_z))
        for dy, dz in ((0.0, 0.0), (s * thick, c * thick))
    ]
    asm.add(hull(points), mattress)
    asm.box((-hx + 0.07, head_y - 0.02, top), (hx - 0.07, knee, top + 0.02), frame)
    pillow_c = (0.0, head_y + 0.2 * c + s * (thick + 0.04), head_z - 0.2 * s + c * (thick + 0.04))
    asm.add(ellipsoid(pillow_c, (0.3, 0.1, 0.06), segments=12, rings=6), (246, 246, 244))
    asm.box(
        (-hx + 0.06, knee + 0.15, top + thick - 0.05),
        (hx - 0.06, hy - 0.08, top + thick + 0.025),
        pick(rng, "bedding"),
    )
    asm.box((-hx + 0.04, -hy, 0.3), (hx - 0.04, -hy + 0.05, h), panel)
    asm.box((-hx + 0.04, hy - 0.05, 0.3), (hx - 0.04, hy, 0.86 * h), panel)
    rail_top = min(top + thick + 0.3, h - 0.04)
    rail_bottom = top + thick - 0.05
    for sx in (-1.0, 1.0):
        x = sx * (hx - 0.015)
        for y0, y1 in ((-hy + 0.2, knee - 0.05), (knee + 0.15, hy - 0.35)):
            asm.box((x - 0.015, y0, rail_top - 0.03), (x + 0.015, y1, rail_top), frame)
            asm.box((x - 0.01, y0, rail_bottom), (x + 0.01, y1, rail_bottom + 0.025), frame)
            for y in np.linspace(y0 + 0.02, y1 - 0.02, 3):
                asm.box(
                    (x - 0.01, float(y) - 0.01, rail_bottom), (x + 0.01, float(y) + 0.01, rail_top), frame
                )
            xa, xb = sorted((x, sx * (hx - 0.05)))
            asm.box((xa, y0 + 0.05, top - 0.03), (xb, y0 + 0.07, top), frame)
            asm.box((x - 0.008, y0 + 0.05, top - 0.03), (x + 0.008, y0 + 0.07, rail_bottom), frame)
    return asm


def _iv_stand(rng: np.random.Generator, size: Size) -> Assembly:
    """An IV pole on a four-leg castor base with hooks, a drip bag and its line, sometimes a pump."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    metal = pick(rng, "chrome")
    for tip in ((hx - 0.0125, 0.0), (-hx + 0.0125, 0.0), (0.0, hy - 0.0125), (0.0, -hy + 0.0125)):
        asm.add(bar((0.0, 0.0, 0.09), (tip[0], tip[1], 0.065), 0.025), metal)
        caster(asm, 0.85 * tip[0], 0.85 * tip[1], 0.022, (40, 40, 42), metal)
    asm.add(cylinder((0, 0, 0.06), (0, 0, h - 0.03), 0.013, sections=12), metal)
    asm.add(ellipsoid((0, 0, h - 0.02), (0.02, 0.02, 0.02), segments=8, rings=4), metal)
    arm = min(0.13, 0.8 * min(hx, hy))
    z_arm = h - 0.12
    for k in range(4):
        a = 0.25 * math.pi + 0.5 * math.pi * k
        tip = (arm * math.cos(a), arm * math.sin(a), z_arm)
        asm.add(bar((0, 0, z_arm), tip, 0.01), metal)
        asm.add(bar(tip, (tip[0], tip[1], z_arm + 0.04), 0.01), metal)
    bx, by = arm * math.cos(0.25 * math.pi), arm * math.sin(0.25 * math.pi)
    asm.add(rounded_prism((bx, by), 0.11, 0.035, 0.015, z_arm - 0.24, z_arm - 0.01), (222, 236, 242))
    asm.add(bar((bx, by, z_arm - 0.24), (bx, by, z_arm - 0.3), 0.012), (240, 240, 240))
    asm.add(bar((bx, by, z_arm - 0.3), (0.03, 0.0, 1.25), 0.005), (226, 236, 240))
    if rng.uniform() < 0.6:
        pump = pick(rng, "medical")
        asm.box((-0.07, 0.015, 1.05), (0.07, 0.12, 1.22), pump)
        asm.box((-0.05, 0.12, 1.14), (0.05, 0.123, 1.2), (30, 60, 80))
    return asm


def _medical_cart(rng: np.random.Generator, size: Size) -> Assembly:
    """A drawer cart on casters with a rimmed top tray, a push handle and a side sharps bin."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    crash = rng.uniform() < 0.3
    body = (190, 40, 40) if crash else pick(rng, "medical")
    drawer = shade(body, 1.08) if crash else pick(rng, "accent")
    frame = pick(rng, "metal")
    x0, x1 = -hx + 0.05, hx - 0.05
    for x in (x0 + 0.05, x1 - 0.05):
        for y in (-hy + 0.06, hy - 0.1):
            caster(asm, x, y, 0.04, (40, 40, 42), frame)
    face = hy - FRONT_THICKNESS - HANDLE_DEPTH
    tray_z = h - 0.05
    asm.box((x0, -hy, 0.1), (x1, face, tray_z - 0.04), body)
    drawer_fronts(
        asm,
        x0,
        x1,
        0.12,
        tray_z - 0.05,
        face,
        rows=int(np.clip(round((tray_z - 0.17) / 0.15), 3, 6)),
        cols=1,
        color=drawer,
        handle_color=frame,
    )
    tray = difference(
        box((x0, -hy, tray_z - 0.04), (x1, face + 0.01, tray_z)),
        box((x0 + 0.02, -hy + 0.02, tray_z - 0.02), (x1 - 0.02, face - 0.01, tray_z + 0.01)),
    )
    asm.add(tray, shade(body, 0.9))
    for y in (-hy + 0.06, face - 0.06):
        asm.box((x1, y - 0.01, tray_z - 0.1), (hx - 0.02, y + 0.01, tray_z - 0.08), frame)
        asm.box((hx - 0.04, y - 0.01, tray_z - 0.1), (hx - 0.02, y + 0.01, h - 0.02), frame)
    asm.add(
        cylinder((hx - 0.02, -hy + 0.04, h - 0.02), (hx - 0.02, face - 0.04, h - 0.02), 0.02, sections=12),
        frame,
    )
    asm.box((-hx, -0.1, tray_z - 0.3), (x0, 0.06, tray_z - 0.08), (240, 200, 40))
    asm.box((-hx + 0.005, -0.08, tray_z - 0.08), (x0 - 0.005, 0.04, tray_z - 0.07), (200, 40, 40))
    return asm


def _wheelchair(rng: np.random.Generator, size: Size) -> Assembly:
    """Big rear wheels with hand rims, front casters, sling seat and back, armrests, handles, footrests."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    frame = pick(rng, "chrome") if rng.uniform() < 0.6 else pick(rng, "dark_metal")
    sling = pick(rng, "leather") if rng.uniform() < 0.5 else pick(rng, "fabric")
    tire = (34, 34, 36)
    radius = 0.3
    y_axle = -hy + radius
    for sx in (-1.0, 1.0):
        xt = sx * (hx - 0.045)
        asm.add(torus((xt, y_axle, radius), radius - 0.016, 0.016, sections=20, tube=4, axis="x"), tire)
        asm.add(
            cylinder((xt - 0.004, y_axle, radius), (xt + 0.004, y_axle, radius), radius - 0.03, sections=20),
            (200, 202, 206),
        )
        rim_center = (sx * (hx - 0.008), y_axle, radius)
        asm.add(torus(rim_center, radius - 0.04, 0.008, sections=20, tube=4, axis="x"), frame)
        asm.add(cylinder((sx * (hx - 0.12), y_axle, radius), (xt, y_axle, radius), 0.02, sections=8), frame)
        xf = sx * (hx - 0.13)
        caster(asm, xf, hy - 0.17, 0.06, tire, frame)
        xs = sx * (hx - 0.1)
        asm.add(bar((xs, y_axle - 0.04, 0.48), (xs, hy - 0.17, 0.48), 0.025), frame)
        asm.add(bar((xs, hy - 0.17, 0.48), (xf, hy - 0.17, 0.14), 0.022), frame)
        asm.add(bar((xs, y_axle, radius), (xs, y_axle - 0.04, 0.48), 0.022), frame)
        asm.add(bar((xs, y_axle - 0.04, 0.46), (xs, -hy + 0.06, h - 0.02), 0.022), frame)
        asm.add(cylinder((xs, -hy + 0.06, h - 0.02), (xs, -hy, h - 0.02), 0.02, sections=8), tire)
        asm.add(bar((xs, y_axle + 0.02, 0.7), (xs, y_axle + 0.3, 0.7), (0.05, 0.03, 0.03)), tire)
        asm.add(bar((xs, y_axle + 0.3, 0.7), (xs, y_axle + 0.3, 0.48), 0.02), frame)
        asm.add(bar((xs, hy - 0.15, 0.45), (xs, hy - 0.05, 0.12), 0.02), frame)
        plate_x = sorted((sx * 0.02, sx * (hx - 0.1)))
        asm.box((plate_x[0], hy - 0.14, 0.09), (plate_x[1], hy, 0.11), (50, 50, 54))
    asm.box((-hx + 0.1, y_axle - 0.05, 0.46), (hx - 0.1, y_axle + 0.38, 0.5), sling)
    back = bar((0.0, y_axle - 0.05, 0.52), (0.0, -hy + 0.07, h - 0.08), (w - 0.22, 0.02, 0.02))
    asm.add(back, sling)
    return asm


def _privacy_screen(rng: np.random.Generator, size: Size) -> Assembly:
    """A folding ward screen: three or four fabric panels zig-zagging between posts on casters."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    frame = pick(rng, "chrome")
    fabric = pick(rng, "medical")
    panels = 3 if w < 1.8 else 4
    joints = [
        (-hx + 0.015 + k * (w - 0.03) / panels, (hy - 0.035) * (1.0 if k % 2 == 0 else -1.0))
        for k in range(panels + 1)
    ]
    for x, y in joints:
        asm.add(cylinder((x, y, 0.08), (x, y, h), 0.015, sections=12), frame)
        caster(asm, x, y, 0.035, (40, 40, 42), frame)
    for (xa, ya), (xb, yb) in itertools.pairwise(joints):
        asm.add(bar((xa, ya, h - 0.03), (xb, yb, h - 0.03), 0.02), frame)
        asm.add(bar((xa, ya, 0.25), (xb, yb, 0.25), 0.02), frame)
        points = [(x, y, z) for x, y in ((xa, ya), (xb, yb)) for z in (0.27, h - 0.05)]
        normal = np.array([-(yb - ya), xb - xa, 0.0])
        normal = 0.004 * normal / np.linalg.norm(normal)
        asm.add(hull([np.array(p) + s * normal for p in points for s in (-1.0, 1.0)]), fabric)
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "hospital_bed",
        (0.95, 2.10, 0.90),
        (1.05, 2.25, 1.10),
        "wall",
        None,
        0.9,
        "metal",
        _hospital_bed,
        contexts=("hospital",),
    ),
    Asset(
        "iv_stand",
        (0.50, 0.50, 1.70),
        (0.65, 0.65, 2.10),
        "floor",
        None,
        0.3,
        "metal",
        _iv_stand,
        contexts=("hospital",),
    ),
    Asset(
        "medical_cart",
        (0.60, 0.45, 0.90),
        (0.85, 0.60, 1.10),
        "floor",
        None,
        0.6,
        "plastic",
        _medical_cart,
        supports=top_support(inset=0.07, top_drop=0.07),
        contexts=("hospital",),
    ),
    Asset(
        "wheelchair",
        (0.60, 0.90, 0.88),
        (0.70, 1.10, 0.98),
        "floor",
        None,
        0.6,
        "metal",
        _wheelchair,
        contexts=("hospital", "retail"),
    ),
    Asset(
        "privacy_screen",
        (1.20, 0.45, 1.60),
        (2.40, 0.60, 1.85),
        "floor",
        None,
        0.3,
        "fabric",
        _privacy_screen,
        contexts=("hospital",),
    ),
)
