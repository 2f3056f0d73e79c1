"""Street furniture: the poles, signals and small structures of sidewalks and kerbs.

Categories: ``street_lamp``, ``traffic_light``, ``stop_sign``, ``street_sign``, ``fire_hydrant``,
``bollard``, ``post_box``, ``parking_meter``, ``bus_shelter``, ``bus_stop_sign``, ``bike_rack``,
``utility_box``, ``phone_booth`` and ``newspaper_box``.

Frame conventions
-----------------
The frame of :mod:`navverse.assets.library` applies (x width, y depth, z up, meters, front at +y). For
these objects the front is the side that road users read or pedestrians use:

- Signs and signals (``traffic_light``, ``stop_sign``, ``bus_stop_sign``) face +y with their pole behind
  the plate, at -y. A ``street_sign`` carries a name blade along x (read from +y and -y) crossed by one
  along y, and may carry fingers pointing along x and a plate facing +y.
- ``street_lamp``: a bracket lamp has its pole at the back (-y) and its arm reaching over the road
  towards +y; a twin lamp (central reservation) has arms towards +y and -y; a heritage lamp carries one
  lantern on top of its pole, or two on a crossbar along y.
- ``fire_hydrant``: the large pumper outlet faces +y (the road), the hose outlets point to -x and +x.
- Boxes and booths (``post_box``, ``parking_meter``, ``utility_box``, ``phone_booth``,
  ``newspaper_box``): slots, screens, doors and windows face +y.
- ``bus_shelter``: the open side faces +y (the kerb), the back wall with the bench is at -y.
- ``bike_rack``: base rails run along x and the hoops stand in planes normal to x, so bicycles park
  along y on either side of a hoop.

Sizes follow common products and standards (sources noted beside each :class:`Asset`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np

from navverse.assets.fittings import door_fronts
from navverse.assets.materials import RGB, pick, shade
from navverse.assets.parts import (
    Assembly,
    Solid,
    bar,
    box,
    cylinder,
    difference,
    ellipsoid,
    extrude,
    extrude_along,
    frustum,
    hull,
    revolve,
    rounded_prism,
    torus,
)
from navverse.assets.spec import Asset, Size

__all__ = ["ASSETS"]

_DARK: RGB = (24, 24, 26)
_WHITE: RGB = (242, 242, 238)
_SIGN_RED: RGB = (196, 26, 34)
_ALUMINIUM: RGB = (178, 182, 186)
_POLE: tuple[RGB, ...] = ((168, 172, 174), (120, 126, 134), (62, 66, 70), (34, 62, 48), (28, 28, 30))
"""Galvanised steel, grey, anthracite, fir green, black."""
_IRON: tuple[RGB, ...] = ((28, 28, 30), (34, 62, 48), (36, 44, 72), (62, 66, 70))
"""Painted cast iron of heritage street furniture: black, green, blue, anthracite."""
_LENS: tuple[RGB, ...] = ((252, 244, 206), (238, 240, 238), (255, 224, 150))
_SIGNAL_HOUSING: tuple[RGB, ...] = ((24, 24, 26), (38, 38, 40), (34, 62, 48), (214, 168, 28), (100, 104, 108))
_SIGNAL_LAMPS: tuple[tuple[RGB, RGB], ...] = (
    ((255, 48, 36), (92, 22, 20)),
    ((255, 170, 20), (104, 70, 16)),
    ((60, 230, 140), (18, 70, 44)),
)
"""``(lit, dark)`` colours of the red, amber and green lamps, top to bottom."""
_BLADES: tuple[tuple[RGB, RGB], ...] = (
    ((20, 110, 60), _WHITE),
    ((24, 64, 150), _WHITE),
    (_WHITE, (24, 24, 26)),
    ((110, 62, 36), _WHITE),
    ((24, 24, 26), _WHITE),
)
"""``(background, lettering)`` of street name blades: green, blue, white, brown, black."""
_PLATES: tuple[tuple[RGB, RGB], ...] = (
    ((24, 64, 150), _WHITE),
    (_WHITE, (24, 64, 150)),
    ((20, 110, 60), _WHITE),
    ((200, 30, 40), _WHITE),
    ((248, 206, 30), (20, 110, 60)),
)
"""``(background, symbol)`` of information plates and bus stop flags."""
_HYDRANT_BODY: tuple[RGB, ...] = (
    (200, 30, 32),
    (232, 190, 30),
    (240, 160, 24),
    (188, 190, 192),
    (60, 140, 70),
)
_HYDRANT_CAP: tuple[RGB, ...] = (
    (200, 30, 32),
    (240, 240, 236),
    (40, 90, 180),
    (60, 150, 80),
    (236, 120, 30),
    (188, 190, 192),
)
"""Bonnet and cap colours (NFPA 291 flow classes use blue, green, orange and red bonnets)."""
_CABINET: tuple[RGB, ...] = (
    (200, 202, 194),
    (156, 160, 156),
    (50, 86, 66),
    (92, 96, 100),
    (204, 194, 166),
    (236, 236, 228),
)
"""Roadside cabinets: light grey (RAL 7035), grey, green, anthracite, beige, white."""
_CONCRETE: tuple[RGB, ...] = ((190, 188, 182), (168, 164, 156), (206, 198, 180), (140, 138, 134))
_POSTAL_RED: tuple[RGB, ...] = ((200, 28, 34), (186, 22, 30), (210, 40, 36))
_POSTAL_YELLOW: tuple[RGB, ...] = ((252, 204, 0), (246, 190, 20))
_BRAND_BOOTH: tuple[RGB, ...] = ((226, 0, 116), (250, 200, 0), (0, 84, 160), (30, 130, 70))
"""Telecom colours of modern phone booths: magenta, yellow, blue, green."""
_VARIATION = 0.05
"""Brightness variation of the colours drawn from the palettes above (:func:`pick`)."""

_SQRT2 = math.sqrt(2.0)


# ---------------------------------------------------------------------------------------------------
# helpers


def _section(
    hx: float,
    hy: float,
    z0: float,
    z1: float,
    *,
    round_: bool = True,
    top: float = 1.0,
    center: tuple[float, float] = (0.0, 0.0),
) -> Solid:
    """A vertical post section of half extents ``(hx, hy)``: elliptic or rectangular, tapered by `top`."""
    cx, cy = center
    if round_:
        return frustum((cx, cy, z0), (cx, cy, z1), (hx, hy), (top * hx, top * hy), sections=16)
    k = _SQRT2
    return frustum(
        (cx, cy, z0),
        (cx, cy, z1),
        (k * hx, k * hy),
        (k * top * hx, k * top * hy),
        sections=4,
        phase=math.pi / 4,
    )


def _dome(center: Sequence[float], radii: Sequence[float], *, sections: int = 16, rings: int = 3) -> Solid:
    """The upper half of an ellipsoid standing on the plane ``z = center[2]`` (a closed convex cap)."""
    cx, cy, cz = center
    rx, ry, rz = radii
    points = [(cx, cy, cz + rz)]
    for k in range(rings):
        polar = 0.5 * math.pi * (k + 1) / rings
        s, c = math.sin(polar), math.cos(polar)
        for j in range(sections):
            a = 2.0 * math.pi * j / sections
            points.append((cx + rx * s * math.cos(a), cy + ry * s * math.sin(a), cz + rz * c))
    return hull(points)


def _tube(
    asm: Assembly, points: Sequence[Sequence[float]], radius: float, color: RGB, *, sections: int = 8
) -> None:
    """A bent round tube through `points`: one cylinder per leg, lengthened at the bends to close them."""
    pts = [np.asarray(p, dtype=np.float64) for p in points]
    dirs = [(b - a) / np.linalg.norm(b - a) for a, b in itertools.pairwise(pts)]
    for i, (a, b) in enumerate(itertools.pairwise(pts)):
        start, end = a.copy(), b.copy()
        if i > 0:
            turn = math.acos(float(np.clip(dirs[i - 1] @ dirs[i], -1.0, 1.0)))
            start -= dirs[i] * radius * math.tan(0.5 * turn)
        if i < len(dirs) - 1:
            turn = math.acos(float(np.clip(dirs[i] @ dirs[i + 1], -1.0, 1.0)))
            end += dirs[i] * radius * math.tan(0.5 * turn)
        asm.add(cylinder(start, end, radius, sections=sections), color)


_GLYPHS: dict[str, tuple[tuple[float, float, float, float], ...]] = {
    # block letters on a unit cell, (u0, v0, u1, v1) with u to the right and v up; stroke 0.22
    "S": ((0, 0.78, 1, 1), (0, 0.39, 1, 0.61), (0, 0, 1, 0.22), (0, 0.5, 0.22, 1), (0.78, 0, 1, 0.5)),
    "T": ((0, 0.78, 1, 1), (0.39, 0, 0.61, 0.78)),
    "O": ((0, 0, 0.22, 1), (0.78, 0, 1, 1), (0.22, 0.78, 0.78, 1), (0.22, 0, 0.78, 0.22)),
    "P": ((0, 0, 0.22, 1), (0.22, 0.78, 1, 1), (0.22, 0.4, 1, 0.62), (0.78, 0.4, 1, 1)),
    "H": ((0, 0, 0.22, 1), (0.78, 0, 1, 1), (0.22, 0.39, 0.78, 0.61)),
    "B": (
        (0, 0, 0.22, 1),
        (0.22, 0.78, 0.9, 1),
        (0.22, 0.39, 0.9, 0.61),
        (0.22, 0, 0.9, 0.22),
        (0.78, 0.05, 1, 0.95),
    ),
    "U": ((0, 0, 0.22, 1), (0.78, 0, 1, 1), (0.22, 0, 0.78, 0.22)),
}


def _lettering(
    asm: Assembly,
    text: str,
    x0: float,
    x1: float,
    z0: float,
    z1: float,
    y0: float,
    y1: float,
    color: RGB,
    *,
    facing: float = 1.0,
) -> None:
    """Block letters of `text` filling ``[x0, x1] x [z0, z1]`` on a layer from `y0` to `y1` (any order).

    The text reads correctly from the side given by the sign of `facing`: from +y, where the reader's
    right is -x, or from -y.
    """
    y0, y1 = sorted((y0, y1))
    cell = (x1 - x0) / len(text)
    width = 0.8 * cell
    mirror = facing > 0.0
    for k, char in enumerate(text):
        left = x0 + k * cell + 0.1 * cell
        for u0, v0, u1, v1 in _GLYPHS[char]:
            a, b = left + u0 * width, left + u1 * width
            if mirror:
                a, b = x0 + x1 - b, x0 + x1 - a
            asm.box((a, y0, z0 + v0 * (z1 - z0)), (b, y1, z0 + v1 * (z1 - z0)), color)


# ---------------------------------------------------------------------------------------------------
# street lamp


def _street_lamp(rng: np.random.Generator, size: Size) -> Assembly:
    """A street light: a bracket lamp with one arm, a twin-arm lamp, or a heritage lantern post."""
    _, d, _ = size
    styles = []
    if d <= 1.3:
        styles.append("lantern")
    if d >= 0.7:
        styles.append("single")
    if d >= 1.4:
        styles.append("twin")
    style = styles[int(rng.integers(len(styles)))]
    if style == "lantern":
        return _heritage_lamp(rng, size)
    return _arm_lamp(rng, size, twin=style == "twin")


def _luminaire(
    asm: Assembly, rng: np.random.Generator, kind: int, w: float, y0: float, y1: float, top: float, body: RGB
) -> float:
    """A luminaire head spanning x in ``±w/2`` and y in ``[y0, y1]`` with its top at `top`; returns its
    height. Kinds: 0 cobra head, 1 flat LED panel, 2 shoebox."""
    lens = pick(rng, _LENS, variation=0.03)
    length = y1 - y0
    yc = 0.5 * (y0 + y1)
    if kind == 0:
        height = float(np.clip(0.3 * length, 0.14, 0.22))
        asm.add(
            ellipsoid((0.0, yc, top - 0.5 * height), (0.5 * w, 0.5 * length, 0.5 * height), segments=16), body
        )
        asm.add(
            ellipsoid(
                (0.0, yc + 0.08 * length, top - 0.75 * height),
                (0.36 * w, 0.3 * length, 0.35 * height),
                segments=12,
                rings=4,
            ),
            lens,
        )
        return height
    if kind == 1:
        height = float(rng.uniform(0.07, 0.1))
        asm.add(rounded_prism((0.0, yc), w, length, min(0.08, 0.3 * w), top - height, top), body)
        asm.box(
            (-0.4 * w, y0 + 0.12 * length, top - height - 0.012),
            (0.4 * w, y1 - 0.06 * length, top - height + 0.01),
            lens,
        )
        asm.box((-0.2 * w, y0 + 0.03, top - 0.004), (0.2 * w, y0 + 0.2 * length, top + 0.0), shade(body, 0.8))
        return height
    height = float(rng.uniform(0.13, 0.18))
    asm.box((-0.5 * w, y0, top - 0.7 * height), (0.5 * w, y1, top), body)
    asm.box((-0.5 * w, y0, top - height), (0.5 * w, y1, top - 0.69 * height), shade(body, 0.85))
    asm.box((-0.42 * w, y0 + 0.04, top - height - 0.006), (0.42 * w, y1 - 0.04, top - height + 0.01), lens)
    return height


def _arm_lamp(rng: np.random.Generator, size: Size, *, twin: bool) -> Assembly:
    """A steel lighting column on a base with one arm towards +y (or two towards ±y) and luminaires."""
    w, d, h = size
    hy = 0.5 * d
    asm = Assembly()
    pole = pick(rng, _POLE, variation=_VARIATION)
    head = (
        pole
        if rng.uniform() < 0.5
        else pick(rng, ((150, 154, 160), (92, 96, 102), (204, 206, 208)), variation=_VARIATION)
    )
    base_r = min(0.15, 0.45 * w, 0.3 * d) * float(rng.uniform(0.85, 1.0))
    yp = 0.0 if twin else -hy + base_r
    r0 = min(float(np.clip(0.017 * h, 0.065, 0.11)), 0.8 * base_r)
    r1 = max(0.035, 0.5 * r0)
    # base: a round door section or a square plinth
    base_h = float(rng.uniform(0.5, 1.1))
    if rng.uniform() < 0.5:
        asm.add(cylinder((0.0, yp, 0.0), (0.0, yp, base_h), base_r, sections=16), shade(pole, 0.9))
    else:
        plinth = _section(base_r, base_r, 0.0, base_h, round_=False, top=0.85, center=(0.0, yp))
        asm.add(plinth, shade(pole, 0.9))
    door_y = yp + 0.85 * base_r
    asm.box(
        (-0.35 * base_r, door_y - 0.02, 0.25 * base_h),
        (0.35 * base_r, door_y + 0.012, 0.8 * base_h),
        shade(pole, 0.75),
    )
    kind = int(rng.integers(3))
    sides = (1.0, -1.0) if twin else (1.0,)
    length = float(np.clip(0.4 + 0.15 * (d - (1.4 if twin else 0.7)), 0.4, 0.72))
    mounts = []
    for s in sides:
        y_in, y_out = s * (hy - length), s * hy
        lum_h = _luminaire(asm, rng, kind, w, min(y_in, y_out), max(y_in, y_out), h, head)
        mounts.append((s, y_in, h - 0.5 * lum_h))
    arm_r = float(rng.uniform(0.025, 0.035))
    curved = rng.uniform() < 0.55
    z_mount = min(m[2] for m in mounts)
    span = abs(mounts[0][1] - yp)
    if curved:
        bend = float(np.clip(0.6 * span, 0.15, 1.0))
        pole_top = z_mount - bend
    else:
        rise = span * math.tan(math.radians(float(rng.uniform(5.0, 15.0))))
        pole_top = z_mount - rise - 0.03
    asm.add(frustum((0.0, yp, base_h - 0.01), (0.0, yp, pole_top + 0.02), r0, r1, sections=16), pole)
    for s, y_in, z in mounts:
        y_end = y_in + s * 0.08
        if curved:
            pts = [(0.0, yp, pole_top - 0.05)]
            for k in range(5):
                t = 0.5 * math.pi * k / 4
                pts.append((0.0, yp + s * bend * (1.0 - math.cos(t)), pole_top + bend * math.sin(t)))
            pts.append((0.0, y_end, z))
            _tube(asm, pts, arm_r, pole)
        else:
            asm.add(cylinder((0.0, yp, pole_top), (0.0, y_end, z), arm_r, sections=12), pole)
            mid = 0.45
            brace_end = (0.0, yp + mid * (y_end - yp), pole_top + mid * (z - pole_top))
            asm.add(cylinder((0.0, yp, pole_top - 0.5), brace_end, 0.6 * arm_r, sections=8), pole)
            if not twin or s > 0:
                asm.add(ellipsoid((0.0, yp, pole_top + 0.02), (r1, r1, 0.05), segments=12, rings=4), pole)
    # number plate on the column
    plate_y = yp + 0.72 * r0
    asm.box(
        (-0.05, plate_y, 2.3),
        (0.05, plate_y + 0.02, 2.5),
        pick(rng, ((240, 240, 236), (236, 200, 40)), variation=_VARIATION),
    )
    return asm


def _lantern(
    asm: Assembly,
    style: int,
    yc: float,
    ax: float,
    ay: float,
    z0: float,
    height: float,
    iron: RGB,
    glass: RGB,
) -> None:
    """A heritage lantern standing at ``z0`` on ``(0, yc)``: half extents `ax`, `ay` at the roof eaves;
    `style` 0, 1, 2 gives a square, octagonal or round lantern."""
    sections, phase, factor = (
        (4, math.pi / 4, _SQRT2),
        (8, math.pi / 8, 1.0 / math.cos(math.pi / 8)),
        (12, 0.0, 1.0),
    )[style]
    rx, ry = factor * ax, factor * ay
    z1, z2, z3 = z0 + 0.18 * height, z0 + 0.68 * height, z0 + 0.88 * height

    def ring(p0: float, p1: float, k0: float, k1: float) -> Solid:
        return frustum(
            (0.0, yc, p0),
            (0.0, yc, p1),
            (k0 * rx, k0 * ry),
            (k1 * rx, k1 * ry),
            sections=sections,
            phase=phase,
        )

    asm.add(ring(z0, z1, 0.25, 0.62), iron)
    asm.add(ring(z1, z2, 0.62, 0.82), glass)
    asm.add(ring(z1 - 0.02, z1 + 0.02, 0.66, 0.66), iron)
    asm.add(ring(z2 - 0.02, z2 + 0.01, 0.86, 0.86), iron)
    asm.add(ring(z2 + 0.01, z3, 1.0, 0.12), iron)
    asm.add(cylinder((0.0, yc, z3 - 0.02), (0.0, yc, z0 + height - 0.04), 0.018, sections=8), iron)
    asm.add(ellipsoid((0.0, yc, z0 + height - 0.035), (0.035, 0.035, 0.035), segments=8, rings=4), iron)


def _heritage_lamp(rng: np.random.Generator, size: Size) -> Assembly:
    """A cast-iron lamp post: moulded base, fluted shaft with collars, a ladder bar and one lantern on top
    (or two on a crossbar along y)."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    iron = pick(rng, _IRON, variation=_VARIATION)
    glass = pick(rng, _LENS, variation=0.03)
    style = int(rng.integers(3))
    twin = d > 0.75
    ly = min(0.45, 0.4 * d) if twin else d
    lx = min(w, ly)
    lantern_h = float(np.clip(1.6 * ly, 0.55, 0.95))
    z_lantern = h - lantern_h
    rb = min(0.2, 0.45 * w, 0.45 * d)
    base_h = float(rng.uniform(0.6, 1.0))
    profile = [
        (0.0, 0.0),
        (rb, 0.0),
        (rb, 0.1),
        (0.8 * rb, 0.18),
        (0.72 * rb, 0.5 * base_h),
        (0.62 * rb, 0.85 * base_h),
        (0.45 * rb, base_h),
        (0.0, base_h),
    ]
    asm.add(revolve(profile, sections=12), iron)
    shaft_top = z_lantern - (0.35 if twin else 0.05)
    r_shaft = min(0.07, 0.4 * rb)
    asm.add(
        frustum((0.0, 0.0, base_h - 0.02), (0.0, 0.0, shaft_top), r_shaft, 0.65 * r_shaft, sections=12), iron
    )
    for z in (base_h + 0.05, 0.55 * shaft_top, shaft_top - 0.45):
        asm.add(torus((0.0, 0.0, z), 1.05 * r_shaft, 0.02, sections=12, tube=6), shade(iron, 1.2))
    # ladder rest across x (fills the width when the lantern is narrower)
    if lx < w - 0.02:
        z_bar = shaft_top - 0.3
        asm.add(cylinder((-hx + 0.02, 0.0, z_bar), (hx - 0.02, 0.0, z_bar), 0.015, sections=8), iron)
        for sx in (-1.0, 1.0):
            asm.add(
                ellipsoid((sx * (hx - 0.025), 0.0, z_bar), (0.025, 0.025, 0.025), segments=8, rings=4), iron
            )
    else:
        lx = w
    if twin:
        yc = hy - 0.5 * ly
        z_cb = z_lantern - 0.12
        asm.add(cylinder((0.0, -yc, z_cb), (0.0, yc, z_cb), 0.025, sections=8), iron)
        for s in (-1.0, 1.0):
            asm.add(bar((0.0, 0.0, z_cb - 0.35), (0.0, s * 0.7 * yc, z_cb), 0.03), iron)
            asm.add(cylinder((0.0, s * yc, z_cb), (0.0, s * yc, z_lantern + 0.01), 0.03, sections=8), iron)
            _lantern(asm, style, s * yc, 0.5 * lx, 0.5 * ly, z_lantern, lantern_h, iron, glass)
        asm.add(ellipsoid((0.0, 0.0, z_cb + 0.03), (0.045, 0.045, 0.06), segments=8, rings=4), iron)
    else:
        asm.add(
            cylinder((0.0, 0.0, shaft_top - 0.02), (0.0, 0.0, z_lantern + 0.01), 0.6 * r_shaft, sections=8),
            iron,
        )
        _lantern(asm, style, 0.0, 0.5 * lx, 0.5 * ly, z_lantern, lantern_h, iron, glass)
    return asm


# ---------------------------------------------------------------------------------------------------
# signals and signs


def _signal_head(
    asm: Assembly,
    rng: np.random.Generator,
    z_top: float,
    width: float,
    lens: float,
    y_back: float,
    y_front: float,
    y_visor: float,
    housing: RGB,
) -> float:
    """A three-aspect vehicle signal (red, amber, green, one lit) below `z_top`; returns its bottom."""
    pitch = lens + 0.06
    height = 3 * pitch + 0.04
    z_bot = z_top - height
    asm.box((-0.5 * width, y_back, z_bot), (0.5 * width, y_front, z_top), housing)
    lit = int(rng.integers(3))
    r = 0.5 * lens
    for k, (on, off) in enumerate(_SIGNAL_LAMPS):
        zc = z_top - 0.02 - pitch * (k + 0.5)
        asm.add(
            cylinder((0.0, y_front - 0.005, zc), (0.0, y_front + 0.01, zc), r, sections=12),
            on if k == lit else off,
        )
        hood = difference(
            cylinder((0.0, y_front - 0.002, zc), (0.0, y_visor, zc), r + 0.02, sections=12),
            cylinder((0.0, y_front - 0.01, zc), (0.0, y_visor + 0.01, zc), r + 0.008, sections=12),
            box((-1.0, y_front - 0.02, zc - 2.0 * lens), (1.0, y_visor + 0.02, zc - 0.3 * r)),
        )
        asm.add(hood, housing)
    return z_bot


def _traffic_light(rng: np.random.Generator, size: Size) -> Assembly:
    """A post-mounted traffic signal: pole, backplate and a red/amber/green head facing +y; sometimes a
    pedestrian head or a second head lower down, and a push-button box."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    housing = pick(rng, _SIGNAL_HOUSING, variation=_VARIATION)
    pole_c = pick(rng, _POLE, variation=_VARIATION)
    rp = float(np.clip(0.12 * d, 0.035, 0.055))
    yp = -hy + rp
    asm.add(cylinder((0.0, yp, 0.0), (0.0, yp, 0.25), rp, sections=12), shade(pole_c, 0.85))
    asm.add(cylinder((0.0, yp, 0.2), (0.0, yp, h - 0.1), 0.85 * rp, sections=12), pole_c)
    asm.add(ellipsoid((0.0, yp, h - 0.1), (0.85 * rp, 0.85 * rp, 0.04), segments=12, rings=4), pole_c)
    if rng.uniform() < 0.35:  # striped pole base
        band = pick(rng, ((240, 240, 236), (236, 190, 30)), variation=_VARIATION)
        for k in range(3):
            z = 0.4 + 0.3 * k
            asm.add(cylinder((0.0, yp, z), (0.0, yp, z + 0.15), 0.9 * rp, sections=12), band)
    lens = 0.3 if w >= 0.5 else 0.2
    hw = min(lens + 0.08, w - 0.04)
    y_back = yp + rp + 0.02
    y_front = y_back + 0.62 * (hy - y_back)
    # backplate, optionally with a retroreflective border
    plate_h = 3 * (lens + 0.06) + 0.04
    border = rng.uniform() < 0.4
    asm.box(
        (-hx, y_back - 0.014, h - plate_h - 0.07),
        (hx, y_back - 0.004, h - 0.004),
        pick(rng, ((240, 200, 30), (240, 240, 236)), variation=_VARIATION) if border else _DARK,
    )
    if border:
        asm.box((-hx + 0.04, y_back - 0.006, h - plate_h - 0.03), (hx - 0.04, y_back, h - 0.04), _DARK)
    z_bot = _signal_head(asm, rng, h, hw, lens, y_back, y_front, hy, housing)
    for z in (z_bot + 0.1, h - 0.1):
        asm.box((-0.04, yp, z - 0.03), (0.04, y_back, z + 0.03), shade(housing, 0.8))
    extra = float(rng.uniform())
    if z_bot - 0.15 - 3 * 0.26 - 0.04 >= 2.0 and extra < 0.35:  # repeater head at eye height
        top2 = z_bot - 0.15
        low = _signal_head(asm, rng, top2, min(0.28, hw), 0.2, y_back, y_front, hy, housing)
        asm.box((-0.04, yp, low + 0.06), (0.04, y_back, low + 0.12), shade(housing, 0.8))
    elif z_bot - 0.12 - 0.5 >= 1.85 and extra < 0.85:  # pedestrian head
        top2 = z_bot - 0.12
        pw = min(0.26, w - 0.04)
        pd = min(0.16, hy - y_back - 0.045)
        asm.box((-0.5 * pw, y_back, top2 - 0.5), (0.5 * pw, y_back + pd, top2), housing)
        red_on = rng.uniform() < 0.5
        for k, (on, off) in enumerate(((_SIGNAL_LAMPS[0]), (_SIGNAL_LAMPS[2]))):
            zc = top2 - 0.125 - 0.25 * k
            color = on if (k == 0) == red_on else off
            asm.box((-0.09, y_back + pd, zc - 0.09), (0.09, y_back + pd + 0.006, zc + 0.09), _DARK)
            asm.box((-0.02, y_back + pd, zc - 0.07), (0.02, y_back + pd + 0.01, zc + 0.03), color)
            asm.add(
                ellipsoid((0.0, y_back + pd + 0.005, zc + 0.055), (0.02, 0.005, 0.02), segments=8, rings=4),
                color,
            )
            asm.box((-0.11, y_back + pd, zc + 0.095), (0.11, y_back + pd + 0.01 + 0.03, zc + 0.11), housing)
        asm.box((-0.04, yp, top2 - 0.3), (0.04, y_back, top2 - 0.2), shade(housing, 0.8))
    if rng.uniform() < 0.6:  # push button unit
        box_c = pick(rng, ((236, 190, 30), (60, 64, 68), (200, 202, 204)), variation=_VARIATION)
        y0 = yp + 0.7 * rp
        asm.box((-0.055, y0, 0.95), (0.055, y0 + 0.085, 1.25), box_c)
        asm.add(cylinder((0.0, y0 + 0.085, 1.05), (0.0, y0 + 0.1, 1.05), 0.025, sections=12), _WHITE)
    return asm


def _octagon(half_width: float, zc: float) -> np.ndarray:
    """Outline (x, z) of a regular octagon with flat top and sides, `half_width` across the flats."""
    radius = half_width / math.cos(math.pi / 8)
    angles = math.pi / 8 + np.arange(8) * math.pi / 4
    return np.stack([radius * np.cos(angles), zc + radius * np.sin(angles)], axis=1)


def _stop_sign(rng: np.random.Generator, size: Size) -> Assembly:
    """A stop sign: red octagonal plate with a white border and STOP lettering, on a steel post."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    post_c = pick(rng, ((168, 172, 174), (120, 126, 134), (34, 62, 48)), variation=_VARIATION)
    post_d = float(np.clip(d - 0.03, 0.04, 0.07))
    yp = -hy + 0.5 * post_d
    zc = h - hx
    post_top = h - 0.06
    if rng.uniform() < 0.5:
        asm.add(cylinder((0.0, yp, 0.0), (0.0, yp, post_top), 0.5 * post_d, sections=12), post_c)
    else:
        asm.box((-0.5 * post_d, -hy, 0.0), (0.5 * post_d, -hy + post_d, post_top), post_c)
        for z in np.arange(0.3, post_top - 0.1, 0.25):  # punched holes of a U-channel post
            asm.box((-0.006, -hy + post_d, float(z)), (0.006, -hy + post_d + 0.001, float(z) + 0.012), _DARK)
    y_plate = hy - 0.0045
    for z in (zc - 0.3 * w, zc + 0.3 * w):
        asm.box((-0.03, -hy + post_d - 0.005, z - 0.02), (0.03, y_plate, z + 0.02), _ALUMINIUM)
    outline = _octagon(hx, zc)
    asm.add(extrude_along(outline, y_plate, y_plate + 0.0025, axis="y"), _ALUMINIUM)
    asm.add(extrude_along(outline, y_plate + 0.0025, y_plate + 0.003, axis="y"), _WHITE)
    red = shade(_SIGN_RED, float(rng.uniform(0.9, 1.08)))
    asm.add(
        extrude_along(_octagon(hx - max(0.02, 0.035 * w), zc), y_plate + 0.003, y_plate + 0.0037, axis="y"),
        red,
    )
    _lettering(asm, "STOP", -0.36 * w, 0.36 * w, zc - 0.15 * w, zc + 0.15 * w, y_plate + 0.0037, hy, _WHITE)
    if rng.uniform() < 0.35:  # supplementary plate (ALL WAY / 4-WAY)
        pz1 = h - w - 0.05
        asm.box((-0.22 * w, y_plate, pz1 - 0.2 * w), (0.22 * w, y_plate + 0.003, pz1), red)
        asm.box((-0.18 * w, y_plate + 0.003, pz1 - 0.13 * w), (0.18 * w, hy, pz1 - 0.07 * w), _WHITE)
    if rng.uniform() < 0.3:  # red reflective strip on the post
        asm.box((-0.015, y_plate - 0.02, 0.5), (0.015, y_plate - 0.015, 1.5), red)
    return asm


def _street_sign(rng: np.random.Generator, size: Size) -> Assembly:
    """A street-name sign: post with finial, two crossed name blades on top, and below them optional
    direction fingers along x and a regulatory plate facing +y."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    post_c = pick(rng, _POLE, variation=_VARIATION)
    r = float(rng.uniform(0.03, 0.038))
    asm.add(cylinder((0.0, 0.0, 0.0), (0.0, 0.0, h - 0.04), r, sections=12), post_c)
    asm.add(ellipsoid((0.0, 0.0, h - 0.04), (0.04, 0.04, 0.04), segments=12, rings=4), post_c)
    bg, fg = _BLADES[int(rng.integers(len(_BLADES)))]
    bg = shade(bg, float(rng.uniform(0.94, 1.06)))
    bh = float(rng.uniform(0.15, 0.22))
    t = 0.012
    top_y = h - 0.07
    top_x = top_y - bh - 0.03
    # blade along y (read from ±x) above the blade along x (read from ±y)
    asm.box((-0.5 * t, -hy, top_y - bh), (0.5 * t, hy, top_y), bg)
    asm.box((-hx, -0.5 * t, top_x - bh), (hx, 0.5 * t, top_x), bg)
    for s in (-1.0, 1.0):
        x0, x1 = sorted((s * 0.5 * t, s * (0.5 * t + 0.0015)))
        for a, b in _word_spans(rng, -hy + 0.04, hy - 0.04):
            asm.box((x0, a, top_y - 0.72 * bh), (x1, b, top_y - 0.28 * bh), fg)
        y0, y1 = sorted((s * 0.5 * t, s * (0.5 * t + 0.0015)))
        for a, b in _word_spans(rng, -hx + 0.04, hx - 0.04):
            asm.box((a, y0, top_x - 0.72 * bh), (b, y1, top_x - 0.28 * bh), fg)
    asm.box((-0.045, -0.045, top_x - bh - 0.03), (0.045, 0.045, top_y + 0.015), shade(post_c, 0.8))
    z = top_x - bh - 0.12
    for _ in range(int(rng.integers(0, 3))):  # direction fingers
        fh = float(rng.uniform(0.12, 0.17))
        s = 1.0 if rng.uniform() < 0.5 else -1.0
        length = float(rng.uniform(0.7, 1.0)) * (hx - r)
        tip = fh * 0.5
        outline = [
            (r, z - fh),
            (r + length - tip, z - fh),
            (r + length, z - 0.5 * fh),
            (r + length - tip, z),
            (r, z),
        ]
        outline = [(s * u, v) for u, v in outline]
        color, text = ((24, 64, 150), _WHITE) if rng.uniform() < 0.4 else (_WHITE, (30, 30, 32))
        asm.add(extrude_along(outline, -0.006, 0.006, axis="y"), color)
        xa, xb = sorted((s * (r + 0.03), s * (r + length - tip - 0.02)))
        for sy in (-1.0, 1.0):
            ya, yb = sorted((sy * 0.006, sy * 0.0075))
            asm.box((xa, ya, z - 0.7 * fh), (xb, yb, z - 0.3 * fh), text)
        z -= fh + 0.05
    if rng.uniform() < 0.5 and z > 2.0:  # regulatory plate on the front of the post
        pw = min(float(rng.uniform(0.3, 0.45)), w - 0.02)
        ph = float(rng.uniform(0.4, 0.6))
        plate, symbol = _PLATES[int(rng.integers(len(_PLATES)))]
        y0 = r + 0.01
        asm.box((-0.03, 0.0, z - 0.8 * ph), (0.03, y0, z - 0.2 * ph), _ALUMINIUM)
        asm.box((-0.5 * pw, y0, z - ph), (0.5 * pw, y0 + 0.003, z), plate)
        asm.box(
            (-0.5 * pw + 0.02, y0 + 0.003, z - ph + 0.02), (0.5 * pw - 0.02, y0 + 0.0035, z - 0.02), symbol
        )
        asm.box(
            (-0.5 * pw + 0.03, y0 + 0.0035, z - ph + 0.03), (0.5 * pw - 0.03, y0 + 0.004, z - 0.03), plate
        )
        _lettering(
            asm, "P", -0.2 * pw, 0.2 * pw, z - 0.75 * ph, z - 0.25 * ph, y0 + 0.004, y0 + 0.0055, symbol
        )
    return asm


def _word_spans(rng: np.random.Generator, a: float, b: float) -> list[tuple[float, float]]:
    """One or two word-long intervals of lettering inside ``[a, b]``, centred as a group."""
    span = b - a
    words = int(rng.integers(1, 3))
    lengths = [float(rng.uniform(0.25, 0.45)) * span for _ in range(words)]
    gap = 0.06 * span
    total = sum(lengths) + gap * (words - 1)
    x = a + 0.5 * (span - total)
    spans = []
    for length in lengths:
        spans.append((x, x + length))
        x += length + gap
    return spans


def _bus_pictogram(
    asm: Assembly,
    x0: float,
    x1: float,
    z0: float,
    z1: float,
    y0: float,
    y1: float,
    ink: RGB,
    ground: RGB,
    facing: float,
) -> None:
    """A bus seen from the side in ``[x0, x1] x [z0, z1]`` on a layer ``[y0, y1]`` of a plate face that
    looks towards the sign of `facing`: body, a window band and two wheels."""
    w, h = x1 - x0, z1 - z0
    asm.box((x0, y0, z0 + 0.15 * h), (x1, y1, z1), ink)
    outer = y1 if facing > 0 else y0
    wa, wb = sorted((outer, outer + facing * 0.0005))
    asm.box((x0 + 0.08 * w, wa, z0 + 0.55 * h), (x1 - 0.08 * w, wb, z1 - 0.12 * h), ground)
    for u in (0.22, 0.78):
        asm.box((x0 + (u - 0.09) * w, y0, z0), (x0 + (u + 0.09) * w, y1, z0 + 0.3 * h), ink)


def _bus_stop_sign(rng: np.random.Generator, size: Size) -> Assembly:
    """A bus stop pole: a flag at the top (a round 'H' disc, a bus plate or route tiles) and a timetable
    case facing +y at eye height."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    pole_c = pick(rng, _POLE, variation=_VARIATION)
    r = float(np.clip(0.3 * d, 0.03, 0.04))
    style = int(rng.integers(3))
    xp = 0.0 if style == 0 else -hx + r
    yp = -hy + r
    asm.add(cylinder((xp, yp, 0.0), (xp, yp, h - 0.02), r, sections=12), pole_c)
    asm.add(cylinder((xp, yp, h - 0.02), (xp, yp, h), 0.8 * r, sections=12), shade(pole_c, 0.7))
    y0 = yp + r + 0.004
    if style == 0:  # round disc with a ring and an H (Germany, Austria)
        R = hx
        zc = h - 0.03 - R
        green, yellow = (20, 120, 70), (248, 206, 30)
        asm.box((-0.03, yp, zc - 0.5 * R), (0.03, y0, zc + 0.5 * R), _ALUMINIUM)
        asm.add(cylinder((0.0, y0, zc), (0.0, y0 + 0.003, zc), R, sections=24), green)
        asm.add(cylinder((0.0, y0 + 0.003, zc), (0.0, y0 + 0.0036, zc), 0.86 * R, sections=24), yellow)
        _lettering(asm, "H", -0.45 * R, 0.45 * R, zc - 0.5 * R, zc + 0.5 * R, y0 + 0.0036, y0 + 0.0045, green)
        flag_bottom = zc - R
    else:
        fw = w - 2 * r - 0.01
        fh = float(rng.uniform(0.35, 0.5)) * (1.0 if style == 1 else 1.3)
        x0 = -hx + 2 * r + 0.01
        top = h - 0.04
        color, ink = _PLATES[int(rng.integers(len(_PLATES)))]
        color = shade(color, float(rng.uniform(0.95, 1.05)))
        for z in (top - 0.2 * fh, top - 0.8 * fh):
            asm.box((xp, yp - 0.02, z - 0.03), (x0 + 0.02, yp + 0.02, z + 0.03), _ALUMINIUM)
        asm.box((x0, yp - 0.003, top - fh), (hx, yp + 0.003, top), color)
        if style == 1:  # plate with a bus pictogram and BUS
            for sy in (-1.0, 1.0):
                ya, yb = sorted((yp + sy * 0.003, yp + sy * 0.0045))
                bx0, bx1 = x0 + 0.2 * fw, x0 + 0.8 * fw
                _bus_pictogram(asm, bx0, bx1, top - 0.55 * fh, top - 0.1 * fh, ya, yb, ink, color, sy)
                _lettering(asm, "BUS", bx0, bx1, top - 0.92 * fh, top - 0.66 * fh, ya, yb, ink, facing=sy)
        else:  # stacked route number tiles
            tiles = int(rng.integers(2, 5))
            th = 0.65 * fh / tiles
            asm.box((x0 + 0.03, yp - 0.0045, top - 0.3 * fh), (hx - 0.03, yp + 0.0045, top - 0.06), ink)
            for k in range(tiles):
                z1 = top - 0.32 * fh - k * th
                tile = pick(rng, "accent")
                asm.box((x0 + 0.04, yp - 0.005, z1 - th + 0.01), (hx - 0.04, yp + 0.005, z1), tile)
                asm.box(
                    (x0 + 0.3 * fw, yp - 0.006, z1 - 0.75 * th),
                    (x0 + 0.6 * fw, yp + 0.006, z1 - 0.25 * th),
                    _WHITE,
                )
        flag_bottom = top - fh
    # timetable case
    case_w = min(float(rng.uniform(0.28, 0.4)), w - 0.04)
    case_top = min(flag_bottom - 0.2, float(rng.uniform(1.7, 1.9)))
    case_h = float(rng.uniform(0.4, 0.55))
    cx = xp + 0.5 * case_w - r if style != 0 else 0.0
    cx = float(np.clip(cx, -hx + 0.5 * case_w, hx - 0.5 * case_w))
    frame = pick(rng, ((200, 202, 204), (60, 64, 68), (24, 64, 150)), variation=_VARIATION)
    asm.box(
        (cx - 0.5 * case_w, y0 - 0.004, case_top - case_h), (cx + 0.5 * case_w, hy - 0.004, case_top), frame
    )
    asm.box(
        (cx - 0.5 * case_w + 0.025, hy - 0.005, case_top - case_h + 0.025),
        (cx + 0.5 * case_w - 0.025, hy, case_top - 0.025),
        (248, 248, 244),
    )
    for k in range(5):
        z = case_top - 0.06 - k * 0.06
        asm.box(
            (cx - 0.5 * case_w + 0.05, hy - 0.001, z - 0.012),
            (cx + 0.5 * case_w - 0.05, hy + 0.0, z),
            (90, 90, 96),
        )
    for z in (case_top - 0.1, case_top - case_h + 0.1):
        asm.box((xp - 0.02, yp, z - 0.02), (xp + 0.02, y0, z + 0.02), shade(frame, 0.8))
    return asm


# ---------------------------------------------------------------------------------------------------
# kerbside objects


def _fire_hydrant(rng: np.random.Generator, size: Size) -> Assembly:
    """A pillar fire hydrant: bolted base flange, barrel, bonnet with operating nut, two hose outlets
    along x and a pumper outlet towards +y; a squat American or a slender European pillar."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    euro = rng.uniform() < (0.6 if h > 0.9 else 0.3)
    if euro:
        body = shade(_HYDRANT_BODY[0], float(rng.uniform(0.92, 1.06)))
        cap = pick(rng, ((188, 190, 192), (40, 40, 42), body), variation=_VARIATION)
        r = min(0.2 * w, 0.26 * d)
    else:
        body = pick(rng, _HYDRANT_BODY, variation=_VARIATION)
        cap = body if rng.uniform() < 0.4 else pick(rng, _HYDRANT_CAP, variation=_VARIATION)
        r = min(0.26 * w, 0.3 * d)
    R = 1.3 * r
    yc = -hy + R
    fz = 0.05 * h
    asm.add(cylinder((0.0, yc, 0.0), (0.0, yc, fz), R, sections=16), shade(body, 0.85))
    for k in range(8):
        a = 2 * math.pi * (k + 0.5) / 8
        bx, by = 1.15 * r * math.cos(a), yc + 1.15 * r * math.sin(a)
        asm.add(cylinder((bx, by, fz - 0.005), (bx, by, fz + 0.018), 0.012, sections=6), (120, 120, 124))
    if euro:
        z_barrel, z_nozzle = 0.74 * h, 0.55 * h
        asm.add(frustum((0.0, yc, fz - 0.005), (0.0, yc, z_barrel), 1.05 * r, r, sections=16), body)
        band = (240, 240, 236)
        asm.add(cylinder((0.0, yc, 0.62 * h), (0.0, yc, 0.68 * h), 1.02 * r, sections=16), band)
        asm.add(cylinder((0.0, yc, z_barrel - 0.01), (0.0, yc, 0.86 * h), 1.12 * r, sections=16), body)
        asm.add(_dome((0.0, yc, 0.86 * h - 0.001), (1.12 * r, 1.12 * r, 0.09 * h)), cap)
        nut0 = 0.94 * h
    else:
        z_barrel, z_nozzle = 0.6 * h, 0.47 * h
        asm.add(frustum((0.0, yc, fz - 0.005), (0.0, yc, z_barrel), 1.06 * r, r, sections=16), body)
        asm.add(
            cylinder((0.0, yc, z_barrel - 0.02), (0.0, yc, z_barrel + 0.03), 1.18 * r, sections=16),
            shade(body, 0.9),
        )
        asm.add(frustum((0.0, yc, z_barrel + 0.03), (0.0, yc, 0.8 * h), 1.05 * r, 0.8 * r, sections=16), cap)
        asm.add(_dome((0.0, yc, 0.8 * h - 0.001), (0.8 * r, 0.8 * r, 0.1 * h)), cap)
        nut0 = 0.88 * h
    asm.add(cylinder((0.0, yc, nut0), (0.0, yc, h), 0.22 * r + 0.01, sections=5), shade(cap, 0.9))
    # hose outlets to -x and +x, pumper outlet to +y
    cap_l = 0.06 * w
    rn = 0.32 * r
    for s in (-1.0, 1.0):
        asm.add(cylinder((0.0, yc, z_nozzle), (s * (hx - cap_l), yc, z_nozzle), rn, sections=12), body)
        asm.add(
            cylinder((s * (hx - cap_l - 0.005), yc, z_nozzle), (s * hx, yc, z_nozzle), 1.25 * rn, sections=6),
            cap,
        )
    zp = z_nozzle - (0.0 if euro else 0.05 * h)
    rpump = 0.5 * r
    cap_p = min(0.06, 0.25 * (hy - yc))
    asm.add(cylinder((0.0, yc, zp), (0.0, hy - cap_p, zp), rpump, sections=12), body)
    asm.add(cylinder((0.0, hy - cap_p - 0.005, zp), (0.0, hy, zp), 1.2 * rpump, sections=6), cap)
    return asm


def _bollard(rng: np.random.Generator, size: Size) -> Assembly:
    """A traffic bollard: a steel post with a domed or flat cap, a concrete post, or a lit bollard with
    a glowing band under its cap; round or square."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    kind = int(rng.integers(3))
    round_ = max(w, d) / min(w, d) <= 1.12 and rng.uniform() < 0.75
    if kind == 0:  # steel
        color = pick(
            rng,
            ((196, 198, 200), (28, 28, 30), (62, 66, 70), (236, 190, 30), (34, 62, 48)),
            variation=_VARIATION,
        )
        cap_h = float(rng.uniform(0.04, 0.08))
        asm.add(_section(hx, hy, 0.0, 0.015, round_=round_), shade(color, 0.8))
        asm.add(_section(0.88 * hx, 0.88 * hy, 0.01, h - cap_h, round_=round_), color)
        band = pick(rng, ((244, 244, 240), (236, 190, 30), (200, 40, 40)), variation=_VARIATION)
        for k in range(int(rng.integers(1, 3))):
            z = h - cap_h - 0.08 - 0.1 * k
            asm.add(_section(0.9 * hx, 0.9 * hy, z - 0.05, z, round_=round_), band)
        if round_ and rng.uniform() < 0.6:
            asm.add(_dome((0.0, 0.0, h - cap_h - 0.002), (0.88 * hx, 0.88 * hy, cap_h + 0.002)), color)
        else:
            asm.add(
                _section(0.92 * hx, 0.92 * hy, h - cap_h - 0.002, h, round_=round_, top=0.7),
                shade(color, 1.1),
            )
    elif kind == 1:  # concrete
        color = pick(rng, _CONCRETE, variation=_VARIATION)
        top_h = float(rng.uniform(0.05, 0.12))
        asm.add(_section(hx, hy, 0.0, h - top_h, round_=round_, top=0.93), color)
        asm.add(
            _section(0.93 * hx, 0.93 * hy, h - top_h - 0.002, h, round_=round_, top=0.55), shade(color, 1.05)
        )
        asm.add(_section(1.0 * hx, 1.0 * hy, 0.0, 0.04, round_=round_, top=0.995), shade(color, 0.75))
        if rng.uniform() < 0.5:
            band = pick(rng, ((244, 244, 240), (200, 40, 40)), variation=_VARIATION)
            z = h - top_h - 0.12
            asm.add(_section(0.945 * hx, 0.945 * hy, z - 0.06, z, round_=round_), band)
    else:  # lit bollard
        color = pick(rng, ((62, 66, 70), (28, 28, 30), (170, 174, 178)), variation=_VARIATION)
        light = pick(rng, _LENS, variation=0.03)
        cap_h = float(rng.uniform(0.03, 0.06))
        band_h = float(rng.uniform(0.08, 0.16))
        asm.add(_section(hx, hy, 0.0, 0.04, round_=round_), shade(color, 0.8))
        asm.add(_section(0.82 * hx, 0.82 * hy, 0.03, h - cap_h - band_h, round_=round_), color)
        asm.add(
            _section(0.76 * hx, 0.76 * hy, h - cap_h - band_h - 0.005, h - cap_h + 0.002, round_=round_),
            light,
        )
        asm.add(_section(hx, hy, h - cap_h, h, round_=round_, top=0.9), shade(color, 1.1))
        asm.box((-0.01, -0.01, h - cap_h - band_h), (0.01, 0.01, h - cap_h), color)
    return asm


def _post_box(rng: np.random.Generator, size: Size) -> Assembly:
    """A mail collection box: a round pillar box (UK, Ireland), a blue US collection box on legs, or a
    square box on a pedestal (Japan, France, Germany). Slots face +y."""
    w, d, _ = size
    ratio = max(w, d) / min(w, d)
    styles = ["us", "square"] + (["pillar", "pillar"] if ratio <= 1.15 else [])
    style = styles[int(rng.integers(len(styles)))]
    if style == "pillar":
        return _pillar_box(rng, size)
    if style == "us":
        return _us_mailbox(rng, size)
    return _square_postbox(rng, size)


def _pillar_box(rng: np.random.Generator, size: Size) -> Assembly:
    """A cylindrical pillar box on a black plinth, with a domed or flat cap, slot, door and plate."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = (
        pick(rng, _POSTAL_RED, variation=_VARIATION)
        if rng.uniform() < 0.8
        else pick(rng, ((30, 100, 60), (28, 28, 30)), variation=_VARIATION)
    )
    base = (30, 30, 32)
    asm.add(_section(hx, hy, 0.0, 0.1, top=0.93), base)
    cap_h = float(rng.uniform(0.12, 0.18))
    asm.add(_section(0.86 * hx, 0.86 * hy, 0.09, h - cap_h, top=1.0), body)
    asm.add(_section(0.93 * hx, 0.93 * hy, h - cap_h - 0.06, h - cap_h + 0.005), shade(body, 0.92))
    if rng.uniform() < 0.6:
        asm.add(_dome((0.0, 0.0, h - cap_h), (0.9 * hx, 0.9 * hy, cap_h)), body)
    else:  # flat 'lamp-top' cap
        asm.add(_section(0.95 * hx, 0.95 * hy, h - cap_h, h - 0.5 * cap_h, top=0.9), body)
        asm.add(_section(0.5 * hx, 0.5 * hy, h - 0.5 * cap_h - 0.002, h, top=0.4), shade(body, 0.9))
    front = 0.86 * hy
    out = min(0.03, 0.12 * hy)
    z_slot = h - cap_h - 0.16
    asm.box((-0.12, front - 0.06, z_slot), (0.12, front + 0.4 * out, z_slot + 0.035), _DARK)
    asm.box((-0.14, front - 0.06, z_slot + 0.035), (0.14, front + out, z_slot + 0.06), shade(body, 1.05))
    asm.box((-0.3 * hx, front - 0.06, 0.35 * h), (0.3 * hx, front + 0.3 * out, 0.62 * h), shade(body, 0.95))
    asm.box((-0.2 * hx, front - 0.06, 0.5 * h), (0.2 * hx, front + 0.5 * out, 0.58 * h), (236, 232, 214))
    asm.box((-0.05, front - 0.06, z_slot - 0.1), (0.05, front + 0.4 * out, z_slot - 0.04), (196, 160, 80))
    return asm


def _us_mailbox(rng: np.random.Generator, size: Size) -> Assembly:
    """A USPS-style collection box: arched body on four legs, pull-down chute and decals."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    blue = pick(rng, ((30, 62, 140), (26, 54, 120), (40, 70, 150)), variation=_VARIATION)
    legs_h = float(rng.uniform(0.1, 0.17))
    rise = float(rng.uniform(0.12, 0.22))
    z_shoulder = h - rise
    angles = np.linspace(0.0, math.pi, 11)
    profile = [(-hx, legs_h), (hx, legs_h)] + [
        (hx * math.cos(a), z_shoulder + rise * math.sin(a)) for a in angles
    ]
    body_front = hy - 0.04
    asm.add(extrude_along(profile, -hy, body_front, axis="y"), blue)
    for x in (-hx + 0.03, hx - 0.07):
        for y in (-hy + 0.03, body_front - 0.07):
            asm.box((x, y, 0.0), (x + 0.04, y + 0.04, legs_h + 0.01), shade(blue, 0.7))
    # pull-down chute with handle
    chute_top = z_shoulder - 0.02
    chute_bot = chute_top - 0.3
    pts = [
        (x, y, z)
        for x in (-0.36 * w, 0.36 * w)
        for y, z in (
            (body_front - 0.01, chute_bot),
            (body_front - 0.01, chute_top),
            (body_front + 0.025, chute_top),
        )
    ]
    asm.add(hull(pts), shade(blue, 1.1))
    asm.box((-0.2 * w, body_front + 0.01, chute_top - 0.04), (0.2 * w, hy, chute_top - 0.01), (170, 174, 178))
    asm.box((-0.3 * w, body_front - 0.005, 0.45 * h), (0.3 * w, body_front + 0.004, 0.62 * h), _WHITE)
    asm.box((-0.22 * w, body_front + 0.004, 0.5 * h), (0.22 * w, body_front + 0.006, 0.57 * h), (190, 30, 40))
    for s in (-1.0, 1.0):  # side decals
        xa, xb = sorted((s * hx, s * (hx - 0.003)))
        asm.box((xa, -0.35 * d, 0.6 * h), (xb, 0.3 * d, 0.7 * h), _WHITE)
    return asm


def _square_postbox(rng: np.random.Generator, size: Size) -> Assembly:
    """A rectangular post box with a rounded cap on a pedestal, with one or two slots (Japan, France,
    Germany)."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = (
        pick(rng, _POSTAL_RED, variation=_VARIATION)
        if rng.uniform() < 0.55
        else pick(rng, _POSTAL_YELLOW, variation=_VARIATION)
    )
    ped_h = float(rng.uniform(0.25, 0.4)) * h
    cap_h = float(rng.uniform(0.06, 0.1))
    asm.box((-0.3 * hx, -0.3 * hy, 0.0), (0.3 * hx, 0.3 * hy, 0.03), shade(body, 0.5))
    asm.box((-0.22 * hx, -0.22 * hy, 0.0), (0.22 * hx, 0.22 * hy, ped_h + 0.01), shade(body, 0.85))
    asm.add(rounded_prism((0.0, 0.0), 0.94 * w, 0.94 * d, 0.04, ped_h, h - cap_h), body)
    asm.add(rounded_prism((0.0, 0.0), w, d, 0.05, h - cap_h, h - 0.5 * cap_h), shade(body, 1.05))
    asm.add(
        extrude(
            [
                (-0.5 * w + 0.02, -0.5 * d + 0.02),
                (0.5 * w - 0.02, -0.5 * d + 0.02),
                (0.5 * w - 0.02, 0.5 * d - 0.02),
                (-0.5 * w + 0.02, 0.5 * d - 0.02),
            ],
            h - 0.5 * cap_h - 0.001,
            h,
            scale_top=(0.8, 0.7),
        ),
        shade(body, 1.05),
    )
    front = 0.47 * d
    slots = 2 if w > 0.5 and rng.uniform() < 0.6 else 1
    z_slot = h - cap_h - 0.12
    for k in range(slots):
        cx = 0.0 if slots == 1 else (-0.22 + 0.44 * k) * w
        sw = 0.26 * w if slots == 2 else 0.5 * w
        asm.box((cx - 0.5 * sw, front - 0.02, z_slot), (cx + 0.5 * sw, front + 0.006, z_slot + 0.035), _DARK)
        asm.box(
            (cx - 0.5 * sw - 0.01, front - 0.02, z_slot + 0.035),
            (cx + 0.5 * sw + 0.01, hy - 0.001, z_slot + 0.055),
            shade(body, 1.1),
        )
    asm.box((-0.25 * w, front - 0.02, z_slot - 0.3), (0.25 * w, front + 0.004, z_slot - 0.1), _WHITE)
    if z_slot - 0.34 > ped_h + 0.1:  # door panel
        asm.box(
            (-0.32 * w, front - 0.02, ped_h + 0.06),
            (0.32 * w, front + 0.003, z_slot - 0.34),
            shade(body, 0.93),
        )
    return asm


def _parking_meter(rng: np.random.Generator, size: Size) -> Assembly:
    """A parking meter: a single-head or twin-head coin/card meter on a post, or a pay-and-display
    station; screens and slots face +y."""
    w, d, h = size
    candidates = []
    if w >= 0.3 and h >= 1.45:
        candidates.append("kiosk")
    if w >= 0.36 and h <= 1.6:
        candidates.append("twin")
    if w <= 0.38:
        candidates.append("single")
    if not candidates:
        candidates.append("twin" if w >= 0.36 else "single")
    style = candidates[int(rng.integers(len(candidates)))]
    if style == "kiosk":
        return _pay_station(rng, size)
    asm = Assembly()
    hy = 0.5 * d
    post_c = pick(rng, ((28, 28, 30), (62, 66, 70), (34, 62, 48), (120, 126, 134)), variation=_VARIATION)
    head_c = pick(
        rng,
        ((176, 180, 184), (28, 28, 30), (34, 62, 48), (24, 64, 150), (236, 190, 30)),
        variation=_VARIATION,
    )
    head_h = float(rng.uniform(0.36, 0.46))
    z_head = h - head_h
    pr = min(0.035, 0.3 * d)
    asm.add(cylinder((0.0, 0.0, 0.0), (0.0, 0.0, 0.02), min(0.08, 0.45 * d), sections=12), shade(post_c, 0.8))
    asm.add(cylinder((0.0, 0.0, 0.0), (0.0, 0.0, z_head + 0.05), pr, sections=12), post_c)
    domed = rng.uniform() < 0.5
    if style == "single":
        _meter_head(asm, rng, -0.5 * w, 0.5 * w, -hy, hy, z_head, h, head_c, domed)
    else:
        asm.box((-0.5 * w + 0.04, -0.04, z_head - 0.06), (0.5 * w - 0.04, 0.04, z_head + 0.005), post_c)
        gap = 0.02
        _meter_head(asm, rng, -0.5 * w, -0.5 * gap, -hy, hy, z_head, h, head_c, domed)
        _meter_head(asm, rng, 0.5 * gap, 0.5 * w, -hy, hy, z_head, h, head_c, domed)
    return asm


def _meter_head(
    asm: Assembly,
    rng: np.random.Generator,
    x0: float,
    x1: float,
    y0: float,
    y1: float,
    z0: float,
    z1: float,
    color: RGB,
    domed: bool,
) -> None:
    """One meter head in ``[x0, x1] x [y0, y1] x [z0, z1]``: housing, window or screen, slots, a dome
    or a solar panel on top. Its front (+y) is at ``y1``."""
    cx = 0.5 * (x0 + x1)
    hw = 0.5 * (x1 - x0)
    face = y1 - 0.012
    height = z1 - z0
    if domed:  # classic mechanical meter: rounded dome with a dial window
        dome_r = min(hw, 0.45 * height)
        shoulder = z1 - dome_r
        asm.box((x0 + 0.01, y0 + 0.01, z0), (x1 - 0.01, face, shoulder + 0.002), color)
        angles = np.linspace(0.0, math.pi, 9)
        profile = [(cx + hw * math.cos(a), shoulder + dome_r * math.sin(a)) for a in angles]
        asm.add(extrude_along(profile, y0, face, axis="y"), shade(color, 1.08))
        asm.add(
            extrude_along(
                [
                    (cx + 0.75 * hw * math.cos(a), shoulder - 0.02 + 0.75 * dome_r * math.sin(a))
                    for a in angles
                ],
                face - 0.01,
                y1,
                axis="y",
            ),
            (226, 232, 230),
        )
        asm.box(
            (cx - 0.6 * hw, face - 0.01, shoulder - 0.02), (cx + 0.6 * hw, y1, shoulder), shade(color, 0.8)
        )
    else:  # electronic meter: box with a screen and a solar panel
        asm.box((x0 + 0.01, y0 + 0.01, z0), (x1 - 0.01, face, z1 - 0.03), color)
        pts = [(x, y, z) for x in (x0, x1) for y, z in ((y0, z1 - 0.03), (y1, z1 - 0.03), (y0, z1))]
        asm.add(hull(pts), (30, 40, 70))
        asm.box((cx - 0.6 * hw, face - 0.01, z1 - 0.17), (cx + 0.6 * hw, y1, z1 - 0.07), (40, 60, 56))
        for r in range(2):
            for c in range(3):
                bx = cx + (c - 1) * 0.35 * hw
                bz = z1 - 0.21 - 0.04 * r
                asm.box(
                    (bx - 0.012, face - 0.01, bz - 0.012),
                    (bx + 0.012, y1 - 0.002, bz + 0.012),
                    (200, 200, 200),
                )
    asm.box(
        (cx - 0.2 * hw, face - 0.01, z0 + 0.5 * height - 0.1),
        (cx + 0.2 * hw, y1 - 0.004, z0 + 0.5 * height - 0.08),
        _DARK,
    )
    asm.box(
        (cx - 0.5 * hw, face - 0.01, z0 + 0.03), (cx + 0.5 * hw, y1 - 0.006, z0 + 0.12), shade(color, 0.85)
    )
    asm.add(cylinder((cx, face - 0.01, z0 + 0.075), (cx, y1, z0 + 0.075), 0.015, sections=8), (200, 180, 100))


def _pay_station(rng: np.random.Generator, size: Size) -> Assembly:
    """A pay-and-display station: plinth, cabinet, roof with a solar panel, screen, keypad, coin and
    card slots, ticket tray and a blue P sign."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = pick(
        rng,
        ((176, 180, 184), (62, 66, 70), (28, 28, 30), (34, 62, 48), (236, 236, 230)),
        variation=_VARIATION,
    )
    roof_h = 0.06
    asm.box((-hx + 0.04, -hy + 0.04, 0.0), (hx - 0.04, hy - 0.06, 0.1), shade(body, 0.6))
    asm.add(rounded_prism((0.0, -0.015), w - 0.03, d - 0.05, 0.04, 0.1, h - roof_h), body)
    face = hy - 0.04
    asm.add(rounded_prism((0.0, 0.0), w, d, 0.03, h - roof_h, h - 0.02), shade(body, 1.1))
    asm.box((-hx + 0.03, -hy + 0.03, h - 0.021), (hx - 0.03, hy - 0.03, h), (30, 40, 70))
    z_screen = h - roof_h - 0.08
    asm.box((-0.3 * w, face - 0.01, z_screen - 0.16), (0.3 * w, hy, z_screen), (40, 60, 56))
    for r in range(4):
        for c in range(3):
            bx = (c - 1) * 0.1 * w
            bz = z_screen - 0.22 - 0.045 * r
            asm.box(
                (bx - 0.015, face - 0.01, bz - 0.015), (bx + 0.015, hy - 0.005, bz + 0.015), (200, 200, 204)
            )
    asm.box((0.2 * w, face - 0.01, z_screen - 0.34), (0.32 * w, hy - 0.003, z_screen - 0.22), _DARK)
    sign_top = z_screen - 0.45
    sign_h = 0.3 * w
    asm.box(
        (-0.5 * sign_h, face - 0.01, sign_top - sign_h), (0.5 * sign_h, hy - 0.006, sign_top), (24, 64, 150)
    )
    _lettering(
        asm,
        "P",
        -0.25 * sign_h,
        0.25 * sign_h,
        sign_top - 0.85 * sign_h,
        sign_top - 0.15 * sign_h,
        hy - 0.006,
        hy - 0.004,
        _WHITE,
    )
    tray = sign_top - sign_h - 0.06
    asm.box((-0.3 * w, face - 0.01, tray - 0.08), (0.3 * w, hy - 0.004, tray), _DARK)
    return asm


def _bike_rack(rng: np.random.Generator, size: Size) -> Assembly:
    """A row of bicycle stands: inverted-U (Sheffield) or arched hoops on two base rails along x."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    metal = pick(
        rng,
        ((176, 180, 184), (28, 28, 30), (62, 66, 70), (40, 110, 190), (200, 60, 50), (34, 62, 48)),
        variation=_VARIATION,
    )
    rail_c = (
        shade(metal, 0.85)
        if rng.uniform() < 0.5
        else pick(rng, ((168, 172, 174), (62, 66, 70)), variation=_VARIATION)
    )
    r = float(rng.uniform(0.021, 0.027))  # 42-54 mm tube
    spacing = float(rng.uniform(0.75, 1.0))
    margin = 0.15
    count = max(2, round((w - 2 * margin) / spacing) + 1)
    xs = np.linspace(-hx + margin, hx - margin, count)
    rail_h = 0.04
    rail_w = 0.06
    for s in (-1.0, 1.0):
        y_mid = s * (hy - 0.5 * rail_w)
        asm.box((-hx, y_mid - 0.5 * rail_w, 0.0), (hx, y_mid + 0.5 * rail_w, rail_h), rail_c)
    for x in (-hx + 0.05, hx - 0.05):
        asm.box((x - 0.03, -hy + r, 0.0), (x + 0.03, hy - r, 0.025), rail_c)
    arch = rng.uniform() < 0.35
    crossbar = rng.uniform() < 0.4
    half = hy - r
    top = h - r
    for x in xs:
        x = float(x)
        if arch:
            radius = half
            shoulder = top - radius
            pts = [(x, -half, rail_h - 0.005), (x, -half, shoulder)]
            for k in range(1, 8):
                a = math.pi - math.pi * k / 8
                pts.append((x, radius * math.cos(a), shoulder + radius * math.sin(a)))
            pts += [(x, half, shoulder), (x, half, rail_h - 0.005)]
        else:
            bend = float(min(0.2, 0.45 * half))
            pts = [(x, -half, rail_h - 0.005), (x, -half, top - bend)]
            for k in range(1, 4):
                a = 0.5 * math.pi * k / 4
                pts.append((x, -half + bend * (1 - math.cos(a)), top - bend + bend * math.sin(a)))
            pts += [(x, -half + bend, top), (x, half - bend, top)]
            for k in range(1, 4):
                a = 0.5 * math.pi * (4 - k) / 4
                pts.append((x, half - bend * (1 - math.cos(a)), top - bend + bend * math.sin(a)))
            pts += [(x, half, top - bend), (x, half, rail_h - 0.005)]
        # drop duplicate consecutive points (an arch without straight legs)
        clean = [pts[0]]
        for p in pts[1:]:
            if np.linalg.norm(np.subtract(p, clean[-1])) > 1e-6:
                clean.append(p)
        _tube(asm, clean, r, metal)
        if crossbar:
            z = 0.3
            asm.add(cylinder((x, -half, z), (x, half, z), 0.7 * r, sections=8), metal)
    return asm


def _utility_box(rng: np.random.Generator, size: Size) -> Assembly:
    """A roadside electrical or telecom cabinet: concrete plinth, body, one to three doors with handles,
    side louvres, a flat or pitched overhanging roof, a warning sign and stray stickers."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    color = pick(rng, _CABINET, variation=_VARIATION)
    ov = float(rng.uniform(0.02, 0.035))
    y_face = hy - 0.05 - ov
    plinth = float(rng.uniform(0.04, 0.14))
    roof_t = float(rng.uniform(0.04, 0.07))
    pitched = rng.uniform() < 0.35
    roof_h = roof_t + (float(rng.uniform(0.05, 0.1)) if pitched else 0.0)
    z_roof = h - roof_h
    asm.box((-hx + ov, -hy + ov, 0.0), (hx - ov, y_face, plinth), pick(rng, _CONCRETE, variation=_VARIATION))
    asm.box((-hx + ov, -hy + ov, plinth - 0.005), (hx - ov, y_face, z_roof + 0.002), color)
    roof = shade(color, 1.06)
    asm.box((-hx, -hy, z_roof), (hx, hy, z_roof + roof_t), roof)
    if pitched:
        pts = [(x, y, z_roof + roof_t - 0.001) for x in (-hx, hx) for y in (-hy, hy)]
        pts += [(x, 0.0, h) for x in (-hx + 0.02, hx - 0.02)]
        asm.add(hull(pts), roof)
    doors = int(np.clip(round((w - 2 * ov) / 0.55), 1, 3))
    door_fronts(
        asm,
        -hx + ov + 0.02,
        hx - ov - 0.02,
        plinth + 0.03,
        z_roof - 0.03,
        y_face,
        count=doors,
        color=shade(color, 0.97),
        handle_color=pick(rng, ((60, 60, 64), (180, 184, 188)), variation=_VARIATION),
        handle_z=float(np.clip(0.5 * (plinth + z_roof), 0.6, 1.0)),
    )
    # louvres on both sides
    for s in (-1.0, 1.0):
        x_side = s * (hx - ov)
        xa, xb = sorted((x_side, x_side + s * (ov - 0.006)))
        for k in range(4):
            z = z_roof - 0.12 - 0.05 * k
            asm.box((xa, -0.3 * d, z - 0.012), (xb, 0.25 * d, z), shade(color, 0.85))
    # warning triangle on the first door
    dw = (w - 2 * ov - 0.04) / doors
    cx = -hx + ov + 0.02 + 0.5 * dw
    cz = z_roof - 0.15
    face = y_face + 0.018
    tri = [(cx - 0.07, cz - 0.06), (cx + 0.07, cz - 0.06), (cx, cz + 0.061)]
    asm.add(extrude_along(tri, face, face + 0.002, axis="y"), (248, 204, 20))
    asm.add(
        extrude_along(
            [(cx - 0.01, cz - 0.04), (cx + 0.02, cz + 0.02), (cx, cz - 0.005), (cx + 0.01, cz - 0.04)],
            face + 0.002,
            face + 0.003,
            axis="y",
        ),
        _DARK,
    )
    for _ in range(int(rng.integers(0, 4))):  # stickers and posters
        sw, sh = float(rng.uniform(0.05, 0.2)), float(rng.uniform(0.05, 0.25))
        sx = float(rng.uniform(-hx + ov + 0.05, max(-hx + ov + 0.05, hx - ov - 0.05 - sw)))
        sz = float(rng.uniform(plinth + 0.1, max(plinth + 0.1, z_roof - 0.3 - sh)))
        asm.box((sx, face, sz), (sx + sw, face + 0.001, sz + sh), pick(rng, "packaging"))
    return asm


# ---------------------------------------------------------------------------------------------------
# shelters and booths


def _bus_shelter(rng: np.random.Generator, size: Size) -> Assembly:
    """A bus shelter open towards +y: posts, a flat, curved or sloping roof, glass back and side panels,
    an advertising case, a bench or a leaning rail, a timetable and a route sign."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    frame = pick(
        rng, ((62, 66, 70), (176, 180, 184), (34, 62, 48), (28, 28, 30), (36, 56, 100)), variation=_VARIATION
    )
    glass = pick(rng, "glass", variation=0.03)
    roof_kind = int(rng.integers(3))
    p = float(rng.uniform(0.06, 0.09))
    ov_b = float(rng.uniform(0.05, 0.12))
    ov_s = float(rng.uniform(0.05, 0.15))
    y_back = -hy + ov_b  # back face of the back posts
    x_end = hx - ov_s - 0.5 * p  # centre of the end posts
    # roof underside as a function of y
    if roof_kind == 0:  # flat slab
        rt = float(rng.uniform(0.1, 0.18))

        def under(y: float) -> float:
            return h - rt

        roof_c = (
            frame
            if rng.uniform() < 0.5
            else pick(rng, ((236, 236, 232), (176, 180, 184)), variation=_VARIATION)
        )
        asm.box((-hx, -hy, h - rt), (hx, hy - 0.012, h), roof_c)
        asm.box((-hx + 0.02, hy - 0.012, h - rt + 0.01), (hx - 0.02, hy, h - 0.01), shade(frame, 1.1))
    elif roof_kind == 1:  # barrel vault across y
        rise = float(rng.uniform(0.12, 0.25))
        rt = 0.05

        def under(y: float) -> float:
            return h - rise + rise * (1.0 - (y / hy) ** 2) - rt

        ys = np.linspace(-hy, hy, 13)
        outer = [(float(y), under(float(y)) + rt) for y in ys]
        inner = [(float(y), under(float(y))) for y in ys[::-1]]
        asm.add(
            extrude_along(outer + inner, -hx, hx, axis="x"),
            glass if rng.uniform() < 0.5 else shade(frame, 1.1),
        )
        for x in (-hx, hx - 0.04):
            asm.add(extrude_along(outer + inner, x, x + 0.04, axis="x"), frame)
    else:  # mono-pitch, rising to the front
        rise = float(rng.uniform(0.1, 0.25))
        rt = 0.08

        def under(y: float) -> float:
            return h - rt - rise * (hy - y) / d

        prof = [(-hy, h - rise - rt), (hy, h - rt), (hy, h), (-hy, h - rise)]
        asm.add(extrude_along(prof, -hx, hx, axis="x"), shade(frame, 1.05))
    # back posts, one per bay
    bays = max(2, round(2 * x_end / float(rng.uniform(1.2, 1.8))))
    xs = np.linspace(-x_end, x_end, bays + 1)
    yb = y_back + 0.5 * p
    top_b = under(yb)
    for x in xs:
        asm.box((float(x) - 0.5 * p, y_back, 0.0), (float(x) + 0.5 * p, y_back + p, top_b + 0.01), frame)
    asm.box((-x_end, y_back, top_b - 0.1), (x_end, y_back + p, top_b + 0.005), frame)
    glass_y0, glass_y1 = yb - 0.006, yb + 0.006
    for x0, x1 in itertools.pairwise(xs):
        asm.box((float(x0) + 0.5 * p, glass_y0, 0.12), (float(x1) - 0.5 * p, glass_y1, top_b - 0.1), glass)
    asm.box((-x_end, y_back + 0.01, 0.06), (x_end, y_back + p - 0.01, 0.12), frame)
    manifest = pick(rng, ((240, 240, 236), (236, 190, 30), (40, 40, 44)), variation=_VARIATION)
    asm.box((-x_end, glass_y1, 1.4), (x_end, glass_y1 + 0.002, 1.46), manifest)
    # front posts or cantilever
    four_post = rng.uniform() < 0.6
    ov_f = float(rng.uniform(0.15, 0.35))
    y_side_end = hy - ov_f - p if four_post else y_back + float(rng.uniform(0.5, 0.75)) * (d - ov_b)
    if four_post:
        for x in (-x_end, x_end):
            top_f = under(hy - ov_f - 0.5 * p)
            asm.box((x - 0.5 * p, hy - ov_f - p, 0.0), (x + 0.5 * p, hy - ov_f, top_f + 0.01), frame)
            asm.box((x - 0.5 * p, y_back, top_f - 0.08), (x + 0.5 * p, hy - ov_f, top_f + 0.005), frame)
    else:
        for x in (-x_end, x_end):
            asm.box((x - 0.5 * p, y_back + p, top_b - 0.1), (x + 0.5 * p, y_side_end, top_b + 0.005), frame)
    # side panels; one end may carry an illuminated advertising case
    ad_side = [-1.0, 1.0][int(rng.integers(2))] if rng.uniform() < 0.6 else 0.0
    for s in (-1.0, 1.0):
        x = s * x_end
        if s == ad_side:
            ad_len = min(1.25, y_side_end - y_back - p - 0.02)
            ya = y_back + p + 0.01
            ad_top = min(2.05, top_b - 0.1)
            asm.box((x - 0.07, ya, 0.08), (x + 0.07, ya + ad_len, ad_top), frame)
            poster = pick(rng, "packaging")
            for sx in (-1.0, 1.0):
                xa, xb = sorted((x + sx * 0.07, x + sx * 0.072))
                asm.box((xa, ya + 0.05, 0.2), (xb, ya + ad_len - 0.05, ad_top - 0.1), poster)
        else:
            side_top = min(under(y_back), under(y_side_end)) - 0.1
            asm.box((x - 0.006, y_back + p, 0.12), (x + 0.006, y_side_end, side_top), glass)
            asm.box((x - 0.02, y_back + p, 0.06), (x + 0.02, y_side_end, 0.12), frame)
    # bench or leaning rail along the back
    seat_len = min(2.0, 0.7 * (2 * x_end))
    sx0 = -0.5 * seat_len + float(rng.uniform(-0.2, 0.2)) * (2 * x_end - seat_len)
    sy0 = y_back + p + 0.02
    if rng.uniform() < 0.7:
        seat_d = float(rng.uniform(0.3, 0.4))
        seat_c = pick(rng, "wood") if rng.uniform() < 0.5 else shade(frame, 1.2)
        for x in (sx0 + 0.1, sx0 + seat_len - 0.14):
            asm.box((x, sy0, 0.0), (x + 0.04, sy0 + seat_d - 0.05, 0.42), frame)
        for k in range(3):
            ya = sy0 + k * seat_d / 3
            asm.box((sx0, ya + 0.005, 0.42), (sx0 + seat_len, ya + seat_d / 3 - 0.005, 0.46), seat_c)
    else:
        asm.add(
            cylinder((sx0, sy0 + 0.06, 0.72), (sx0 + seat_len, sy0 + 0.06, 0.72), 0.05, sections=12),
            shade(frame, 1.2),
        )
        for x in (sx0 + 0.1, sx0 + seat_len - 0.1):
            asm.box((x - 0.02, y_back + p, 0.68), (x + 0.02, sy0 + 0.06, 0.72), frame)
    # timetable on the back wall and a route sign
    tx = float(xs[-1]) - 0.5 * p - 0.45
    asm.box((tx - 0.3, glass_y1, 1.1), (tx + 0.3, glass_y1 + 0.03, 1.8), frame)
    asm.box((tx - 0.27, glass_y1 + 0.03, 1.13), (tx + 0.27, glass_y1 + 0.032, 1.77), (248, 248, 244))
    if roof_kind == 0:
        sign = pick(rng, ((24, 64, 150), (20, 110, 60), (236, 190, 30), (200, 30, 40)), variation=_VARIATION)
        asm.box((-hx + 0.1, hy - 0.002, h - rt + 0.02), (-hx + 0.1 + min(1.0, 0.3 * w), hy, h - 0.02), sign)
    return asm


def _phone_booth(rng: np.random.Generator, size: Size) -> Assembly:
    """A telephone kiosk: a red K6 box with a domed roof and glazing bars, or a glass cabin with a
    branded roof; the door faces +y."""
    if rng.uniform() < 0.5:
        return _k6_kiosk(rng, size)
    return _glass_cabin(rng, size)


def _wall_box(
    asm: Assembly,
    wall: tuple[str, float, float],
    a0: float,
    a1: float,
    z0: float,
    z1: float,
    t0: float,
    t1: float,
    color: RGB,
) -> None:
    """A box on a vertical wall ``(normal axis, face coordinate, outward sign)``: from `a0` to `a1` along
    the wall, `z0` to `z1` up, and `t0` to `t1` inwards from the face (negative: outside it)."""
    normal, face, sign = wall
    n0, n1 = sorted((face - sign * t0, face - sign * t1))
    if normal == "y":
        asm.box((a0, n0, z0), (a1, n1, z1), color)
    else:
        asm.box((n0, a0, z0), (n1, a1, z1), color)


def _k6_kiosk(rng: np.random.Generator, size: Size) -> Assembly:
    """A K6-style kiosk: plinth, corner piers, glazed sides with 3 x 8 panes, TELEPHONE headers, cornice
    and dome; a handle on the door at +y."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    red = pick(rng, _POSTAL_RED, variation=_VARIATION)
    glass = pick(rng, "glass", variation=0.03)
    b = 0.03
    bx, by = hx - b, hy - b
    plinth = 0.08
    dome_h = float(rng.uniform(0.12, 0.18))
    z_c = h - dome_h - 0.1
    asm.box(
        (-hx, -hy, 0.0), (hx, hy, plinth), pick(rng, ((200, 28, 34), (150, 148, 144)), variation=_VARIATION)
    )
    pw = 0.1
    for sx in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            x0, x1 = sorted((sx * bx, sx * (bx - pw)))
            y0, y1 = sorted((sy * by, sy * (by - pw)))
            asm.box((x0, y0, plinth), (x1, y1, z_c), red)
    asm.box((-hx, -hy, z_c), (hx, hy, z_c + 0.1), red)
    asm.add(_dome((0.0, 0.0, z_c + 0.1 - 0.001), (bx - 0.02, by - 0.02, dome_h + 0.001)), red)
    asm.box((-0.05, -0.05, h - 0.01), (0.05, 0.05, h - 0.002), red)
    z_glass0 = plinth + 0.25
    z_glass1 = z_c - 0.25
    header_c = (236, 236, 228)
    # the four sides: (axis normal, sign)
    for normal, s in (("y", 1.0), ("y", -1.0), ("x", 1.0), ("x", -1.0)):
        half = bx if normal == "y" else by
        face = (by if normal == "y" else bx) * s
        span0, span1 = -half + pw, half - pw

        wall = (normal, face, s)

        _wall_box(asm, wall, span0, span1, plinth, z_glass0, 0.0, 0.04, red)
        _wall_box(asm, wall, span0, span1, z_glass1, z_c, 0.0, 0.04, red)
        _wall_box(asm, wall, span0, span1, z_glass0, z_glass1, 0.03, 0.04, glass)
        for k in (1, 2):
            a = span0 + k * (span1 - span0) / 3
            _wall_box(asm, wall, a - 0.012, a + 0.012, z_glass0, z_glass1, 0.0, 0.03, red)
        for k in range(1, 8):
            z = z_glass0 + k * (z_glass1 - z_glass0) / 8
            _wall_box(asm, wall, span0, span1, z - 0.01, z + 0.01, 0.0, 0.03, red)
        _wall_box(asm, wall, span0 + 0.05, span1 - 0.05, z_c - 0.2, z_c - 0.06, -0.003, 0.0, header_c)
        _wall_box(asm, wall, span0 + 0.12, span1 - 0.12, z_c - 0.15, z_c - 0.11, -0.005, -0.003, (30, 30, 32))
        _wall_box(asm, wall, -0.05, 0.05, z_c + 0.015, z_c + 0.085, -0.005, 0.0, (214, 176, 80))
    asm.box((bx - pw - 0.07, by, 0.95), (bx - pw - 0.05, hy, 1.25), (196, 160, 80))
    return asm


def _glass_cabin(rng: np.random.Generator, size: Size) -> Assembly:
    """A modern telephone cabin: aluminium posts, glass walls over opaque kick panels, a glass door with
    a handle (or an open front), a branded roof, and the telephone on the back wall."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    frame = pick(rng, ((176, 180, 184), (120, 126, 134), (62, 66, 70)), variation=_VARIATION)
    brand = pick(rng, _BRAND_BOOTH, variation=_VARIATION)
    glass = pick(rng, "glass", variation=0.03)
    rt = float(rng.uniform(0.15, 0.25))
    inset = 0.03
    bx, by = hx - inset, hy - inset
    p = 0.05
    asm.box((-hx, -hy, h - rt), (hx, hy - 0.003, h - 0.02), brand)
    asm.box((-hx + 0.01, -hy + 0.01, h - 0.021), (hx - 0.01, hy - 0.01, h), frame)
    asm.box((-0.3 * w, hy - 0.003, h - 0.7 * rt), (0.3 * w, hy, h - 0.3 * rt), _WHITE)
    asm.box((-bx, -by, 0.0), (bx, by, 0.04), frame)
    for sx in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            x0, x1 = sorted((sx * bx, sx * (bx - p)))
            y0, y1 = sorted((sy * by, sy * (by - p)))
            asm.box((x0, y0, 0.0), (x1, y1, h - rt + 0.005), frame)
    kick = float(rng.uniform(0.5, 0.9))
    kick_c = shade(frame, 0.85)
    open_front = rng.uniform() < 0.3
    for normal, s in (("y", -1.0), ("x", 1.0), ("x", -1.0), ("y", 1.0)):
        if normal == "y" and s > 0 and open_front:
            continue
        half = bx if normal == "y" else by
        face = (by if normal == "y" else bx) * s
        a0, a1 = -half + p, half - p
        wall = (normal, face, s)
        if normal == "y" and s > 0:  # door: glass in a frame, with a handle bar
            _wall_box(asm, wall, a0, a1, 0.04, h - rt, 0.02, 0.03, frame)
            _wall_box(asm, wall, a0 + 0.06, a1 - 0.06, 0.12, h - rt - 0.08, 0.019, 0.031, glass)
            asm.box((a1 - 0.12, face - 0.02, 0.8), (a1 - 0.09, hy, 1.3), _ALUMINIUM)
        else:
            _wall_box(asm, wall, a0, a1, 0.04, kick, 0.02, 0.03, kick_c)
            _wall_box(asm, wall, a0, a1, kick, h - rt, 0.02, 0.03, glass)
            _wall_box(asm, wall, a0, a1, kick - 0.02, kick + 0.02, 0.018, 0.032, frame)
            if normal == "x":
                _wall_box(asm, wall, a0 + 0.02, a1 - 0.02, h - rt - 0.4, h - rt - 0.05, 0.018, 0.02, brand)
    # telephone on the back wall
    yb = -by + 0.03
    asm.box(
        (-0.14, yb, 1.05),
        (0.14, yb + 0.14, 1.55),
        pick(rng, ((60, 64, 68), (200, 202, 204)), variation=_VARIATION),
    )
    asm.box((-0.1, yb + 0.14, 1.3), (0.08, yb + 0.145, 1.48), (40, 60, 56))
    asm.box((-0.16, yb + 0.06, 1.2), (-0.13, yb + 0.2, 1.42), _DARK)
    asm.box((-0.3, yb, 0.95), (0.3, yb + 0.25, 0.98), frame)
    return asm


def _newspaper_box(rng: np.random.Generator, size: Size) -> Assembly:
    """A newspaper vending box: cabinet on four legs or a pedestal, window door showing the paper,
    pull handle, coin mechanism on top and a logo panel."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = pick(rng, "brand")
    leg_c = pick(rng, ((62, 66, 70), (28, 28, 30), (176, 180, 184)), variation=_VARIATION)
    leg_h = float(rng.uniform(0.12, 0.3))
    top_h = float(rng.uniform(0.1, 0.16))
    z_top = h - top_h
    front = hy - 0.03
    if rng.uniform() < 0.6:
        for x in (-hx + 0.02, hx - 0.05):
            for y in (-hy + 0.02, front - 0.05):
                asm.box((x, y, 0.0), (x + 0.03, y + 0.03, leg_h + 0.01), leg_c)
        for y in (-hy + 0.02, front - 0.05):
            asm.box((-hx + 0.02, y, 0.06), (hx - 0.02, y + 0.03, 0.09), leg_c)
    else:
        asm.box((-hx + 0.03, -hy + 0.03, 0.0), (hx - 0.03, front - 0.03, 0.02), leg_c)
        asm.box((-0.06, -0.06, 0.0), (0.06, 0.06, leg_h + 0.01), leg_c)
    asm.box((-hx + 0.003, -hy, leg_h), (hx - 0.003, front, z_top), body)
    # window door with the front page behind it
    z0, z1 = leg_h + 0.25 * (z_top - leg_h), z_top - 0.04
    door = shade(body, 0.8) if rng.uniform() < 0.5 else (236, 236, 232)
    asm.box((-hx + 0.02, front - 0.005, z0), (hx - 0.02, front + 0.012, z1), door)
    asm.box((-hx + 0.05, front + 0.011, z0 + 0.04), (hx - 0.05, front + 0.014, z1 - 0.04), (246, 244, 236))
    asm.box((-hx + 0.07, front + 0.014, z1 - 0.1), (hx - 0.07, front + 0.016, z1 - 0.06), (30, 30, 32))
    asm.box((-hx + 0.07, front + 0.014, z1 - 0.25), (-0.02, front + 0.016, z1 - 0.13), (120, 140, 160))
    for k in range(3):
        z = z1 - 0.14 - 0.04 * k
        asm.box((0.01, front + 0.014, z - 0.015), (hx - 0.07, front + 0.016, z), (150, 150, 154))
    asm.box((-0.35 * w, front + 0.012, z1 - 0.035), (0.35 * w, hy, z1 - 0.015), _ALUMINIUM)
    # logo panel under the door and on the sides
    logo = pick(rng, "brand")
    if z0 - leg_h > 0.1:
        asm.box((-hx + 0.03, front - 0.002, leg_h + 0.04), (hx - 0.03, front + 0.004, z0 - 0.03), logo)
    for s in (-1.0, 1.0):
        xa, xb = sorted((s * hx, s * (hx - 0.004)))
        asm.box((xa, -0.3 * d, 0.5 * (z0 + z1) - 0.08), (xb, 0.3 * d, 0.5 * (z0 + z1) + 0.08), logo)
    # coin mechanism on top
    coin = pick(rng, ((176, 180, 184), (62, 66, 70)), variation=_VARIATION)
    asm.box((-0.3 * w, 0.0, z_top - 0.002), (0.3 * w, front, h), coin)
    asm.box((-0.05, front, h - 0.07), (0.05, front + 0.005, h - 0.05), _DARK)
    asm.box((-0.3 * w, front - 0.002, h - top_h + 0.02), (-0.1 * w, front + 0.004, h - 0.02), (236, 236, 232))
    return asm


# ---------------------------------------------------------------------------------------------------
# catalogue

ASSETS: tuple[Asset, ...] = (
    # EN 40 / AASHTO lighting columns 4-10 m; bracket outreach 0.5-2.5 m; luminaires 0.3-0.6 m wide
    Asset(
        "street_lamp",
        (0.30, 0.35, 4.0),
        (0.60, 2.60, 9.0),
        "floor",
        None,
        0.0,
        "metal",
        _street_lamp,
        contexts=("street",),
    ),
    # post-mounted signals: 200 or 300 mm lenses, head 0.75-1.1 m tall, clearance under it >= 2.1-2.5 m
    Asset(
        "traffic_light",
        (0.30, 0.28, 2.8),
        (0.60, 0.50, 5.0),
        "floor",
        None,
        0.0,
        "metal",
        _traffic_light,
        contexts=("street",),
    ),
    # MUTCD R1-1 / Vienna convention: 0.6-0.9 m octagon, bottom 1.5-2.2 m above the ground
    Asset(
        "stop_sign",
        (0.60, 0.06, 2.1),
        (0.92, 0.10, 3.0),
        "floor",
        None,
        0.0,
        "metal",
        _stop_sign,
        contexts=("street",),
    ),
    # street name blades 0.6-1.1 m long, 150-230 mm high, mounted 2.1-3.5 m up
    Asset(
        "street_sign",
        (0.60, 0.45, 2.4),
        (1.10, 0.95, 3.6),
        "floor",
        None,
        0.0,
        "metal",
        _street_sign,
        contexts=("street",),
    ),
    # AWWA C502 dry-barrel hydrants stand 0.6-0.9 m; EN 14384 pillar hydrants up to about 1.1 m
    Asset(
        "fire_hydrant",
        (0.34, 0.28, 0.62),
        (0.52, 0.46, 1.10),
        "floor",
        None,
        0.9,
        "metal",
        _fire_hydrant,
        contexts=("street",),
    ),
    # bollards: 100-400 mm across, 0.6-1.2 m high (typically 0.9-1.0 m)
    Asset(
        "bollard",
        (0.12, 0.12, 0.60),
        (0.40, 0.40, 1.20),
        "floor",
        None,
        0.0,
        "metal",
        _bollard,
        contexts=("street",),
    ),
    # UK type A pillar box 0.55 m x 1.6 m; USPS collection box 0.51 W x 0.61 D x 1.24 H
    Asset(
        "post_box",
        (0.42, 0.42, 1.15),
        (0.65, 0.70, 1.65),
        "floor",
        None,
        0.6,
        "metal",
        _post_box,
        contexts=("street",),
    ),
    # single-space meter heads 0.2-0.3 m wide on 1.0-1.2 m posts; pay stations 0.35-0.5 m x 1.6-1.8 m
    Asset(
        "parking_meter",
        (0.20, 0.16, 1.20),
        (0.50, 0.35, 1.80),
        "floor",
        None,
        0.6,
        "metal",
        _parking_meter,
        contexts=("street",),
    ),
    # 2-4 bay shelters: 1.2-1.5 m bays, 1.2-2.0 m deep, 2.3-2.8 m high
    Asset(
        "bus_shelter",
        (2.40, 1.20, 2.30),
        (6.00, 2.00, 2.80),
        "floor",
        None,
        1.5,
        "glass",
        _bus_shelter,
        contexts=("transit", "street"),
    ),
    # bus stop flags 0.35-0.7 m (German H disc 450 mm) on 2.4-3.3 m poles
    Asset(
        "bus_stop_sign",
        (0.35, 0.10, 2.40),
        (0.70, 0.20, 3.30),
        "floor",
        None,
        0.5,
        "metal",
        _bus_stop_sign,
        contexts=("transit", "street"),
    ),
    # Sheffield stands: 0.7-0.9 m long, 0.75-0.95 m high, 0.75-1.0 m apart on rails of 1-4 m
    Asset(
        "bike_rack",
        (1.00, 0.50, 0.70),
        (4.20, 0.90, 0.95),
        "floor",
        None,
        1.0,
        "metal",
        _bike_rack,
        contexts=("street", "plaza", "park"),
    ),
    # street cabinets (feeder pillars, telecom cabinets): 0.6-1.6 m wide, 0.3-0.6 m deep, 0.9-1.6 m high
    Asset(
        "utility_box",
        (0.60, 0.30, 0.90),
        (1.60, 0.60, 1.60),
        "floor",
        None,
        0.9,
        "metal",
        _utility_box,
        contexts=("street",),
    ),
    # K6 kiosk 0.91 x 0.91 x 2.51 m; glass cabins about 1.0 x 1.0 x 2.3 m
    Asset(
        "phone_booth",
        (0.85, 0.85, 2.20),
        (1.15, 1.15, 2.60),
        "floor",
        None,
        0.8,
        "metal",
        _phone_booth,
        contexts=("street",),
    ),
    # newspaper racks (K-Jack and similar): about 0.41-0.53 W x 0.38-0.48 D x 0.9-1.15 H
    Asset(
        "newspaper_box",
        (0.40, 0.35, 0.85),
        (0.56, 0.50, 1.20),
        "floor",
        None,
        0.6,
        "metal",
        _newspaper_box,
        contexts=("street",),
    ),
)
