"""Shops and supermarkets: checkout counter, shopping cart, refrigerated display, vending machine, shelf
rack, grocery gondola shelf, clothes rack and a bakery display case.

Customers stand at +y: the open side of a chiller, the window of a vending machine, the customer side
of a checkout. The gondola shelf is double-sided (products towards +y and -y).
"""

from __future__ import annotations

import numpy as np

from navverse.assets.fittings import caster
from navverse.assets.materials import RGB, pick, shade
from navverse.assets.parts import (
    Assembly,
    bar,
    box,
    cylinder,
    difference,
    ellipsoid,
    frustum,
    hull,
)
from navverse.assets.spec import Asset, Size, SupportArea

__all__ = ["ASSETS"]

_DARK: RGB = (26, 28, 32)


def _products(
    asm: Assembly,
    rng: np.random.Generator,
    x0: float,
    x1: float,
    y_back: float,
    y_front: float,
    z0: float,
    max_height: float,
) -> None:
    """Facings of products on a shelf between `x0` and `x1`: cartons, or bottles in front of a carton row.

    `y_front` may be smaller than `y_back` (a shelf facing -y).
    """
    sign = 1.0 if y_front > y_back else -1.0
    depth = abs(y_front - y_back)
    x = x0 + 0.005
    while x < x1 - 0.05:
        width = min(float(rng.uniform(0.1, 0.3)), x1 - x)
        height = max_height * float(rng.uniform(0.45, 0.9))
        color = pick(rng, "packaging")
        fill = float(rng.uniform(0.75, 0.98))
        ya, yb = sorted((y_back, y_back + sign * fill * depth))
        if rng.uniform() < 0.82 or width < 0.07:
            asm.box((x + 0.003, ya, z0), (x + width - 0.003, yb, z0 + height), color)
        else:
            bottles = min(3, max(1, int(width / 0.07)))
            r = 0.5 * width / bottles - 0.004
            front = y_back + sign * (fill * depth - r)
            back_a, back_b = sorted((y_back, front - sign * r))
            asm.box(
                (x + 0.003, back_a, z0), (x + width - 0.003, back_b, z0 + 0.8 * height), shade(color, 0.8)
            )
            for k in range(bottles):
                cx = x + (k + 0.5) * width / bottles
                asm.add(cylinder((cx, front, z0), (cx, front, z0 + height), r, sections=6), color)
        x += width


def _shelf_rack(rng: np.random.Generator, size: Size) -> Assembly:
    """Open steel shelving: four posts, shelves with price rails, cross bracing, stocked with products."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    metal = pick(rng, "metal") if rng.uniform() < 0.6 else pick(rng, "white_plastic")
    post = 0.035
    for x in (-hx, hx - post):
        for y in (-hy, hy - post):
            asm.box((x, y, 0.0), (x + post, y + post, h), shade(metal, 0.8))
        xm = x + 0.5 * post
        asm.add(bar((xm, -hy + post, 0.1), (xm, hy - post, 0.5 * h), 0.012), shade(metal, 0.8))
        asm.add(bar((xm, hy - post, 0.5 * h), (xm, -hy + post, h - 0.1), 0.012), shade(metal, 0.8))
    levels = int(np.clip(round(h / 0.4), 3, 6))
    zs = np.linspace(0.1, h - 0.03, levels)
    rail = pick(rng, "accent")
    stocked = float(rng.uniform(0.6, 1.0))
    for k, z in enumerate(zs):
        z = float(z)
        asm.box((-hx + post, -hy, z), (hx - post, hy, z + 0.03), metal)
        asm.box((-hx + post, hy - 0.01, z - 0.03), (hx - post, hy, z + 0.03), rail)
        if k < levels - 1 and rng.uniform() < stocked:
            clear = float(zs[k + 1] - z) - 0.06
            _products(asm, rng, -hx + post, hx - post, -hy + 0.02, hy - 0.03, z + 0.03, clear)
    return asm


def _grocery_shelf(rng: np.random.Generator, size: Size) -> Assembly:
    """A double-sided supermarket gondola: back panel, base decks, stocked shelves on both sides, header."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    metal = pick(rng, "white_plastic") if rng.uniform() < 0.6 else pick(rng, "metal")
    header_h = 0.14
    asm.box((-hx, -0.03, 0.0), (hx, 0.03, h - header_h), shade(metal, 0.92))
    asm.box((-0.4 * w, -0.02, h - header_h), (0.4 * w, 0.02, h), pick(rng, "brand"))
    for x in (-hx, hx - 0.03):
        asm.box((x, -0.04, 0.0), (x + 0.03, 0.04, h - header_h + 0.02), shade(metal, 0.7))
    levels = int(np.clip(round((h - header_h) / 0.42), 3, 4))
    zs = np.linspace(0.12, h - header_h - 0.3, levels)
    for sign in (1.0, -1.0):
        asm.box(
            (-hx, min(0.03 * sign, sign * hy), 0.0),
            (hx, max(0.03 * sign, sign * hy), 0.12),
            shade(metal, 0.85),
        )
        for k, z in enumerate(zs):
            z = float(z)
            reach = hy - 0.02 if k == 0 else hy - 0.08 - 0.02 * k
            if k > 0:
                ya, yb = sorted((0.03 * sign, reach * sign))
                asm.box((-hx + 0.03, ya, z - 0.025), (hx - 0.03, yb, z), metal)
                ra, rb = sorted((reach * sign, (reach - 0.01) * sign))
                asm.box((-hx + 0.03, ra, z - 0.05), (hx - 0.03, rb, z + 0.02), pick(rng, "accent"))
            top = float(zs[k + 1]) - 0.05 if k + 1 < levels else h - header_h - 0.02
            _products(asm, rng, -hx + 0.03, hx - 0.03, 0.035 * sign, (reach - 0.02) * sign, z, top - z - 0.03)
    return asm


def _refrigerated_display(rng: np.random.Generator, size: Size) -> Assembly:
    """An open multideck chiller: carcass with the front cut open, lit canopy, shelves and chilled products;
    sometimes framed glass doors."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    skin = pick(rng, "white_plastic") if rng.uniform() < 0.5 else pick(rng, "dark_metal")
    deck = 0.45
    canopy = h - 0.3
    opening = box((-hx + 0.05, -hy + 0.12, deck), (hx - 0.05, hy + 0.01, canopy))
    asm.add(difference(box((-hx, -hy, 0.0), (hx, hy - 0.005, h)), opening), skin)
    asm.box((-hx + 0.05, hy - 0.006, 0.05), (hx - 0.05, hy, 0.15), _DARK)
    asm.box((-hx + 0.05, hy - 0.006, canopy + 0.08), (hx - 0.05, hy, h - 0.05), pick(rng, "brand"))
    asm.box((-hx + 0.05, -hy + 0.12, canopy - 0.02), (hx - 0.05, hy - 0.05, canopy), (250, 250, 244))
    asm.box((-hx + 0.05, -hy + 0.12, deck), (hx - 0.05, -hy + 0.13, canopy), shade(skin, 1.1))
    shelves = int(rng.integers(3, 5))
    zs = np.linspace(deck, canopy - 0.3, shelves + 1)
    for k, z in enumerate(zs):
        z = float(z)
        front = hy - 0.08 - 0.05 * k
        if k > 0:
            asm.box((-hx + 0.05, -hy + 0.13, z - 0.02), (hx - 0.05, front, z), shade(skin, 0.9))
            asm.box((-hx + 0.05, front - 0.01, z - 0.05), (hx - 0.05, front, z + 0.02), pick(rng, "accent"))
        top = float(zs[k + 1]) if k < shelves else canopy - 0.02
        _products(asm, rng, -hx + 0.06, hx - 0.06, -hy + 0.14, front - 0.02, z, top - z - 0.06)
    if rng.uniform() < 0.4:
        doors = max(2, round((w - 0.1) / 0.7))
        dw = (w - 0.1) / doors
        frame = shade(skin, 0.6)
        for k in range(doors + 1):
            x = -hx + 0.05 + k * dw
            asm.box((x - 0.015, hy - 0.04, deck), (x + 0.015, hy - 0.01, canopy), frame)
        asm.box((-hx + 0.05, hy - 0.04, deck), (hx - 0.05, hy - 0.01, deck + 0.04), frame)
        asm.box((-hx + 0.05, hy - 0.04, canopy - 0.04), (hx - 0.05, hy - 0.01, canopy), frame)
        for k in range(doors):
            x = -hx + 0.05 + (k + 1) * dw - 0.06
            asm.box((x - 0.01, hy - 0.03, deck + 0.4), (x + 0.01, hy - 0.005, canopy - 0.4), (200, 204, 208))
    return asm


def _vending_machine(rng: np.random.Generator, size: Size) -> Assembly:
    """A vending machine: branded cabinet, product window (cut-out) with rows of products, keypad, flap."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    brand = pick(rng, "brand")
    panel_w = 0.24
    win = (-hx + 0.05, hx - panel_w - 0.03, 0.55, h - 0.15)
    cabinet = box((-hx, -hy, 0.03), (hx, hy, h))
    asm.add(difference(cabinet, box((win[0], hy - 0.2, win[2]), (win[1], hy + 0.01, win[3]))), brand)
    for x in (-hx + 0.05, hx - 0.05):
        for y in (-hy + 0.05, hy - 0.05):
            asm.box((x - 0.03, y - 0.03, 0.0), (x + 0.03, y + 0.03, 0.03), _DARK)
    asm.box((win[0], hy - 0.2, win[2]), (win[1], hy - 0.19, win[3]), (236, 236, 236))
    rows = 5
    pitch = (win[3] - win[2]) / rows
    for r in range(rows):
        z = win[2] + r * pitch
        asm.box((win[0], hy - 0.19, z), (win[1], hy - 0.02, z + 0.01), (180, 184, 190))
        _products(asm, rng, win[0] + 0.01, win[1] - 0.01, hy - 0.19, hy - 0.05, z + 0.01, pitch - 0.04)
    px0, px1 = hx - panel_w, hx - 0.03
    asm.box((px0, hy - 0.005, 0.9), (px1, hy, 1.45), _DARK)
    asm.box((px0 + 0.03, hy - 0.003, 1.33), (px1 - 0.03, hy + 0.0, 1.41), (60, 120, 90))
    for r in range(4):
        for c in range(3):
            bx = px0 + 0.05 + c * 0.05
            bz = 1.25 - r * 0.05
            asm.box((bx - 0.015, hy - 0.002, bz - 0.015), (bx + 0.015, hy, bz + 0.015), (200, 200, 200))
    asm.box((-hx + 0.08, hy - 0.005, 0.15), (hx - panel_w - 0.06, hy, 0.42), _DARK)
    asm.box((-hx + 0.02, hy - 0.004, h - 0.13), (hx - 0.02, hy, h - 0.02), shade(brand, 1.3))
    return asm


def _checkout_counter(rng: np.random.Generator, size: Size) -> Assembly:
    """A supermarket checkout: conveyor belt with rollers and rails, scanner, bagging well (cut-out),
    POS monitor on a pole facing the cashier (-y), card terminal facing the customer (+y)."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = pick(rng, "painted") if rng.uniform() < 0.5 else pick(rng, "wood")
    accent = pick(rng, "brand")
    chrome = pick(rng, "chrome")
    top = 0.9
    belt_x1, scan_x, term_x, well_x0 = _checkout_layout(w)
    well = box((well_x0, -hy + 0.06, 0.72), (hx - 0.04, hy - 0.06, top + 0.01))
    asm.add(difference(box((-hx, -hy, 0.06), (hx, hy, top)), well), body)
    asm.box((-hx + 0.03, -hy + 0.03, 0.0), (hx - 0.03, hy - 0.03, 0.06), shade(body, 0.4))
    asm.box((-hx, hy - 0.002, 0.3), (hx, hy, 0.45), accent)
    belt_x0 = -hx + 0.05
    asm.box((belt_x0, -0.3 * d, top), (belt_x1, 0.35 * d, top + 0.02), _DARK)
    for x in (belt_x0, belt_x1):
        asm.add(cylinder((x, -0.3 * d, top + 0.01), (x, 0.35 * d, top + 0.01), 0.02, sections=12), chrome)
    for y in (-0.3 * d - 0.02, 0.35 * d + 0.02):
        asm.box((belt_x0, y - 0.01, top), (belt_x1, y + 0.01, top + 0.06), chrome)
    asm.box((scan_x - 0.15, -0.15, top), (scan_x + 0.15, 0.15, top + 0.004), (40, 60, 70))
    asm.box((scan_x - 0.15, -hy + 0.05, top), (scan_x + 0.15, -hy + 0.13, top + 0.2), _DARK)
    pole_x, pole_y = belt_x1 + 0.02, -hy + 0.08
    asm.add(cylinder((pole_x, pole_y, top), (pole_x, pole_y, h - 0.2), 0.02, sections=12), chrome)
    screen = bar((pole_x, pole_y + 0.03, h - 0.2), (pole_x, pole_y - 0.03, h - 0.02), (0.32, 0.03, 0.03))
    asm.add(screen, _DARK)
    asm.add(cylinder((term_x, hy - 0.1, top), (term_x, hy - 0.1, top + 0.12), 0.015, sections=8), chrome)
    asm.box((term_x - 0.05, hy - 0.14, top + 0.12), (term_x + 0.05, hy - 0.06, top + 0.15), _DARK)
    asm.box((-0.1 * w, -hy, 0.55), (0.1 * w, -hy + 0.002, 0.75), shade(body, 0.8))
    return asm


def _checkout_layout(width: float) -> tuple[float, float, float, float]:
    """Along x: belt end, scanner centre, card terminal, start of the bagging well."""
    belt_x1 = -0.5 * width + 0.05 + 0.45 * width
    scan_x = belt_x1 + 0.2
    term_x = scan_x + 0.25
    return belt_x1, scan_x, term_x, term_x + 0.1


def _checkout_supports(size: Size) -> list[SupportArea]:
    w, d, _ = size
    hx, hy = 0.5 * w, 0.5 * d
    well_x0 = _checkout_layout(w)[3]
    return [
        SupportArea(height=0.72, x_min=well_x0 + 0.03, x_max=hx - 0.07, y_min=-hy + 0.09, y_max=hy - 0.09)
    ]


def _shopping_cart(rng: np.random.Generator, size: Size) -> Assembly:
    """A supermarket trolley: wire basket (thin bars) tapering to the nose at -y, push handle at +y,
    chassis with a bottom tray, four casters."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wire = pick(rng, "chrome")
    handle = pick(rng, "accent")
    wheel = (36, 36, 38)
    r = 0.05
    for x, y in (
        (hx - 0.06, hy - 0.2),
        (-hx + 0.06, hy - 0.2),
        (hx - 0.12, -hy + 0.09),
        (-hx + 0.12, -hy + 0.09),
    ):
        caster(asm, x, y, r, wheel, wire)
    z_chassis = 2 * r + 0.03
    for sx in (-1.0, 1.0):
        asm.add(
            bar((sx * (hx - 0.12), -hy + 0.09, z_chassis), (sx * (hx - 0.06), hy - 0.2, z_chassis), 0.02),
            wire,
        )
    asm.add(bar((-hx + 0.06, hy - 0.2, z_chassis), (hx - 0.06, hy - 0.2, z_chassis), 0.02), wire)
    asm.add(bar((-hx + 0.12, -hy + 0.09, z_chassis), (hx - 0.12, -hy + 0.09, z_chassis), 0.02), wire)
    for x in np.linspace(-hx + 0.14, hx - 0.14, 5):
        asm.add(
            bar((float(x), -hy + 0.12, z_chassis + 0.06), (float(x), hy - 0.24, z_chassis + 0.06), 0.01), wire
        )
    zb, zt = 0.45, h - 0.12
    y_back = hy - 0.14
    t = 0.012
    e = 0.5 * 0.016
    back_top = [np.array([s * (hx - e), y_back, zt]) for s in (-1.0, 1.0)]
    back_bot = [np.array([s * (hx - 0.06), y_back - 0.05, zb]) for s in (-1.0, 1.0)]
    front_top = [np.array([s * (hx - 0.07), -hy + e, zt]) for s in (-1.0, 1.0)]
    front_bot = [np.array([s * (hx - 0.11), -hy + 0.12, zb + 0.05]) for s in (-1.0, 1.0)]
    for a, b in ((back_top, front_top), (back_top, back_top[::-1]), (front_top, front_top[::-1])):
        for i in range(2):
            asm.add(bar(a[i], b[i], 0.016), wire)
    for a, b in ((back_bot, front_bot), (back_top, back_bot), (front_top, front_bot)):
        for i in range(2):
            asm.add(bar(a[i], b[i], t), wire)
    asm.add(bar(back_bot[0], back_bot[1], t), wire)
    asm.add(bar(front_bot[0], front_bot[1], t), wire)
    for i in range(2):  # side walls: vertical wires and two rails
        for f in np.linspace(0.0, 1.0, 9)[1:-1]:
            asm.add(
                bar(
                    front_top[i] + f * (back_top[i] - front_top[i]),
                    front_bot[i] + f * (back_bot[i] - front_bot[i]),
                    t,
                ),
                wire,
            )
        for g in (0.33, 0.66):
            asm.add(
                bar(
                    front_top[i] + g * (front_bot[i] - front_top[i]),
                    back_top[i] + g * (back_bot[i] - back_top[i]),
                    t,
                ),
                wire,
            )
    for top, bottom, n in ((front_top, front_bot, 6), (back_top, back_bot, 7)):  # front and back walls
        for f in np.linspace(0.0, 1.0, n)[1:-1]:
            asm.add(bar(top[0] + f * (top[1] - top[0]), bottom[0] + f * (bottom[1] - bottom[0]), t), wire)
    for f in np.linspace(0.0, 1.0, 7)[1:-1]:  # basket floor
        asm.add(
            bar(
                front_bot[0] + f * (front_bot[1] - front_bot[0]),
                back_bot[0] + f * (back_bot[1] - back_bot[0]),
                t,
            ),
            wire,
        )
    for i, s in enumerate((-1.0, 1.0)):
        asm.add(bar(back_top[i], (s * (hx - 0.04), hy - 0.03, h - 0.03), 0.016), wire)
        asm.add(bar(back_bot[i], (s * (hx - 0.06), hy - 0.2, z_chassis), 0.02), wire)
    asm.add(
        cylinder((-hx + 0.03, hy - 0.015, h - 0.015), (hx - 0.03, hy - 0.015, h - 0.015), 0.015, sections=12),
        handle,
    )
    return asm


def _clothes_rack(rng: np.random.Generator, size: Size) -> Assembly:
    """A garment rail on two uprights and feet, with clothes on hangers."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    metal = pick(rng, "chrome")
    for x in (-hx + 0.02, hx - 0.02):
        asm.add(bar((x, -hy + 0.02, 0.02), (x, hy - 0.02, 0.02), 0.04), metal)
        asm.add(cylinder((x, 0.0, 0.04), (x, 0.0, h - 0.015), 0.015, sections=12), metal)
    asm.add(cylinder((-hx + 0.02, 0.0, h - 0.015), (hx - 0.02, 0.0, h - 0.015), 0.015, sections=12), metal)
    hanger = (60, 44, 30) if rng.uniform() < 0.5 else (30, 30, 32)
    x = -hx + 0.08
    half = min(0.22, hy - 0.02)
    while x < hx - 0.08:
        if rng.uniform() < 0.85:
            length = float(min(rng.uniform(0.6, 1.05), h - 0.45))
            top = h - 0.09
            asm.box((x - 0.004, -0.8 * half, top), (x + 0.004, 0.8 * half, top + 0.015), hanger)
            asm.add(bar((x, 0.0, top + 0.015), (x, 0.0, h - 0.02), 0.006), hanger)
            points = [
                (x + dx, y, z)
                for dx, span, z in (
                    (-0.015, 0.8, top),
                    (0.015, 0.8, top),
                    (-0.025, 1.0, top - length),
                    (0.025, 1.0, top - length),
                )
                for y in (-span * half, span * half)
            ]
            asm.add(hull(points), pick(rng, "fabric" if rng.uniform() < 0.6 else "accent"))
        x += float(rng.uniform(0.05, 0.08))
    return asm


def _display_case(rng: np.random.Generator, size: Size) -> Assembly:
    """A bakery counter: cabinet, cakes and pastries on two tiers, slanted front glass and glass ends."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = pick(rng, "wood") if rng.uniform() < 0.5 else pick(rng, "stainless")
    glass = pick(rng, "glass")
    deck = 0.85
    asm.box((-hx, -hy, 0.08), (hx, hy, deck), body)
    asm.box((-hx + 0.03, -hy + 0.03, 0.0), (hx - 0.03, hy - 0.03, 0.08), shade(body, 0.45))
    asm.box((-hx + 0.03, -hy + 0.05, deck), (hx - 0.03, hy - 0.05, deck + 0.005), (246, 246, 244))
    shelf_z = deck + 0.5 * (h - deck)
    asm.box((-hx + 0.04, -hy + 0.05, shelf_z), (hx - 0.04, 0.1 * d, shelf_z + 0.008), glass)
    for z0, y0, y1 in ((deck + 0.005, -hy + 0.1, hy - 0.12), (shelf_z + 0.008, -hy + 0.1, 0.05 * d)):
        x = -hx + 0.12
        while x < hx - 0.12:
            if rng.uniform() < 0.5:
                r = float(rng.uniform(0.07, 0.1))
                ch = float(rng.uniform(0.05, 0.09))
                c = (x, 0.5 * (y0 + y1), z0)
                asm.add(frustum(c, (c[0], c[1], z0 + ch), r, r, sections=12), pick(rng, "accent"))
                asm.add(
                    frustum((c[0], c[1], z0 + ch), (c[0], c[1], z0 + ch + 0.01), r, 0.9 * r, sections=12),
                    (250, 246, 236),
                )
                x += 2 * r + 0.05
            else:
                for y in np.linspace(y0 + 0.05, y1 - 0.05, 3):
                    asm.add(
                        ellipsoid((x, float(y), z0 + 0.025), (0.045, 0.035, 0.025), segments=6, rings=3),
                        (206, 150, 80),
                    )
                x += 0.14
    front = [
        (x, y, z)
        for x in (-hx + 0.01, hx - 0.01)
        for y, z in ((hy - 0.02, deck), (hy, deck), (-0.1 * d, h - 0.01), (-0.1 * d + 0.02, h - 0.01))
    ]
    asm.add(hull(front), glass)
    asm.box((-hx + 0.01, -hy + 0.05, h - 0.02), (hx - 0.01, -0.1 * d + 0.02, h), glass)
    for x in (-hx, hx - 0.01):
        points = [
            (xx, y, z)
            for xx in (x, x + 0.01)
            for y, z in ((hy, deck), (-hy + 0.05, deck), (-hy + 0.05, h), (-0.1 * d, h))
        ]
        asm.add(hull(points), glass)
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "checkout_counter",
        (1.60, 0.70, 1.20),
        (2.60, 0.95, 1.45),
        "floor",
        None,
        1.0,
        "wood",
        _checkout_counter,
        supports=_checkout_supports,
        contexts=("retail",),
    ),
    Asset(
        "shopping_cart",
        (0.50, 0.80, 0.95),
        (0.62, 1.00, 1.08),
        "floor",
        None,
        0.8,
        "metal",
        _shopping_cart,
        contexts=("retail",),
    ),
    Asset(
        "refrigerated_display",
        (1.20, 0.70, 1.90),
        (2.50, 0.95, 2.10),
        "wall",
        None,
        1.2,
        "metal",
        _refrigerated_display,
        contexts=("retail", "cafe"),
    ),
    Asset(
        "vending_machine",
        (0.75, 0.70, 1.75),
        (1.00, 0.90, 1.95),
        "wall",
        None,
        0.8,
        "metal",
        _vending_machine,
        contexts=("office", "school", "hospital", "retail"),
    ),
    Asset(
        "shelf_rack",
        (0.90, 0.40, 1.50),
        (1.50, 0.60, 2.20),
        "wall",
        None,
        0.9,
        "metal",
        _shelf_rack,
        contexts=("retail", "office", "home"),
    ),
    Asset(
        "grocery_shelf",
        (1.00, 0.90, 1.40),
        (2.50, 1.30, 2.00),
        "floor",
        None,
        1.0,
        "metal",
        _grocery_shelf,
        contexts=("retail",),
    ),
    Asset(
        "clothes_rack",
        (1.00, 0.45, 1.40),
        (1.80, 0.60, 1.75),
        "floor",
        None,
        0.7,
        "metal",
        _clothes_rack,
        contexts=("retail", "home"),
    ),
    Asset(
        "display_case",
        (1.00, 0.60, 1.10),
        (2.00, 0.90, 1.40),
        "floor",
        None,
        1.0,
        "glass",
        _display_case,
        contexts=("cafe", "retail"),
    ),
)
