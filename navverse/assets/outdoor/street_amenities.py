"""Street amenities: park bench, picnic table, bistro table and chair, patio umbrella, A-frame sign, street
planter, waste bin, recycling bin, dumpster, drinking fountain and parking ticket machine.

Frame conventions of these categories (on top of the library's: x width, y depth, z up, front +y):

- ``park_bench`` and ``bistro_chair``: the seat faces +y, the backrest (if any) leans back towards -y.
- ``picnic_table``: the table runs along x; its two benches lie along the +y and -y edges.
- ``bistro_table``, ``patio_umbrella``, ``street_planter``: symmetric; ``patio_umbrella`` is sized open
  (the canopy spans the whole footprint, the pole stands at the centre).
- ``a_frame_sign``: the two boards face +y and -y and meet at the top; the front board is at +y.
- ``waste_bin`` and ``recycling_bin``: the openings face +y (a post-mounted bin has its post at -y).
- ``dumpster``: the lids are hinged at the back (-y); handles and the lifting side face +y.
- ``drinking_fountain``: the user stands at +y, the bowls project towards +y from the pedestal.
- ``ticket_machine``: screen, keypad and ticket slot face +y.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from navverse.assets.fittings import caster
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
    rotate,
    rounded_prism,
)
from navverse.assets.spec import Asset, Size, SupportArea

__all__ = ["ASSETS"]

# Local palettes (sRGB) for outdoor finishes that materials.py has no palette for.
_COATS: tuple[RGB, ...] = (
    (36, 72, 52),  # fir green, RAL 6009
    (30, 32, 34),  # jet black
    (58, 62, 66),  # anthracite, RAL 7016
    (32, 50, 88),  # steel blue
    (88, 60, 42),  # chocolate brown
    (128, 132, 136),  # galvanised / silver grey
)
_RECYCLED: tuple[RGB, ...] = ((88, 72, 56), (62, 62, 60), (122, 98, 72), (72, 86, 64))  # recycled plastic
_CONCRETE: tuple[RGB, ...] = ((190, 186, 178), (160, 158, 152), (208, 202, 190), (138, 136, 132))
_CORTEN: tuple[RGB, ...] = ((142, 74, 42), (118, 62, 38), (156, 88, 52))
_RATTAN: tuple[RGB, ...] = ((198, 162, 110), (150, 110, 64), (226, 208, 172), (104, 76, 48))
_WEAVE: tuple[RGB, ...] = (
    (236, 232, 220),
    (34, 34, 36),
    (160, 42, 40),
    (40, 50, 92),
    (52, 100, 72),
    (96, 146, 192),
    (212, 170, 60),
)
_ENAMEL: tuple[RGB, ...] = (
    (178, 40, 40),
    (40, 70, 122),
    (60, 110, 80),
    (232, 228, 216),
    (230, 170, 50),
    (30, 30, 32),
    (120, 170, 190),
    (196, 96, 60),
)
_CANOPY: tuple[RGB, ...] = (
    (240, 234, 218),  # ecru
    (250, 250, 248),  # white
    (178, 40, 40),  # red
    (34, 48, 84),  # navy
    (60, 96, 64),  # forest green
    (196, 110, 60),  # terracotta
    (44, 44, 46),  # black
    (214, 180, 90),  # ochre
    (128, 124, 116),  # taupe
)
_STREAMS: tuple[RGB, ...] = (
    (36, 90, 170),  # paper: blue
    (240, 196, 30),  # plastics and cans: yellow
    (40, 140, 72),  # glass: green
    (72, 74, 78),  # residual waste: grey
    (122, 78, 42),  # organic: brown
    (200, 64, 40),  # metal / hazardous: red
)
_SKIPS: tuple[RGB, ...] = (
    (40, 96, 60),
    (34, 60, 112),
    (76, 78, 82),
    (112, 72, 42),
    (170, 42, 38),
    (226, 178, 40),
)
_CHALKBOARD: tuple[RGB, ...] = ((34, 38, 36), (30, 52, 44), (26, 28, 30))
_CHALK: tuple[RGB, ...] = ((240, 240, 234), (246, 214, 90), (240, 150, 170), (150, 210, 240))
_PAY: tuple[RGB, ...] = ((172, 176, 180), (62, 66, 70), (30, 50, 92), (36, 72, 52), (222, 178, 40))
_PARKING_BLUE: RGB = (24, 82, 170)
_WHITE: RGB = (244, 244, 240)
_DARK: RGB = (26, 28, 32)
_X = (1.0, 0.0, 0.0)


def _slab(
    origin: Sequence[float],
    u: Sequence[float],
    v: Sequence[float],
    n: Sequence[float],
    u_range: tuple[float, float],
    v_range: tuple[float, float],
    n_range: tuple[float, float],
) -> Solid:
    """A parallelepiped ``origin + a u + b v + c n`` over the three ranges: a tilted board or panel."""
    o, uu, vv, nn = (np.asarray(p, dtype=np.float64) for p in (origin, u, v, n))
    points = [o + a * uu + b * vv + c * nn for a in u_range for b in v_range for c in n_range]
    return hull(points)


def _yz_axes(dy: float, dz: float) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """Unit vector along ``(0, dy, dz)`` and the normal obtained by turning it -90 degrees about x."""
    length = math.hypot(dy, dz)
    return (0.0, dy / length, dz / length), (0.0, dz / length, -dy / length)


def _lerp(p: Sequence[float], q: Sequence[float], t: float) -> tuple[float, float, float]:
    """The point a fraction `t` of the way from `p` to `q`."""
    return (p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2]))


# --- park bench -------------------------------------------------------------------------------------

_BENCH_GAP = 0.012


def _bench_layout(size: Size) -> tuple[bool, float, float, int, float]:
    """Seat of a park bench: (has a backrest, seat height, back edge y of the seat, slats, slat width).

    Only the size decides it, so the support rule and the builder agree; the slat count is odd so that
    the middle of the seat is a slat, not a gap.
    """
    _, d, h = size
    backed = h >= 0.65
    if backed:
        seat_top = 0.45
        seat_d = min(float(np.clip(0.62 * d, 0.34, 0.5)), d - 0.14)  # room for a reclined backrest
    else:
        seat_top = h if h <= 0.52 else 0.45
        seat_d = d
    n = max(3, 2 * round((seat_d / 0.1 - 1.0) / 2.0) + 1)
    slat = (seat_d - (n - 1) * _BENCH_GAP) / n
    return backed, seat_top, 0.5 * d - seat_d, n, slat


def _park_bench(rng: np.random.Generator, size: Size) -> Assembly:
    """A slatted park bench on cast-iron, steel or concrete ends; tall ones get a reclined slatted
    backrest (sometimes armrests), low ones are backless (with end rails when the size leaves room)."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    backed, seat_top, y0, n, slat = _bench_layout(size)
    asm = Assembly()
    wood = pick(rng, "wood") if rng.uniform() < 0.7 else pick(rng, _RECYCLED)
    frame = pick(rng, _COATS)
    style = int(rng.integers(3))  # 0 cast-iron frames, 1 steel legs, 2 concrete blocks
    st = float(rng.uniform(0.03, 0.045))
    for k in range(n):
        ya = y0 + k * (slat + _BENCH_GAP)
        asm.box(
            (-hx, ya, seat_top - st), (hx, ya + slat, seat_top), shade(wood, float(rng.uniform(0.93, 1.05)))
        )
    arms = bool(rng.uniform() < 0.5) if backed else h > seat_top + 0.05
    inset = float(rng.uniform(0.08, 0.12)) if arms or style == 2 else float(rng.uniform(0.1, 0.25))
    ends = (-(hx - inset), hx - inset)
    supports = ends + ((0.0,) if w > 1.9 else ())
    rail_top = seat_top - st
    back = None
    if backed:
        tt = st + 0.03  # slat and frame upright behind it
        az, ay = seat_top + 0.05, y0 - 0.01
        yb = -hy + tt
        for _ in range(12):  # the back top edge at z = h, the frame behind it touching y = -hy
            yb = -hy + tt * (h - az) / math.hypot(h - az, ay - yb)
        up, _ = _yz_axes(yb - ay, h - az)
        rise, run = h - az, ay - yb
        length = math.hypot(rise, run)
        normal = (0.0, -rise / length, -run / length)  # towards the back
        origin = (0.0, ay, az)
        m = max(2, round((length + 0.02) / 0.12))
        bw = (length - (m - 1) * 0.02) / m
        for k in range(m):
            s0 = k * (bw + 0.02)
            asm.add(
                _slab(origin, _X, up, normal, (-hx, hx), (s0, s0 + bw), (0.0, st)),
                shade(wood, float(rng.uniform(0.93, 1.05))),
            )
        back = (origin, up, normal, length, tt, ay, az, rise, run)
    block = pick(rng, _CONCRETE)
    for x in supports:
        if style == 2:
            asm.box((x - 0.07, -hy + 0.04, 0.0), (x + 0.07, hy - 0.04, rail_top), block)
        else:
            asm.box(
                (x - 0.025, (y0 + 0.01) if backed else -hy + 0.03, rail_top - 0.05),
                (x + 0.025, hy - 0.03, rail_top),
                frame,
            )
            yf = hy - 0.07
            if back is not None:
                origin, up, normal, length, tt, *_ = back
                foot = (x, -hy + 0.035, 0.02)
                top = np.asarray(origin) + (-0.12) * np.asarray(up) + tt * np.asarray(normal) + (x, 0.0, 0.0)
            else:
                foot = (x, -hy + 0.05, 0.02)
                top = np.array((x, -hy + 0.07, rail_top - 0.025))
            if style == 0:
                asm.add(bar((x, yf + 0.02, 0.02), (x, yf, rail_top - 0.025), (0.05, 0.04, 0.04)), frame)
                asm.add(bar(foot, top, (0.05, 0.04, 0.04)), frame)
                for y in (yf + 0.02, foot[1]):
                    asm.box((x - 0.035, y - 0.03, 0.0), (x + 0.035, y + 0.03, 0.025), frame)
            else:
                asm.add(cylinder((x, yf, 0.0), (x, yf, rail_top - 0.04), 0.022, sections=12), frame)
                asm.add(bar((x, foot[1], 0.0125), top, 0.025), frame)
                asm.box((x - 0.02, -hy + 0.04, 0.0), (x + 0.02, hy - 0.04, 0.02), frame)
        if back is not None:
            origin, up, normal, length, tt, *_ = back
            lo = -0.12 if style != 2 else -0.3
            asm.add(_slab(origin, _X, up, normal, (x - 0.025, x + 0.025), (lo, length), (st, tt)), frame)
    if arms:
        for x in ends:
            if backed and back is not None:
                _, _, _, _, tt, ay, az, rise, run = back
                z_arm = min(seat_top + 0.23, h - 0.04)
                y_line = ay - (z_arm - az) * run / rise
                asm.box((x - 0.03, y_line - tt, z_arm - 0.035), (x + 0.03, hy - 0.005, z_arm), frame)
                asm.add(bar((x, hy - 0.05, seat_top), (x, hy - 0.05, z_arm - 0.03), 0.035), frame)
            else:
                asm.box((x - 0.03, -hy + 0.04, h - 0.035), (x + 0.03, hy - 0.04, h), frame)
                for y in (-hy + 0.08, hy - 0.08):
                    asm.add(bar((x, y, seat_top), (x, y, h - 0.03), 0.035), frame)
    return asm


def _bench_supports(size: Size) -> list[SupportArea]:
    w, d, _ = size
    _, seat_top, y0, _, _ = _bench_layout(size)
    return [
        SupportArea(height=seat_top, x_min=-0.5 * w + 0.16, x_max=0.5 * w - 0.16, y_min=y0, y_max=0.5 * d)
    ]


# --- picnic table -----------------------------------------------------------------------------------


def _picnic_layout(size: Size) -> tuple[float, int, float, float]:
    """Top of a picnic table: (depth, board count (odd), board width, gap)."""
    top_d = float(np.clip(0.45 * size[1], 0.6, 0.82))
    n = 5 if top_d < 0.72 else 7
    gap = 0.008
    return top_d, n, (top_d - (n - 1) * gap) / n, gap


def _picnic_table(rng: np.random.Generator, size: Size) -> Assembly:
    """A board top and two attached bench seats on wooden A-frames with braces, or on steel tube frames."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    top_d, n, bw, gap = _picnic_layout(size)
    asm = Assembly()
    metal = bool(rng.uniform() < 0.4)
    wood = pick(rng, "wood") if rng.uniform() < 0.75 else pick(rng, _RECYCLED)
    frame = pick(rng, _COATS) if metal else shade(wood, 0.85)
    tt = 0.04
    for k in range(n):
        ya = -0.5 * top_d + k * (bw + gap)
        asm.box((-hx, ya, h - tt), (hx, ya + bw, h), shade(wood, float(rng.uniform(0.93, 1.05))))
    seat_top = min(0.45, h - 0.25)
    bench_d = float(np.clip(0.5 * (d - top_d) - 0.08, 0.22, 0.32))
    bench_x = hx - float(rng.uniform(0.0, 0.1))
    seat_w = 0.5 * (bench_d - gap)
    for s in (-1.0, 1.0):
        for k in range(2):
            ya = hy - bench_d + k * (seat_w + gap)
            y_lo, y_hi = sorted((s * ya, s * (ya + seat_w)))
            asm.box(
                (-bench_x, y_lo, seat_top - tt),
                (bench_x, y_hi, seat_top),
                shade(wood, float(rng.uniform(0.93, 1.05))),
            )
    ex = float(np.clip(0.2 * w, 0.25, 0.45))
    xs = (-(hx - ex), hx - ex)
    member_z = seat_top - tt
    for x in xs:
        if metal:
            for s in (-1.0, 1.0):
                asm.add(bar((x, s * (hy - 0.1), 0.0225), (x, s * 0.2 * top_d, h - tt - 0.0225), 0.045), frame)
            asm.add(
                bar((x, -0.5 * top_d + 0.04, h - tt - 0.02), (x, 0.5 * top_d - 0.04, h - tt - 0.02), 0.04),
                frame,
            )
            asm.add(bar((x, -(hy - 0.03), member_z - 0.02), (x, hy - 0.03, member_z - 0.02), 0.04), frame)
        else:
            asm.box(
                (x - 0.025, -0.5 * top_d + 0.02, h - tt - 0.06),
                (x + 0.025, 0.5 * top_d - 0.02, h - tt),
                frame,
            )
            asm.box((x - 0.025, -(hy - 0.02), member_z - 0.08), (x + 0.025, hy - 0.02, member_z), frame)
            for s in (-1.0, 1.0):
                asm.add(
                    bar(
                        (x, s * 0.3 * top_d, h - tt - 0.045), (x, s * (hy - 0.12), 0.045), (0.045, 0.09, 0.09)
                    ),
                    frame,
                )
            inward = -0.35 if x > 0 else 0.35
            asm.add(bar((x, 0.0, member_z - 0.04), (x + inward, 0.0, h - tt - 0.025), 0.04), frame)
    asm.add(bar((xs[0], 0.0, h - tt - 0.03), (xs[1], 0.0, h - tt - 0.03), 0.04), frame)
    return asm


def _picnic_supports(size: Size) -> list[SupportArea]:
    w, _, h = size
    half = 0.5 * _picnic_layout(size)[0] - 0.005
    return [SupportArea(height=h, x_min=-0.5 * w + 0.05, x_max=0.5 * w - 0.05, y_min=-half, y_max=half)]


# --- cafe furniture ---------------------------------------------------------------------------------


def _bistro_table(rng: np.random.Generator, size: Size) -> Assembly:
    """A small round or square cafe table (enamel, marble, wood or metal top on a rim) on a pedestal
    with a cross foot or a cast tripod, or on four splayed tube legs."""
    w, d, h = size
    rx, ry = 0.5 * w, 0.5 * d
    asm = Assembly()
    finish = int(rng.integers(4))
    if finish == 0:
        top = pick(rng, _ENAMEL)
    elif finish == 1:
        top = pick(rng, "stone")
    elif finish == 2:
        top = pick(rng, "wood")
    else:
        top = pick(rng, "metal")
    metal = pick(rng, _COATS) if rng.uniform() < 0.7 else pick(rng, "chrome")
    tt = float(rng.uniform(0.018, 0.03))
    under = h - tt
    if rng.uniform() < 0.6:
        asm.add(frustum((0, 0, under), (0, 0, h), (rx, ry), (rx, ry), sections=24), top)
        asm.add(
            frustum(
                (0, 0, under - 0.03), (0, 0, under), (0.9 * rx, 0.9 * ry), (0.95 * rx, 0.95 * ry), sections=24
            ),
            metal,
        )
    else:
        asm.add(rounded_prism((0.0, 0.0), w, d, 0.015, under, h), top)
        asm.add(rounded_prism((0.0, 0.0), w - 0.05, d - 0.05, 0.01, under - 0.03, under), metal)
    base = int(rng.integers(3))
    r = min(rx, ry)
    if base == 2:  # four splayed tube legs with a stretcher ring
        feet, tops = [], []
        for k in range(4):
            a = 0.25 * math.pi + 0.5 * math.pi * k
            c, s = math.cos(a), math.sin(a)
            feet.append((0.72 * rx * c, 0.72 * ry * s, 0.0125))
            tops.append((0.55 * rx * c, 0.55 * ry * s, under - 0.03))
            asm.add(bar(feet[-1], tops[-1], 0.025), metal)
        for k in range(4):
            p = _lerp(feet[k], tops[k], 0.3)
            q = _lerp(feet[(k + 1) % 4], tops[(k + 1) % 4], 0.3)
            asm.add(bar(p, q, 0.016), metal)
        return asm
    asm.add(
        cylinder((0, 0, 0.02), (0, 0, under - 0.03), float(rng.uniform(0.022, 0.032)), sections=12), metal
    )
    asm.add(frustum((0, 0, under - 0.1), (0, 0, under - 0.03), 0.035, 0.09, sections=12), metal)
    if base == 0:  # cross foot with levelling pads
        for k in range(4):
            a = 0.25 * math.pi + 0.5 * math.pi * k
            tip = (0.68 * rx * math.cos(a), 0.68 * ry * math.sin(a))
            asm.add(bar((0, 0, 0.025), (tip[0], tip[1], 0.025), (0.04, 0.04, 0.03)), metal)
            asm.add(cylinder((tip[0], tip[1], 0.0), (tip[0], tip[1], 0.012), 0.02, sections=8), _DARK)
    else:  # cast tripod: three S-curved legs
        asm.add(frustum((0, 0, 0.2), (0, 0, 0.32), 0.05, 0.03, sections=12), metal)
        for k in range(3):
            a = 0.5 * math.pi + 2.0 * math.pi * k / 3.0
            c, s = math.cos(a), math.sin(a)
            knee = (0.45 * r * c, 0.45 * r * s, 0.12)
            foot = (0.75 * rx * c, 0.75 * ry * s, 0.015)
            asm.add(bar((0.03 * c, 0.03 * s, 0.26), knee, 0.03), metal)
            asm.add(bar(knee, foot, 0.03), metal)
    return asm


def _bistro_table_supports(size: Size) -> list[SupportArea]:
    w, d, h = size
    # the largest rectangle in a round top, less a margin (a square top contains it too)
    return [SupportArea(height=h, x_min=-0.33 * w, x_max=0.33 * w, y_min=-0.33 * d, y_max=0.33 * d)]


def _bistro_chair(rng: np.random.Generator, size: Size) -> Assembly:
    """A terrace chair facing +y: a Parisian chair with a two-tone woven seat and back on a bamboo-look
    frame, a slatted painted-steel chair, or a stacking aluminium chair with armrests."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    style = int(rng.integers(3))
    t = float(rng.uniform(0.02, 0.026))
    seat_top = float(np.clip(0.45, 0.4, h - 0.3))
    if style == 0:
        frame = pick(rng, _RATTAN)
        first = int(rng.integers(len(_WEAVE)))
        second = (first + 1 + int(rng.integers(len(_WEAVE) - 1))) % len(_WEAVE)
        weave = (_WEAVE[first], _WEAVE[second])
    elif style == 1:
        frame = pick(rng, _ENAMEL)
        weave = (frame, shade(frame, 0.92))
    else:
        frame = pick(rng, "chrome") if rng.uniform() < 0.5 else pick(rng, _COATS)
        wood = pick(rng, "wood") if rng.uniform() < 0.6 else pick(rng, _RECYCLED)
        weave = (wood, shade(wood, 0.94))
    xp = hx - 0.06  # back posts and seat sides
    joint_z = seat_top - 0.03
    arm_z = min(seat_top + 0.22, h - 0.12)
    rear_joint = (-hy + 0.09, joint_z)
    back_top = (-hy + 0.5 * t, h - 0.5 * t)
    for sx in (-1.0, 1.0):
        front_top = (sx * xp, hy - 0.06, arm_z if style == 2 else joint_z)
        asm.add(bar((sx * (hx - 0.5 * t), hy - 0.5 * t, 0.5 * t), front_top, t), frame)
        rear_foot = (sx * (hx - 0.5 * t - 0.02), -hy + 0.5 * t + 0.03, 0.5 * t)
        asm.add(bar(rear_foot, (sx * xp, *rear_joint), t), frame)
        asm.add(bar((sx * xp, *rear_joint), (sx * xp, *back_top), t), frame)
        asm.add(bar((sx * xp, -hy + 0.09, joint_z), (sx * xp, hy - 0.06, joint_z), t), frame)  # seat side
        if style == 0:
            p = _lerp((sx * (hx - 0.5 * t), hy - 0.5 * t, 0.5 * t), front_top, 0.4)
            q = _lerp(rear_foot, (sx * xp, *rear_joint), 0.4)
            asm.add(bar(p, q, 0.6 * t), frame)
        if style == 2:
            y_post = rear_joint[0] + (arm_z - joint_z) / (back_top[1] - joint_z) * (
                back_top[0] - rear_joint[0]
            )
            asm.add(bar((sx * xp, y_post, arm_z), front_top, (t, t, 0.02)), frame)
    asm.add(bar((-xp, hy - 0.06, joint_z), (xp, hy - 0.06, joint_z), t), frame)
    asm.add(bar((-xp, -hy + 0.09, joint_z), (xp, -hy + 0.09, joint_z), t), frame)
    rail_h = 0.05 if style == 1 else t
    asm.add(
        bar((-xp, back_top[0], h - 0.5 * rail_h), (xp, back_top[0], h - 0.5 * rail_h), (t, t, rail_h)), frame
    )
    # seat: strips or slats across the frame
    y_a, y_b = -hy + 0.08, hy - 0.05
    if style == 2:  # slats front to back
        k_n = 6
        pitch = 2 * xp / k_n
        for k in range(k_n):
            x0 = -xp + k * pitch + 0.006
            asm.box((x0, y_a, joint_z), (x0 + pitch - 0.012, y_b, seat_top), weave[k % 2])
    else:
        k_n = 9 if style == 0 else 5
        pitch = (y_b - y_a) / k_n
        for k in range(k_n):
            ya = y_a + k * pitch
            gap = 0.0 if style == 0 else 0.01
            asm.box((-xp, ya, joint_z), (xp, ya + pitch - gap, seat_top), weave[k % 2])
    # back: horizontal strips or slats in the plane of the back posts
    up, normal = _yz_axes(back_top[0] - rear_joint[0], back_top[1] - rear_joint[1])
    length = math.hypot(back_top[0] - rear_joint[0], back_top[1] - rear_joint[1])
    origin = (0.0, *rear_joint)
    s_lo, s_hi = (0.3 if style == 0 else 0.45) * length, length - 0.03
    count = 6 if style == 0 else 3
    pitch = (s_hi - s_lo) / count
    for k in range(count):
        s0 = s_lo + k * pitch
        gap = 0.0 if style == 0 else 0.015
        asm.add(
            _slab(origin, _X, up, normal, (-xp, xp), (s0, s0 + pitch - gap), (-0.008, 0.008)), weave[k % 2]
        )
    return asm


# --- patio umbrella ---------------------------------------------------------------------------------


def _patio_umbrella(rng: np.random.Generator, size: Size) -> Assembly:
    """An open market umbrella: weighted base, pole with crank and runner, ribs and stretchers under a
    shallow octagonal or square canopy (plain or striped, sometimes with a valance and a vent), finial."""
    w, d, h = size
    rx, ry = 0.5 * w, 0.5 * d
    asm = Assembly()
    cloth = pick(rng, _CANOPY)
    stripe = pick(rng, _CANOPY) if rng.uniform() < 0.3 else cloth
    metal = pick(rng, "chrome") if rng.uniform() < 0.5 else pick(rng, "dark_wood")
    square = bool(rng.uniform() < 0.35) or abs(w - d) > 0.15 * min(w, d)
    panels = 4 if square else 8
    fin_h = float(rng.uniform(0.06, 0.12))
    apex = h - fin_h
    rise = float(np.clip(0.16 * (rx + ry), 0.3, 0.55))
    rim_z = apex - rise
    shell = 0.02
    if square:
        rim = [
            (rx * math.sqrt(2.0) * math.cos(a), ry * math.sqrt(2.0) * math.sin(a))
            for a in (0.25 * math.pi + 0.5 * math.pi * k for k in range(4))
        ]
    else:
        rim = [(rx * math.cos(a), ry * math.sin(a)) for a in (0.25 * math.pi * k for k in range(8))]
    for k in range(panels):
        (ax, ay), (bx, by) = rim[k], rim[(k + 1) % panels]
        points = [
            (px, py, z - dz)
            for px, py, z in ((0.0, 0.0, apex), (ax, ay, rim_z), (bx, by, rim_z))
            for dz in (0.0, shell)
        ]
        asm.add(hull(points), cloth if k % 2 == 0 else stripe)
    if rng.uniform() < 0.5:  # valance flaps
        drop = float(rng.uniform(0.1, 0.18))
        for k in range(panels):
            (ax, ay), (bx, by) = rim[k], rim[(k + 1) % panels]
            points = [
                (f * px, f * py, z)
                for px, py in ((ax, ay), (bx, by))
                for f in (1.0, 0.985)
                for z in (rim_z - shell, rim_z - drop)
            ]
            asm.add(hull(points), shade(stripe, 0.9))
    vent = rng.uniform() < 0.5
    if vent:
        vr = 0.22 * min(rx, ry)
        asm.add(
            frustum(
                (0, 0, apex - 0.06),
                (0, 0, apex + 0.04),
                vr,
                0.04,
                sections=panels,
                phase=0.25 * math.pi if square else 0.0,
            ),
            cloth,
        )
    finial_base = apex + (0.04 if vent else 0.0)
    asm.add(frustum((0, 0, finial_base - 0.02), (0, 0, h), 0.035, 0.012, sections=12), metal)
    # pole, hub, runner, ribs and stretchers
    pole_r = float(rng.uniform(0.019, 0.026))
    style = int(rng.integers(3))
    base_top = 0.1
    if style == 0:  # round concrete or resin base with a socket
        br = float(rng.uniform(0.24, 0.3))
        asm.add(frustum((0, 0, 0), (0, 0, 0.09), br, 0.9 * br, sections=16), pick(rng, _CONCRETE))
        asm.add(cylinder((0, 0, 0.09), (0, 0, 0.3), pole_r + 0.012, sections=12), _DARK)
    elif style == 1:  # granite slab
        side = float(rng.uniform(0.42, 0.5))
        asm.box((-0.5 * side, -0.5 * side, 0.0), (0.5 * side, 0.5 * side, 0.07), pick(rng, "stone"))
        asm.add(cylinder((0, 0, 0.07), (0, 0, 0.25), pole_r + 0.012, sections=12), _DARK)
    else:  # steel cross stand weighted with four paving slabs
        arm = float(rng.uniform(0.45, 0.55))
        for k in range(2):
            a = 0.5 * math.pi * k
            asm.add(
                bar(
                    (-arm * math.cos(a), -arm * math.sin(a), 0.02),
                    (arm * math.cos(a), arm * math.sin(a), 0.02),
                    0.04,
                ),
                _DARK,
            )
        slab = pick(rng, _CONCRETE)
        for sx in (-1.0, 1.0):
            for sy in (-1.0, 1.0):
                x_lo, x_hi = sorted((sx * 0.03, sx * 0.33))
                y_lo, y_hi = sorted((sy * 0.03, sy * 0.33))
                asm.box((x_lo, y_lo, 0.04), (x_hi, y_hi, 0.09), slab)
        asm.add(cylinder((0, 0, 0.04), (0, 0, 0.3), pole_r + 0.012, sections=12), _DARK)
    asm.add(cylinder((0, 0, base_top), (0, 0, apex - 0.02), pole_r, sections=12), metal)
    asm.add(cylinder((0, 0, apex - 0.2), (0, 0, apex - shell - 0.02), pole_r + 0.02, sections=12), metal)
    runner = rim_z - 0.35
    asm.add(cylinder((0, 0, runner - 0.06), (0, 0, runner + 0.06), pole_r + 0.018, sections=12), metal)
    asm.box((-0.02, pole_r, 1.1), (0.02, pole_r + 0.06, 1.16), metal)  # crank
    tips = list(rim)
    if square:  # ribs to the corners and to the middles of the edges
        tips += [
            (0.5 * (rim[k][0] + rim[(k + 1) % 4][0]), 0.5 * (rim[k][1] + rim[(k + 1) % 4][1]))
            for k in range(4)
        ]
    for px, py in tips:
        hub = (0.0, 0.0, apex - shell - 0.05)
        tip = (0.96 * px, 0.96 * py, rim_z - shell - 0.012)
        asm.add(bar(hub, tip, 0.014), metal)
        asm.add(bar((0.0, 0.0, runner), _lerp(hub, tip, 0.45), 0.012), metal)
    return asm


# --- A-frame sign -----------------------------------------------------------------------------------


def _a_frame_sign(rng: np.random.Generator, size: Size) -> Assembly:
    """A sandwich board: two framed boards leaning together under a top handle, with side stays and feet;
    a chalkboard with chalk lines, or a poster board."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    chalk = bool(rng.uniform() < 0.55)
    if chalk:
        frame = pick(rng, "wood")
        face = pick(rng, _CHALKBOARD)
    else:
        frame = pick(rng, _COATS) if rng.uniform() < 0.6 else pick(rng, "white_plastic")
        face = pick(rng, "paper")
    cap = float(rng.uniform(0.05, 0.08))
    top = h - cap
    t = float(rng.uniform(0.022, 0.03))
    g = 0.004
    border = float(rng.uniform(0.03, 0.05))
    lines = [
        (float(rng.uniform(0.5, 0.9)), pick(rng, _CHALK) if chalk else pick(rng, "brand")) for _ in range(5)
    ]
    for s in (1.0, -1.0):
        yb, yt = s * hy, s * (g + t)
        points = [
            (x, y, z)
            for x in (-hx, hx)
            for y, z in ((yb, 0.0), (yb - s * t, 0.0), (yt, top), (yt - s * t, top))
        ]
        asm.add(hull(points), frame)
        up, normal = _yz_axes(yt - yb, top)
        if s < 0:
            normal = tuple(-c for c in normal)
        length = math.hypot(yt - yb, top)
        origin = (0.0, yb, 0.0)
        s0, s1 = 0.12 * length, length - border
        asm.add(_slab(origin, _X, up, normal, (-hx + border, hx - border), (s0, s1), (-0.002, 0.003)), face)
        if chalk:
            pitch = (s1 - s0) / (len(lines) + 1)
            for k, (frac, color) in enumerate(lines):
                sk = s1 - (k + 1) * pitch
                half = frac * (hx - border - 0.04)
                asm.add(
                    _slab(origin, _X, up, normal, (-half, half), (sk - 0.012, sk + 0.012), (0.0, 0.005)),
                    color,
                )
        else:
            span = s1 - s0
            asm.add(
                _slab(
                    origin, _X, up, normal, (-hx + border, hx - border), (s1 - 0.2 * span, s1), (0.0, 0.005)
                ),
                lines[0][1],
            )
            asm.add(
                _slab(
                    origin,
                    _X,
                    up,
                    normal,
                    (-hx + border + 0.03, hx - border - 0.03),
                    (s0 + 0.35 * span, s1 - 0.25 * span),
                    (0.0, 0.005),
                ),
                pick(rng, "accent"),
            )
            for k in range(3):
                sk = s0 + (0.08 + 0.08 * k) * span
                asm.add(
                    _slab(
                        origin,
                        _X,
                        up,
                        normal,
                        (-hx + border + 0.03, (0.4 - 0.1 * k) * hx),
                        (sk, sk + 0.02),
                        (0.0, 0.005),
                    ),
                    _DARK,
                )
        for x in (-hx + 0.03, hx - 0.03):  # rubber feet
            y_lo, y_hi = sorted((yb, yb - s * t))
            asm.box((x - 0.025, y_lo, 0.0), (x + 0.025, y_hi, 0.02), _DARK)
    handle = box((-hx + 0.02, -(g + t), top - 0.02), (hx - 0.02, g + t, h))
    hole = box((-0.07, -1.0, top + 0.012), (0.07, 1.0, h - 0.015))
    asm.add(difference(handle, hole), shade(frame, 0.85))
    zs = 0.4 * top
    for x in (-hx + 0.015, hx - 0.015):  # side stays holding the boards apart
        y_in = hy - t - (hy - g - t) * zs / top - 0.003
        asm.add(bar((x, y_in, zs), (x, -y_in, zs), (0.008, 0.008, 0.012)), pick(rng, "chrome"))
    return asm


# --- street planter ---------------------------------------------------------------------------------


def _street_planter(rng: np.random.Generator, size: Size) -> Assembly:
    """A planter (concrete box, wooden box, corten trough or round concrete bowl) filled with soil and
    a bush, a clipped hedge, ornamental grasses with flowers, or a topiary ball on a stem."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    bh = float(np.clip(0.5 * h, 0.4, 0.75))
    soil_color = pick(rng, "soil")
    round_ok = abs(w - d) < 0.25 * min(w, d)
    style = int(rng.integers(4 if round_ok else 3))
    if style == 0:  # precast concrete box with a lip and a recessed plinth
        concrete = pick(rng, _CONCRETE)
        wall = 0.07
        asm.add(rounded_prism((0.0, 0.0), w - 0.03, d - 0.03, 0.03, 0.05, bh - 0.06), concrete)
        lip = rounded_prism((0.0, 0.0), w, d, 0.03, bh - 0.06, bh)
        asm.add(
            difference(lip, box((-hx + wall, -hy + wall, bh - 0.07), (hx - wall, hy - wall, bh + 0.01))),
            shade(concrete, 1.05),
        )
        asm.box((-hx + 0.06, -hy + 0.06, 0.0), (hx - 0.06, hy - 0.06, 0.05), shade(concrete, 0.6))
        px, py = hx - wall - 0.01, hy - wall - 0.01
        asm.box((-hx + wall, -hy + wall, bh - 0.07), (hx - wall, hy - wall, bh - 0.04), soil_color)
    elif style == 1:  # wooden box: corner posts, horizontal boards, top frame
        wood = pick(rng, "wood")
        post = 0.08
        for x in (-hx + 0.015, hx - 0.015 - post):
            for y in (-hy + 0.015, hy - 0.015 - post):
                asm.box((x, y, 0.0), (x + post, y + post, bh - 0.03), shade(wood, 0.85))
        rows = max(2, round((bh - 0.07) / 0.14))
        pitch = (bh - 0.07) / rows
        for k in range(rows):
            z0 = 0.04 + k * pitch
            shade_k = shade(wood, float(rng.uniform(0.92, 1.06)))
            for y in (-hy + 0.025, hy - 0.045):
                asm.box(
                    (-hx + 0.015 + post, y, z0), (hx - 0.015 - post, y + 0.02, z0 + pitch - 0.008), shade_k
                )
            for x in (-hx + 0.025, hx - 0.045):
                asm.box(
                    (x, -hy + 0.015 + post, z0), (x + 0.02, hy - 0.015 - post, z0 + pitch - 0.008), shade_k
                )
        rim = box((-hx, -hy, bh - 0.03), (hx, hy, bh))
        asm.add(
            difference(rim, box((-hx + 0.1, -hy + 0.1, bh - 0.04), (hx - 0.1, hy - 0.1, bh + 0.01))), wood
        )
        px, py = hx - 0.1, hy - 0.1
        asm.box((-hx + 0.04, -hy + 0.04, 0.04), (hx - 0.04, hy - 0.04, bh - 0.05), soil_color)
    elif style == 2:  # corten steel trough
        steel = pick(rng, _CORTEN)
        shell = difference(
            box((-hx, -hy, 0.0), (hx, hy, bh)),
            box((-hx + 0.012, -hy + 0.012, 0.03), (hx - 0.012, hy - 0.012, bh + 0.01)),
        )
        asm.add(shell, steel)
        px, py = hx - 0.03, hy - 0.03
        asm.box((-hx + 0.012, -hy + 0.012, 0.03), (hx - 0.012, hy - 0.012, bh - 0.05), soil_color)
    else:  # round concrete bowl on a foot
        concrete = pick(rng, _CONCRETE)
        foot = 0.1
        outer = frustum((0, 0, foot), (0, 0, bh), (0.72 * hx, 0.72 * hy), (hx, hy), sections=20)
        inner = frustum(
            (0, 0, foot + 0.06),
            (0, 0, bh + 0.01),
            (0.72 * hx - 0.05, 0.72 * hy - 0.05),
            (hx - 0.05, hy - 0.05),
            sections=20,
        )
        asm.add(difference(outer, inner), concrete)
        asm.add(
            frustum((0, 0, 0), (0, 0, foot), (0.5 * hx, 0.5 * hy), (0.45 * hx, 0.45 * hy), sections=20),
            shade(concrete, 0.85),
        )
        asm.add(
            frustum(
                (0, 0, bh - 0.1),
                (0, 0, bh - 0.06),
                (hx - 0.07, hy - 0.07),
                (hx - 0.055, hy - 0.055),
                sections=20,
            ),
            soil_color,
        )
        px, py = 0.68 * (hx - 0.06), 0.68 * (hy - 0.06)
    _planting(asm, rng, bh - 0.05, h, px, py)
    return asm


def _planting(asm: Assembly, rng: np.random.Generator, z0: float, top: float, px: float, py: float) -> None:
    """Plants standing on soil at `z0` within ``|x| <= px, |y| <= py``, the highest point at `top`."""
    kind = int(rng.integers(4))
    ph = top - z0
    leaf = pick(rng, "foliage")
    if kind == 0:  # a bush of overlapping leaf balls
        rz = 0.5 * ph
        asm.add(ellipsoid((0.0, 0.0, top - rz), (0.85 * px, 0.85 * py, rz)), leaf)
        for _ in range(int(rng.integers(3, 6))):
            rx_k, ry_k = float(rng.uniform(0.35, 0.55)) * px, float(rng.uniform(0.35, 0.55)) * py
            cx = float(rng.uniform(-1.0, 1.0)) * (px - rx_k)
            cy = float(rng.uniform(-1.0, 1.0)) * (py - ry_k)
            rz_k = float(rng.uniform(0.3, 0.45)) * ph
            cz = z0 + rz_k * float(rng.uniform(0.6, 1.1))
            asm.add(ellipsoid((cx, cy, cz), (rx_k, ry_k, rz_k)), shade(leaf, float(rng.uniform(0.85, 1.12))))
    elif kind == 1:  # a clipped box hedge
        asm.add(rounded_prism((0.0, 0.0), 2 * px, 2 * py, 0.08, z0 - 0.02, top - 0.06), leaf)
        asm.add(
            rounded_prism((0.0, 0.0), 2 * px - 0.08, 2 * py - 0.08, 0.08, top - 0.07, top), shade(leaf, 1.08)
        )
    elif kind == 2:  # clumps of ornamental grass with a few flowers
        flower = pick(rng, "accent")
        asm.add(frustum((0, 0, z0 - 0.01), (0, 0, top), (0.02, 0.006), (0.004, 0.002), sections=4), leaf)
        clumps = int(rng.integers(3, 6))
        for c in range(clumps):
            mx = float(rng.uniform(-0.55, 0.55)) * px
            my = float(rng.uniform(-0.55, 0.55)) * py
            spread = 0.45 * min(px, py)
            asm.add(ellipsoid((mx, my, z0), (spread, spread, 0.08), segments=8, rings=4), shade(leaf, 0.8))
            for k in range(int(rng.integers(10, 15))):
                a = float(rng.uniform(0.0, 2.0 * math.pi))
                lean = float(rng.uniform(0.3, 1.0)) * spread * 1.6
                tx = float(np.clip(mx + lean * math.cos(a), -px + 0.01, px - 0.01))
                ty = float(np.clip(my + lean * math.sin(a), -py + 0.01, py - 0.01))
                tz = z0 + ph * float(rng.uniform(0.5, 0.9))
                color = shade(leaf, float(rng.uniform(0.85, 1.25)))
                asm.add(frustum((mx, my, z0), (tx, ty, tz), (0.02, 0.007), (0.003, 0.002), sections=4), color)
                if (k + c) % 4 == 0:
                    asm.add(ellipsoid((tx, ty, tz), (0.03, 0.03, 0.035), segments=8, rings=4), flower)
    else:  # topiary ball on a stem over ground cover
        r = min(px, py, 0.4 * ph)
        asm.add(cylinder((0, 0, z0 - 0.02), (0, 0, top - r), 0.025, sections=8), pick(rng, "bark"))
        asm.add(ellipsoid((0.0, 0.0, top - r), (r, r, r)), leaf)
        asm.add(ellipsoid((0.0, 0.0, z0), (0.9 * px, 0.9 * py, min(0.08, 0.2 * ph))), shade(leaf, 0.85))


# --- bins -------------------------------------------------------------------------------------------


def _waste_bin(rng: np.random.Generator, size: Size) -> Assembly:
    """A public litter bin: a bin hung on a post (round or square, with a rain hood), a slatted round
    bin under a hood on posts, or a square steel bin with a front throw slot and a door."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    color = pick(rng, _COATS)
    style = int(rng.integers(3))
    if style == 0:
        post = float(rng.uniform(0.06, 0.08))
        asm.box((-0.5 * post, -hy, 0.0), (0.5 * post, -hy + post, h - 0.01), shade(color, 0.8))
        asm.box((-0.5 * post - 0.005, -hy, h - 0.01), (0.5 * post + 0.005, -hy + post, h), shade(color, 0.6))
        zt = h - float(rng.uniform(0.02, 0.08))
        zb = zt - float(np.clip(0.6 * h, 0.45, 0.7))
        ry = 0.5 * (d - post)
        cy = hy - ry
        for z in (zb + 0.1, zt - 0.12):
            asm.box((-0.06, -hy + post, z - 0.03), (0.06, cy - 0.5 * ry, z + 0.03), shade(color, 0.8))
        if rng.uniform() < 0.5:  # round bin with a rain hood over the opening
            body = frustum((0, cy, zb), (0, cy, zt - 0.1), (0.9 * hx, 0.9 * ry), (hx, ry), sections=16)
            asm.add(body, color)
            asm.add(
                frustum(
                    (0, cy, zt - 0.1),
                    (0, cy, zt - 0.06),
                    (0.92 * hx, 0.92 * ry),
                    (0.92 * hx, 0.92 * ry),
                    sections=16,
                ),
                _DARK,
            )
            hood = frustum((0, cy, zt - 0.06), (0, cy, zt), (hx, ry), (0.75 * hx, 0.75 * ry), sections=16)
            asm.add(hood, shade(color, 0.9))
            for a in (0.75 * math.pi, 0.25 * math.pi):
                x, y = 0.9 * hx * math.cos(a), cy + 0.9 * ry * math.sin(a)
                asm.add(bar((x, y, zt - 0.1), (x, y, zt - 0.06), 0.012), shade(color, 0.9))
        else:  # rectangular bin with an open top and a front band
            shell = box((-hx, hy - 2 * ry, zb), (hx, hy - 0.004, zt))
            opening = box((-hx + 0.02, hy - 2 * ry + 0.02, zt - 0.2), (hx - 0.02, hy - 0.024, zt + 0.01))
            asm.add(difference(shell, opening), color)
            asm.box((-hx + 0.02, hy - 2 * ry + 0.02, zt - 0.2), (hx - 0.02, hy - 0.024, zt - 0.12), _DARK)
            asm.box((-hx + 0.04, hy - 0.006, zb + 0.08), (hx - 0.04, hy, zb + 0.14), pick(rng, "accent"))
        return asm
    if style == 1:
        hood_h = float(rng.uniform(0.1, 0.16))
        gap = float(rng.uniform(0.1, 0.14))
        body_top = h - hood_h - gap
        asm.add(
            frustum((0, 0, 0), (0, 0, 0.04), (0.85 * hx, 0.85 * hy), (0.85 * hx, 0.85 * hy), sections=16),
            _DARK,
        )
        asm.add(
            frustum(
                (0, 0, 0.04),
                (0, 0, body_top + 0.02),
                (0.88 * hx, 0.88 * hy),
                (0.88 * hx, 0.88 * hy),
                sections=16,
            ),
            _DARK,
        )
        slat_color = pick(rng, "wood") if rng.uniform() < 0.4 else color
        n = 16
        for k in range(n):
            a = 2.0 * math.pi * k / n
            r = 1.0 / math.hypot(math.cos(a) / (hx - 0.004), math.sin(a) / (hy - 0.004))
            slat = box((r - 0.014, -0.022, 0.06), (r, 0.022, body_top))
            asm.add(rotate(slat, "z", a), slat_color)
        for z in (0.1, body_top - 0.08):
            asm.add(frustum((0, 0, z), (0, 0, z + 0.03), (hx, hy), (hx, hy), sections=16), color)
        for k in range(4):
            a = 0.25 * math.pi + 0.5 * math.pi * k
            x, y = 0.8 * hx * math.cos(a), 0.8 * hy * math.sin(a)
            asm.add(bar((x, y, body_top - 0.02), (x, y, body_top + gap + 0.01), 0.02), color)
        asm.add(
            frustum((0, 0, body_top + gap), (0, 0, body_top + gap + 0.04), (hx, hy), (hx, hy), sections=16),
            color,
        )
        asm.add(
            frustum((0, 0, body_top + gap + 0.04), (0, 0, h), (hx, hy), (0.35 * hx, 0.35 * hy), sections=16),
            shade(color, 0.9),
        )
        return asm
    # square steel bin with a throw slot, a door and a top with an ashtray grille
    asm.box((-hx + 0.03, -hy + 0.03, 0.0), (hx - 0.03, hy - 0.03, 0.05), _DARK)
    face = hy - 0.012
    slot = box((-0.35 * w, face - 0.05, h - 0.28), (0.35 * w, hy + 0.01, h - 0.12))
    asm.add(difference(box((-hx + 0.01, -hy + 0.01, 0.05), (hx - 0.01, face, h - 0.03)), slot), color)
    asm.box((-0.35 * w, face - 0.05, h - 0.28), (0.35 * w, face - 0.04, h - 0.12), _DARK)
    asm.box((-hx, -hy, h - 0.03), (hx, hy, h - 0.004), shade(color, 0.85))
    asm.box((-0.12, -0.12, h - 0.006), (0.12, 0.0, h), pick(rng, "stainless"))  # ashtray grille
    asm.box((-hx + 0.05, face, 0.1), (hx - 0.05, face + 0.006, h - 0.34), shade(color, 1.1))  # door
    asm.box((hx - 0.1, face, 0.5 * h - 0.05), (hx - 0.08, hy, 0.5 * h + 0.05), pick(rng, "chrome"))
    asm.box((-0.1, face, h - 0.1), (0.1, face + 0.006, h - 0.06), pick(rng, "accent"))
    return asm


def _recycling_bin(rng: np.random.Generator, size: Size) -> Assembly:
    """A recycling station with two or three colour-coded streams facing +y: one cabinet with round,
    slot or square openings in coloured front panels, or separate coloured bins with hooded lids in a
    frame with a sign board."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    streams = 2 if w < 1.05 else 3
    order = rng.permutation(len(_STREAMS))[:streams]
    colors = [shade(_STREAMS[int(i)], float(rng.uniform(0.94, 1.06))) for i in order]
    pitch = w / streams
    if rng.uniform() < 0.55:
        body = pick(rng, _COATS) if rng.uniform() < 0.6 else pick(rng, "stainless")
        roof = 0.05
        face = hy - 0.012
        cutters, holes = [], []
        open_z = h - roof - 0.22
        for k in range(streams):
            cx = -hx + (k + 0.5) * pitch
            shape = int(rng.integers(3))
            if shape == 0:
                r = min(0.08, 0.3 * pitch)
                cutters.append(cylinder((cx, face - 0.1, open_z), (cx, hy + 0.01, open_z), r, sections=16))
                holes.append(cylinder((cx, face - 0.1, open_z), (cx, face - 0.09, open_z), r, sections=16))
            else:
                half_w = (0.35 if shape == 1 else 0.22) * pitch
                half_h = 0.025 if shape == 1 else 0.08
                cutters.append(
                    box((cx - half_w, face - 0.1, open_z - half_h), (cx + half_w, hy + 0.01, open_z + half_h))
                )
                holes.append(
                    box(
                        (cx - half_w, face - 0.1, open_z - half_h),
                        (cx + half_w, face - 0.09, open_z + half_h),
                    )
                )
            panel = box(
                (cx - 0.5 * pitch + 0.02, face, 0.1), (cx + 0.5 * pitch - 0.02, hy - 0.004, h - roof - 0.04)
            )
            asm.add(difference(panel, cutters[-1]), colors[k])
            asm.box((cx - 0.08, hy - 0.006, open_z - 0.2), (cx + 0.08, hy, open_z - 0.12), _WHITE)
        asm.add(difference(box((-hx, -hy + 0.01, 0.06), (hx, face, h - roof)), *cutters), body)
        for hole in holes:
            asm.add(hole, _DARK)
        asm.box((-hx, -hy, h - roof), (hx, hy, h), shade(body, 0.8))
        asm.box((-hx + 0.03, -hy + 0.04, 0.0), (hx - 0.03, hy - 0.04, 0.06), _DARK)
        return asm
    frame = pick(rng, _COATS)
    asm.box((-hx, -hy, 0.0), (hx, -hy + 0.05, 0.04), frame)
    for x in (-hx, hx - 0.04):
        asm.box((x, -hy, 0.0), (x + 0.04, -hy + 0.04, h), frame)
    sign_z = h - float(rng.uniform(0.12, 0.2))
    asm.box((-hx + 0.04, -hy + 0.01, sign_z), (hx - 0.04, -hy + 0.03, h - 0.01), _WHITE)
    bin_h = min(sign_z - 0.05, h - 0.12)
    ry = 0.5 * (d - 0.05)
    cy = hy - ry
    rx = 0.5 * pitch - 0.03
    for k in range(streams):
        cx = -hx + (k + 0.5) * pitch
        asm.box(
            (cx - 0.5 * pitch + 0.06, -hy + 0.032, sign_z + 0.02),
            (cx + 0.5 * pitch - 0.06, -hy + 0.035, h - 0.03),
            colors[k],
        )
        asm.add(
            frustum((cx, cy, 0.0), (cx, cy, bin_h - 0.08), (0.9 * rx, 0.9 * ry), (rx, ry), sections=16),
            colors[k],
        )
        lid = frustum((cx, cy, bin_h - 0.08), (cx, cy, bin_h), (rx, ry), (0.7 * rx, 0.7 * ry), sections=16)
        mouth = box(
            (cx - 0.5 * rx, cy + 0.2 * ry, bin_h - 0.07), (cx + 0.5 * rx, cy + ry + 0.01, bin_h - 0.02)
        )
        asm.add(difference(lid, mouth), shade(colors[k], 0.8))
        asm.box(
            (cx - 0.5 * rx, cy + 0.2 * ry, bin_h - 0.08),
            (cx + 0.5 * rx, cy + 0.2 * ry + 0.01, bin_h - 0.02),
            _DARK,
        )
        z_label = 0.45 * bin_h
        front = cy + ry * (0.9 + 0.1 * (z_label + 0.1) / (bin_h - 0.08)) + 0.004
        asm.box((cx - 0.05, cy, z_label), (cx + 0.05, front, z_label + 0.1), _WHITE)
    return asm


def _dumpster(rng: np.random.Generator, size: Size) -> Assembly:
    """A wheeled steel waste container: a tapered EN 840 bin with dome lids, lifting trunnions and push
    handles on four casters, or a front-load dumpster with a sloped top, two plastic lids and fork
    pockets on the sides."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = pick(rng, _SKIPS)
    lid = pick(rng, "dark_plastic") if rng.uniform() < 0.6 else shade(body, 0.85)
    steel = pick(rng, "metal")
    if rng.uniform() < 0.5:
        r = 0.1  # 200 mm wheels
        z0 = r * 2 + 0.02
        bx, by = hx - 0.06, hy - 0.07
        zt = h - 0.1
        taper = 0.08
        pts = [(x, y, z0) for x in (-bx + taper, bx - taper) for y in (-by + taper, by - taper)]
        pts += [(x, y, zt) for x in (-bx, bx) for y in (-by, by)]
        asm.add(hull(pts), body)
        asm.box((-bx - 0.01, -by - 0.01, zt - 0.06), (bx + 0.01, by + 0.01, zt), shade(body, 0.8))
        for x in (-bx + taper + 0.1, bx - taper - 0.1):
            for y in (-by + taper + 0.1, by - taper - 0.1):
                caster(asm, x, y, r, _DARK, steel)
        lids = 2 if w >= 1.5 else 1
        span = 2 * bx / lids
        for k in range(lids):
            x0 = -bx + k * span
            x1 = x0 + span
            dome = [(x, y, zt) for x in (x0 + 0.005, x1 - 0.005) for y in (-by - 0.01, by + 0.01)]
            dome += [(x, y, h) for x in (x0 + 0.08, x1 - 0.08) for y in (-by + 0.08, by - 0.08)]
            asm.add(hull(dome), lid)
            for x in (x0 + 0.15, x1 - 0.15):  # hinges at the back
                asm.add(bar((x, -by - 0.01, zt - 0.01), (x, -hy + 0.015, zt - 0.01), 0.03), steel)
            asm.box(
                (0.5 * (x0 + x1) - 0.1, by + 0.01, zt - 0.02),
                (0.5 * (x0 + x1) + 0.1, by + 0.04, zt + 0.02),
                lid,
            )
        for sx in (-1.0, 1.0):
            asm.add(
                cylinder((sx * (bx - 0.02), 0.0, zt - 0.16), (sx * hx, 0.0, zt - 0.16), 0.03, sections=12),
                steel,
            )
        z_handle = zt - 0.12
        y_face = by - taper * (zt - z_handle) / (zt - z0)
        for x in (-0.3 * w, 0.3 * w):
            asm.add(bar((x, y_face - 0.01, z_handle), (x, hy - 0.015, z_handle), 0.02), steel)
        asm.add(
            cylinder(
                (-0.3 * w - 0.01, hy - 0.015, z_handle),
                (0.3 * w + 0.01, hy - 0.015, z_handle),
                0.015,
                sections=8,
            ),
            steel,
        )
        return asm
    # front-load dumpster
    r = float(rng.uniform(0.06, 0.08))
    z0 = 2 * r + 0.02
    bx, by = hx - 0.1, hy - 0.03
    lid_t = 0.05
    z_back = h - lid_t
    z_front = z_back - float(rng.uniform(0.08, 0.15))
    z_knee = z0 + 0.45 * (z_front - z0)
    y_toe = by - 0.3 * (2 * by)
    profile = ((-by, z0), (y_toe, z0), (by, z_knee), (by, z_front), (-by, z_back))
    asm.add(hull([(x, y, z) for x in (-bx, bx) for y, z in profile]), body)
    for x in (-bx + 0.12, bx - 0.12):
        for y in (-by + 0.12, y_toe - 0.08):
            caster(asm, x, y, r, _DARK, steel)
    up, normal = _yz_axes(2 * by, z_front - z_back)
    normal = tuple(-c for c in normal)
    reach = 2.0 * hy / up[1]  # from the hinge at -hy to the front lip at +hy
    for k in range(2):
        x0, x1 = (k - 1) * bx, k * bx
        lid_solid = _slab(
            (0.0, -hy, z_back), _X, up, normal, (x0 + 0.01, x1 - 0.01), (0.0, reach), (0.0, lid_t)
        )
        asm.add(lid_solid, lid)
    asm.add(
        cylinder((-bx, -by - 0.005, z_back - 0.015), (bx, -by - 0.005, z_back - 0.015), 0.02, sections=8),
        steel,
    )
    zp = z0 + 0.45 * (z_back - z0)
    for sx in (-1.0, 1.0):
        x_lo, x_hi = sorted((sx * bx, sx * hx))
        asm.box((x_lo, -by + 0.1, zp - 0.07), (x_hi, by - 0.15, zp + 0.07), shade(body, 0.8))
        asm.box((x_lo + 0.015, by - 0.151, zp - 0.055), (x_hi - 0.015, by - 0.14, zp + 0.055), _DARK)
    return asm


# --- drinking fountain and ticket machine -----------------------------------------------------------


def _bowl(
    asm: Assembly, cx: float, cy: float, rim: float, rx: float, ry: float, color: RGB, chrome: RGB
) -> Solid:
    """A fountain bowl (cut-out basin) with its rim at `rim`, a bubbler and a front push button; returns
    the basin's cavity, to be cut out of the pedestal under it."""
    depth = 0.11
    outer = frustum((cx, cy, rim - depth), (cx, cy, rim), (0.6 * rx, 0.6 * ry), (rx, ry), sections=16)
    inner = frustum(
        (cx, cy, rim - depth + 0.03),
        (cx, cy, rim + 0.01),
        (0.5 * rx, 0.5 * ry),
        (rx - 0.02, ry - 0.02),
        sections=16,
    )
    asm.add(difference(outer, inner), color)
    floor = rim - depth + 0.03
    asm.add(
        frustum((cx, cy - 0.3 * ry, floor), (cx, cy - 0.3 * ry, rim - 0.02), 0.02, 0.012, sections=8), chrome
    )
    asm.add(bar((cx, cy - 0.3 * ry, rim - 0.025), (cx, cy - 0.2 * ry, rim - 0.015), 0.012), chrome)
    z_btn = rim - 0.6 * depth
    asm.add(cylinder((cx, cy + 0.7 * ry, z_btn), (cx, cy + ry + 0.025, z_btn), 0.02, sections=12), chrome)
    return inner


def _drinking_fountain(rng: np.random.Generator, size: Size) -> Assembly:
    """A pedestal drinking fountain: a round or square column with a basin, bubbler and push button
    (wide ones are hi-lo units with two basins at two heights), sometimes a dog bowl at its foot."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    finish = int(rng.integers(3))
    column_color = (pick(rng, "stainless"), pick(rng, _COATS), pick(rng, _CONCRETE))[finish]
    bowl_color = pick(rng, "stainless") if finish != 1 else column_color
    chrome = pick(rng, "chrome")
    hi_lo = w >= 0.65
    cw = float(np.clip(0.3 * w if hi_lo else 0.7 * w, 0.2, 0.3))
    cd = float(np.clip(0.5 * d, 0.2, 0.32))
    cyc = -hy + 0.5 * cd
    column_top = h - 0.04
    if rng.uniform() < 0.5:
        column = frustum(
            (0, cyc, 0.0), (0, cyc, column_top), (0.5 * cw, 0.5 * cd), (0.45 * cw, 0.45 * cd), sections=16
        )
    else:
        column = rounded_prism((0.0, cyc), cw, cd, 0.02, 0.0, column_top)
    asm.box(
        (-0.5 * cw - 0.02, cyc - 0.5 * cd, 0.0),
        (0.5 * cw + 0.02, cyc + 0.5 * cd + 0.02, 0.015),
        shade(column_color, 0.7),
    )
    ry = 0.5 * (hy - 0.025 - cyc)
    by = hy - 0.025 - ry
    if hi_lo:
        rb = max(0.14, 0.5 * (hx - 0.5 * cw) + 0.02)
        rb = min(rb, 0.5 * hx)
        low = float(np.clip(h - 0.22, 0.7, 0.84))
        cavities = []
        for cx, rim in ((-(hx - rb), low), (hx - rb, h)):
            asm.box(
                (min(0.0, cx), cyc - 0.05, rim - 0.16), (max(0.0, cx), cyc + 0.05, rim - 0.1), column_color
            )
            cavities.append(_bowl(asm, cx, by, rim, rb, ry, bowl_color, chrome))
        asm.add(difference(column, *cavities), column_color)
    else:
        asm.add(difference(column, _bowl(asm, 0.0, by, h, hx, ry, bowl_color, chrome)), column_color)
        if rng.uniform() < 0.4 and hy - 0.24 > cyc + 0.5 * cd:  # a dog bowl at the foot
            dog = frustum((0, hy - 0.12, 0.0), (0, hy - 0.12, 0.08), 0.08, 0.1, sections=12)
            asm.add(
                difference(
                    dog, frustum((0, hy - 0.12, 0.02), (0, hy - 0.12, 0.09), 0.065, 0.085, sections=12)
                ),
                bowl_color,
            )
            asm.add(bar((0, cyc + 0.5 * cd - 0.01, 0.3), (0, hy - 0.14, 0.28), 0.02), chrome)
    return asm


def _ticket_machine(rng: np.random.Generator, size: Size) -> Assembly:
    """A parking pay station: plinth, cabinet, slanted console with screen, keypad and card slot, coin
    slot, ticket tray, a blue "P" sign, and a solar panel, rounded hood or flat cap on top."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = pick(rng, _PAY)
    trim = shade(body, 0.7) if rng.uniform() < 0.5 else pick(rng, _COATS)
    fd = float(rng.uniform(0.05, 0.07))
    face = hy - fd
    top = int(rng.integers(3))
    if top == 0:  # solar panel tilted towards the front
        zt = h - 0.12
    elif top == 1:  # rounded hood
        zt = h - 0.5 * (d - fd)
    else:  # flat cap
        zt = h - 0.04
    asm.box((-hx + 0.02, -hy + 0.02, 0.0), (hx - 0.02, face - 0.02, 0.06), _DARK)
    asm.add(rounded_prism((0.0, 0.5 * (face - hy)), w, d - fd, 0.02, 0.06, zt), body)
    if top == 0:
        asm.box((-0.05, -0.05, zt - 0.01), (0.05, 0.05, zt + 0.05), trim)
        pts = [(x, y, z) for x in (-hx, hx) for y, z in ((-hy, h), (face, zt + 0.04)) for z in (z, z - 0.03)]
        asm.add(hull(pts), (30, 40, 70))
    elif top == 1:
        rad = 0.5 * (d - fd)
        asm.add(cylinder((-hx, 0.5 * (face - hy), zt), (hx, 0.5 * (face - hy), zt), rad, sections=16), trim)
    else:
        asm.box((-hx, -hy, zt), (hx, face + 0.01, h), trim)
    z_c0, z_c1 = 0.5 * h, 0.7 * h
    cx = hx - 0.03
    console = [
        (x, y, z)
        for x in (-cx, cx)
        for y, z in ((face, z_c0), (hy, z_c0), (hy, z_c0 + 0.05), (face + 0.015, z_c1), (face, z_c1))
    ]
    asm.add(hull(console), trim)
    up, normal = _yz_axes(face + 0.015 - hy, z_c1 - z_c0 - 0.05)
    normal = tuple(-c for c in normal)
    origin = (0.0, hy, z_c0 + 0.05)
    length = math.hypot(hy - face - 0.015, z_c1 - z_c0 - 0.05)
    asm.add(
        _slab(
            origin, _X, up, normal, (-cx + 0.03, cx - 0.03), (0.55 * length, 0.93 * length), (-0.002, 0.003)
        ),
        pick(rng, "screen"),
    )
    key = pick(rng, "chrome")
    for r in range(4):
        for c in range(3):
            x0 = -cx + 0.04 + c * 0.035
            s0 = 0.1 * length + r * 0.1 * length
            asm.add(
                _slab(origin, _X, up, normal, (x0, x0 + 0.025), (s0, s0 + 0.07 * length), (0.0, 0.004)), key
            )
    asm.add(
        _slab(origin, _X, up, normal, (cx - 0.12, cx - 0.03), (0.2 * length, 0.3 * length), (0.0, 0.006)),
        _DARK,
    )
    asm.box((0.05 * w, face, z_c0 - 0.08), (0.05 * w + 0.06, face + 0.01, z_c0 - 0.05), key)  # coin slot
    tray = box((-0.12, face - 0.02, 0.3 * h), (0.12, face + 0.03, 0.3 * h + 0.08))
    asm.add(
        difference(tray, box((-0.1, face - 0.01, 0.3 * h + 0.015), (0.1, face + 0.04, 0.3 * h + 0.065))), trim
    )
    asm.box((-0.1, face - 0.015, 0.3 * h + 0.015), (0.1, face - 0.01, 0.3 * h + 0.065), _DARK)
    asm.box((-hx + 0.04, face, 0.3 * h + 0.12), (hx - 0.04, face + 0.003, z_c0 - 0.12), _WHITE)
    sign = min(0.18, zt - z_c1 - 0.08, w - 0.12)
    if sign >= 0.08:
        zc = 0.5 * (z_c1 + zt)
        asm.box(
            (-0.5 * sign, face, zc - 0.5 * sign), (0.5 * sign, face + 0.004, zc + 0.5 * sign), _PARKING_BLUE
        )
        u = sign / 6.0
        y0, y1 = face + 0.004, face + 0.007
        for lo, hi in (
            ((-2 * u, -2.4 * u), (-1.2 * u, 2.4 * u)),  # stem
            ((-1.2 * u, 1.6 * u), (1.0 * u, 2.4 * u)),  # top bar
            ((-1.2 * u, -0.2 * u), (1.0 * u, 0.6 * u)),  # middle bar
            ((1.0 * u, -0.2 * u), (1.8 * u, 2.4 * u)),  # bowl side
        ):
            # seen from the front (+y), +x is on the viewer's left: mirror x so the letter reads "P"
            asm.box((-hi[0], y0, zc + lo[1]), (-lo[0], y1, zc + hi[1]), _WHITE)
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "park_bench",  # backed 1.5-1.8 m x 0.6-0.75 m x 0.8-0.9 m, seat 0.45 m (EN 1729 / ADA 17-19 in)
        (1.20, 0.42, 0.45),
        (2.40, 0.78, 0.92),
        "floor",
        None,
        0.6,
        "wood",
        _park_bench,
        supports=_bench_supports,
        contexts=("park", "street", "plaza", "transit"),
    ),
    Asset(
        "picnic_table",  # the 6 ft table: 1.83 m x 1.5-1.6 m over both benches, top at 0.76 m
        (1.50, 1.40, 0.72),
        (2.40, 1.90, 0.79),
        "floor",
        None,
        0.6,
        "wood",
        _picnic_table,
        supports=_picnic_supports,
        contexts=("park", "plaza"),
    ),
    Asset(
        "bistro_table",  # cafe terrace tables: 0.57-0.77 m round or square, 0.72-0.75 m high
        (0.55, 0.55, 0.71),
        (0.80, 0.80, 0.76),
        "floor",
        None,
        0.4,
        "metal",
        _bistro_table,
        supports=_bistro_table_supports,
        contexts=("frontage", "plaza"),
    ),
    Asset(
        "bistro_chair",  # Parisian bistro chairs: about 0.45 m x 0.5 m x 0.85 m, seat 0.45 m
        (0.40, 0.46, 0.78),
        (0.56, 0.60, 0.92),
        "floor",
        None,
        0.5,
        "metal",
        _bistro_chair,
        contexts=("frontage", "plaza"),
    ),
    Asset(
        "patio_umbrella",  # market umbrellas 2-3.5 m across (9 ft = 2.7 m), 2.2-2.7 m high when open
        (2.00, 2.00, 2.20),
        (3.50, 3.50, 2.70),
        "floor",
        None,
        0.0,
        "fabric",
        _patio_umbrella,
        contexts=("frontage", "plaza"),
    ),
    Asset(
        "a_frame_sign",  # A1 poster boards: about 0.64 m x 1.0 m, 0.5-0.6 m deep when open
        (0.50, 0.45, 0.85),
        (0.75, 0.70, 1.20),
        "floor",
        None,
        0.5,
        "wood",
        _a_frame_sign,
        contexts=("frontage", "street"),
    ),
    Asset(
        "street_planter",  # precast planters 0.8-2 m x 0.5-1.2 m, box 0.4-0.75 m high, plus the plant
        (0.80, 0.50, 0.80),
        (2.00, 1.20, 1.60),
        "floor",
        None,
        0.0,
        "stone",
        _street_planter,
        contexts=("street", "plaza", "frontage", "park"),
    ),
    Asset(
        "waste_bin",  # 50-120 l litter bins: 0.4-0.65 m across, 0.8-1.15 m high (post bins on 1 m posts)
        (0.40, 0.34, 0.80),
        (0.65, 0.62, 1.15),
        "floor",
        None,
        0.5,
        "metal",
        _waste_bin,
        contexts=("street", "park", "plaza", "transit"),
    ),
    Asset(
        "recycling_bin",  # 2-3 stream stations: 0.8-1.6 m wide, 0.4-0.6 m deep, about 1.0-1.1 m high
        (0.80, 0.38, 0.90),
        (1.60, 0.60, 1.20),
        "floor",
        None,
        0.6,
        "metal",
        _recycling_bin,
        contexts=("street", "plaza", "park"),
    ),
    Asset(
        "dumpster",  # EN 840 1100 l: 1.37 x 1.07 x 1.47 m; US 2-4 yd front-load: 1.8 x 0.9-1.4 x 1.1-1.5 m
        (1.20, 0.95, 1.15),
        (2.00, 1.60, 1.60),
        "floor",
        None,
        1.0,
        "metal",
        _dumpster,
        contexts=("street", "parking"),
    ),
    Asset(
        "drinking_fountain",  # pedestal units 0.3-0.45 m, hi-lo 0.7-0.95 m wide; spouts 0.9-1.0 m high
        (0.35, 0.40, 0.85),
        (0.95, 0.65, 1.10),
        "floor",
        None,
        0.8,
        "metal",
        _drinking_fountain,
        contexts=("park", "plaza", "sports"),
    ),
    Asset(
        "ticket_machine",  # parking pay stations: about 0.4-0.55 m x 0.3-0.45 m x 1.6-1.9 m
        (0.36, 0.28, 1.45),
        (0.60, 0.50, 1.95),
        "floor",
        None,
        0.8,
        "metal",
        _ticket_machine,
        contexts=("parking", "street"),
    ),
)
