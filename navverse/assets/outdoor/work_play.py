"""Work and play outdoors: construction-site gear, sports equipment and a baby stroller.

Categories
----------
``traffic_cone``, ``traffic_barrier``, ``sawhorse_barricade``, ``construction_fence``, ``ladder``,
``cargo_pallet``, ``wheelbarrow``, ``toolbox``, ``sandbag_stack`` (construction sites and roadworks);
``soccer_ball``, ``basketball_hoop``, ``skateboard`` (pitches, courts, parks); ``stroller`` (sidewalks,
parks).

Frame conventions
-----------------
The library frame applies (x width, y depth, z up, the side a person uses at +y). In particular:

- Barriers, barricades and the fence panel run along x (their length is the width); their striped or
  meshed faces look to +y and -y, and the depth is that of their feet.
- ``ladder``: the climbing side with the steps faces +y, the rear legs are at -y.
- ``wheelbarrow`` and ``stroller``: the push handles -- where the user walks -- are at +y, the wheel (the
  front wheels) at -y, like the shopping cart of the indoor library.
- ``skateboard``: the length runs along y, the nose at +y and the tail at -y.
- ``basketball_hoop``: the court is at +y; the backboard faces +y with the rim at the +y edge, the base
  and the pole are at -y.
- ``toolbox``: the latches are on the front (+y); the flat lid is a support area.
- ``cargo_pallet``: the top deck is a support area.
- ``soccer_ball``: a size-5 ball, centred like every object; it stands on the floor.
"""

from __future__ import annotations

import math

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
    frustum,
    hull,
    rounded_prism,
    rounded_rectangle,
    torus,
)
from navverse.assets.spec import Asset, Size, top_support

__all__ = ["ASSETS"]

# safety colours (not in the shared palettes)
_SAFETY_ORANGE: tuple[RGB, ...] = ((250, 96, 20), (240, 110, 30), (255, 80, 10), (232, 88, 24))
_SAFETY_RED: RGB = (204, 30, 36)
_SAFETY_YELLOW: RGB = (246, 196, 20)
_LIME: RGB = (196, 222, 40)
_REFLECTIVE: tuple[RGB, ...] = ((238, 240, 238), (222, 226, 230))
_RUBBER: RGB = (32, 32, 34)
_CONCRETE: tuple[RGB, ...] = ((172, 170, 164), (150, 148, 142), (190, 186, 178))
_GALVANISED: tuple[RGB, ...] = ((186, 190, 188), (166, 172, 172), (200, 202, 200))
_VARIATION = 0.05
"""Brightness variation of the colours drawn from the palettes above (:func:`pick`)."""


def _wheel_x(
    asm: Assembly,
    x0: float,
    x1: float,
    y: float,
    z: float,
    radius: float,
    tire: RGB,
    hub: RGB,
    *,
    sections: int = 16,
) -> None:
    """A wheel turning about the x axis between ``x0`` and ``x1``: a round tyre (torus) and a hub disc."""
    width = x1 - x0
    minor = 0.5 * width
    if radius - minor <= 1.2 * minor:  # a fat, small wheel: a plain cylinder with a hub cap
        asm.add(cylinder((x0, y, z), (x1, y, z), radius, sections=sections), tire)
        asm.add(cylinder((x0 + 0.2 * width, y, z), (x1 - 0.2 * width, y, z), 0.55 * radius + 1e-3), hub)
        return
    asm.add(torus((0.5 * (x0 + x1), y, z), radius - minor, minor, sections=sections, tube=8, axis="x"), tire)
    asm.add(
        cylinder(
            (x0 + 0.15 * width, y, z), (x1 - 0.15 * width, y, z), radius - 1.6 * minor, sections=sections
        ),
        hub,
    )


def _outline(width: float, depth: float, radius: float, cy: float) -> np.ndarray:
    """A rounded rectangle centred at ``(0, cy)``, as ``(K, 2)`` points."""
    return rounded_rectangle(width, depth, radius) + np.array((0.0, cy))


def _clip(polygon: list[tuple[float, float]], x0: float, x1: float, s0: float, s1: float) -> np.ndarray:
    """Clip a convex polygon in the (x, s) plane to the rectangle ``[x0, x1] x [s0, s1]``."""
    pts = list(polygon)
    for axis, bound, keep_above in ((0, x0, True), (0, x1, False), (1, s0, True), (1, s1, False)):
        out: list[tuple[float, float]] = []
        for i, cur in enumerate(pts):
            prev = pts[i - 1]
            cur_in = cur[axis] >= bound if keep_above else cur[axis] <= bound
            prev_in = prev[axis] >= bound if keep_above else prev[axis] <= bound
            if cur_in != prev_in:
                t = (bound - prev[axis]) / (cur[axis] - prev[axis])
                out.append((prev[0] + t * (cur[0] - prev[0]), prev[1] + t * (cur[1] - prev[1])))
            if cur_in:
                out.append(cur)
        pts = out
        if not pts:
            break
    return np.array(pts, dtype=np.float64).reshape(-1, 2)


def _striped_board(
    asm: Assembly,
    x0: float,
    x1: float,
    height: float,
    origin: tuple[float, float],
    up: tuple[float, float],
    normal: tuple[float, float],
    thickness: float,
    stripe: float,
    colours: tuple[RGB, RGB],
    *,
    slope: float = 0.0,
    phase: float = 0.0,
) -> None:
    """A board between ``x0`` and ``x1`` made of alternating stripes (one closed part each).

    The board lies in a plane through ``origin = (y, z)`` spanned by x and the unit vector `up` in the yz
    plane; it is `height` tall along `up` and `thickness` thick along the unit `normal`. Stripes are
    `stripe` wide along x and lean by `slope` (x per unit of height, 1 = 45 degree chevrons).
    """
    oy, oz = origin
    span = abs(slope) * height
    start = x0 - span - stripe + phase % (2.0 * stripe) - 2.0 * stripe
    k = 0
    a = start
    while a < x1 + span:
        b = a + stripe
        quad = [(a, 0.0), (b, 0.0), (b + slope * height, height), (a + slope * height, height)]
        poly = _clip(quad, x0, x1, 0.0, height)
        if len(poly) >= 3:
            area = 0.5 * abs(
                float(
                    np.dot(poly[:, 0], np.roll(poly[:, 1], -1)) - np.dot(np.roll(poly[:, 0], -1), poly[:, 1])
                )
            )
            if area > 1e-5:
                points = [
                    (x, oy + s * up[0] + n * normal[0], oz + s * up[1] + n * normal[1])
                    for x, s in poly
                    for n in (0.0, thickness)
                ]
                asm.add(hull(points), colours[k % 2])
        a = b
        k += 1


# --------------------------------------------------------------------------------------------------
# construction site


def _traffic_cone(rng: np.random.Generator, size: Size) -> Assembly:
    """A traffic cone: square base, collar, tapered body with one or two reflective bands."""
    w, d, h = size
    asm = Assembly()
    body = pick(rng, (*_SAFETY_ORANGE, *_SAFETY_ORANGE, _LIME, _SAFETY_RED), variation=_VARIATION)
    base_colour = _RUBBER if rng.uniform() < 0.6 else shade(body, 0.82)
    band = pick(rng, _REFLECTIVE, variation=0.02)
    short = min(w, d)
    base_t = float(np.clip(0.05 * h, 0.025, 0.045))
    asm.add(rounded_prism((0.0, 0.0), w, d, float(rng.uniform(0.05, 0.14)) * short, 0.0, base_t), base_colour)
    r0 = float(rng.uniform(0.33, 0.38)) * short  # body foot: ~0.26 m across on a 0.36 m base
    r1 = float(np.clip(0.035 * h, 0.018, 0.03))
    z0 = base_t
    asm.add(frustum((0, 0, z0), (0, 0, h), r0, r1, sections=16), body)
    collar = min(0.03, 0.5 * (h - z0))
    asm.add(frustum((0, 0, z0 - 0.005), (0, 0, z0 + collar), 1.12 * r0, 1.04 * r0, sections=16), base_colour)

    def radius(z: float) -> float:
        return r0 + (r1 - r0) * (z - z0) / (h - z0)

    body_h = h - z0
    # 36" cones carry a 6" upper and a 4" lower band, 28" cones one 6" band
    two = h > 0.6 and rng.uniform() < 0.7
    bands = ((0.62, 0.78), (0.42, 0.52)) if two else ((0.52, 0.72),)
    for fa, fb in bands:
        za, zb = z0 + fa * body_h, z0 + fb * body_h
        asm.add(frustum((0, 0, za), (0, 0, zb), radius(za) + 0.003, radius(zb) + 0.003, sections=16), band)
    if rng.uniform() < 0.4:  # a darker tip ring
        zt = h - 0.04 * body_h
        asm.add(
            frustum((0, 0, zt), (0, 0, h - 0.004), radius(zt) + 0.002, r1 + 0.002, sections=16),
            shade(body, 0.7),
        )
    return asm


def _jersey_barrier(rng: np.random.Generator, size: Size) -> Assembly:
    """A water-filled plastic jersey barrier: safety-shape shell, fork slots, cap, knuckles, reflectors."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    colour = pick(
        rng, (_SAFETY_RED, (240, 240, 236), _SAFETY_ORANGE[0], _SAFETY_YELLOW), variation=_VARIATION
    )
    dark = (40, 40, 42)
    lug = float(np.clip(0.04 * w, 0.04, 0.07))
    x0, x1 = -hx + lug, hx - lug
    top = h - 0.012
    profile = ((1.0, 0.0), (1.0, 0.07), (0.62, 0.3), (0.34, 0.93), (0.24, 1.0))
    points = [(x, s * f * hy, z * top) for x in (x0, x1) for s in (-1.0, 1.0) for f, z in profile]
    shell = hull(points)
    slot_w = float(np.clip(0.15 * w, 0.14, 0.22))
    slot_h = float(np.clip(0.1 * h, 0.07, 0.1))
    cuts = [
        box((c - 0.5 * slot_w, -hy - 0.01, -0.01), (c + 0.5 * slot_w, hy + 0.01, slot_h))
        for c in (-0.25 * w, 0.25 * w)
    ]
    asm.add(difference(shell, *cuts), colour)
    # knuckles: two at +x, one at -x, with a vertical pin through the +x pair
    knuckle_y = 0.3 * hy
    for lo, hi in ((0.15, 0.35), (0.6, 0.8)):
        asm.box((x1 - 0.01, -knuckle_y, lo * h), (hx, knuckle_y, hi * h), colour)
    asm.box((-hx, -knuckle_y, 0.38 * h), (x0 + 0.01, knuckle_y, 0.58 * h), colour)
    asm.add(
        cylinder((hx - 0.5 * lug, 0.0, 0.1 * h), (hx - 0.5 * lug, 0.0, 0.86 * h), 0.012, sections=8), dark
    )
    cap_x = float(rng.uniform(-0.3, 0.3)) * w
    asm.add(cylinder((cap_x, 0.0, top - 0.02), (cap_x, 0.0, h), 0.05, sections=12), shade(colour, 0.75))
    # reflectors on the upper slope of both faces
    reflector = pick(rng, ((250, 250, 246), (250, 170, 30)), variation=0.02)
    ya, za, yb, zb = 0.62 * hy, 0.3 * top, 0.34 * hy, 0.93 * top
    length = math.hypot(ya - yb, zb - za)
    ny, nz = (zb - za) / length, (ya - yb) / length  # outward normal of the +y slope
    for xc in (-0.3 * w, 0.3 * w) if w > 1.4 else (0.0,):
        for sign in (-1.0, 1.0):
            pts = []
            for f in (0.45, 0.6):
                py, pz = ya + f * (yb - ya), za + f * (zb - za)
                for n in (-0.004, 0.003):
                    for x in (xc - 0.08, xc + 0.08):
                        pts.append((x, sign * (py + n * ny), pz + n * nz))
            asm.add(hull(pts), reflector)
    return asm


def _barrier_board(rng: np.random.Generator, size: Size) -> Assembly:
    """One or two red-and-white barrier boards on two posts in foot plates, sometimes with a warning lamp."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    colours = (pick(rng, (_SAFETY_RED,), variation=0.04), pick(rng, _REFLECTIVE, variation=0.02))
    foot = (
        _RUBBER
        if rng.uniform() < 0.6
        else pick(rng, (_SAFETY_YELLOW, _SAFETY_ORANGE[1], _CONCRETE[0]), variation=_VARIATION)
    )
    post_colour = pick(rng, _GALVANISED, variation=_VARIATION) if rng.uniform() < 0.5 else colours[1]
    fw = float(np.clip(0.2 * w, 0.25, 0.36))
    fh = float(rng.uniform(0.06, 0.1))
    post = 0.04
    lamp = rng.uniform() < 0.35
    lamp_h = 0.17 if lamp else 0.0
    post_top = h - lamp_h - (0.0 if lamp else 0.01)
    for sx in (-1.0, 1.0):
        xc = sx * (hx - 0.5 * fw)
        pts = [(xc + ex * 0.5 * fw, ey * hy, 0.0) for ex in (-1.0, 1.0) for ey in (-1.0, 1.0)] + [
            (xc + ex * 0.42 * fw, ey * (hy - 0.05), fh) for ex in (-1.0, 1.0) for ey in (-1.0, 1.0)
        ]
        asm.add(hull(pts), foot)
        asm.box((xc - 0.04, -0.04, fh - 0.005), (xc + 0.04, 0.04, fh + 0.05), shade(foot, 0.8))
        asm.box((xc - 0.5 * post, -0.5 * post, fh), (xc + 0.5 * post, 0.5 * post, post_top), post_colour)
    board_h = float(rng.uniform(0.18, 0.25))
    board_t = 0.018
    board_top = h if not lamp else post_top - 0.02
    tops = [board_top]
    if rng.uniform() < 0.5 and board_top - 2.2 * board_h > fh + 0.25:
        tops.append(board_top - float(rng.uniform(0.35, 0.45)) * (board_top - fh))
    stripe = w / max(3, round(w / 0.25))  # 0.25 m red and white fields
    for top in tops:
        _striped_board(
            asm,
            -hx,
            hx,
            board_h,
            (0.5 * post, top - board_h),
            (0.0, 1.0),
            (1.0, 0.0),
            board_t,
            stripe,
            colours,
        )
    if lamp:
        xl = hx - 0.5 * fw
        asm.box((xl - 0.03, -0.03, post_top - 0.01), (xl + 0.03, 0.03, post_top + 0.03), (40, 40, 42))
        asm.add(
            cylinder((xl, -0.03, post_top + 0.1), (xl, 0.03, post_top + 0.1), 0.07, sections=12),
            pick(rng, ((250, 170, 30), (250, 200, 40)), variation=0.03),
        )
    return asm


def _traffic_barrier(rng: np.random.Generator, size: Size) -> Assembly:
    """A plastic water-filled jersey barrier or a striped barrier board on foot plates."""
    if rng.uniform() < 0.55:
        return _jersey_barrier(rng, size)
    return _barrier_board(rng, size)


def _sawhorse_barricade(rng: np.random.Generator, size: Size) -> Assembly:
    """A Type I/II barricade: two A-frames carrying striped rails on both faces, sometimes an amber lamp."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    frame = (
        pick(rng, ((240, 240, 236), _SAFETY_ORANGE[0]), variation=_VARIATION)
        if rng.uniform() < 0.6
        else pick(rng, _GALVANISED, variation=_VARIATION)
    )
    stripe_colours = (
        pick(rng, (*_SAFETY_ORANGE, _SAFETY_RED), variation=0.03),
        pick(rng, _REFLECTIVE, variation=0.02),
    )
    lamp = rng.uniform() < 0.35
    lamp_h = 0.19 if lamp else 0.0
    apex = h - lamp_h
    inset = float(np.clip(0.12 * w, 0.1, 0.25))
    lt = 0.04  # leg section
    top_y = 0.03
    y_foot = hy - 0.5 * lt
    dz = apex - lt
    for sx in (-1.0, 1.0):
        x = sx * (hx - inset)
        for sy in (-1.0, 1.0):
            asm.add(bar((x, sy * y_foot, 0.5 * lt), (x, sy * top_y, apex - 0.5 * lt), (0.045, lt, lt)), frame)
            fy0, fy1 = sorted((sy * hy, sy * (hy - 0.07)))
            asm.box((x - 0.03, fy0, 0.0), (x + 0.03, fy1, 0.025), _RUBBER)
        asm.box((x - 0.035, -top_y - 0.03, apex - 0.06), (x + 0.035, top_y + 0.03, apex), shade(frame, 0.85))
        brace_z = 0.25 * apex
        fy = y_foot + (top_y - y_foot) * (brace_z - 0.5 * lt) / dz
        asm.add(bar((x, -fy, brace_z), (x, fy, brace_z), 0.015), shade(frame, 0.8))
    # rails on both faces, leaning with the legs
    length = math.hypot(y_foot - top_y, dz)
    uy, uz = (top_y - y_foot) / length, dz / length  # up along the +y legs
    ny, nz = uz, -uy  # outward (+y) normal
    rails = 2 if (rng.uniform() < 0.6 and apex > 0.85) else 1
    rail_h = float(rng.uniform(0.2, 0.3))
    gap = float(rng.uniform(0.12, 0.2))
    slope = 1.0 if rng.uniform() < 0.5 else -1.0
    for k in range(rails):
        z_bottom = apex - 0.03 - (k + 1) * rail_h - k * gap
        s0 = (z_bottom - 0.5 * lt) / uz
        for sy in (-1.0, 1.0):
            py = y_foot + s0 * uy + 0.45 * lt * ny
            pz = 0.5 * lt + s0 * uz + 0.45 * lt * nz
            _striped_board(
                asm,
                -hx,
                hx,
                rail_h,
                (sy * py, pz),
                (sy * uy, uz),
                (sy * ny, nz),
                0.02,
                0.15,
                stripe_colours,
                slope=slope * sy,
            )
    if lamp:
        xl = -(hx - inset) if rng.uniform() < 0.5 else hx - inset
        asm.box((xl - 0.02, -0.02, apex), (xl + 0.02, 0.02, apex + 0.06), _RUBBER)
        asm.box((xl - 0.06, -0.03, apex + 0.04), (xl + 0.06, 0.03, apex + 0.06), (40, 40, 42))
        asm.add(
            cylinder((xl, -0.035, apex + 0.125), (xl, 0.035, apex + 0.125), 0.065, sections=12),
            pick(rng, ((250, 170, 30), (250, 200, 40)), variation=0.03),
        )
    return asm


def _construction_fence(rng: np.random.Generator, size: Size) -> Assembly:
    """A temporary fence panel: tube frame, wire mesh, two block feet, clamps, sometimes a screen or sign."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    tube = (
        pick(rng, _GALVANISED, variation=_VARIATION)
        if rng.uniform() < 0.75
        else pick(rng, ((40, 90, 50), (226, 110, 30)), variation=_VARIATION)
    )
    wire = shade(tube, 0.95)
    foot = (
        pick(rng, _CONCRETE, variation=_VARIATION)
        if rng.uniform() < 0.5
        else pick(rng, (_RUBBER, (226, 100, 30)), variation=_VARIATION)
    )
    fw = float(np.clip(0.07 * w, 0.18, 0.24))
    fh = float(rng.uniform(0.12, 0.15))
    r = 0.02
    post_x = hx - 0.5 * fw
    for sx in (-1.0, 1.0):
        xc = sx * post_x
        pts = [(xc + ex * 0.5 * fw, ey * hy, 0.0) for ex in (-1.0, 1.0) for ey in (-1.0, 1.0)]
        pts += [(xc + ex * 0.5 * fw, ey * (hy - 0.6 * fh), fh) for ex in (-1.0, 1.0) for ey in (-1.0, 1.0)]
        asm.add(hull(pts), foot)
        asm.add(cylinder((xc, 0.0, 0.3 * fh), (xc, 0.0, h - r), r, sections=12), tube)
        for zc in (0.3 * h, h - 0.25):  # couplers
            asm.box((xc - 0.03, -0.025, zc - 0.03), (xc + 0.03, 0.025, zc + 0.03), shade(tube, 0.8))
    z_bottom = fh + 0.06
    z_top = h - r
    asm.add(bar((-post_x, 0.0, z_top), (post_x, 0.0, z_top), 2.0 * r), tube)
    asm.add(bar((-post_x, 0.0, z_bottom), (post_x, 0.0, z_bottom), 2.0 * r), tube)
    pitch_x = float(rng.uniform(0.075, 0.1))
    n_x = max(2, round(2.0 * post_x / pitch_x))
    t = 0.006
    for x in np.linspace(-post_x, post_x, n_x + 1)[1:-1]:
        asm.box((float(x) - 0.5 * t, -0.5 * t, z_bottom), (float(x) + 0.5 * t, 0.5 * t, z_top), wire)
    n_z = max(2, round((z_top - z_bottom) / float(rng.uniform(0.25, 0.32))))
    for z in np.linspace(z_bottom, z_top, n_z + 1)[1:-1]:
        asm.box((-post_x, -0.5 * t, float(z) - 0.5 * t), (post_x, 0.5 * t, float(z) + 0.5 * t), wire)
    screen_roll = rng.uniform()
    if screen_roll < 0.35:  # privacy screen with a printed band
        cloth = pick(rng, ((40, 92, 52), (30, 60, 120), (36, 36, 40), (236, 236, 232)), variation=_VARIATION)
        asm.box((-post_x + r, 0.004, z_bottom + r), (post_x - r, 0.008, z_top - r), cloth)
        band_z = z_bottom + float(rng.uniform(0.45, 0.7)) * (z_top - z_bottom)
        asm.box((-post_x + 0.1, 0.008, band_z), (post_x - 0.1, 0.01, band_z + 0.2), pick(rng, "brand"))
    elif screen_roll < 0.6:  # a site sign wired to the mesh
        sx = float(rng.uniform(-0.5, 0.5)) * (post_x - 0.4)
        asm.box(
            (sx - 0.3, 0.004, 1.1),
            (sx + 0.3, 0.01, 1.5),
            pick(rng, (_SAFETY_YELLOW, (240, 240, 236)), variation=_VARIATION),
        )
        asm.box((sx - 0.2, 0.01, 1.25), (sx + 0.2, 0.012, 1.35), (30, 30, 32))
    return asm


def _ladder(rng: np.random.Generator, size: Size) -> Assembly:
    """An A-frame step ladder: stepped front rails (+y), braced rear rails, spreaders, top cap, feet."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    fibreglass = rng.uniform() < 0.5
    rail_colour = (
        pick(rng, (_SAFETY_YELLOW, _SAFETY_ORANGE[1], (40, 90, 170), (60, 130, 70)), variation=_VARIATION)
        if fibreglass
        else pick(rng, "chrome")
    )
    alu = pick(rng, "chrome")
    cap_colour = pick(
        rng, ((36, 36, 40), (90, 92, 96), _SAFETY_ORANGE[1], (40, 90, 170)), variation=_VARIATION
    )
    cap_h = float(np.clip(0.06 * h, 0.06, 0.1))
    h_top = h - cap_h
    cap_d = float(np.clip(0.22 * d, 0.14, 0.26))
    run = d - cap_d
    front_run = 0.45 * run
    cap_y0 = -hy + (run - front_run)
    cap_y1 = hy - front_run
    rx = 0.026  # rail width along x
    ry_front, ry_rear = 0.07, 0.045
    x_bot = hx - 0.5 * rx
    x_top = max(0.78 * x_bot, 0.14)
    ez = 0.01

    def front(f: float) -> tuple[float, float]:
        """x and y of the front rail's centre line at a fraction `f` of the height."""
        return x_bot + (x_top - x_bot) * f, hy - 0.5 * ry_front + (cap_y1 - hy) * f

    def rear(f: float) -> tuple[float, float]:
        """x and y of the rear rail's centre line at a fraction `f` of the height."""
        return x_bot + (x_top - x_bot) * f, -hy + 0.5 * ry_rear + (cap_y0 + hy) * f

    for sx in (-1.0, 1.0):
        for rail, ry in ((front, ry_front), (rear, ry_rear)):
            xb, yb = rail(0.0)
            xt, yt = rail(1.0)
            asm.add(bar((sx * xb, yb, ez), (sx * xt, yt, h_top + ez), (rx, ry, 2 * ez)), rail_colour)
            lo_x = max(sx * xb - 0.5 * rx - 0.003, -hx)
            hi_x = min(sx * xb + 0.5 * rx + 0.003, hx)
            lo_y, hi_y = max(yb - 0.5 * ry - 0.003, -hy), min(yb + 0.5 * ry + 0.003, hy)
            asm.box((lo_x, lo_y, 0.0), (hi_x, hi_y, 0.05), _RUBBER)
        f = 0.5  # spreader between front and rear rail
        xf, yf = front(f)
        xr, yr = rear(f)
        asm.add(
            bar(
                (sx * (xf - 0.005), yf - 0.03, f * h_top),
                (sx * (xr - 0.005), yr + 0.02, f * h_top),
                (0.008, 0.02, 0.02),
            ),
            alu,
        )
    steps = max(1, int((h_top - 0.12) / 0.26))
    for k in range(1, steps + 1):
        f = k / (steps + 1)
        z = f * h_top
        x, y = front(f)
        asm.box((-x, max(y - 0.07, cap_y0), z - 0.03), (x, min(y + 0.035, hy), z), alu)
    for f in (0.22, 0.55):  # rear braces
        x, y = rear(f)
        asm.box((-x, y - 0.01, f * h_top - 0.015), (x, y + 0.01, f * h_top + 0.015), alu)
    xa, ya = rear(0.22)
    xb2, yb2 = rear(0.55)
    asm.add(bar((-xa, ya, 0.22 * h_top), (xb2, yb2, 0.55 * h_top), (0.01, 0.015, 0.015)), alu)
    if rng.uniform() < 0.5 and h_top > 0.8:  # fold-down paint shelf
        f = 0.72
        x, yr = rear(f)
        _, yf = front(f)
        asm.box((-0.8 * x, yr, f * h_top - 0.015), (0.8 * x, min(yr + 0.2, yf - 0.04), f * h_top), cap_colour)
    cap_w = x_top + 0.5 * rx + 0.015
    cap = box((-cap_w, cap_y0 - 0.01, h_top), (cap_w, cap_y1 + 0.015, h))
    slots = [
        box((-0.6 * cap_w, cap_y0 + 0.02, h - 0.02), (-0.1 * cap_w, cap_y0 + 0.02 + 0.35 * cap_d, h + 0.01)),
        box((0.1 * cap_w, cap_y0 + 0.02, h - 0.02), (0.6 * cap_w, cap_y0 + 0.02 + 0.35 * cap_d, h + 0.01)),
    ]
    asm.add(difference(cap, *slots), cap_colour)
    return asm


def _cargo_pallet(rng: np.random.Generator, size: Size) -> Assembly:
    """A wooden pallet: a EUR-style block pallet (nine blocks) or a GMA-style pallet on notched stringers."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    roll = rng.uniform()
    if roll < 0.2:
        wood: tuple[RGB, ...] = ((40, 84, 160),)  # CHEP blue
    elif roll < 0.3:
        wood = ((150, 60, 44),)  # LPR red
    elif roll < 0.55:
        wood = ((150, 142, 128), (132, 126, 116))  # weathered
    else:
        wood = ((214, 184, 132), (200, 168, 118), (222, 196, 150))  # fresh pine

    def board(lo: tuple[float, float, float], hi: tuple[float, float, float]) -> None:
        asm.box(lo, hi, pick(rng, wood, variation=0.08))

    t = 0.153 * h  # 22 mm of 144 mm
    if rng.uniform() < 0.6:  # EUR block pallet
        edge = 0.145 * d / 0.8 if d < 0.8 else 0.145
        centre_w = edge
        mid_w = 0.1 * min(1.0, d / 0.8)
        ys = (-hy + 0.5 * edge, -0.5 * (hy - 0.5 * edge), 0.0, 0.5 * (hy - 0.5 * edge), hy - 0.5 * edge)
        widths = (edge, mid_w, centre_w, mid_w, edge)
        for y, bw in zip(ys, widths, strict=True):
            board((-hx, y - 0.5 * bw, h - t), (hx, y + 0.5 * bw, h))
        block_x = 0.145
        xs = (-hx + 0.5 * block_x, 0.0, hx - 0.5 * block_x)
        block_ys = (-hy + 0.052, 0.0, hy - 0.052)  # outer blocks 2 mm in from the deck edge
        for x in xs:
            board((x - 0.5 * block_x, -hy, h - 2 * t), (x + 0.5 * block_x, hy, h - t))  # stringer board
            for y, by in zip(block_ys, (0.1, 0.145, 0.1), strict=True):
                board((x - 0.5 * block_x, y - 0.5 * by, t), (x + 0.5 * block_x, y + 0.5 * by, h - 2 * t))
        for y, by in zip((-hy + 0.05, 0.0, hy - 0.05), (0.1, 0.145, 0.1), strict=True):
            board((-hx, y - 0.5 * by, 0.0), (hx, y + 0.5 * by, t))
        if rng.uniform() < 0.6:  # burnt-in stamps on the outer blocks of both long sides
            for x in xs:
                for sy in (-1.0, 1.0):
                    y0, y1 = sorted((sy * (hy - 0.003), sy * hy))
                    asm.box((x - 0.045, y0, t + 0.015), (x + 0.045, y1, h - 2 * t - 0.015), (60, 46, 34))
    else:  # GMA stringer pallet
        top_t = 0.12 * h
        n = 7
        bw = float(np.clip(0.09 * w / 1.2, 0.075, 0.095))
        xs = np.linspace(-hx + 0.5 * bw, hx - 0.5 * bw, n)
        for x in xs:
            board((float(x) - 0.5 * bw, -hy, h - top_t), (float(x) + 0.5 * bw, hy, h))
        for x in np.linspace(-hx + 0.5 * bw, hx - 0.5 * bw, 5):
            board((float(x) - 0.5 * bw, -hy, 0.0), (float(x) + 0.5 * bw, hy, top_t))
        sw = 0.038
        notch_w = 0.23 * w
        for y in (-hy + 0.5 * sw, 0.0, hy - 0.5 * sw):
            stringer = box((-hx, y - 0.5 * sw, top_t), (hx, y + 0.5 * sw, h - top_t))
            notches = [
                box(
                    (c - 0.5 * notch_w, y - sw, top_t - 0.01),
                    (c + 0.5 * notch_w, y + sw, top_t + 0.4 * (h - 2 * top_t)),
                )
                for c in (-0.27 * w, 0.27 * w)
            ]
            asm.add(difference(stringer, *notches), pick(rng, wood, variation=0.08))
    return asm


def _wheelbarrow(rng: np.random.Generator, size: Size) -> Assembly:
    """A wheelbarrow: wheel (-y) in a fork, deep tray with a rolled rim, handles with grips (+y), two legs."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    tray_colour = pick(
        rng,
        (
            (46, 120, 60),
            (196, 40, 36),
            (232, 110, 30),
            (170, 174, 176),
            (36, 36, 40),
            (40, 90, 170),
            _SAFETY_YELLOW,
        ),
        variation=_VARIATION,
    )
    wooden = rng.uniform() < 0.35
    handle_colour = (
        pick(rng, "light_wood")
        if wooden
        else pick(rng, ((42, 44, 48), tray_colour, (150, 154, 160)), variation=_VARIATION)
    )
    grip = pick(rng, (_RUBBER, (200, 40, 36), (60, 60, 64)), variation=_VARIATION)
    r_wheel = float(np.clip(0.28 * h, 0.15, 0.2))
    tw = float(np.clip(0.13 * w, 0.07, 0.1))
    yw = -hy + r_wheel
    _wheel_x(
        asm,
        -0.5 * tw,
        0.5 * tw,
        yw,
        r_wheel,
        r_wheel,
        _RUBBER,
        pick(rng, ((200, 40, 36), (230, 190, 40), (170, 172, 176)), variation=_VARIATION),
    )
    asm.add(cylinder((-0.07, yw, r_wheel), (0.07, yw, r_wheel), 0.012, sections=8), (90, 92, 96))
    # tray: a tapered tub with a sloped front wall
    rim = 0.012
    z_top = h - rim
    depth = float(np.clip(0.45 * h, 0.22, 0.32))
    z_bot = z_top - depth
    yt0 = -hy + 0.5 * r_wheel
    tray_len = float(np.clip(0.62 * d, 0.75, 1.0))
    yt1 = yt0 + tray_len
    yb0, yb1 = yt0 + 0.45 * tray_len, yt1 - 0.06
    wt, wb = w - 2 * rim, 0.62 * w
    top_ring = _outline(wt, tray_len, 0.08, 0.5 * (yt0 + yt1))
    bot_ring = _outline(wb, yb1 - yb0, 0.06, 0.5 * (yb0 + yb1))
    outer = hull([(x, y, z_top) for x, y in top_ring] + [(x, y, z_bot) for x, y in bot_ring])
    th = 0.012
    top_in = _outline(wt - 2 * th, tray_len - 2 * th, 0.07, 0.5 * (yt0 + yt1))
    bot_in = _outline(wb - 2 * th, yb1 - yb0 - 2 * th, 0.05, 0.5 * (yb0 + yb1))
    inner = hull(
        [(x, y, z) for x, y in top_in for z in (z_top, z_top + 0.05)]
        + [(x, y, z_bot + th) for x, y in bot_in]
    )
    asm.add(difference(outer, inner), tray_colour)
    corners = [
        (-hx + rim, yt0 + 0.03),
        (hx - rim, yt0 + 0.03),
        (hx - rim, yt1 - 0.03),
        (-hx + rim, yt1 - 0.03),
    ]
    for i in range(4):
        (xa, ya), (xb, yb) = corners[i], corners[(i + 1) % 4]
        asm.add(bar((xa, ya, z_top), (xb, yb, z_top), 2 * rim), shade(tray_colour, 0.85))
    # handles: from the axle under the tray to the grips at +y
    xg = min(0.28, hx - 0.03)
    zg = float(np.clip(z_bot + 0.12, 0.4, h - 0.08))
    hs = 0.035
    for sx in (-1.0, 1.0):
        p0 = (sx * 0.07, yw, r_wheel)
        p1 = (sx * 0.5 * wb, yb0, z_bot - 0.5 * hs)
        p2 = (sx * min(0.5 * wb + 0.02, xg), yb1, z_bot - 0.5 * hs)
        p3 = (sx * xg, hy - 0.14, zg)
        for a, b in ((p0, p1), (p1, p2), (p2, p3)):
            asm.add(bar(a, b, hs), handle_colour)
        asm.add(cylinder((sx * xg, hy - 0.15, zg), (sx * xg, hy, zg), 0.019, sections=12), grip)
        # leg with a foot
        leg_top = (sx * 0.5 * wb, yb1 - 0.08, z_bot - hs)
        leg_foot = (sx * (0.5 * wb + 0.03), yb1 - 0.02, 0.015)
        asm.add(bar(leg_top, leg_foot, 0.03), shade(handle_colour, 0.8) if not wooden else (60, 62, 66))
        # fork arm from the axle to the tray front
        front_wall = (sx * 0.3 * wt, yt0 + 0.3 * (yb0 - yt0), z_top - 0.3 * depth - 0.02)
        asm.add(bar(p0, front_wall, 0.02), (60, 62, 66))
    asm.add(
        bar((-0.5 * wb - 0.03, yb1 - 0.05, 0.12), (0.5 * wb + 0.03, yb1 - 0.05, 0.12), 0.02), (60, 62, 66)
    )
    return asm


def _toolbox(rng: np.random.Generator, size: Size) -> Assembly:
    """A plastic toolbox (flush lid handle, latches) or a steel box (end handles, hasp) with a flat lid."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    if rng.uniform() < 0.6:  # plastic hand toolbox
        pair = (
            ((36, 36, 40), (200, 36, 36)),
            ((232, 190, 40), (36, 36, 40)),
            ((40, 90, 170), (44, 100, 186)),
            ((90, 92, 96), (232, 110, 30)),
            ((200, 36, 36), (36, 36, 40)),
        )[int(rng.integers(5))]
        body, lid = (
            shade(pair[0], float(rng.uniform(0.94, 1.06))),
            shade(pair[1], float(rng.uniform(0.94, 1.06))),
        )
        accent = pick(
            rng, ((232, 190, 40), (200, 36, 36), (60, 60, 64), (220, 220, 220)), variation=_VARIATION
        )
        lp = 0.012  # latches stick out at the front
        yc = -0.5 * lp
        seam = float(rng.uniform(0.55, 0.68)) * h
        asm.add(rounded_prism((0.0, yc), w - 0.012, d - lp - 0.012, 0.025, 0.0, seam), body)
        asm.add(rounded_prism((0.0, yc), w, d - lp, 0.028, seam, h), lid)
        grip = 0.3 * w
        asm.box((-grip, yc - 0.018, h - 0.02), (grip, yc + 0.018, h), accent)
        for sx in (-1.0, 1.0):
            asm.box(
                (sx * grip - 0.025, yc - 0.028, h - 0.03), (sx * grip + 0.025, yc + 0.028, h), shade(lid, 0.8)
            )
            xl = sx * 0.3 * w
            asm.box((xl - 0.03, hy - lp - 0.01, seam - 0.04), (xl + 0.03, hy, seam + 0.03), accent)
        if rng.uniform() < 0.5:  # organiser windows in the lid
            for sx in (-1.0, 1.0):
                x0 = sx * (grip + 0.05)
                x1 = sx * (hx - 0.04)
                if abs(x1) - abs(x0) > 0.03:
                    asm.box(
                        (min(x0, x1), yc + 0.035, h - 0.004),
                        (max(x0, x1), hy - lp - 0.03, h),
                        (150, 180, 200),
                    )
        asm.box((-0.3 * w, -hy, seam - 0.02), (0.3 * w, -hy + 0.008, seam + 0.01), shade(body, 0.7))
    else:  # steel box
        colour = pick(
            rng,
            ((190, 36, 32), (40, 80, 160), (46, 110, 64), (120, 124, 128), (30, 30, 34)),
            variation=_VARIATION,
        )
        hp, lp = 0.03, 0.01
        seam = float(rng.uniform(0.65, 0.75)) * h
        x_body = hx - hp
        asm.box((-x_body + 0.004, -hy + 0.004, 0.012), (x_body - 0.004, hy - lp - 0.004, seam), colour)
        asm.box((-x_body, -hy, seam), (x_body, hy - lp, h), shade(colour, 1.08))
        asm.box(
            (-x_body + 0.006, -hy + 0.006, seam - 0.006),
            (x_body - 0.006, hy - lp - 0.006, seam),
            (30, 30, 32),
        )
        for sx in (-1.0, 1.0):
            for sy in (-1.0, 1.0):
                xc, yc = sx * (x_body - 0.03), sy * (hy - 0.03) - 0.5 * lp
                asm.box((xc - 0.02, yc - 0.02, 0.0), (xc + 0.02, yc + 0.02, 0.012), _RUBBER)
            zc = 0.55 * h
            for sy in (-1.0, 1.0):
                inner_x, outer_x = sx * x_body, sx * (hx - 0.01)
                asm.box(
                    (min(inner_x, outer_x), sy * 0.3 * d - 0.006, zc - 0.006),
                    (max(inner_x, outer_x), sy * 0.3 * d + 0.006, zc + 0.006),
                    (60, 62, 66),
                )
            grip_x0, grip_x1 = sx * (hx - 0.012), sx * hx
            asm.box(
                (min(grip_x0, grip_x1), -0.3 * d - 0.01, zc - 0.012),
                (max(grip_x0, grip_x1), 0.3 * d + 0.01, zc + 0.012),
                (60, 62, 66),
            )
        asm.box((-0.035, hy - lp, seam - 0.06), (0.035, hy, seam + 0.025), pick(rng, "chrome"))
        for sx in (-1.0, 1.0):
            asm.box(
                (sx * 0.6 * x_body - 0.02, hy - lp - 0.002, seam - 0.03),
                (sx * 0.6 * x_body + 0.02, hy - 0.004, seam + 0.015),
                (60, 62, 66),
            )
    return asm


def _sandbag(
    length: float, width: float, thick: float, center: tuple[float, float, float], *, fine: bool = True
) -> Solid:
    """One filled sandbag: a pillow, full size at mid height, rounder and narrower towards its flat top
    and bottom faces."""
    cx, cy, cz = center
    ring = rounded_rectangle(length, width, 0.3 * width, corner_segments=1)
    levels = (
        ((0.0, 1.0, 1.0), (0.55, 0.95, 0.86), (1.0, 0.82, 0.64))
        if fine
        else ((0.0, 1.0, 1.0), (1.0, 0.8, 0.6))
    )
    points = []
    for fz, fx, fy in levels:
        for sz in (-1.0, 1.0) if fz > 0 else (0.0,):
            points += [(cx + fx * x, cy + fy * y, cz + sz * fz * 0.5 * thick) for x, y in ring]
    return hull(points)


def _sandbag_stack(rng: np.random.Generator, size: Size) -> Assembly:
    """A stack of filled sandbags: a pyramid or a bonded wall, one or two rows deep."""
    w, d, h = size
    hy = 0.5 * d
    asm = Assembly()
    base = pick(
        rng, ((226, 220, 200), (176, 150, 106), (108, 112, 72), (240, 240, 236), (40, 40, 44)), variation=0.03
    )
    rows = 1 if d < 0.55 else 2
    bag_w = d / rows
    n = max(1, round(w / 0.6))
    bag_l = w / n
    layers = max(2, round(h / 0.13))
    if n * rows == 1:  # a single column: at least three bags
        layers = max(3, layers)
    swell = 1.2
    step = h / (layers - 1 + swell)
    thick = swell * step
    pyramid = n >= layers and rng.uniform() < 0.6
    counts = [n - k if pyramid else (n if k % 2 == 0 else max(1, n - 1)) for k in range(layers)]
    fine = rows * sum(counts) <= 45  # keep big stacks under the triangle budget
    for k, count in enumerate(counts):
        x_first = -0.5 * (count - 1) * bag_l
        for i in range(count):
            jitter = float(rng.uniform(-0.02, 0.02)) if count < n else 0.0
            for j in range(rows):
                y = -hy + (j + 0.5) * bag_w
                centre = (x_first + i * bag_l + jitter, y, k * step + 0.5 * thick)
                colour = shade(base, float(rng.uniform(0.86, 1.08)))
                asm.add(_sandbag(bag_l, bag_w, thick, centre, fine=fine), colour)
    return asm


# --------------------------------------------------------------------------------------------------
# sports and play


def _icosahedron() -> tuple[np.ndarray, list[tuple[int, int, int]]]:
    """Unit vertices of an icosahedron and its 20 faces."""
    phi = 0.5 * (1.0 + math.sqrt(5.0))
    verts = []
    for a in (-1.0, 1.0):
        for b in (-phi, phi):
            verts += [(0.0, a, b), (a, b, 0.0), (b, 0.0, a)]
    v = np.array(verts)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    dots = v @ v.T
    adjacent = dots > 0.4
    faces = []
    for i in range(12):
        for j in range(i + 1, 12):
            for k in range(j + 1, 12):
                if adjacent[i, j] and adjacent[j, k] and adjacent[i, k]:
                    faces.append((i, j, k))
    return v, faces


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _ball_patch(corners: list[np.ndarray], radii: np.ndarray, centre: np.ndarray) -> Solid:
    """A curved panel on the ball's surface spanning the unit directions `corners` (shrunk a little)."""
    c = _unit(np.mean(corners, axis=0))
    shrunk = [_unit(c + 0.86 * (q - c)) for q in corners]
    outer = [c] + shrunk + [_unit(c + 0.5 * (q - c)) for q in shrunk]
    outer += [_unit(shrunk[i] + shrunk[(i + 1) % len(shrunk)]) for i in range(len(shrunk))]
    points = [centre + 1.002 * radii * p for p in outer] + [centre + 0.9 * radii * p for p in shrunk]
    return hull(points)


def _soccer_ball(rng: np.random.Generator, size: Size) -> Assembly:
    """A size-5 football: white ball, 12 pentagon panels, sometimes coloured hexagons, turned at random."""
    w, d, h = size
    radii = np.array([0.5 * w, 0.5 * d, 0.5 * h])
    centre = np.array([0.0, 0.0, 0.5 * h])
    asm = Assembly()
    scheme = (
        ((246, 246, 244), (24, 24, 26)),
        ((246, 246, 244), (30, 50, 120)),
        ((246, 246, 244), (190, 30, 36)),
        ((250, 220, 40), (24, 24, 26)),
        ((250, 120, 30), (24, 24, 26)),
    )[int(rng.choice(5, p=(0.5, 0.15, 0.15, 0.1, 0.1)))]
    body, patch = shade(scheme[0], float(rng.uniform(0.95, 1.02))), scheme[1]
    asm.add(ellipsoid(centre, radii, segments=16, rings=8), body)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    verts, faces = _icosahedron()
    verts = verts @ q.T
    for i in range(12):
        nbrs = [j for j in range(12) if j != i and verts[i] @ verts[j] > 0.4]
        ring = [verts[i] + (verts[j] - verts[i]) / 3.0 for j in nbrs]
        # order the pentagon corners around the vertex
        e1 = _unit(np.cross(verts[i], [0.3, 0.5, 0.8]))
        e2 = np.cross(verts[i], e1)
        ring.sort(key=lambda p: math.atan2(float(p @ e2), float(p @ e1)))
        asm.add(_ball_patch([_unit(p) for p in ring], radii, centre), patch)
    if rng.uniform() < 0.4:
        accent = pick(rng, "accent")
        chosen = rng.choice(len(faces), size=6, replace=False)
        for f in chosen:
            a, b, c = (verts[k] for k in faces[int(f)])
            hexagon = [
                a + (b - a) / 3,
                b + (a - b) / 3,
                b + (c - b) / 3,
                c + (b - c) / 3,
                c + (a - c) / 3,
                a + (c - a) / 3,
            ]
            asm.add(_ball_patch([_unit(p) for p in hexagon], radii, centre), accent)
    return asm


def _basketball_hoop(rng: np.random.Generator, size: Size) -> Assembly:
    """A basketball hoop: in-ground or portable pole, arms, backboard with shooter's square, rim and net."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    pole_colour = pick(rng, ((30, 30, 34), (60, 62, 66), (40, 60, 110)), variation=_VARIATION)
    glass = rng.uniform() < 0.5
    board_colour = (196, 216, 224) if glass else (246, 246, 244)
    line = (
        (246, 246, 244)
        if glass
        else pick(rng, ((200, 36, 36), (30, 30, 34), (30, 60, 140)), variation=_VARIATION)
    )
    frame = pick(rng, ((30, 30, 34), (90, 92, 96)), variation=_VARIATION)
    orange = pick(rng, ((236, 90, 24), (220, 60, 30)), variation=0.03)
    bh = float(np.clip(0.58 * w, 0.74, 1.07))
    bt = 0.04
    z_bb = h - bh
    major, minor = 0.2386, 0.01  # 18" rim, 16 mm tube
    y_rc = hy - major - minor
    z_r = z_bb + 0.15
    y_bf = y_rc - major - 0.15
    # backboard with a frame and painted lines
    asm.box((-hx + 0.03, y_bf - bt, z_bb + 0.03), (hx - 0.03, y_bf - 0.01, h - 0.03), board_colour)
    for lo, hi in (
        ((-hx, y_bf - bt, h - 0.03), (hx, y_bf, h)),
        ((-hx, y_bf - bt, z_bb), (hx, y_bf, z_bb + 0.03)),
        ((-hx, y_bf - bt, z_bb + 0.03), (-hx + 0.03, y_bf, h - 0.03)),
        ((hx - 0.03, y_bf - bt, z_bb + 0.03), (hx, y_bf, h - 0.03)),
    ):
        asm.box(lo, hi, frame)
    lw = 0.05
    sq_x, sq_z0, sq_z1 = 0.295, z_r, z_r + 0.45
    for lo, hi in (
        ((-sq_x, y_bf - 0.012, sq_z1 - lw), (sq_x, y_bf - 0.006, sq_z1)),
        ((-sq_x, y_bf - 0.012, sq_z0), (sq_x, y_bf - 0.006, sq_z0 + lw)),
        ((-sq_x, y_bf - 0.012, sq_z0 + lw), (-sq_x + lw, y_bf - 0.006, sq_z1 - lw)),
        ((sq_x - lw, y_bf - 0.012, sq_z0 + lw), (sq_x, y_bf - 0.006, sq_z1 - lw)),
    ):
        asm.box(lo, hi, line)
    # rim, bracket and net
    asm.box((-0.08, y_bf - 0.01, z_r - 0.12), (0.08, y_bf + 0.01, z_r + 0.02), orange)
    asm.box((-0.05, y_bf, z_r - 0.04), (0.05, y_rc - major + 0.005, z_r + 0.005), orange)
    asm.add(torus((0.0, y_rc, z_r), major, minor, sections=16, tube=6), orange)
    net = pick(rng, ((246, 246, 244), (230, 230, 226)), variation=0.02)
    low_r, net_h = 0.6 * major, 0.42
    for k in range(12):
        a = 2.0 * math.pi * (k + 0.5) / 12
        b = a + math.pi / 6
        top = (major * math.cos(a), y_rc + major * math.sin(a), z_r)
        bottom = (low_r * math.cos(b), y_rc + low_r * math.sin(b), z_r - net_h)
        asm.add(bar(top, bottom, 0.008), net)
    asm.add(torus((0.0, y_rc, z_r - net_h), low_r, 0.005, sections=12, tube=4), net)
    mid_r = 0.5 * (major + low_r)
    asm.add(torus((0.0, y_rc, z_r - 0.5 * net_h), mid_r, 0.005, sections=12, tube=4), net)
    # support: arms from the pole to the back of the board
    y_back = y_bf - bt
    asm.box((-0.25, y_back - 0.02, z_bb + 0.1), (0.25, y_back, z_bb + 0.6 * bh), frame)
    if rng.uniform() < 0.45:  # in-ground pole
        ps = float(rng.uniform(0.1, 0.15))
        y_p = -hy + 0.2
        z_pt = z_bb + 0.55 * bh
        asm.box((-0.2, -hy, 0.0), (0.2, -hy + 0.4, 0.02), (90, 92, 96))
        for sx in (-1.0, 1.0):
            for sy in (-1.0, 1.0):
                asm.add(
                    cylinder(
                        (sx * 0.15, y_p + sy * 0.15, 0.02),
                        (sx * 0.15, y_p + sy * 0.15, 0.06),
                        0.012,
                        sections=8,
                    ),
                    (150, 154, 160),
                )
        asm.box((-0.5 * ps, y_p - 0.5 * ps, 0.02), (0.5 * ps, y_p + 0.5 * ps, z_pt), pole_colour)
        if rng.uniform() < 0.6:
            pad = pick(rng, ((30, 50, 120), (190, 36, 36), (30, 30, 34), (40, 110, 60)), variation=_VARIATION)
            asm.box(
                (-0.5 * ps - 0.04, y_p - 0.5 * ps - 0.04, 0.15),
                (0.5 * ps + 0.04, y_p + 0.5 * ps + 0.04, 1.6),
                pad,
            )
        for z_arm in (z_pt - 0.05, z_pt - 0.45):
            for sx in (-1.0, 1.0):
                z_b = z_arm + 0.08
                asm.add(
                    bar((sx * 0.15, y_p, z_arm), (sx * 0.15, y_back - 0.01, z_b), (0.05, 0.05, 0.07)),
                    pole_colour,
                )
    else:  # portable system
        bd = float(np.clip(d - 1.0, 0.6, 1.2))
        bw = min(0.8, 0.62 * w)
        bz = float(rng.uniform(0.26, 0.34))
        tank = pick(rng, ((30, 30, 34), (60, 62, 66)), variation=_VARIATION)
        pts = [(sx * 0.5 * bw, y, 0.0) for sx in (-1.0, 1.0) for y in (-hy, -hy + bd)]
        pts += [(sx * 0.42 * bw, y, bz) for sx in (-1.0, 1.0) for y in (-hy + 0.1, -hy + bd - 0.15)]
        asm.add(hull(pts), tank)
        asm.add(
            cylinder((-0.08, -hy + 0.18, bz - 0.01), (-0.08, -hy + 0.18, bz + 0.02), 0.05, sections=12),
            shade(tank, 1.5),
        )
        for sx in (-1.0, 1.0):
            x = sx * (0.5 * bw - 0.03)
            asm.add(
                cylinder(
                    (x - 0.025, -hy + bd - 0.07, 0.06), (x + 0.025, -hy + bd - 0.07, 0.06), 0.06, sections=12
                ),
                _RUBBER,
            )
        p_base = np.array([0.0, -hy + 0.7 * bd, bz - 0.05])
        p_top = np.array([0.0, y_back - 0.3, z_bb + 0.5 * bh])
        pr = float(rng.uniform(0.045, 0.055))
        for k, (fa, fb) in enumerate(((0.0, 0.36), (0.34, 0.69), (0.67, 1.0))):
            asm.add(
                cylinder(
                    p_base + fa * (p_top - p_base),
                    p_base + fb * (p_top - p_base),
                    pr * (1.0 - 0.1 * k),
                    sections=12,
                ),
                pole_colour,
            )
        strut_top = p_base + 0.3 * (p_top - p_base)
        for sx in (-1.0, 1.0):
            asm.add(
                bar(
                    (sx * 0.3 * bw, -hy + 0.15, bz - 0.03), strut_top + np.array((sx * 0.03, 0.0, 0.0)), 0.03
                ),
                pole_colour,
            )
        for z_off in (0.0, -0.35):
            for sx in (-1.0, 1.0):
                asm.add(
                    bar(
                        p_top + np.array((sx * 0.1, 0.0, z_off)),
                        (sx * 0.15, y_back - 0.01, p_top[2] + z_off + 0.05),
                        (0.04, 0.04, 0.05),
                    ),
                    pole_colour,
                )
    return asm


def _tail_plate(
    lt: float, hw: float, t: float, angle: float, y_j: float, z_j: float, sign: float, n0: float
) -> Solid:
    """A kicktail: a plate of length `lt` with a rounded end, tilted up by `angle` from the joint
    ``(y_j, z_j)`` towards ``sign * y``; it spans ``n0 .. n0 + t`` across its thickness."""
    r = min(hw, 0.9 * lt)
    outline = [(0.0, -hw), (0.0, hw)]
    for k in range(9):
        a = 0.5 * math.pi - math.pi * k / 8
        outline.append((lt - r + r * math.cos(a), hw * math.sin(a)))
    ca, sa = math.cos(angle), math.sin(angle)
    points = []
    for s, x in outline:
        for n in (n0, n0 + t):
            points.append((x, y_j + sign * (s * ca - n * sa), z_j + s * sa + n * ca))
    return hull(points)


def _skateboard(rng: np.random.Generator, size: Size) -> Assembly:
    """A skateboard: deck with grip tape and one or two kicktails, two trucks and four wheels."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    graphic = pick(rng, "accent") if rng.uniform() < 0.6 else pick(rng, "wood")
    grip_tape = pick(rng, ((30, 30, 32), (44, 44, 48)), variation=_VARIATION)
    metal = pick(rng, "chrome") if rng.uniform() < 0.6 else pick(rng, ((40, 40, 44),), variation=_VARIATION)
    wheel = pick(
        rng, ((240, 236, 220), (250, 220, 60), (220, 60, 50), (60, 130, 200), (80, 190, 110)), variation=0.03
    )
    cruiser = rng.uniform() < 0.3
    r_w = float(np.clip(0.26 * h, 0.026, 0.032))
    ww = float(rng.uniform(0.032, 0.042))
    t = 0.012
    g = 0.002
    z_db = float(np.clip(h - 0.045, 2 * r_w + 0.008, r_w + 0.055))
    lt = max(float(rng.uniform(0.15, 0.18)) * d / 0.8, hx + 0.02)
    # tilt so that the tip of the kicktail reaches the top: lt sin a + t cos a = h - z_db
    rise = h - z_db
    amp = math.hypot(lt, t)
    angle = math.asin(min(1.0, rise / amp)) - math.atan2(t, lt)
    angle = max(angle, 0.0)
    tail_y = lt * math.cos(angle)
    nose_angle = 0.0 if cruiser else angle
    nose_y = lt * math.cos(nose_angle)
    y_tail_j, y_nose_j = -hy + tail_y, hy - nose_y
    asm.box((-hx, y_tail_j, z_db), (hx, y_nose_j, z_db + t - g), graphic)
    asm.box((-hx, y_tail_j, z_db + t - g), (hx, y_nose_j, z_db + t), grip_tape)
    for sign, a, y_j in ((-1.0, angle, y_tail_j), (1.0, nose_angle, y_nose_j)):
        asm.add(_tail_plate(lt, hx, t - g, a, y_j, z_db, sign, 0.0), graphic)
        asm.add(_tail_plate(lt, hx, g, a, y_j, z_db, sign, t - g), grip_tape)
    for y in (y_tail_j + 0.035, y_nose_j - 0.035):
        asm.box((-0.03, y - 0.04, z_db - 0.008), (0.03, y + 0.04, z_db), metal)
        hanger = [
            (x, y + dy, r_w + dz) for x in (-0.045, 0.045) for dy in (-0.012, 0.012) for dz in (-0.01, 0.012)
        ]
        hanger += [(x, y + dy, z_db - 0.008) for x in (-0.015, 0.015) for dy in (-0.02, 0.02)]
        asm.add(hull(hanger), metal)
        axle_x = hx - ww - 0.01
        asm.add(cylinder((-axle_x, y, r_w), (axle_x, y, r_w), 0.012, sections=8), metal)
        for sx in (-1.0, 1.0):
            x0, x1 = sorted((sx * (hx - ww), sx * hx))
            asm.add(cylinder((x0, y, r_w), (x1, y, r_w), r_w, sections=16), wheel)
            inner = x0 if sx > 0 else x1
            asm.add(cylinder((inner - 0.006, y, r_w), (inner + 0.006, y, r_w), 0.4 * r_w, sections=8), metal)
    return asm


def _stroller(rng: np.random.Generator, size: Size) -> Assembly:
    """A pram (bassinet) or pushchair (seat) on four wheels with frame, hood, handlebar (+y) and basket."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    pram = rng.uniform() < 0.45
    fabric = pick(rng, "fabric") if rng.uniform() < 0.7 else pick(rng, "accent")
    frame = (
        pick(rng, "chrome")
        if rng.uniform() < 0.4
        else pick(rng, ((30, 30, 34), (60, 62, 66), (226, 226, 222)), variation=_VARIATION)
    )
    hub = pick(rng, ((200, 200, 204), (40, 40, 44), (236, 236, 232)), variation=_VARIATION)
    grip = pick(rng, ((36, 30, 28), (30, 30, 32), (100, 62, 40)), variation=_VARIATION)
    r_rear = float(np.clip(0.15 * h, 0.13, 0.17)) if pram else float(np.clip(0.12 * h, 0.1, 0.14))
    r_front = (0.85 if pram else 0.65) * r_rear
    ww = float(rng.uniform(0.035, 0.05))
    y_r = hy - max(r_rear + 0.1, 0.25 * d)
    y_f = -hy + r_front
    x_rw = hx - 0.5 * ww
    x_fw = hx - 0.06 - 0.5 * ww
    for sx in (-1.0, 1.0):
        _wheel_x(asm, sx * x_rw - 0.5 * ww, sx * x_rw + 0.5 * ww, y_r, r_rear, r_rear, _RUBBER, hub)
        _wheel_x(
            asm, sx * x_fw - 0.5 * ww, sx * x_fw + 0.5 * ww, y_f, r_front, r_front, _RUBBER, hub, sections=12
        )
    tube = 0.024
    asm.add(cylinder((-x_rw, y_r, r_rear), (x_rw, y_r, r_rear), 0.01, sections=8), frame)
    asm.add(cylinder((-x_fw, y_f, r_front), (x_fw, y_f, r_front), 0.008, sections=8), frame)
    rg = 0.018
    x_h = hx - 0.07
    y_handle, z_handle = hy - rg, h - rg
    asm.add(cylinder((-x_h, y_handle, z_handle), (x_h, y_handle, z_handle), rg, sections=12), grip)
    z_hinge = 0.45 * h
    y_hinge = y_r - 0.12
    x_side = hx - ww - 0.03
    for sx in (-1.0, 1.0):
        hinge = (sx * x_side, y_hinge, z_hinge)
        asm.add(bar((sx * x_side, y_r, r_rear), hinge, tube), frame)
        asm.add(bar(hinge, (sx * x_h, y_handle - 0.01, z_handle - 0.01), tube), frame)
        asm.add(bar((sx * x_fw, y_f + 0.02, 2 * r_front + 0.03), hinge, tube), frame)
        asm.add(
            bar((sx * x_fw, y_f, r_front), (sx * x_fw, y_f + 0.02, 2 * r_front + 0.04), (0.03, 0.03, 0.03)),
            frame,
        )
        asm.box(
            (sx * x_side - 0.025, y_hinge - 0.025, z_hinge - 0.03),
            (sx * x_side + 0.025, y_hinge + 0.025, z_hinge + 0.03),
            shade(frame, 0.7),
        )
    # basket between the axles
    bx = x_side - 0.03
    b_y0, b_y1 = y_f + r_front + 0.03, y_r - r_rear * 0.3
    b_z0 = max(0.1, r_front + 0.02)
    basket = box((-bx, b_y0, b_z0), (bx, b_y1, b_z0 + 0.14))
    basket = difference(
        basket, box((-bx + 0.012, b_y0 + 0.012, b_z0 + 0.012), (bx - 0.012, b_y1 - 0.012, b_z0 + 0.2))
    )
    asm.add(basket, (40, 40, 44))
    body_w = min(0.42, 2 * x_side - 0.04)
    if pram:
        bl = float(np.clip(0.75 * d, 0.62, 0.82))
        yc = 0.5 * (y_f + y_r) + 0.04
        yc = float(np.clip(yc, -hy + 0.5 * bl, hy - 0.5 * bl - 0.05))
        z0 = z_hinge - 0.02
        z_rim = min(z0 + 0.26, h - 0.3)
        top = _outline(body_w, bl, 0.1, yc)
        bottom = _outline(0.85 * body_w, 0.85 * bl, 0.08, yc)
        asm.add(hull([(x, y, z_rim) for x, y in top] + [(x, y, z0) for x, y in bottom]), fabric)
        inner = _outline(body_w - 0.05, bl - 0.05, 0.08, yc)
        asm.add(hull([(x, y, z) for x, y in inner for z in (z_rim - 0.04, z_rim + 0.006)]), (236, 232, 222))
        cover = _outline(body_w - 0.03, 0.45 * bl, 0.06, yc - 0.25 * bl)
        asm.add(
            hull([(x, y, z) for x, y in cover for z in (z_rim - 0.02, z_rim + 0.012)]), shade(fabric, 0.8)
        )
        hood_y, hood_z, hood_len = yc + 0.05 * bl, z_rim, 0.45 * bl
    else:
        seat_z = z_hinge + 0.06
        y0, y1 = y_f + 0.12, y_hinge + 0.02
        asm.box((-0.5 * body_w, y0, seat_z - 0.05), (0.5 * body_w, y1, seat_z), fabric)
        back_top = (0.0, min(y1 + 0.22, hy - 0.08), min(seat_z + 0.45, h - 0.25))
        asm.add(bar((0.0, y1 - 0.02, seat_z - 0.01), back_top, (body_w, 0.05, 0.05)), fabric)
        asm.add(
            bar((0.0, y0 + 0.02, seat_z - 0.03), (0.0, y0 - 0.1, seat_z - 0.22), (body_w, 0.03, 0.03)),
            shade(fabric, 0.85),
        )
        asm.add(
            cylinder(
                (-0.5 * body_w, y0 + 0.02, seat_z + 0.16),
                (0.5 * body_w, y0 + 0.02, seat_z + 0.16),
                0.015,
                sections=8,
            ),
            grip,
        )
        for sx in (-1.0, 1.0):
            asm.add(
                bar(
                    (sx * 0.5 * body_w, y0 + 0.02, seat_z + 0.16), (sx * 0.5 * body_w, y0 + 0.1, seat_z), 0.02
                ),
                frame,
            )
        hood_y, hood_z, hood_len = back_top[1] - 0.22, back_top[2] - 0.04, 0.24
    hood_h = min(0.28, h - 0.04 - hood_z)
    rx = 0.5 * body_w + 0.012
    outer = ellipsoid((0.0, hood_y, hood_z), (rx, hood_len, hood_h), segments=16, rings=8)
    inner = ellipsoid(
        (0.0, hood_y, hood_z), (rx - 0.012, hood_len - 0.012, hood_h - 0.012), segments=16, rings=8
    )
    big = 2.0
    cut_front = box((-big, hood_y - big, hood_z - big), (big, hood_y, hood_z + big))
    cut_below = box((-big, -big, hood_z - big), (big, big, hood_z))
    asm.add(difference(outer, inner, cut_front, cut_below), shade(fabric, 0.9))
    return asm


ASSETS: tuple[Asset, ...] = (
    # MUTCD cones: 18" (0.45 m) to 36" (0.91 m) tall on 0.30-0.50 m square bases
    Asset(
        "traffic_cone",
        (0.30, 0.30, 0.45),
        (0.50, 0.50, 0.92),
        "floor",
        None,
        0.0,
        "plastic",
        _traffic_cone,
        contexts=("construction", "street", "parking"),
    ),
    # plastic water-filled barriers 1.0-2.0 m long, 0.4-0.6 m wide, 0.8-1.0 m tall;
    # barrier boards 1.0-2.0 m on 0.4-0.65 m foot plates, 1.0 m board top
    Asset(
        "traffic_barrier",
        (1.00, 0.40, 0.80),
        (2.00, 0.65, 1.10),
        "floor",
        None,
        0.0,
        "plastic",
        _traffic_barrier,
        contexts=("construction", "street"),
    ),
    # Type I/II barricades: rails 8-12" high, 1.0-1.8 m long, at least 0.9 m tall
    Asset(
        "sawhorse_barricade",
        (1.00, 0.50, 0.90),
        (1.80, 0.80, 1.20),
        "floor",
        None,
        0.0,
        "plastic",
        _sawhorse_barricade,
        contexts=("construction",),
    ),
    # Heras-type panels: 2.0-3.5 m long, 2.0 m tall in 0.12-0.15 m high, 0.5-0.75 m long feet
    Asset(
        "construction_fence",
        (2.00, 0.50, 1.80),
        (3.50, 0.75, 2.20),
        "floor",
        None,
        0.0,
        "metal",
        _construction_fence,
        contexts=("construction",),
    ),
    # step ladders: 3 ft (0.9 m) to 7 ft (2.1 m), 0.45-0.7 m wide at the feet
    Asset(
        "ladder",
        (0.45, 0.55, 0.90),
        (0.70, 1.25, 2.10),
        "floor",
        None,
        0.6,
        "metal",
        _ladder,
        contexts=("construction",),
    ),
    # EUR 1.2 x 0.8 x 0.144, EUR2 1.2 x 1.0, GMA 1.219 x 1.016 x ~0.14, half pallet 0.8 x 0.6
    Asset(
        "cargo_pallet",
        (0.80, 0.60, 0.12),
        (1.22, 1.10, 0.16),
        "floor",
        None,
        0.0,
        "wood",
        _cargo_pallet,
        supports=top_support(inset=0.03),
        contexts=("construction",),
    ),
    # contractor wheelbarrows: ~1.5 m long, 0.6-0.7 m wide, 0.6-0.7 m to the tray rim
    Asset(
        "wheelbarrow",
        (0.55, 1.20, 0.55),
        (0.75, 1.60, 0.75),
        "floor",
        None,
        0.6,
        "metal",
        _wheelbarrow,
        contexts=("construction",),
    ),
    # hand toolboxes 16-26" (0.4-0.66 m) long; steel site boxes up to 0.7 m
    Asset(
        "toolbox",
        (0.36, 0.18, 0.16),
        (0.70, 0.35, 0.38),
        "floor",
        None,
        0.4,
        "plastic",
        _toolbox,
        supports=top_support(inset=0.05),
        contexts=("construction",),
    ),
    # filled sandbags ~0.6 x 0.3 x 0.12 m; stacks 1-4 bags long, 2-7 layers high
    Asset(
        "sandbag_stack",
        (0.80, 0.32, 0.25),
        (2.20, 0.80, 0.90),
        "floor",
        None,
        0.0,
        "fabric",
        _sandbag_stack,
        contexts=("construction",),
    ),
    # FIFA size 5: 68-70 cm circumference, 0.216-0.223 m across
    Asset(
        "soccer_ball",
        (0.216, 0.216, 0.216),
        (0.223, 0.223, 0.223),
        "floor",
        None,
        0.0,
        "leather",
        _soccer_ball,
        contexts=("sports", "park"),
    ),
    # backboards 44-72" (1.12-1.83 m) wide, rim at 2.3-3.05 m
    Asset(
        "basketball_hoop",
        (1.05, 1.60, 3.00),
        (1.83, 2.40, 4.10),
        "floor",
        None,
        2.0,
        "metal",
        _basketball_hoop,
        contexts=("sports", "park"),
    ),
    # decks 7.5-9" (0.19-0.23 m) wide, 28-33" (0.71-0.84 m) long
    Asset(
        "skateboard",
        (0.19, 0.70, 0.105),
        (0.23, 0.84, 0.14),
        "floor",
        None,
        0.0,
        "wood",
        _skateboard,
        contexts=("sports", "park"),
    ),
    # prams and pushchairs: 0.5-0.65 m wide, 0.8-1.1 m long, handle at 0.95-1.15 m
    Asset(
        "stroller",
        (0.50, 0.80, 0.95),
        (0.65, 1.10, 1.15),
        "floor",
        None,
        0.5,
        "fabric",
        _stroller,
        contexts=("street", "park"),
    ),
)
