"""Vehicles: sedan, hatchback, suv, van, pickup_truck, bus, box_truck, motorcycle, bicycle, motor_scooter
and kick_scooter.

Frame conventions of this module
--------------------------------
- The **front of every vehicle faces +y** (headlights, windscreen, front wheel); the rear is at -y.
- x is the vehicle's width: the size includes the wing mirrors (cars, vans, trucks, bus) or the
  handlebar and its mirrors (two-wheelers), y the length bumper to bumper (tyre to tyre for
  two-wheelers), z the height from the ground to the highest point (roof, roof unit or cargo box; the
  mirror, windscreen, handlebar or saddle top of a two-wheeler).
- The wheels stand on the ground (z = 0 in the builder's floor frame); cars keep their left-hand and
  right-hand sides mirror images, the bus has its passenger doors on the +x side (right-hand traffic).
- Car bodies are painted from realistic car-paint colours (white, black, greys and silver dominate),
  windows are dark tinted glass.
"""

from __future__ import annotations

import itertools
import math
from typing import NamedTuple

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
    extrude_along,
    frustum,
    hull,
    rounded_prism,
    rounded_rectangle,
    torus,
)
from navverse.assets.spec import Asset, Size

__all__ = ["ASSETS"]

# -- colours ------------------------------------------------------------------------------------------

# car paints with rough market shares (white, black, grey and silver make up ~80 % of new cars)
_CAR_PAINT: tuple[tuple[RGB, float], ...] = (
    ((236, 236, 234), 0.22),  # white
    ((222, 220, 212), 0.06),  # pearl white
    ((22, 23, 26), 0.17),  # black
    ((178, 182, 186), 0.12),  # silver
    ((106, 110, 114), 0.12),  # grey
    ((62, 64, 68), 0.06),  # dark grey
    ((28, 42, 84), 0.06),  # dark blue
    ((42, 88, 162), 0.04),  # blue
    ((168, 24, 30), 0.07),  # red
    ((96, 20, 28), 0.02),  # burgundy
    ((40, 70, 52), 0.02),  # dark green
    ((196, 182, 152), 0.02),  # beige
    ((206, 108, 32), 0.01),  # orange
    ((226, 186, 40), 0.01),  # yellow
    ((110, 78, 56), 0.01),  # brown
)
# city-bus liveries and delivery-truck cab colours
_LIVERY: tuple[RGB, ...] = (
    (238, 238, 236),
    (232, 186, 28),
    (190, 30, 36),
    (30, 82, 160),
    (36, 130, 72),
    (226, 108, 30),
    (180, 184, 188),
    (20, 120, 140),
)
# motorcycle tanks and fairings, bicycle frames
_MOTO_PAINT: tuple[RGB, ...] = (
    (22, 22, 24),
    (186, 24, 28),
    (30, 70, 160),
    (232, 110, 24),
    (90, 160, 40),
    (236, 236, 232),
    (226, 190, 30),
    (110, 112, 116),
    (20, 110, 120),
)
# Vespa-like scooters: pastels as well as the classic red, white, black and grey
_SCOOTER_PAINT: tuple[RGB, ...] = (
    (170, 214, 198),
    (236, 226, 196),
    (150, 190, 216),
    (184, 28, 36),
    (238, 238, 234),
    (28, 28, 30),
    (120, 124, 122),
    (232, 196, 60),
    (214, 120, 110),
)
_GLASS: tuple[RGB, ...] = ((32, 38, 46), (24, 28, 34), (44, 54, 62), (38, 46, 56))
_TYRE: RGB = (28, 28, 30)
_DARK: RGB = (34, 34, 38)
_HEADLIGHT: RGB = (226, 230, 232)
_TAIL: RGB = (176, 22, 26)
_AMBER: RGB = (236, 142, 30)
_PLATE_EU: RGB = (236, 236, 230)
_PLATE_US: RGB = (226, 228, 222)
_BRIGHTNESS = (0.94, 1.06)
"""Range of the brightness factor of the colours drawn from the palettes above (:func:`pick`)."""


def _car_paint(rng: np.random.Generator) -> RGB:
    """A body colour drawn by market share, its brightness varied by a few percent."""
    weights = np.array([w for _, w in _CAR_PAINT])
    base = _CAR_PAINT[int(rng.choice(len(_CAR_PAINT), p=weights / weights.sum()))][0]
    return shade(base, float(rng.uniform(0.95, 1.05)))


# -- geometry helpers --------------------------------------------------------------------------------


def _slab(points: np.ndarray, normal: np.ndarray, t0: float = 0.002, t1: float = 0.01) -> Solid:
    """A thin panel over planar `points`, lifted `t0` to `t1` along the unit `normal` (windows, lights)."""
    pts = np.asarray(points, dtype=np.float64)
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    return hull(np.concatenate([pts + t0 * n, pts + t1 * n]))


def _wheel_yz(center: tuple[float, float, float], radius: float, tube: float, *, sections: int = 16) -> Solid:
    """A tyre as a torus in the y-z plane (axle along x), outer radius `radius`."""
    return torus(center, radius - tube, tube, sections=sections, tube=6, axis="x")


def _spokes(
    asm: Assembly, center: tuple[float, float, float], r0: float, r1: float, count: int, t: float, color: RGB
) -> None:
    """Radial spokes in the y-z plane around `center`, from radius `r0` to `r1`."""
    x, y, z = center
    for k in range(count):
        a = 2.0 * math.pi * (k + 0.5) / count
        c, s = math.cos(a), math.sin(a)
        asm.add(bar((x, y + r0 * c, z + r0 * s), (x, y + r1 * c, z + r1 * s), t), color)


def _car_wheel(
    asm: Assembly,
    x_out: float,
    y: float,
    radius: float,
    width: float,
    hub: RGB,
    *,
    spokes: int = 5,
    dual: bool = False,
) -> None:
    """A tyre with its outer face at ``x = x_out`` (sign gives the side), a rim disc, spokes and a cap."""
    sx = 1.0 if x_out > 0 else -1.0
    x_in = x_out - sx * width * (2.04 if dual else 1.0)
    asm.add(cylinder((x_in, y, radius), (x_out, y, radius), radius, sections=16), _TYRE)
    if dual:  # the inner tyre of twin rear wheels shows as a groove between two treads
        asm.add(
            cylinder(
                (x_out - sx * width, y, radius),
                (x_out - sx * 1.04 * width, y, radius),
                radius - 0.012,
                sections=16,
            ),
            shade(_TYRE, 0.7),
        )
    rim = 0.64 * radius
    asm.add(
        cylinder((x_out - sx * 0.03, y, radius), (x_out + sx * 0.004, y, radius), rim, sections=16),
        shade(hub, 0.55),
    )
    if spokes:
        for k in range(spokes):
            a = 2.0 * math.pi * k / spokes + 0.3
            asm.add(
                bar(
                    (x_out + sx * 0.008, y, radius),
                    (x_out + sx * 0.008, y + 0.9 * rim * math.cos(a), radius + 0.9 * rim * math.sin(a)),
                    (0.012, 0.055 * radius / 0.33, 0.055 * radius / 0.33),
                ),
                hub,
            )
        asm.add(cylinder((x_out, y, radius), (x_out + sx * 0.016, y, radius), 0.2 * rim, sections=12), hub)
    else:  # a plain steel or covered wheel
        asm.add(cylinder((x_out, y, radius), (x_out + sx * 0.01, y, radius), 0.8 * rim, sections=16), hub)


def _plate(asm: Assembly, y_face: float, z: float, sign: float, eu: bool) -> None:
    """A licence plate centred at height `z` on the face ``y = y_face``, sticking out towards `sign`."""
    pw, ph = (0.52, 0.11) if eu else (0.305, 0.152)
    ya, yb = sorted((y_face, y_face + sign * 0.012))
    asm.box((-0.5 * pw, ya, z - 0.5 * ph), (0.5 * pw, yb, z + 0.5 * ph), _PLATE_EU if eu else _PLATE_US)


# -- cars -------------------------------------------------------------------------------------------


class _Car(NamedTuple):
    """Proportions of a car body; lengths in m, `glass` and `pillars` as fractions."""

    wheel: tuple[float, float]  # tyre radius range
    tyre: tuple[float, float]  # tyre width range
    overhang: tuple[float, float]  # front and rear overhang as fractions of the body length
    clearance: float  # body bottom above the ground
    belt: float  # beltline (bottom of the side windows) as a fraction of the height
    belt_max: float  # ... but at most this high
    nose: float  # front edge of the hood below the beltline
    deck: float  # rear deck (boot lid) below the beltline
    glass: tuple[float, float, float, float]  # greenhouse base rear, roof rear, roof front, base front
    tumble: float  # roof narrower than the greenhouse base, per side
    pillars: tuple[float, ...]  # B (C) pillars as fractions of the roof length from its rear
    rear_pillar: float  # width of the rearmost pillar
    window: float  # tallest side window
    mirror: float  # mirror reach beyond the body, per side
    bumper: float  # bumper top as a fraction of the height


_SEDAN = _Car(
    wheel=(0.31, 0.34),
    tyre=(0.205, 0.245),
    overhang=(0.2, 0.23),
    clearance=0.15,
    belt=0.64,
    belt_max=1.0,
    nose=0.2,
    deck=0.03,
    glass=(0.16, 0.29, 0.55, 0.72),
    tumble=0.13,
    pillars=(0.52,),
    rear_pillar=0.1,
    window=0.5,
    mirror=0.1,
    bumper=0.35,
)
_HATCHBACK = _Car(
    wheel=(0.29, 0.32),
    tyre=(0.185, 0.225),
    overhang=(0.2, 0.15),
    clearance=0.14,
    belt=0.63,
    belt_max=1.0,
    nose=0.17,
    deck=0.0,
    glass=(0.02, 0.12, 0.52, 0.71),
    tumble=0.12,
    pillars=(0.5,),
    rear_pillar=0.16,
    window=0.52,
    mirror=0.09,
    bumper=0.35,
)
_SUV = _Car(
    wheel=(0.35, 0.4),
    tyre=(0.225, 0.275),
    overhang=(0.19, 0.2),
    clearance=0.22,
    belt=0.6,
    belt_max=1.16,
    nose=0.12,
    deck=0.0,
    glass=(0.01, 0.04, 0.58, 0.73),
    tumble=0.11,
    pillars=(0.22, 0.6),
    rear_pillar=0.12,
    window=0.55,
    mirror=0.11,
    bumper=0.32,
)
_MINIVAN = _Car(
    wheel=(0.32, 0.36),
    tyre=(0.215, 0.245),
    overhang=(0.18, 0.2),
    clearance=0.17,
    belt=0.54,
    belt_max=1.05,
    nose=0.26,
    deck=0.0,
    glass=(0.005, 0.03, 0.62, 0.83),
    tumble=0.1,
    pillars=(0.26, 0.64),
    rear_pillar=0.12,
    window=0.6,
    mirror=0.13,
    bumper=0.3,
)
_PANEL_VAN = _Car(
    wheel=(0.33, 0.37),
    tyre=(0.205, 0.235),
    overhang=(0.16, 0.21),
    clearance=0.19,
    belt=0.5,
    belt_max=1.12,
    nose=0.1,
    deck=0.0,
    glass=(0.0, 0.0, 0.76, 0.86),
    tumble=0.06,
    pillars=(0.8,),
    rear_pillar=0.1,
    window=0.72,
    mirror=0.2,
    bumper=0.26,
)
_PICKUP = _Car(
    wheel=(0.38, 0.42),
    tyre=(0.245, 0.285),
    overhang=(0.17, 0.22),
    clearance=0.26,
    belt=0.63,
    belt_max=1.3,
    nose=0.06,
    deck=0.0,
    glass=(0.37, 0.385, 0.63, 0.74),
    tumble=0.1,
    pillars=(0.5,),
    rear_pillar=0.08,
    window=0.5,
    mirror=0.17,
    bumper=0.3,
)


def _car(
    rng: np.random.Generator,
    size: Size,
    style: _Car,
    *,
    bed: bool = False,
    panel: bool = False,
    rails: bool = False,
    spare: bool = False,
    contrast_roof: bool = False,
) -> Assembly:
    """A car body from a side profile: lower body with wheel arches, glass-house, roof, wheels, lights."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    paint = _car_paint(rng)
    glass = pick(rng, _GLASS, brightness=_BRIGHTNESS)
    trim = _DARK if rng.uniform() < 0.45 else shade(paint, 0.94)
    if bed or panel:
        trim = _DARK if rng.uniform() < 0.6 else ((196, 200, 204) if bed else trim)
    hub = ((198, 200, 204), (150, 154, 160), (60, 62, 66), (40, 40, 42))[int(rng.integers(4))]
    spokes = 0 if (panel and rng.uniform() < 0.6) else int(rng.integers(5, 7))
    eu = rng.uniform() < 0.5
    radius = float(rng.uniform(*style.wheel))
    tyre_w = float(rng.uniform(*style.tyre))

    hw = hx - style.mirror  # body half width
    y0, y1 = (-hy + 0.26 if spare else -hy + 0.04), hy - 0.04
    length = y1 - y0
    zc = style.clearance
    z_belt = min(style.belt * h, style.belt_max)
    z_nose, z_deck = z_belt - style.nose, z_belt - style.deck
    g0, g1, g2, g3 = (y0 + g * length for g in style.glass)
    h_roof = h - (0.07 if rails else 0.0)
    zr, zb = h_roof - 0.03, z_belt - 0.04
    y_front_axle = y1 - style.overhang[0] * length
    y_rear_axle = y0 + style.overhang[1] * length

    # lower body: a side profile with chamfered plan corners and a rounded shoulder, wheel arches cut out
    c = 0.1
    profile = [
        (y0 + 0.12, zc),
        (y1 - 0.12, zc),
        (y1, zc + 0.14),
        (y1, z_nose - 0.07),
        (y1 - 0.1, z_nose),
        (g3, z_belt),
        (max(g0, y0 + 0.1), z_belt),
        (y0 + 0.1, z_deck),
        (y0, z_deck - 0.06),
        (y0, zc + 0.14),
    ]
    points = []
    for y, z in profile:
        for sx in (-1.0, 1.0):
            points.append((sx * (hw - c), y, z))
            points.append((sx * hw, float(np.clip(y, y0 + c, y1 - c)), z - 0.05 if z > zc + 0.15 else z))
    body = hull(points)
    cutters = [
        cylinder((sx * (hw - 0.3), ya, radius), (sx * (hw + 0.05), ya, radius), radius + 0.04, sections=16)
        for ya in (y_front_axle, y_rear_axle)
        for sx in (-1.0, 1.0)
    ]
    y_bed = g0 - 0.06
    if bed:
        z_floor = max(2.0 * radius + 0.08, z_belt - 0.5)
        cutters.append(box((-(hw - 0.07), y0 + 0.06, z_floor), (hw - 0.07, y_bed, z_belt + 0.3)))
        asm.box((-(hw - 0.07), y0 + 0.06, z_floor - 0.01), (hw - 0.07, y_bed, z_floor + 0.005), _DARK)
    asm.add(difference(body, *cutters), paint)

    # glass-house: body-coloured pillars and roof, tinted windows laid on its faces
    gw0 = hw - 0.06
    gw1 = gw0 - style.tumble

    def x_side(z: float) -> float:
        return gw0 + (gw1 - gw0) * (z - zb) / (zr - zb)

    def on_line(y_base: float, y_roof: float, z: float) -> float:
        return y_base + (y_roof - y_base) * (z - zb) / (zr - zb)

    asm.add(
        hull(
            [(sx * gw0, y, zb) for sx in (-1, 1) for y in (g0, g3)]
            + [(sx * gw1, y, zr) for sx in (-1, 1) for y in (g1, g2)]
        ),
        paint,
    )
    top = [(sx * (gw1 - 0.05), y, h_roof) for sx in (-1, 1) for y in (g1 + 0.04, g2 - 0.07)]
    roof = hull([(sx * gw1, y, zr) for sx in (-1, 1) for y in (g1, g2)] + top)
    roof_color = paint
    if contrast_roof:
        roof_color = (236, 236, 234) if sum(paint) < 360 else (24, 24, 26)
    asm.add(roof, roof_color)

    slope = -(gw1 - gw0) / (zr - zb)
    z_lo, z_hi = z_belt + 0.04, min(zr - 0.05, zb + style.window)
    pillars = [g1 + f * (g2 - g1) for f in sorted(style.pillars)]
    edges = [lambda z: on_line(g0, g1, z) + style.rear_pillar]
    for p in pillars:
        edges += [lambda z, p=p: p - 0.045, lambda z, p=p: p + 0.045]
    edges.append(lambda z: on_line(g3, g2, z) - 0.08)
    panes = list(zip(edges[::2], edges[1::2], strict=True))
    if panel:
        panes = panes[-1:]
    for fa, fb in panes:
        if min(fb(z_lo) - fa(z_lo), fb(z_hi) - fa(z_hi)) < 0.1:
            continue
        for sx in (-1.0, 1.0):
            corners = [
                (sx * x_side(z_lo), fa(z_lo), z_lo),
                (sx * x_side(z_lo), fb(z_lo), z_lo),
                (sx * x_side(z_hi), fb(z_hi), z_hi),
                (sx * x_side(z_hi), fa(z_hi), z_hi),
            ]
            asm.add(_slab(np.array(corners), np.array([sx, 0.0, slope])), glass)
    # windscreen and rear window
    zl, zh = zb + 0.06, min(zr - 0.05, zb + style.window + 0.2)
    corners = [
        (sx * (x_side(z) - 0.08), on_line(g3, g2, z), z) for z, sx in ((zl, -1), (zl, 1), (zh, 1), (zh, -1))
    ]
    asm.add(_slab(np.array(corners), np.array([0.0, 1.0, -(g2 - g3) / (zr - zb)])), glass)
    zl, zh = zb + 0.07, min(zr - 0.06, zb + style.window + 0.1)
    inset = 0.3 if bed else 0.1
    rear_n = np.array([0.0, -1.0, (g1 - g0) / (zr - zb)])
    spans = ((-1.0, 0.0, -0.05), (0.05, 0.0, 1.0)) if panel else ((-1.0, 0.0, 1.0),)
    for a, _, b in spans:
        corners = []
        for z in (zl, zh):
            xa = -(x_side(z) - inset) if a < -0.5 else a
            xb = x_side(z) - inset if b > 0.5 else b
            corners += [(xa, on_line(g0, g1, z), z), (xb, on_line(g0, g1, z), z)]
        asm.add(_slab(np.array(corners), rear_n), glass)

    # wheels
    for ya in (y_front_axle, y_rear_axle):
        for sx in (-1.0, 1.0):
            _car_wheel(asm, sx * (hw - 0.025), ya, radius, tyre_w, hub, spokes=spokes)

    # bumpers, grille, plates, lights
    z_bump = style.bumper * h
    for sign in (1.0, -1.0):
        yc = hy - 0.112 if sign > 0 else y0 - 0.028 + 0.1
        asm.add(rounded_prism((0.0, yc), 2.0 * hw - 0.04, 0.2, 0.09, zc + 0.03, z_bump), trim)
        face = yc + sign * 0.1
        _plate(asm, face, 0.5 * (zc + 0.03 + z_bump), sign, eu)
    light_w, light_h = float(rng.uniform(0.26, 0.4)), float(rng.uniform(0.08, 0.13))
    grille = _DARK if rng.uniform() < 0.7 else (196, 200, 204)
    gx = hw - c - light_w - 0.03
    asm.box((-gx, y1 - 0.04, z_bump - 0.03), (gx, y1 + 0.01, z_nose - 0.08), grille)
    tail_w = float(rng.uniform(0.2, 0.34))
    vertical_tail = bed or panel or (style.deck == 0.0 and rng.uniform() < 0.5)
    for sx in (-1.0, 1.0):
        xa, xb = sorted((sx * (hw - c - light_w), sx * (hw - c - 0.01)))
        asm.box((xa, y1 - 0.05, z_nose - 0.07 - light_h), (xb, y1 + 0.012, z_nose - 0.07), _HEADLIGHT)
        if vertical_tail:
            xa, xb = sorted((sx * (hw - c - 0.1), sx * (hw - c - 0.01)))
            za, zt = z_bump + 0.06, z_belt + 0.12 if panel else z_belt - 0.04
        else:
            xa, xb = sorted((sx * (hw - c - tail_w), sx * (hw - c - 0.01)))
            za, zt = z_deck - 0.2, z_deck - 0.08
        asm.box((xa, y0 - 0.012, za), (xb, y0 + 0.05, zt), _TAIL)
        xa, xb = sorted((sx * (hw - c - 0.05), sx * (hw - c - 0.005)))
        asm.box((xa, y1 - 0.04, z_nose - 0.07 - light_h), (xb, y1 + 0.016, z_nose - 0.07), _AMBER)

    # mirrors and door handles
    mirror_color = paint if rng.uniform() < 0.6 else _DARK
    y_m, z_m = g3 - 0.12, z_belt + 0.1
    tall = 0.1 if panel or bed else 0.065
    handles = [pillars[-1] - 0.17 if pillars else g0 + 0.25]
    if len(pillars) > 1 and not panel:
        handles.append(pillars[0] - 0.17)
    handle = paint if rng.uniform() < 0.5 else ((196, 200, 204) if rng.uniform() < 0.4 else _DARK)
    for sx in (-1.0, 1.0):
        xa, xb = sorted((sx * (hw - 0.12), sx * (hx - 0.08)))
        asm.box((xa, y_m - 0.02, z_m - 0.02), (xb, y_m + 0.03, z_m + 0.02), mirror_color)
        xa, xb = sorted((sx * (hx - 0.11), sx * hx))
        asm.box((xa, y_m - 0.05, z_m - tall + 0.01), (xb, y_m + 0.06, z_m + tall), mirror_color)
        for y in handles:
            xa, xb = sorted((sx * (hw - 0.012), sx * (hw + 0.012)))
            asm.box((xa, y - 0.08, z_belt - 0.14), (xb, y + 0.08, z_belt - 0.11), handle)

    if rails:
        rail = (40, 40, 42) if rng.uniform() < 0.6 else (176, 180, 184)
        for sx in (-1.0, 1.0):
            x = sx * (gw1 - 0.1)
            asm.add(bar((x, g1 + 0.2, h - 0.025), (x, g2 - 0.15, h - 0.025), (0.035, 0.02, 0.05)), rail)
            for y in (g1 + 0.22, g2 - 0.17):
                asm.box((x - 0.018, y - 0.04, h_roof - 0.01), (x + 0.018, y + 0.04, h - 0.04), rail)
    if spare:
        zs = max(z_belt - 0.1, zc + radius + 0.05)
        asm.add(cylinder((0.0, -hy + 0.01, zs), (0.0, y0 + 0.01, zs), radius, sections=16), _TYRE)
        cover = paint if rng.uniform() < 0.5 else _DARK
        asm.add(cylinder((0.0, -hy, zs), (0.0, -hy + 0.02, zs), radius * 0.8, sections=16), cover)
    return asm


def _sedan(rng: np.random.Generator, size: Size) -> Assembly:
    """A three-box saloon: long hood, glass-house with B pillars, boot lid, four doors."""
    return _car(rng, size, _SEDAN)


def _hatchback(rng: np.random.Generator, size: Size) -> Assembly:
    """A two-box compact with a steep hatch, three or five doors, sometimes a contrasting roof."""
    style = _HATCHBACK if rng.uniform() < 0.7 else _HATCHBACK._replace(pillars=(0.3,), rear_pillar=0.28)
    return _car(rng, size, style, contrast_roof=rng.uniform() < 0.25)


def _suv(rng: np.random.Generator, size: Size) -> Assembly:
    """A tall two-box SUV on big wheels, often with roof rails, sometimes a tailgate spare wheel."""
    return _car(rng, size, _SUV, rails=rng.uniform() < 0.55, spare=rng.uniform() < 0.2)


def _van(rng: np.random.Generator, size: Size) -> Assembly:
    """A one-box van: a minivan with windows all round, or a high-roof delivery van with panel sides."""
    h = size[2]
    panel = h > 2.05 or (h > 1.8 and rng.uniform() < 0.5)
    if panel:
        return _car(rng, size, _PANEL_VAN, panel=True)
    return _car(rng, size, _MINIVAN, rails=rng.uniform() < 0.3)


def _pickup_truck(rng: np.random.Generator, size: Size) -> Assembly:
    """A pickup: long hood, single or crew cab, open load bed with a tailgate, big wheels."""
    style = _PICKUP
    if rng.uniform() < 0.3:  # single cab: a longer bed, one side window
        style = _PICKUP._replace(glass=(0.5, 0.515, 0.63, 0.74), pillars=())
    return _car(rng, size, style, bed=True)


def _free_spans(a: float, b: float, blocked: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The parts of ``[a, b]`` outside the `blocked` intervals."""
    spans, start = [], a
    for lo, hi in sorted(blocked):
        if lo > start:
            spans.append((start, min(lo, b)))
        start = max(start, hi)
    if start < b:
        spans.append((start, b))
    return [(lo, hi) for lo, hi in spans if hi - lo > 0.2]


def _window_row(
    asm: Assembly,
    x_face: float,
    spans: list[tuple[float, float]],
    z0: float,
    z1: float,
    pitch: float,
    color: RGB,
) -> None:
    """Side windows on the face ``x = x_face`` (sign gives the side): each span split into panes of about
    `pitch` with body-coloured pillars between them."""
    sx = 1.0 if x_face > 0 else -1.0
    xa, xb = sorted((x_face - sx * 0.004, x_face + sx * 0.012))
    for lo, hi in spans:
        count = max(1, round((hi - lo) / pitch))
        step = (hi - lo) / count
        for k in range(count):
            asm.box((xa, lo + k * step + 0.05, z0), (xb, lo + (k + 1) * step - 0.05, z1), color)


def _bus(rng: np.random.Generator, size: Size) -> Assembly:
    """A low-floor city bus: boxy body, window band, two or three doors on +x, roof air conditioning."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    livery = pick(rng, _LIVERY, brightness=_BRIGHTNESS)
    accent = pick(rng, _LIVERY, brightness=_BRIGHTNESS)
    glass = pick(rng, _GLASS, brightness=_BRIGHTNESS)
    hw = hx - 0.2  # mirrors on arms reach 0.2 m beyond the body
    y0, y1 = -hy + 0.05, hy - 0.05
    length = y1 - y0
    scale = length / 12.0
    radius = float(rng.uniform(0.47, 0.5))  # 275/70 R22.5
    zf = 0.3
    z_roof = h - float(rng.uniform(0.22, 0.3))
    y_front_axle, y_rear_axle = y1 - 2.65 * scale, y1 - (2.65 + 5.9) * scale

    centre = np.array([0.0, 0.5 * (y0 + y1)])
    outline = rounded_rectangle(2.0 * hw, length, 0.2) + centre
    inner = rounded_rectangle(2.0 * hw - 0.16, length - 0.12, 0.14) + centre
    points = [(x, y, z) for x, y in outline for z in (zf, z_roof - 0.1)] + [(x, y, z_roof) for x, y in inner]
    cutters = [
        cylinder((sx * (hw - 0.45), ya, radius), (sx * (hw + 0.05), ya, radius), radius + 0.06, sections=16)
        for ya in (y_front_axle, y_rear_axle)
        for sx in (-1.0, 1.0)
    ]
    asm.add(difference(hull(points), *cutters), livery)
    for ya, dual in ((y_front_axle, False), (y_rear_axle, True)):
        for sx in (-1.0, 1.0):
            _car_wheel(asm, sx * (hw - 0.03), ya, radius, 0.28, (176, 180, 184), spokes=0, dual=dual)

    # doors on the +x side: front (ahead of the front axle), middle, sometimes a rear door
    doors = [(y1 - 1.45, y1 - 0.25), (y_rear_axle + radius + 0.25, y_rear_axle + radius + 1.5)]
    if length > 11.0 and rng.uniform() < 0.5:
        doors.append((y_rear_axle - radius - 1.45, y_rear_axle - radius - 0.25))
    frame = _DARK if rng.uniform() < 0.6 else (150, 154, 160)
    z_door = z_roof - 0.3
    for lo, hi in doors:
        asm.box((hw - 0.01, lo, zf + 0.04), (hw + 0.012, hi, z_door), frame)
        mid = 0.5 * (lo + hi)
        for a, b in ((lo + 0.05, mid - 0.02), (mid + 0.02, hi - 0.05)):
            asm.box((hw, a, zf + 0.12), (hw + 0.018, b, z_door - 0.06), glass)
    # window band and livery stripe
    z_win0, z_win1 = 1.15, z_roof - 0.22
    pitch = float(rng.uniform(1.2, 1.6))
    blocked = [(lo - 0.12, hi + 0.12) for lo, hi in doors]
    _window_row(asm, hw, _free_spans(y0 + 0.5, y1 - 0.3, blocked), z_win0, z_win1, pitch, glass)
    _window_row(asm, -hw, _free_spans(y0 + 0.5, y1 - 0.3, []), z_win0, z_win1, pitch, glass)
    if rng.uniform() < 0.6:
        arches = [(ya - radius - 0.1, ya + radius + 0.1) for ya in (y_front_axle, y_rear_axle)]
        right, left = (
            _free_spans(y0 + 0.2, y1 - 0.2, blocked + arches),
            _free_spans(y0 + 0.2, y1 - 0.2, arches),
        )
        for x_face, spans in ((hw, right), (-hw, left)):
            xa, xb = sorted((x_face - 0.004, x_face + (0.008 if x_face > 0 else -0.008)))
            for lo, hi in spans:
                asm.box((xa, lo, 0.62), (xb, hi, 0.9), accent)

    # front: windscreen, destination sign, bumper, lights; rear: engine grille, lights, window
    asm.add(box((-(hw - 0.12), y1 - 0.01, 0.9), (hw - 0.12, y1 + 0.012, z_roof - 0.38)), glass)
    asm.box((-(hw - 0.25), y1 - 0.01, z_roof - 0.34), (hw - 0.25, y1 + 0.012, z_roof - 0.1), _DARK)
    asm.box((-(hw - 0.55), y1 - 0.01, z_roof - 0.28), (hw - 0.55, y1 + 0.016, z_roof - 0.16), _AMBER)
    bumper = _DARK if rng.uniform() < 0.5 else shade(livery, 0.85)
    for sign in (1.0, -1.0):
        ya, yb = sorted((sign * (hy - 0.15), sign * hy))
        asm.box((-(hw - 0.02), ya, zf - 0.05), (hw - 0.02, yb, 0.62), bumper)
    for sx in (-1.0, 1.0):
        xa, xb = sorted((sx * (hw - 0.45), sx * (hw - 0.12)))
        asm.box((xa, y1 - 0.02, 0.66), (xb, y1 + 0.02, 0.8), _HEADLIGHT)
        xa, xb = sorted((sx * (hw - 0.22), sx * (hw - 0.08)))
        asm.box((xa, y0 - 0.02, 0.75), (xb, y0 + 0.02, 1.45), _TAIL)
        # mirror on an arm that reaches out and forward from the top front corner
        asm.add(
            bar((sx * (hw - 0.1), y1 - 0.2, z_roof - 0.35), (sx * (hx - 0.05), y1 - 0.05, 2.05), 0.04), _DARK
        )
        xa, xb = sorted((sx * (hx - 0.1), sx * hx))
        asm.box((xa, y1 - 0.12, 1.55), (xb, y1 - 0.02, 2.08), _DARK)
    asm.box((-(hw - 0.3), y0 - 0.015, 0.7), (hw - 0.3, y0 + 0.02, 1.3), _DARK)
    if rng.uniform() < 0.6:
        asm.box((-(hw - 0.3), y0 - 0.012, 1.6), (hw - 0.3, y0 + 0.02, z_roof - 0.3), glass)
    # roof: air-conditioning unit, sometimes a rear equipment pod (CNG tanks, batteries)
    roof_color = (222, 224, 226) if rng.uniform() < 0.5 else livery
    ac_len = float(rng.uniform(2.4, 3.4))
    yc = y1 - 3.0 * scale - 0.5 * ac_len
    asm.add(
        rounded_prism((0.0, yc), float(rng.uniform(1.5, 1.9)), ac_len, 0.25, z_roof - 0.02, h), roof_color
    )
    if rng.uniform() < 0.5:
        asm.add(
            rounded_prism((0.0, y0 + 2.0 * scale), 1.8, 2.4 * scale, 0.2, z_roof - 0.02, h - 0.06), roof_color
        )
    return asm


def _box_truck(rng: np.random.Generator, size: Size) -> Assembly:
    """A light truck: cab-over or bonneted cab, chassis with twin rear wheels, a tall cargo box."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    cab_color = (238, 238, 236) if rng.uniform() < 0.5 else pick(rng, _LIVERY, brightness=_BRIGHTNESS)
    box_color = (
        (240, 240, 238)
        if rng.uniform() < 0.65
        else pick(rng, (*_LIVERY, (200, 190, 168)), brightness=_BRIGHTNESS)
    )
    glass = pick(rng, _GLASS, brightness=_BRIGHTNESS)
    hb = hx - 0.2  # half width of the cargo box; mirrors reach 0.2 m further
    hc = hb - float(rng.uniform(0.05, 0.15))  # cab half width
    radius = float(rng.uniform(0.39, 0.44))
    bonnet = rng.uniform() < 0.4
    y_cab_front = hy - 0.08
    cab_len = float(rng.uniform(1.55, 1.75))
    hood_len = float(rng.uniform(0.9, 1.15)) if bonnet else 0.0
    y_cab_back = y_cab_front - hood_len - cab_len
    y_box_front = y_cab_back - 0.12
    y_box_back = -hy + 0.06
    z_cab = float(np.clip(0.66 * h, 2.2, 2.6))
    z_floor = float(rng.uniform(0.95, 1.15))
    y_front_axle = y_cab_front - (1.6 if bonnet else 1.05)
    y_rear_axle = y_box_back + float(np.clip(0.24 * d, 1.4, 2.6))

    # chassis rails, fuel tank, wheels (twin tyres at the rear)
    asm.box((-0.5, y_box_back + 0.1, 0.62), (0.5, y_cab_front - 0.3, 0.86), _DARK)
    tank = (176, 180, 184) if rng.uniform() < 0.6 else _DARK
    yt = 0.5 * (y_front_axle + y_rear_axle)
    asm.add(cylinder((-(hc - 0.3), yt - 0.45, 0.62), (-(hc - 0.3), yt + 0.45, 0.62), 0.24, sections=12), tank)
    for ya, dual in ((y_front_axle, False), (y_rear_axle, True)):
        for sx in (-1.0, 1.0):
            _car_wheel(asm, sx * (hc - 0.02), ya, radius, 0.215, (186, 190, 194), spokes=0, dual=dual)
            # mudguard over the wheel
            xa, xb = sorted((sx * (hc - 0.02), sx * (hc - 0.5)))
            if dual:
                asm.box(
                    (xa, ya - radius - 0.08, 2.0 * radius + 0.04), (xb, ya + radius + 0.08, z_floor), _DARK
                )

    # cargo box: panels with aluminium corner posts, a roll-up rear door and a rub rail
    asm.box((-hb, y_box_back, z_floor), (hb, y_box_front, h), box_color)
    alu = (190, 194, 198)
    for sx in (-1.0, 1.0):
        xa, xb = sorted((sx * (hb + 0.004), sx * (hb - 0.045)))
        asm.box((xa, y_box_back - 0.02, z_floor), (xb, y_box_back + 0.045, h), alu)
        asm.box((xa, y_box_front - 0.045, z_floor), (xb, y_box_front + 0.004, h), alu)
    asm.box(
        (-hb - 0.004, y_box_back + 0.05, z_floor - 0.02), (hb + 0.004, y_box_front - 0.05, z_floor + 0.1), alu
    )
    door = shade(box_color, 0.9)
    asm.box((-(hb - 0.08), y_box_back - 0.015, z_floor + 0.1), (hb - 0.08, y_box_back, h - 0.12), door)
    for z in np.linspace(z_floor + 0.4, h - 0.35, int(rng.integers(4, 8))):
        asm.box((-(hb - 0.1), y_box_back - 0.025, z - 0.012), (hb - 0.1, y_box_back - 0.01, z + 0.012), door)
    if rng.uniform() < 0.45:  # a coloured band along both sides
        band = pick(rng, _LIVERY, brightness=_BRIGHTNESS)
        z0 = float(rng.uniform(z_floor + 0.3, h - 0.9))
        for sx in (-1.0, 1.0):
            xa, xb = sorted((sx * hb, sx * (hb + 0.006)))
            asm.box((xa, y_box_back + 0.1, z0), (xb, y_box_front - 0.1, z0 + 0.45), band)
    # rear underrun bar with the tail lights
    asm.box((-(hb - 0.15), -hy, 0.4), (hb - 0.15, -hy + 0.08, 0.55), _DARK)
    for sx in (-1.0, 1.0):
        xa, xb = sorted((sx * (hb - 0.1), sx * (hb - 0.35)))
        asm.box((xa, y_box_back - 0.02, z_floor - 0.14), (xb, y_box_back + 0.05, z_floor - 0.02), _TAIL)
        asm.box((sx * 0.45 - 0.04, -hy + 0.01, 0.5), (sx * 0.45 + 0.04, y_box_back + 0.3, z_floor), _DARK)

    # cab: a rounded block with windscreen and door windows; a bonnet in front of it if conventional
    zc0 = 0.55
    y_face = y_cab_back + cab_len
    cab = hull(
        [(sx * hc, y, z) for sx in (-1, 1) for y in (y_cab_back, y_face) for z in (zc0, z_cab - 0.25)]
        + [(sx * (hc - 0.1), y, z_cab) for sx in (-1, 1) for y in (y_cab_back, y_face - 0.2)]
    )
    asm.add(cab, cab_color)
    zw0 = 1.45 if not bonnet else 1.55
    asm.box((-(hc - 0.12), y_face - 0.01, zw0), (hc - 0.12, y_face + 0.012, z_cab - 0.28), glass)
    for sx in (-1.0, 1.0):
        xa, xb = sorted((sx * (hc - 0.01), sx * (hc + 0.012)))
        asm.box((xa, y_face - 0.85, zw0 + 0.05), (xb, y_face - 0.12, z_cab - 0.3), glass)
        asm.box((xa, y_face - 0.8, 0.45), (xb, y_face - 0.3, 0.55), _DARK)  # step
        # mirror on an arm
        asm.add(
            bar((sx * (hc - 0.05), y_face - 0.1, 1.95), (sx * (hx - 0.05), y_face - 0.1, 1.95), 0.035), _DARK
        )
        xa, xb = sorted((sx * (hx - 0.09), sx * hx))
        asm.box((xa, y_face - 0.15, 1.45), (xb, y_face - 0.05, 2.0), _DARK)
    if bonnet:
        hood = hull(
            [(sx * 0.62, y, z) for sx in (-1, 1) for y in (y_face - 0.1, y_cab_front) for z in (0.6, 1.3)]
            + [(sx * 0.55, y, 1.42) for sx in (-1, 1) for y in (y_face - 0.1, y_cab_front - 0.12)]
        )
        asm.add(hood, cab_color)
        for sx in (-1.0, 1.0):
            xa, xb = sorted((sx * 0.55, sx * (hc - 0.04)))
            asm.add(
                bar(
                    (0.5 * (xa + xb), y_face - 0.05, 1.02),
                    (0.5 * (xa + xb), y_cab_front - 0.25, 1.02),
                    (xb - xa, 0.1, 0.16),
                ),
                _DARK,
            )  # front wings
        front = y_cab_front
    else:
        front = y_face
    grille = _DARK if rng.uniform() < 0.6 else (190, 194, 198)
    asm.box((-0.5, front - 0.02, 0.75), (0.5, front + 0.01, 1.25 if not bonnet else 1.3), grille)
    for sx in (-1.0, 1.0):
        x_out = hc - 0.08 if not bonnet else 0.6
        xa, xb = sorted((sx * x_out, sx * (x_out - 0.28)))
        asm.box((xa, front - 0.02, 0.78), (xb, front + 0.015, 0.92), _HEADLIGHT)
    asm.box(
        (-(hc - 0.02), front - 0.1, 0.35), (hc - 0.02, hy, 0.62), _DARK if rng.uniform() < 0.6 else grille
    )
    return asm


def _arc_guard(yc: float, zc: float, r0: float, r1: float, a0: float, a1: float, half_w: float) -> Solid:
    """A mudguard: the annular sector between radii `r0` and `r1` and angles `a0` to `a1` (radians, 0 =
    +y, counter-clockwise towards +z) around a wheel centre ``(yc, zc)`` in the y-z plane, `half_w` wide
    in x. The angles are narrowed so that the guard stays within the tyre's length (radius `zc`)."""
    limit = math.acos(min(1.0, zc / r1)) + 0.02
    angles = np.linspace(max(a0, limit), min(a1, math.pi - limit), 9)
    outer = [(yc + r1 * math.cos(a), zc + r1 * math.sin(a)) for a in angles]
    inner = [(yc + r0 * math.cos(a), zc + r0 * math.sin(a)) for a in angles[::-1]]
    return extrude_along(outer + inner, -half_w, half_w, axis="x")


def _tube(p0: tuple[float, float, float], p1: tuple[float, float, float], radius: float) -> Solid:
    """A round tube (8 sides) between two points."""
    return cylinder(p0, p1, radius, sections=8)


def _bicycle(rng: np.random.Generator, size: Size) -> Assembly:
    """A road, city or mountain bike: spoked wheels, tube frame, fork, crankset, saddle and handlebar."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    if w < 0.5:
        style = "road"
    elif w > 0.64:
        style = "mtb" if rng.uniform() < 0.7 else "city"
    else:
        style = ("city", "mtb", "road")[int(rng.integers(3)) if w < 0.56 else int(rng.integers(2))]
    frame = pick(rng, (*_MOTO_PAINT, (170, 214, 198), (236, 226, 196)), brightness=_BRIGHTNESS)
    rim_color = (40, 40, 42) if rng.uniform() < 0.5 else (196, 198, 202)
    black = (26, 26, 28)
    tube_r = {"road": 0.014, "city": 0.02, "mtb": 0.028}[style]
    radius = {"road": 0.34, "city": 0.35, "mtb": 0.36}[style] + float(rng.uniform(-0.005, 0.005))
    yr, yf = -hy + radius, hy - radius
    yb, zb = yr + float(rng.uniform(0.41, 0.45)), 0.3 if style == "mtb" else 0.28

    # wheels: tyre, rim, spokes and hub
    for y in (yr, yf):
        asm.add(_wheel_yz((0.0, y, radius), radius, tube_r), _TYRE)
        asm.add(_wheel_yz((0.0, y, radius), radius - 2.0 * tube_r + 0.004, 0.008), rim_color)
        _spokes(asm, (0.0, y, radius), 0.025, radius - 2.0 * tube_r, 12, 0.004, (190, 192, 196))
        asm.add(cylinder((-0.05, y, radius), (0.05, y, radius), 0.022, sections=8), (150, 152, 156))

    # contact points: saddle and handlebar; one of them is the top of the bike
    saddle_top = h if style != "city" else h - float(rng.uniform(0.02, 0.06))
    bar_top = h if style == "city" else h - (0.08 if style == "road" else float(rng.uniform(0.0, 0.05)))
    seat_dir = np.array([0.0, -math.cos(math.radians(73)), math.sin(math.radians(73))])
    head_dir = np.array([0.0, -math.cos(math.radians(71)), math.sin(math.radians(71))])
    bb = np.array([0.0, yb, zb])
    seat_top = bb + seat_dir * (saddle_top - 0.2 - zb) / seat_dir[2]
    post_top = bb + seat_dir * (saddle_top - 0.05 - zb) / seat_dir[2]
    fork_len = 0.5 if style == "mtb" else 0.4
    head_lo = np.array([0.0, yf, radius]) + head_dir * fork_len
    head_hi = head_lo + head_dir * (0.12 if style == "road" else 0.18)
    rear = np.array([0.0, yr, radius])

    asm.add(cylinder(head_lo - head_dir * 0.02, head_hi, tube_r + 0.006, sections=8), frame)
    asm.add(_tube(tuple(bb), tuple(seat_top), tube_r), frame)
    asm.add(_tube(tuple(head_lo + head_dir * 0.02), tuple(bb), tube_r + 0.004), frame)
    if style == "city" and rng.uniform() < 0.6:  # step-through: a low, bent top tube
        knee = bb + np.array([0.0, 0.16, 0.16])
        asm.add(_tube(tuple(head_lo + head_dir * 0.06), tuple(knee), tube_r), frame)
        asm.add(_tube(tuple(knee), tuple(bb + seat_dir * 0.12), tube_r), frame)
    else:
        asm.add(_tube(tuple(seat_top - seat_dir * 0.03), tuple(head_hi - head_dir * 0.03), tube_r), frame)
    for sx in (-1.0, 1.0):
        side = np.array([sx * 0.055, 0.0, 0.0])
        asm.add(_tube(tuple(bb + 0.5 * side), tuple(rear + side), 0.9 * tube_r), frame)
        asm.add(
            _tube(tuple(seat_top - seat_dir * 0.04 + 0.3 * side), tuple(rear + side), 0.8 * tube_r), frame
        )
        fork = black if style == "mtb" else frame
        asm.add(
            _tube(tuple(head_lo + 0.5 * side), (sx * 0.05, yf, radius), 0.012 if style != "mtb" else 0.02),
            fork,
        )
    asm.add(cylinder(tuple(seat_top - seat_dir * 0.02), tuple(post_top), 0.014, sections=8), (170, 172, 176))

    # saddle
    saddle = black if rng.uniform() < 0.7 else (120, 80, 50)
    half = 0.1 if style == "city" else 0.07
    sy = post_top[1]
    asm.add(
        hull(
            [(sx * half, sy - 0.1, z) for sx in (-1, 1) for z in (saddle_top - 0.05, saddle_top)]
            + [(sx * 0.02, sy + 0.16, z) for sx in (-1, 1) for z in (saddle_top - 0.045, saddle_top - 0.008)]
            + [(sx * half * 0.8, sy - 0.13, saddle_top - 0.03) for sx in (-1, 1)]
        ),
        saddle,
    )

    # steerer, stem and handlebar
    stem_top = head_hi + head_dir * max(0.03, (bar_top - 0.015 - head_hi[2]) / head_dir[2])
    asm.add(cylinder(tuple(head_hi), tuple(stem_top), 0.016, sections=8), (60, 62, 66))
    yb_bar = stem_top[1] + (0.09 if style != "city" else -0.02)
    z_bar = bar_top - 0.015
    asm.add(bar(tuple(stem_top), (0.0, yb_bar, z_bar), 0.032), (60, 62, 66))
    metal = (40, 40, 42) if style != "city" else (190, 192, 196)
    if style == "road":
        xe = hx - 0.012
        asm.add(bar((-xe, yb_bar, z_bar), (xe, yb_bar, z_bar), 0.024), metal)
        for sx in (-1.0, 1.0):
            path = [
                (yb_bar, z_bar),
                (yb_bar + 0.08, z_bar - 0.03),
                (yb_bar + 0.07, z_bar - 0.12),
                (yb_bar - 0.03, z_bar - 0.14),
            ]
            for (ya, za), (yb2, zb2) in itertools.pairwise(path):
                asm.add(bar((sx * xe, ya, za), (sx * xe, yb2, zb2), 0.024), black)
            asm.box(
                (sx * xe - 0.012, yb_bar + 0.05, z_bar - 0.02),
                (sx * xe + 0.012, yb_bar + 0.1, z_bar + 0.03),
                black,
            )  # brake hood
    else:
        back = -0.12 if style == "city" else 0.0
        xe = hx - 0.11
        for sx in (-1.0, 1.0):
            asm.add(bar((0.0, yb_bar, z_bar), (sx * xe, yb_bar + back, z_bar), 0.024), metal)
            xa, xb = sorted((sx * (hx - 0.12), sx * hx))
            asm.add(
                cylinder((xa, yb_bar + back, z_bar), (xb, yb_bar + back, z_bar), 0.016, sections=8),
                black if rng.uniform() < 0.7 else (120, 80, 50),
            )
            asm.add(
                bar(
                    (sx * (xe - 0.02), yb_bar + back, z_bar),
                    (sx * (xe - 0.08), yb_bar + back + 0.09, z_bar),
                    0.012,
                ),
                black,
            )  # brake lever

    # drivetrain: chainring, cranks, pedals, chain, rear sprocket
    asm.add(cylinder((0.045, yb, zb), (0.052, yb, zb), 0.1, sections=16), (150, 152, 156))
    asm.add(cylinder((0.045, yr, radius), (0.06, yr, radius), 0.045, sections=12), (150, 152, 156))
    for dz in (0.1, -0.1):
        asm.add(bar((0.055, yb, zb + dz), (0.055, yr, radius + 0.45 * dz), 0.01), (60, 60, 62))
    angle = float(rng.uniform(0.0, math.pi))
    for sx, a in ((1.0, angle), (-1.0, angle + math.pi)):
        end = (sx * 0.085, yb + 0.17 * math.cos(a), zb + 0.17 * math.sin(a))
        asm.add(bar((sx * 0.07, yb, zb), end, (0.012, 0.025, 0.025)), (60, 62, 66))
        xa, xb = sorted((sx * 0.09, sx * 0.17))
        asm.box((xa, end[1] - 0.05, end[2] - 0.012), (xb, end[1] + 0.05, end[2] + 0.012), black)

    if style == "city":
        guard = frame if rng.uniform() < 0.5 else (40, 40, 42)
        asm.add(_arc_guard(yr, radius, radius + 0.01, radius + 0.03, 0.35, 2.9, 0.032), guard)
        asm.add(_arc_guard(yf, radius, radius + 0.01, radius + 0.03, 0.25, 2.6, 0.032), guard)
        rack_z = radius * 2.0 + 0.07
        asm.box((-0.08, yr - 0.18, rack_z - 0.012), (0.08, yr + 0.2, rack_z), (60, 60, 62))
        for sx in (-1.0, 1.0):
            asm.add(bar((sx * 0.07, yr - 0.15, rack_z), (sx * 0.07, yr, radius), 0.01), (60, 60, 62))
        asm.add(
            bar((0.068, yb + 0.05, zb + 0.08), (0.068, yr + 0.08, radius + 0.05), (0.012, 0.03, 0.07)), guard
        )
        if rng.uniform() < 0.5:  # front basket above the front wheel
            lo = (-0.17, stem_top[1] + 0.04, bar_top - 0.33)
            hi = (0.17, min(stem_top[1] + 0.36, hy - 0.1), bar_top - 0.05)
            basket = difference(
                box(lo, hi),
                box(
                    (lo[0] + 0.012, lo[1] + 0.012, lo[2] + 0.012),
                    (hi[0] - 0.012, hi[1] - 0.012, hi[2] + 0.01),
                ),
            )
            asm.add(basket, (150, 110, 70) if rng.uniform() < 0.5 else (40, 40, 42))
        asm.add(
            cylinder(
                (0.0, head_hi[1] + 0.03, head_hi[2] - 0.05),
                (0.0, head_hi[1] + 0.09, head_hi[2] - 0.05),
                0.03,
                sections=8,
            ),
            _HEADLIGHT,
        )
    return asm


def _kick_scooter(rng: np.random.Generator, size: Size) -> Assembly:
    """A standing kick scooter, plain or electric: deck, two small wheels, stem, T-bar with grips."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    electric = rng.uniform() < 0.5
    body = pick(
        rng,
        ((30, 30, 32), (236, 236, 232), (120, 124, 128), (186, 28, 34), (36, 80, 160), (40, 130, 120)),
        brightness=_BRIGHTNESS,
    )
    metal = (176, 180, 184) if rng.uniform() < 0.5 else (44, 44, 48)
    r = float(rng.uniform(0.1, 0.112)) if electric else float(rng.uniform(0.06, 0.1))
    tyre_w = 0.05 if electric else 0.026
    yr, yf = -hy + r, hy - r
    wheel = _TYRE if electric or rng.uniform() < 0.5 else pick(rng, _LIVERY, brightness=_BRIGHTNESS)
    for y in (yr, yf):
        asm.add(cylinder((-0.5 * tyre_w, y, r), (0.5 * tyre_w, y, r), r, sections=16), wheel)
        asm.add(
            cylinder((-0.5 * tyre_w - 0.004, y, r), (0.5 * tyre_w + 0.004, y, r), 0.55 * r, sections=12),
            metal,
        )

    # deck between the wheels, grip tape on top; electric decks are thicker (battery inside)
    z0 = 0.06 if electric else max(0.035, r - 0.02)
    z1 = z0 + (0.06 if electric else 0.028)
    deck_w = 0.16 if electric else float(rng.uniform(0.11, 0.14))
    y_deck0, y_deck1 = yr + 0.5 * r, yf - r - 0.1
    asm.add(rounded_prism((0.0, 0.5 * (y_deck0 + y_deck1)), deck_w, y_deck1 - y_deck0, 0.03, z0, z1), body)
    asm.add(
        rounded_prism(
            (0.0, 0.5 * (y_deck0 + y_deck1) + 0.02),
            deck_w - 0.03,
            y_deck1 - y_deck0 - 0.1,
            0.02,
            z1,
            z1 + 0.004,
        ),
        (36, 36, 38),
    )
    # rear: fender brake over the wheel, joined to the deck
    asm.add(
        _arc_guard(yr, r, r + 0.006, r + 0.02, 0.1, 2.4, 0.5 * tyre_w + 0.008), body if electric else metal
    )
    for sx in (-1.0, 1.0):
        asm.add(
            bar((sx * (0.5 * tyre_w + 0.01), yr, r), (sx * 0.04, y_deck0 + 0.05, 0.5 * (z0 + z1)), 0.014),
            metal,
        )
    # neck, fork and stem, leaning back about 12 degrees
    lean = math.radians(float(rng.uniform(8.0, 14.0)))
    z_bar = h - 0.018
    y_bar = yf - 0.04 - (z_bar - r) * math.tan(lean)
    asm.add(
        bar((0.0, y_deck1 - 0.05, 0.5 * (z0 + z1)), (0.0, yf - 0.04 - 0.1 * math.tan(lean), r + 0.1), 0.04),
        body,
    )
    for sx in (-1.0, 1.0):
        asm.add(
            bar(
                (sx * (0.5 * tyre_w + 0.01), yf, r),
                (sx * 0.035, yf - 0.04 - 0.12 * math.tan(lean), r + 0.12),
                0.014,
            ),
            metal,
        )
    stem_r = 0.024 if electric else 0.017
    asm.add(
        cylinder(
            (0.0, yf - 0.04 - 0.1 * math.tan(lean), r + 0.1), (0.0, y_bar, z_bar - 0.01), stem_r, sections=12
        ),
        body if electric else metal,
    )
    asm.add(cylinder((-hx + 0.12, y_bar, z_bar), (hx - 0.12, y_bar, z_bar), 0.012, sections=8), metal)
    for sx in (-1.0, 1.0):
        xa, xb = sorted((sx * (hx - 0.13), sx * hx))
        asm.add(cylinder((xa, y_bar, z_bar), (xb, y_bar, z_bar), 0.018, sections=8), (30, 30, 32))
        asm.add(bar((sx * 0.1, y_bar, z_bar), (sx * 0.16, y_bar + 0.08, z_bar - 0.01), 0.01), (30, 30, 32))
    if electric:  # display at the stem head, headlight, kickstand
        asm.box((-0.04, y_bar - 0.03, z_bar - 0.02), (0.04, y_bar + 0.04, z_bar + 0.018), (30, 30, 32))
        asm.add(
            cylinder((0.0, y_bar + 0.02, z_bar - 0.15), (0.0, y_bar + 0.05, z_bar - 0.15), 0.022, sections=8),
            _HEADLIGHT,
        )
        asm.box((-0.03, y_deck0 - 0.04, z0 + 0.01), (0.03, y_deck0 + 0.005, z1 - 0.01), _TAIL)
    return asm


def _moto_wheel(asm: Assembly, y: float, radius: float, tube: float, rim: RGB, *, disc: bool) -> None:
    """A motorcycle wheel in the y-z plane: a fat torus tyre, a cast rim and (front) a brake disc."""
    asm.add(_wheel_yz((0.0, y, radius), radius, tube, sections=20), _TYRE)
    inner = radius - 1.6 * tube
    asm.add(cylinder((-0.03, y, radius), (0.03, y, radius), inner, sections=16), shade(rim, 0.6))
    _spokes(asm, (-0.036, y, radius), 0.04, inner, 5, 0.022, rim)
    _spokes(asm, (0.036, y, radius), 0.04, inner, 5, 0.022, rim)
    asm.add(cylinder((-0.07, y, radius), (0.07, y, radius), 0.035, sections=8), (150, 152, 156))
    if disc:
        for sx in (-1.0, 1.0):
            asm.add(
                cylinder((sx * 0.05, y, radius), (sx * 0.056, y, radius), 0.7 * inner, sections=16),
                (176, 178, 182),
            )


def _motorcycle(rng: np.random.Generator, size: Size) -> Assembly:
    """A naked, sport, cruiser or touring motorcycle: wheels, fork, tank, seat, engine, exhaust, bars."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    style = "touring" if h > 1.22 else ("naked", "sport", "cruiser")[int(rng.integers(3))]
    paint = pick(rng, _MOTO_PAINT, brightness=_BRIGHTNESS)
    dark = (30, 30, 32)
    engine = (150, 152, 156) if rng.uniform() < 0.5 else (48, 48, 52)
    rim = (40, 40, 42) if rng.uniform() < 0.6 else (190, 192, 196)
    rf = float(rng.uniform(0.3, 0.33))
    rr = rf + (0.01 if style != "cruiser" else 0.0)
    tube_f = 0.05 if style != "cruiser" else 0.06
    tube_r = 0.075 if style != "cruiser" else 0.08
    yf, yr = hy - rf, -hy + rr
    _moto_wheel(asm, yf, rf, tube_f, rim, disc=True)
    _moto_wheel(asm, yr, rr, tube_r, rim, disc=False)

    # steering head, fork and front mudguard
    # the mirrors (or the touring windscreen) are the top; handlebar and steering head sit below them
    z_bar = {"naked": h - 0.16, "sport": h - 0.2, "cruiser": h - 0.12, "touring": min(1.12, h - 0.2)}[style]
    head_z = z_bar + {"naked": -0.08, "sport": 0.02, "cruiser": -0.2, "touring": -0.1}[style]
    rake = math.radians(32.0 if style == "cruiser" else 25.0)
    fork_len = (head_z - rf) / math.cos(rake)
    head = np.array([0.0, yf - fork_len * math.sin(rake), head_z])
    for sx in (-1.0, 1.0):
        asm.add(
            cylinder((sx * 0.09, yf, rf), (sx * 0.09, head[1], head[2]), 0.026, sections=8),
            (176, 178, 182) if style == "cruiser" else (60, 62, 66),
        )
    asm.box((-0.12, head[1] - 0.06, head[2] - 0.04), (0.12, head[1] + 0.05, head[2]), dark)
    asm.add(_arc_guard(yf, rf, rf + 0.02, rf + 0.04, 0.5, 2.2, 0.07), paint if style != "naked" else dark)

    # frame, swingarm, rear shock
    pivot = np.array([0.0, yr + 0.58, 0.42])
    seat_z = min({"naked": 0.8, "sport": 0.83, "cruiser": 0.68, "touring": 0.85}[style], head_z - 0.1)
    frame = dark if rng.uniform() < 0.6 else (176, 30, 36)
    for sx in (-1.0, 1.0):
        asm.add(
            bar((sx * 0.1, head[1] - 0.05, head[2] - 0.08), (sx * 0.13, pivot[1], pivot[2] + 0.05), 0.045),
            frame,
        )
        asm.add(bar((sx * 0.1, pivot[1], pivot[2]), (sx * 0.1, yr, rr), (0.03, 0.06, 0.06)), dark)
        asm.add(
            bar((sx * 0.09, pivot[1] - 0.05, seat_z - 0.12), (sx * 0.08, yr + 0.25, seat_z - 0.02), 0.03),
            frame,
        )
    asm.add(bar((0.0, pivot[1] - 0.25, 0.5), (0.0, pivot[1] - 0.08, seat_z - 0.1), 0.05), (200, 150, 30))

    # engine block with cylinder(s), exhaust on the right
    ye0, ye1 = pivot[1] - 0.05, head[1] - 0.05
    asm.add(rounded_prism((0.0, 0.5 * (ye0 + ye1)), 0.34, ye1 - ye0, 0.06, 0.24, 0.5), engine)
    if style == "cruiser":  # V-twin
        for a in (-0.45, 0.45):
            top = (0.0, 0.5 * (ye0 + ye1) + 0.3 * math.sin(a), 0.5 + 0.3 * math.cos(a))
            asm.add(frustum((0.0, 0.5 * (ye0 + ye1), 0.45), top, 0.09, 0.07, sections=12), engine)
    else:
        asm.add(
            hull(
                [
                    (sx * 0.17, y, z)
                    for sx in (-1, 1)
                    for y, z in ((ye1 - 0.3, 0.45), (ye1, 0.45), (ye1 - 0.05, 0.68), (ye1 - 0.26, 0.68))
                ]
            ),
            engine,
        )
    exhaust = (186, 188, 192) if rng.uniform() < 0.6 else (48, 48, 52)
    muffler_y1 = yr + float(rng.uniform(0.25, 0.4))
    muffler_y0 = max(yr - 0.1, -hy + 0.05)
    z_m = 0.36 if style != "sport" else 0.5
    asm.add(bar((0.1, ye1 - 0.1, 0.3), (0.17, muffler_y1 + 0.1, z_m - 0.04), 0.04), exhaust)
    asm.add(
        frustum((0.18, muffler_y1 + 0.12, z_m), (0.18, muffler_y0, z_m + 0.05), 0.05, 0.065, sections=12),
        exhaust,
    )

    # tank, seat, tail with the rear light
    tank_y = head[1] - 0.28
    tank_top = min(seat_z + (0.16 if style != "cruiser" else 0.2), head_z + 0.05)
    asm.add(ellipsoid((0.0, tank_y, tank_top - 0.12), (0.17, 0.27, 0.13)), paint)
    seat_color = dark if rng.uniform() < 0.8 else (110, 70, 46)
    seat_front = tank_y - 0.22
    seat_back = yr + (0.1 if style != "cruiser" else 0.25)
    asm.add(
        hull(
            [
                (sx * 0.13, y, z)
                for sx in (-1, 1)
                for y in (seat_front, seat_back + 0.1)
                for z in (seat_z - 0.08, seat_z)
            ]
            + [(sx * 0.08, seat_back, seat_z + 0.02) for sx in (-1, 1)]
        ),
        seat_color,
    )
    cover = paint if rng.uniform() < 0.5 else dark  # side covers between engine and seat
    asm.add(
        hull(
            [
                (sx * 0.12, y, z)
                for sx in (-1, 1)
                for y, z in (
                    (pivot[1] - 0.12, pivot[2] + 0.1),
                    (pivot[1] - 0.12, seat_z - 0.06),
                    (tank_y - 0.1, seat_z - 0.06),
                    (ye0 + 0.1, 0.48),
                )
            ]
        ),
        cover,
    )
    if style == "cruiser":
        asm.add(_arc_guard(yr, rr, rr + 0.03, rr + 0.05, 0.5, 2.6, 0.1), paint)
        tail_y = yr - rr * math.cos(0.5) * 0.9
        asm.box((-0.05, tail_y - 0.03, seat_z - 0.08), (0.05, tail_y + 0.02, seat_z - 0.03), _TAIL)
    else:
        tail = hull(
            [
                (sx * 0.11, y, z)
                for sx in (-1, 1)
                for y, z in (
                    (seat_back + 0.15, seat_z - 0.12),
                    (seat_back + 0.15, seat_z - 0.02),
                    (yr - 0.05, seat_z + 0.02),
                    (yr - 0.05, seat_z + 0.08),
                )
            ]
        )
        asm.add(tail, paint)
        asm.box((-0.06, yr - 0.08, seat_z + 0.02), (0.06, yr - 0.04, seat_z + 0.07), _TAIL)
        asm.add(bar((0.0, yr - 0.02, seat_z - 0.02), (0.0, yr - 0.2, rr + 0.25), (0.03, 0.02, 0.03)), dark)
        asm.box((-0.09, yr - 0.23, rr + 0.17), (0.09, yr - 0.21, rr + 0.3), _PLATE_EU)

    # headlight, fairing, windscreen, handlebar and mirrors
    light_y = head[1] + 0.12
    asm.add(
        cylinder((0.0, light_y - 0.08, head[2] - 0.12), (0.0, light_y, head[2] - 0.12), 0.085, sections=12),
        dark if style in ("naked", "cruiser") else paint,
    )
    asm.add(
        cylinder((0.0, light_y, head[2] - 0.12), (0.0, light_y + 0.01, head[2] - 0.12), 0.075, sections=12),
        _HEADLIGHT,
    )
    y_bar = head[1] - (0.15 if style == "cruiser" else 0.08)
    if style in ("sport", "touring"):
        top = h if style == "touring" else min(h - 0.05, head[2] + 0.15)
        fairing = hull(
            [(sx * 0.07, light_y + 0.06, head[2] - 0.16) for sx in (-1, 1)]
            + [(sx * 0.12, light_y + 0.01, z) for sx in (-1, 1) for z in (head[2] - 0.26, head[2] + 0.02)]
            + [(sx * 0.23, head[1] - 0.2, z) for sx in (-1, 1) for z in (head[2] - 0.3, head[2] + 0.03)]
            + [(sx * 0.2, head[1] - 0.34, 0.45) for sx in (-1, 1)]
        )
        asm.add(fairing, paint)
        screen = np.array(
            [
                (sx * 0.14, light_y - 0.02 - k * 0.16, head[2] + 0.02 + k * (top - head[2] - 0.02))
                for k, sx in ((0, -1), (0, 1), (1, 1), (1, -1))
            ]
        )
        asm.add(_slab(screen, np.array([0.0, 1.0, 0.6]), 0.0, 0.008), (70, 80, 90))
    bar_x = hx - 0.06
    asm.add(
        cylinder((-bar_x + 0.12, y_bar, z_bar), (bar_x - 0.12, y_bar, z_bar), 0.012, sections=8), (60, 62, 66)
    )
    for sx in (-1.0, 1.0):
        xa, xb = sorted((sx * (bar_x - 0.13), sx * bar_x))
        asm.add(cylinder((xa, y_bar, z_bar), (xb, y_bar, z_bar), 0.018, sections=8), dark)
        asm.add(bar((sx * 0.09, y_bar, z_bar), (sx * 0.09, head[1], head[2]), 0.03), (60, 62, 66))
        # mirror: a stem from the bar rising to a head whose top is the top of the bike (unless windscreen)
        m_top = h if style != "touring" else min(h - 0.1, z_bar + 0.28)
        base = (sx * (bar_x - 0.2), y_bar + 0.02, z_bar)
        asm.add(bar(base, (sx * (hx - 0.07), y_bar + 0.04, m_top - 0.05), 0.012), dark)
        xa, xb = sorted((sx * (hx - 0.14), sx * hx))
        asm.box((xa, y_bar + 0.02, m_top - 0.08), (xb, y_bar + 0.06, m_top), dark)
    for sx in (-1.0, 1.0):  # footpegs
        xa, xb = sorted((sx * 0.14, sx * 0.24))
        asm.box((xa, pivot[1] - 0.02, 0.33), (xb, pivot[1] + 0.06, 0.36), dark)
    return asm


def _motor_scooter(rng: np.random.Generator, size: Size) -> Assembly:
    """A Vespa-like scooter: small wheels, floorboard, leg shield, bulging rear body, seat, handlebar."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    paint = pick(rng, _SCOOTER_PAINT, brightness=_BRIGHTNESS)
    seat = (30, 30, 32) if rng.uniform() < 0.7 else (110, 70, 46)
    chrome = (196, 198, 202)
    dark = (34, 34, 36)
    radius = float(rng.uniform(0.2, 0.23))
    yf, yr = hy - radius, -hy + radius
    for y in (yf, yr):
        asm.add(_wheel_yz((0.0, y, radius), radius, 0.055), _TYRE)
        asm.add(cylinder((-0.045, y, radius), (0.045, y, radius), radius - 0.085, sections=16), chrome)
    windscreen = rng.uniform() < 0.3
    top_case = rng.uniform() < 0.3

    # floorboard and leg shield
    y_floor0, y_floor1 = yr + 0.5, yf - 0.34
    asm.add(
        rounded_prism((0.0, 0.5 * (y_floor0 + y_floor1)), 0.34, y_floor1 - y_floor0, 0.04, 0.2, 0.29), paint
    )
    asm.box((-0.15, y_floor0 + 0.02, 0.29), (0.15, y_floor1 - 0.02, 0.3), dark)  # rubber mat
    z_head = min(0.98, h - 0.14)
    shield = hull(
        [(sx * 0.2, y, 0.2) for sx in (-1, 1) for y in (yf - 0.4, yf - 0.3)]
        + [(sx * 0.17, y, z_head - 0.06) for sx in (-1, 1) for y in (yf - 0.47, yf - 0.4)]
        + [(0.0, yf - 0.22, 0.45), (0.0, yf - 0.3, z_head - 0.1)]
    )
    asm.add(shield, paint)
    asm.add(bar((0.0, yf - 0.24, 0.62), (0.0, yf - 0.3, 0.8), (0.05, 0.03, 0.05)), chrome)  # horn cover
    # front: steering column, single-sided link, mudguard
    asm.add(cylinder((0.0, yf - 0.3, 0.55), (0.0, yf - 0.04, 2.0 * radius + 0.06), 0.03, sections=8), dark)
    asm.add(bar((-0.07, yf - 0.06, 2.0 * radius + 0.02), (-0.07, yf, radius), (0.03, 0.05, 0.05)), dark)
    asm.add(_arc_guard(yf, radius, radius + 0.015, radius + 0.05, 0.35, 2.5, 0.085), paint)

    # rear body with the engine under it, seat on top, tail light, exhaust
    sections = (
        (yr + 0.6, 0.15, 0.28, 0.68),
        (yr + 0.38, 0.28, 0.26, 0.74),
        (yr + 0.02, 0.27, 0.3, 0.74),
        (yr - 0.13, 0.13, 0.46, 0.68),
    )
    points = []
    for y, half, z0, z1 in sections:
        for sx in (-1.0, 1.0):
            points += [(sx * 0.6 * half, y, z0), (sx * half, y, 0.5 * (z0 + z1)), (sx * 0.65 * half, y, z1)]
    asm.add(hull(points), paint)
    seat_top = min(0.82, h - 0.26)
    asm.add(
        hull(
            [
                (sx * 0.14, y, z)
                for sx in (-1, 1)
                for y in (yr - 0.04, yr + 0.6)
                for z in (0.7, seat_top - 0.03)
            ]
            + [(sx * 0.1, y, seat_top) for sx in (-1, 1) for y in (yr + 0.02, yr + 0.54)]
        ),
        seat,
    )
    asm.box((-0.06, yr - 0.15, 0.6), (0.06, yr - 0.11, 0.66), _TAIL)
    asm.box((-0.1, yr + 0.12, 0.12), (0.1, yr + 0.5, 0.3), dark)  # engine and swingarm
    asm.add(frustum((0.16, yr + 0.32, 0.24), (0.17, yr - 0.06, 0.3), 0.06, 0.05, sections=12), dark)
    if top_case:
        top = min(h - 0.02, seat_top + 0.32)
        asm.add(rounded_prism((0.0, yr - 0.01), 0.36, 0.32, 0.06, seat_top - 0.02, top), dark)

    # headset with the headlight, handlebar grips, mirrors, optional windscreen
    y_head = yf - 0.45
    asm.add(
        hull(
            [
                (sx * 0.22, y, z)
                for sx in (-1, 1)
                for y in (y_head - 0.1, y_head + 0.1)
                for z in (z_head - 0.05, z_head + 0.06)
            ]
            + [(sx * 0.1, y_head + 0.15, z_head) for sx in (-1, 1)]
        ),
        paint,
    )
    asm.add(cylinder((0.0, y_head + 0.1, z_head), (0.0, y_head + 0.17, z_head), 0.07, sections=12), chrome)
    asm.add(
        cylinder((0.0, y_head + 0.17, z_head), (0.0, y_head + 0.18, z_head), 0.06, sections=12), _HEADLIGHT
    )
    for sx in (-1.0, 1.0):
        xa, xb = sorted((sx * 0.2, sx * (hx - 0.05)))
        asm.add(cylinder((xa, y_head - 0.03, z_head), (xb, y_head - 0.03, z_head), 0.018, sections=8), dark)
        m_top = h if not windscreen else min(h - 0.08, z_head + 0.3)
        asm.add(
            bar((sx * 0.18, y_head, z_head + 0.05), (sx * (hx - 0.06), y_head + 0.02, m_top - 0.04), 0.012),
            chrome,
        )
        asm.add(
            cylinder(
                (sx * (hx - 0.12), y_head + 0.02, m_top - 0.035),
                (sx * hx, y_head + 0.02, m_top - 0.035),
                0.035,
                sections=8,
            ),
            chrome,
        )
        xa, xb = sorted((sx * 0.16, sx * 0.2))
        asm.box((xa, y_head + 0.08, z_head - 0.02), (xb, y_head + 0.12, z_head + 0.01), _AMBER)  # indicators
    if windscreen:
        screen = np.array(
            [
                (-0.2, y_head + 0.12, z_head + 0.05),
                (0.2, y_head + 0.12, z_head + 0.05),
                (0.18, y_head + 0.02, h),
                (-0.18, y_head + 0.02, h),
            ]
        )
        asm.add(_slab(screen, np.array([0.0, 1.0, 0.25]), 0.0, 0.006), (150, 170, 180))
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "sedan",
        (1.92, 4.40, 1.38),  # e.g. Civic 4.67 x 1.80 (2.0 with mirrors) x 1.41, Camry 4.89 x 1.84 x 1.45
        (2.10, 5.05, 1.50),  # BMW 5 series 4.96 x 1.87 x 1.48
        "floor",
        None,
        1.0,
        "metal",
        _sedan,
        contexts=("street", "parking"),
    ),
    Asset(
        "hatchback",
        (1.80, 3.55, 1.42),  # Fiat 500 3.57 x 1.63 x 1.49, Yaris 3.94 x 1.75 x 1.50
        (2.02, 4.35, 1.56),  # Golf 4.28 x 1.79 (2.0 with mirrors) x 1.46
        "floor",
        None,
        1.0,
        "metal",
        _hatchback,
        contexts=("street", "parking"),
    ),
    Asset(
        "suv",
        (2.00, 4.30, 1.60),  # RAV4 4.60 x 1.86 x 1.69, CR-V 4.69 x 1.86 x 1.69
        (2.30, 5.30, 1.95),  # Tahoe 5.35 x 2.06 x 1.93
        "floor",
        None,
        1.0,
        "metal",
        _suv,
        contexts=("street", "parking"),
    ),
    Asset(
        "van",
        (
            2.15,
            4.80,
            1.70,
        ),  # Sienna / Odyssey 5.2 x 2.0 (2.25 with mirrors) x 1.75, VW Transporter 4.9 x 1.9 x 2.0
        (2.50, 6.20, 2.75),  # Transit / Sprinter high roof 5.9-6.0 x 2.05 (2.45 with mirrors) x 2.7
        "floor",
        None,
        1.0,
        "metal",
        _van,
        contexts=("street", "parking"),
    ),
    Asset(
        "pickup_truck",
        (2.05, 5.10, 1.75),  # Hilux 5.33 x 1.86 x 1.82, Tacoma 5.39 x 1.91 x 1.79
        (2.45, 6.10, 2.00),  # F-150 5.89 x 2.03 (2.4 with mirrors) x 1.96, Ram 1500 5.82 x 2.08 x 1.97
        "floor",
        None,
        1.0,
        "metal",
        _pickup_truck,
        contexts=("street", "parking", "construction"),
    ),
    Asset(
        "bus",
        (2.85, 10.50, 2.95),  # midi bus 10.5 m; body 2.50-2.55 m wide plus mirror arms
        (3.05, 12.20, 3.35),  # 12 m city bus (Citaro 12.1 x 2.55 x 3.1, Lion's City 12.2 x 2.55 x 3.3)
        "floor",
        None,
        2.0,
        "metal",
        _bus,
        contexts=("street", "transit"),
    ),
    Asset(
        "box_truck",
        (2.55, 6.00, 2.90),  # 10-14 ft cutaway / Isuzu NPR: 6.3 x 2.0 (2.6 with mirrors) x 3.0
        (2.95, 9.50, 3.90),  # 26 ft box truck: 10.4 x 2.6 x 4.0; Fuso Canter 7.5 t box 8.5 x 2.5 x 3.6
        "floor",
        None,
        1.5,
        "metal",
        _box_truck,
        contexts=("street", "parking"),
    ),
    Asset(
        "bicycle",
        (0.42, 1.60, 0.95),  # road bike: 0.42 m drop bar, 1.65-1.7 m long, saddle ~0.95-1.05 m
        (0.72, 1.85, 1.20),  # mountain bike: 0.72-0.78 m riser bar; city bike 1.85 m long
        "floor",
        None,
        0.5,
        "metal",
        _bicycle,
        contexts=("street", "parking", "park", "plaza"),
    ),
    Asset(
        "kick_scooter",
        (0.38, 0.85, 0.85),  # Micro kick scooter 0.9 x 0.4 x 0.9 (adjustable bar)
        (0.58, 1.20, 1.22),  # e-scooters: Xiaomi M365 1.08 x 0.43 x 1.14, Ninebot Max 1.18 x 0.47 x 1.2
        "floor",
        None,
        0.4,
        "metal",
        _kick_scooter,
        contexts=("street", "parking", "park", "plaza"),
    ),
    Asset(
        "motorcycle",
        (0.70, 1.95, 1.02),  # sport: R6 2.04 x 0.70 x 1.15; naked: CB500F 2.08 x 0.80 x 1.06
        (0.95, 2.35, 1.42),  # cruiser 2.3-2.4 x 0.95; touring / adventure (windscreen) up to 1.4 m
        "floor",
        None,
        0.8,
        "metal",
        _motorcycle,
        contexts=("street", "parking"),
    ),
    Asset(
        "motor_scooter",
        (0.68, 1.75, 1.08),  # Vespa Primavera 1.86 x 0.74 x 1.14, Honda PCX 1.93 x 0.74 x 1.11
        (0.80, 1.98, 1.30),  # Vespa GTS 1.95 x 0.77 x 1.17; with a windscreen up to 1.3
        "floor",
        None,
        0.6,
        "metal",
        _motor_scooter,
        contexts=("street", "parking"),
    ),
)
