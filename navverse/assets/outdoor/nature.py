"""Nature and animals: deciduous tree, conifer tree, palm tree, street tree, birch tree, bush, hedge, flower
bed, boulder, tree stump, cat and dog.

Frame conventions of these categories
-------------------------------------
- Trees stand on their trunk base at the centre of the footprint; x and y are the crown (or frond)
  spread, z the height to the top of the crown. Plants and rocks have no front: their +y side is
  arbitrary, and they are modelled without one.
- The hedge runs along x (its long axis); y is its thickness.
- The street tree includes its tree pit grate and guard cage; its footprint is the larger of the crown
  and the grate.
- Animals face +y: the nose (or, for a sitting cat, the front paws) is at +y, the tail at -y; z is the
  height to the ear tips (or the top of the head for dogs with floppy ears).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

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
    revolve,
    rotate,
    torus,
    translate,
)
from navverse.assets.spec import Asset, Size

__all__ = ["ASSETS"]

# local palettes (sRGB) for what materials.py does not cover
_LEAF: tuple[RGB, ...] = ((62, 112, 44), (78, 128, 50), (52, 98, 46), (96, 138, 58), (70, 104, 40))
_AUTUMN: tuple[RGB, ...] = ((196, 150, 48), (208, 112, 40), (170, 70, 36), (214, 176, 70))
_BIRCH_LEAF: tuple[RGB, ...] = ((120, 160, 70), (140, 172, 78), (104, 150, 64), (150, 172, 84))
_CONIFER: tuple[RGB, ...] = ((34, 74, 44), (40, 84, 50), (28, 62, 42), (76, 110, 108), (48, 88, 56))
_FROND: tuple[RGB, ...] = ((76, 120, 52), (92, 130, 56), (64, 108, 58), (104, 128, 62))
_PALM_BARK: tuple[RGB, ...] = ((128, 112, 92), (112, 98, 80), (150, 132, 104), (96, 84, 70))
_BIRCH_BARK: tuple[RGB, ...] = ((236, 232, 222), (226, 224, 216), (242, 240, 232))
_HEDGE: tuple[RGB, ...] = ((48, 92, 42), (60, 104, 44), (36, 76, 40), (74, 112, 50), (104, 52, 48))
_FLOWERS: tuple[RGB, ...] = (
    (214, 40, 48),
    (240, 200, 40),
    (236, 120, 170),
    (246, 244, 236),
    (130, 80, 170),
    (240, 130, 40),
    (200, 50, 120),
    (100, 120, 210),
)
_BED_EDGE: dict[str, tuple[RGB, ...]] = {
    "wood": ((150, 110, 72), (122, 88, 60), (170, 140, 100)),
    "stone": ((178, 174, 166), (150, 146, 140), (196, 186, 166)),
    "steel": ((140, 74, 40), (120, 62, 36)),  # weathering (corten) steel
}
_ROCK: tuple[RGB, ...] = ((138, 136, 132), (112, 110, 108), (176, 164, 140), (84, 82, 82), (150, 120, 100))
_MOSS: tuple[RGB, ...] = ((92, 116, 48), (110, 128, 56), (74, 100, 46))
_MULCH: tuple[RGB, ...] = ((78, 56, 40), (64, 46, 34), (96, 70, 48))
_GUARD: tuple[RGB, ...] = ((34, 60, 44), (36, 36, 40), (92, 96, 102), (60, 44, 36))
_IRON: tuple[RGB, ...] = ((46, 44, 44), (62, 58, 56), (80, 70, 62))
_CAT_FUR: tuple[RGB, ...] = (
    (34, 32, 32),
    (234, 230, 222),
    (130, 130, 134),
    (206, 124, 58),
    (120, 96, 72),
    (220, 200, 164),
    (90, 84, 80),
)
_DOG_FUR: tuple[RGB, ...] = (
    (34, 30, 30),
    (206, 162, 92),
    (116, 74, 44),
    (236, 232, 222),
    (188, 146, 96),
    (142, 140, 144),
    (160, 96, 50),
)
_FUR_ACCENT: tuple[RGB, ...] = ((240, 238, 232), (226, 214, 190), (196, 150, 100))
_COLLAR: tuple[RGB, ...] = ((200, 40, 40), (40, 90, 180), (40, 140, 70), (230, 170, 30), (30, 30, 34))
_EYE: RGB = (30, 34, 24)
_NOSE_DOG: RGB = (26, 24, 24)
_NOSE_CAT: RGB = (210, 130, 130)


def _blob(
    rng: np.random.Generator,
    center: Sequence[float],
    radii: Sequence[float],
    *,
    segments: int = 12,
    rings: int = 6,
    jitter: float = 0.12,
) -> Solid:
    """An ellipsoid with radially jittered vertices (a lumpy clump of leaves or a rough stone).

    Vertices move along their ray from the centre, so the surface stays star-shaped and closed; the
    six axis-extreme vertices keep their place and no vertex leaves the ellipsoid's bounding box, so
    the clump spans exactly ``center ± radii``.
    """
    c, r = np.asarray(center, dtype=np.float64), np.asarray(radii, dtype=np.float64)
    vertices, faces = ellipsoid(c, r, segments=segments, rings=rings)
    unit = (vertices - c) / r
    peak = np.abs(unit).max(axis=1)
    low, high = 1.0 - jitter, np.minimum(1.0 + jitter, 1.0 / peak)
    factor = low + rng.uniform(0.0, 1.0, len(unit)) * (high - low)
    factor[peak > 1.0 - 1e-9] = 1.0
    return c + unit * r * factor[:, None], faces


def _tube(points: Sequence[Sequence[float]], radii: Sequence[float], *, sections: int = 8) -> list[Solid]:
    """A bent tube (tail, trunk, branch): a frustum per segment and a ball at every inner joint."""
    pts = [np.asarray(p, dtype=np.float64) for p in points]
    solids = [
        frustum(pts[i], pts[i + 1], radii[i], radii[i + 1], sections=sections) for i in range(len(pts) - 1)
    ]
    for i in range(1, len(pts) - 1):
        solids.append(ellipsoid(pts[i], (radii[i],) * 3, segments=8, rings=4))
    return solids


def _crown(
    asm: Assembly,
    rng: np.random.Generator,
    lo: Sequence[float],
    hi: Sequence[float],
    colors: Sequence[RGB],
    *,
    extra: int,
    scale: tuple[float, float],
    core: float = 0.65,
    segments: int = 12,
    rings: int = 6,
    jitter: float = 0.12,
) -> list[tuple[np.ndarray, np.ndarray]]:
    """Foliage clumps filling the box `lo`..`hi`; returns the clumps' ``(centre, radii)``.

    A core clump fills the middle, one clump touches each side and the top (so the crown spans the box
    exactly) and `extra` more lie inside the ellipsoid inscribed in the box. Clump radii are `scale`
    times the box's half extents (the vertical one capped so clumps of tall crowns stay roundish).
    """
    lo_, hi_ = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
    c, e = 0.5 * (lo_ + hi_), 0.5 * (hi_ - lo_)
    clump = np.array([e[0], e[1], min(e[2], 1.3 * max(e[0], e[1]))])
    clumps: list[tuple[np.ndarray, np.ndarray]] = []

    def add(center: np.ndarray, radii: np.ndarray, *, seg: int = segments, rng_: int = rings) -> None:
        radii = np.minimum(radii, e)
        center = np.clip(center, lo_ + radii, hi_ - radii)
        color = colors[int(rng.integers(len(colors)))]
        asm.add(_blob(rng, center, radii, segments=seg, rings=rng_, jitter=jitter), color)
        clumps.append((center, radii))

    add(c.copy(), core * e)
    for axis, sign in ((0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0), (2, 1.0)):
        r = clump * float(rng.uniform(*scale))
        center = c + rng.uniform(-0.3, 0.3, 3) * (e - r)
        center[axis] = c[axis] + sign * (e[axis] - r[axis])
        add(center, r, seg=12, rng_=6)
    for _ in range(extra):
        r = clump * float(rng.uniform(*scale))
        u = rng.normal(size=3)
        u *= float(rng.uniform(0.3, 1.0)) ** (1.0 / 3.0) / max(float(np.linalg.norm(u)), 1e-9)
        add(c + u * (e - r), r)
    return clumps


# --------------------------------------------------------------------------------------------- trees


def _root_flare(asm: Assembly, radius: float, height: float, color: RGB) -> None:
    """The widened foot of a trunk standing at the origin."""
    asm.add(frustum((0, 0, 0), (0, 0, height), 1.5 * radius, radius, sections=12), color)


def _limbs(
    asm: Assembly, start: Sequence[float], ends: Sequence[np.ndarray], r0: float, color: RGB, reach: float
) -> None:
    """Tapering limbs from `start` part of the way (`reach`) towards each end point."""
    p0 = np.asarray(start, dtype=np.float64)
    for end in ends:
        p1 = p0 + reach * (end - p0)
        if np.linalg.norm(p1 - p0) > 1e-3:
            asm.add(frustum(p0, p1, r0, 0.45 * r0, sections=8), color)


def _deciduous_tree(rng: np.random.Generator, size: Size) -> Assembly:
    """A broadleaf tree: flared trunk, a few limbs and a crown of overlapping leaf clumps."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    bark = pick(rng, "bark")
    palette = _AUTUMN if rng.uniform() < 0.15 else _LEAF
    greens = [pick(rng, palette) for _ in range(3)]
    crown_base = h * float(rng.uniform(0.25, 0.45))
    radius = min(float(np.clip(0.022 * h, 0.1, 0.35) * rng.uniform(0.85, 1.15)), 0.15 * min(w, d))
    fork = crown_base + 0.2 * (h - crown_base)
    _root_flare(asm, radius, min(0.4, 0.1 * h), bark)
    asm.add(frustum((0, 0, 0.05), (0, 0, fork), radius, 0.7 * radius, sections=12), bark)
    style = int(rng.integers(3))  # round, spreading (big flat clumps), loose (many small clumps)
    scale = ((0.35, 0.5), (0.45, 0.6), (0.25, 0.38))[style]
    extra = (int(rng.integers(4, 7)), int(rng.integers(3, 5)), int(rng.integers(7, 10)))[style]
    clumps = _crown(asm, rng, (-hx, -hy, crown_base), (hx, hy, h), greens, extra=extra, scale=scale)
    _limbs(asm, (0.0, 0.0, fork - 0.1 * radius), [c for c, _ in clumps[1:6]], 0.55 * radius, bark, 0.7)
    return asm


def _cone_tier(rx: float, ry: float, z0: float, height: float, droop: float) -> Solid:
    """One tier of a conifer: a cone with a hollow underside and a concave (drooping) skirt."""
    profile = [
        (0.0, z0 + 0.35 * height),
        (1.0, z0),
        (0.62 - 0.2 * droop, z0 + 0.28 * height),
        (0.32 - 0.1 * droop, z0 + 0.62 * height),
        (0.0, z0 + height),
    ]
    vertices, faces = revolve(profile, sections=16)
    return vertices * np.array([rx, ry, 1.0]), faces


def _conifer_tree(rng: np.random.Generator, size: Size) -> Assembly:
    """A spruce or fir: a short visible trunk under stacked, drooping cone tiers up to a pointed top."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    bark = pick(rng, "bark")
    needle = pick(rng, _CONIFER)
    needles = [needle, shade(needle, float(rng.uniform(0.84, 0.92)))]
    skirt = h * float(rng.uniform(0.04, 0.16))  # bottom of the lowest tier
    tiers = int(rng.integers(4, 8))
    span = h - skirt
    tier_h = span * float(rng.uniform(0.28, 0.4))
    step = (span - tier_h) / (tiers - 1)
    droop = float(rng.uniform(0.0, 1.0))
    radius = min(float(np.clip(0.014 * h, 0.06, 0.25)), 0.15 * min(w, d))
    _root_flare(asm, radius, min(0.3, 0.05 * h), bark)
    asm.add(frustum((0, 0, 0.02), (0, 0, 0.7 * h), radius, 0.4 * radius, sections=12), bark)
    for k in range(tiers):
        z0 = skirt + k * step
        f = 1.0 if k == 0 else (h - z0) / span * float(rng.uniform(0.92, 1.02))
        asm.add(_cone_tier(f * hx, f * hy, z0, tier_h, droop), needles[k % 2])
    return asm


def _frond(
    base: np.ndarray, azimuth: float, reach: float, width: float, droop: float
) -> tuple[list[Solid], float]:
    """A pinnate palm frond from `base`: three flat blade pieces rising, arching and drooping.

    Returns the pieces and the highest point above the base. The horizontal reach of the tip from the
    base is exactly `reach`, and the blade's cross-sections are perpendicular to the frond's azimuth.
    """
    elevations = np.radians([35.0, 5.0, -25.0 - 35.0 * droop])
    fractions = np.array([0.3, 0.4, 0.3])
    length = reach / float(np.sum(fractions * np.cos(elevations)))
    direction = np.array([math.cos(azimuth), math.sin(azimuth), 0.0])
    side = np.array([-math.sin(azimuth), math.cos(azimuth), 0.0])
    up = np.array([0.0, 0.0, 1.0])
    nodes = [base]
    for f, e in zip(fractions, elevations, strict=True):
        step = f * length * (math.cos(e) * direction + math.sin(e) * up)
        nodes.append(nodes[-1] + step)
    nodes[-1] = base + reach * direction + (nodes[-1] - base)[2] * up  # exact reach despite rounding
    widths = (0.15 * width, width, 0.8 * width, 0.04 * width)
    thick = 0.03
    pieces = []
    for i in range(3):
        pts = [
            nodes[j] + s * 0.5 * widths[j] * side + t * 0.5 * thick * up
            for j in (i, i + 1)
            for s in (-1, 1)
            for t in (-1, 1)
        ]
        pieces.append(hull(pts))
    rise = max(float(n[2] - base[2]) for n in nodes) + 0.5 * thick
    return pieces, rise


def _palm_tree(rng: np.random.Generator, size: Size) -> Assembly:
    """A palm: a curved, ringed trunk of tilted segments under a crown of arching pinnate fronds."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    trunk_color = pick(rng, _PALM_BARK)
    ring_color = shade(trunk_color, 0.82)
    greens = [pick(rng, _FROND) for _ in range(2)]
    radius = float(np.clip(0.022 * h, 0.14, 0.25) * rng.uniform(0.9, 1.1))
    lean = rng.uniform(-0.12, 0.12, 2) * np.array([w, d])
    count = int(rng.integers(9, 15))
    droop = float(rng.uniform(0.0, 1.0))
    frond_w = float(rng.uniform(0.35, 0.6))
    # fronds relative to a crown centre at height 0; the crown height follows from their rise
    top = np.array([lean[0], lean[1], 0.0])
    azimuths = [0.0, 0.5 * math.pi, math.pi, 1.5 * math.pi]
    azimuths += [float(a) for a in rng.uniform(0.0, 2.0 * math.pi, count - 4)]
    fronds: list[tuple[list[Solid], RGB]] = []
    rise = 0.0
    for k, a in enumerate(azimuths):
        direction = np.array([math.cos(a), math.sin(a)])
        limits = []
        for axis, half in ((0, hx), (1, hy)):
            if abs(direction[axis]) > 1e-9:
                face = half if direction[axis] > 0 else -half
                limits.append((face - top[axis]) / direction[axis])
        reach = min(limits) * (1.0 if k < 4 else float(rng.uniform(0.7, 0.92)))
        for _ in range(8):  # shorten a slanted frond until its wide blade stays inside the footprint
            pieces, frond_rise = _frond(top, a, reach, frond_w, droop)
            pts = np.concatenate([p[0] for p in pieces])
            if k < 4 or (np.abs(pts[:, 0]).max() <= hx and np.abs(pts[:, 1]).max() <= hy):
                break
            reach *= 0.9
        rise = max(rise, frond_rise)
        fronds.append((pieces, greens[k % 2]))
    crown_z = h - max(rise + 0.15, 0.8)
    # trunk: a quadratic curve from the base (vertical there) to the crown, in tilted ringed segments
    segments = 8
    trunk_top = crown_z - 0.25
    ts = np.linspace(0.0, 1.0, segments + 1)
    foot = 0.4  # a vertical, flared foot; the curved trunk rises from inside it
    pts = np.stack([lean[0] * ts**2, lean[1] * ts**2, 0.5 * foot + (trunk_top - 0.5 * foot) * ts], axis=1)
    radii = radius * (1.0 - 0.25 * ts)
    asm.add(frustum((0, 0, 0), (0, 0, foot), 1.4 * radius, radius, sections=12), trunk_color)
    for i in range(segments):
        asm.add(frustum(pts[i], pts[i + 1], radii[i], radii[i + 1], sections=12), trunk_color)
    for i in range(1, segments + 1):
        tangent = pts[i] - pts[i - 1]
        tangent /= np.linalg.norm(tangent)
        ring = frustum(
            pts[i] - 0.06 * tangent, pts[i] + 0.03 * tangent, radii[i] + 0.02, radii[i], sections=12
        )
        asm.add(ring, ring_color)
    crown = np.array([lean[0], lean[1], crown_z])
    asm.add(frustum(pts[-1], crown, radii[-1] + 0.02, radii[-1] + 0.06, sections=12), shade(greens[0], 0.7))
    asm.add(ellipsoid(crown, (0.3, 0.3, 0.22), segments=12, rings=6), shade(trunk_color, 0.9))
    for pieces, color in fronds:
        asm.add_all((translate(p, (0.0, 0.0, crown_z)) for p in pieces), color)
    asm.add(frustum(crown, (lean[0], lean[1], h), 0.06, 0.01, sections=8), greens[0])  # the new spear
    if rng.uniform() < 0.45:  # a bunch of coconuts / dates under the crown
        nut = pick(rng, ((110, 80, 40), (150, 120, 50), (200, 140, 50)))
        for k in range(int(rng.integers(3, 7))):
            a = 2.0 * math.pi * k / 6 + float(rng.uniform(-0.3, 0.3))
            c = crown + np.array([0.28 * math.cos(a), 0.28 * math.sin(a), -0.25])
            asm.add(ellipsoid(c, (0.1, 0.1, 0.12), segments=8, rings=4), nut)
    return asm


def _tree_grate(asm: Assembly, side: float, hole: float, color: RGB, soil: RGB) -> None:
    """A square cast-iron tree pit grate with slotted bands around a round trunk opening, and its soil."""
    t = 0.03
    half = 0.5 * side
    plate = box((-half, -half, 0.0), (half, half, t))
    cutters = [cylinder((0, 0, -0.01), (0, 0, t + 0.01), hole, sections=16)]
    slot = box((-0.065, -0.011, -0.01), (0.065, 0.011, t + 0.01))  # radial slots in rings
    for ring, count in ((hole + 0.12, 16), (hole + 0.3, 24)):
        if ring + 0.1 > half:
            break
        for k in range(count):
            a = 2.0 * math.pi * (k + 0.5) / count
            cutters.append(rotate(translate(slot, (ring, 0.0, 0.0)), "z", a))
    asm.add(difference(plate, *cutters), color)
    asm.add(cylinder((0, 0, 0.0), (0, 0, 0.5 * t), hole, sections=16), soil)


def _street_tree(rng: np.random.Generator, size: Size) -> Assembly:
    """A young street tree in a square pit grate, protected by a tree guard cage of bars."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    bark = pick(rng, "bark")
    greens = [pick(rng, _LEAF) for _ in range(3)]
    side = min(float(rng.uniform(1.2, 1.5)), w, d)  # grates are 1.2 m (4 ft) or 1.5 m square
    hole = float(rng.uniform(0.2, 0.3))
    _tree_grate(asm, side, hole, pick(rng, _IRON), pick(rng, _MULCH))
    radius = float(rng.uniform(0.05, 0.09))
    crown_base = min(float(rng.uniform(2.0, 2.6)), 0.55 * h)  # clearance over the sidewalk
    fork = crown_base + 0.25 * (h - crown_base)
    asm.add(frustum((0, 0, 0.0), (0, 0, fork), 1.2 * radius, 0.6 * radius, sections=12), bark)
    clumps = _crown(
        asm,
        rng,
        (-hx, -hy, crown_base),
        (hx, hy, h),
        greens,
        extra=int(rng.integers(3, 6)),
        scale=(0.35, 0.5),
        segments=8,
        rings=4,
    )
    _limbs(asm, (0.0, 0.0, fork), [c for c, _ in clumps[1:5]], 0.6 * radius, bark, 0.6)
    guard = pick(rng, _GUARD)
    cage_r = min(float(rng.uniform(0.22, 0.32)), 0.5 * side - 0.05)
    cage_h = float(rng.uniform(1.3, 1.8))
    if rng.uniform() < 0.5:  # round cage: vertical bars held by hoops
        n = int(rng.integers(5, 9))
        for k in range(n):
            a = 2.0 * math.pi * k / n
            p = (cage_r * math.cos(a), cage_r * math.sin(a))
            asm.add(cylinder((p[0], p[1], 0.0), (p[0], p[1], cage_h), 0.012, sections=8), guard)
        for z in (0.35 * cage_h, cage_h - 0.04):
            asm.add(torus((0, 0, z), cage_r, 0.012, sections=16, tube=4), guard)
    else:  # square cage: corner posts, top and middle rails and thin infill bars
        c = cage_r
        for x, y in ((-c, -c), (c, -c), (c, c), (-c, c)):
            asm.box((x - 0.02, y - 0.02, 0.0), (x + 0.02, y + 0.02, cage_h), guard)
        for z in (0.3 * cage_h, cage_h - 0.03):
            for sign in (-1.0, 1.0):
                asm.box((-c, sign * c - 0.012, z - 0.015), (c, sign * c + 0.012, z + 0.015), guard)
                asm.box((sign * c - 0.012, -c, z - 0.015), (sign * c + 0.012, c, z + 0.015), guard)
        for v in np.linspace(-c, c, 5)[1:-1]:
            for sign in (-1.0, 1.0):
                asm.box(
                    (v - 0.006, sign * c - 0.006, 0.3 * cage_h), (v + 0.006, sign * c + 0.006, cage_h), guard
                )
                asm.box(
                    (sign * c - 0.006, v - 0.006, 0.3 * cage_h), (sign * c + 0.006, v + 0.006, cage_h), guard
                )
    return asm


def _birch_tree(rng: np.random.Generator, size: Size) -> Assembly:
    """A birch: one to three slim white stems with dark marks, thin branches and an airy light crown."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    white = pick(rng, _BIRCH_BARK, variation=0.03)
    dark = (44, 42, 40)
    greens = [pick(rng, _BIRCH_LEAF) for _ in range(3)]
    crown_base = h * float(rng.uniform(0.3, 0.45))
    stems = 1 if rng.uniform() < 0.6 else int(rng.integers(2, 4))
    radius = float(np.clip(0.011 * h, 0.06, 0.16)) * (1.0 if stems == 1 else 0.75)
    top_z = crown_base + 0.6 * (h - crown_base)
    tops = []
    for k in range(stems):
        a = 2.0 * math.pi * k / stems + float(rng.uniform(-0.4, 0.4))
        spread = 0.0 if stems == 1 else 0.12
        lean = 0.0 if stems == 1 else float(rng.uniform(0.15, 0.35)) * min(hx, hy)
        base = np.array([spread * math.cos(a), spread * math.sin(a), 0.03 * h])
        mid = np.array([(spread + 0.4 * lean) * math.cos(a), (spread + 0.4 * lean) * math.sin(a), crown_base])
        top = np.array([(spread + lean) * math.cos(a), (spread + lean) * math.sin(a), top_z])
        asm.add(frustum(base, mid, radius, 0.8 * radius, sections=12), white)
        asm.add(frustum(mid, top, 0.8 * radius, 0.3 * radius, sections=12), white)
        foot = float(rng.uniform(0.03, 0.07)) * h  # old birches are dark and fissured at the foot
        asm.add(frustum((base[0], base[1], 0.0), (base[0], base[1], foot), 1.2 * radius, 1.03 * radius), dark)
        for _ in range(int(rng.integers(10, 17))):  # dark horizontal lenticel marks on the white bark
            f = float(rng.uniform(0.08, 0.95))
            p = base + f * (mid - base)
            r = radius * (1.0 - 0.2 * f)
            b = float(rng.uniform(0.0, 2.0 * math.pi))
            tangent = np.array([-math.sin(b), math.cos(b), 0.0])
            centre = p + r * np.array([math.cos(b), math.sin(b), 0.0])
            half = float(rng.uniform(0.4, 0.8)) * r
            height = float(rng.uniform(0.015, 0.035))
            asm.add(bar(centre - half * tangent, centre + half * tangent, (0.015, 0.015, height)), dark)
        tops.append(top)
    clumps = _crown(
        asm,
        rng,
        (-hx, -hy, crown_base),
        (hx, hy, h),
        greens,
        extra=int(rng.integers(7, 11)),
        scale=(0.2, 0.32),
        core=0.35,
        segments=8,
        rings=4,
        jitter=0.18,
    )
    for i, (c, _) in enumerate(clumps[1:]):
        start = tops[i % stems] * np.array([1.0, 1.0, float(rng.uniform(0.75, 1.0))])
        asm.add(frustum(start, start + 0.85 * (c - start), 0.3 * radius, 0.1 * radius, sections=6), white)
    return asm


# ------------------------------------------------------------------------------- plants and rocks


def _bush(rng: np.random.Generator, size: Size) -> Assembly:
    """A shrub of clumped leafy ellipsoids on a mulch patch, sometimes in flower."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    greens = [pick(rng, _LEAF) for _ in range(3)]
    trimmed = rng.uniform() < 0.3
    asm.add(
        frustum((0, 0, 0), (0, 0, 0.02), (0.75 * hx, 0.75 * hy), (0.7 * hx, 0.7 * hy), sections=16),
        pick(rng, _MULCH),
    )
    skirt = int(rng.integers(3, 6))
    for k in range(skirt):  # clumps resting on the ground, so the shrub sits on its base
        a = 2.0 * math.pi * (k + float(rng.uniform(-0.2, 0.2))) / skirt
        s = float(rng.uniform(0.35, 0.5))
        r = np.array([s * hx, s * hy, min(s * max(hx, hy), 0.35 * h)])
        c = np.array([0.5 * hx * math.cos(a), 0.5 * hy * math.sin(a), r[2]])
        c[:2] = np.clip(c[:2], [-hx + r[0], -hy + r[1]], [hx - r[0], hy - r[1]])
        asm.add(_blob(rng, c, r, segments=8, rings=4, jitter=0.03 if trimmed else 0.14), greens[k % 3])
    clumps = _crown(
        asm,
        rng,
        (-hx, -hy, 0.0),
        (hx, hy, h),
        greens,
        extra=int(rng.integers(1, 3)) if trimmed else int(rng.integers(4, 8)),
        scale=(0.6, 0.75) if trimmed else (0.4, 0.6),
        core=0.8 if trimmed else 0.7,
        segments=12,
        rings=6,
        jitter=0.03 if trimmed else 0.14,
    )
    if rng.uniform() < 0.45:  # blossoms on the clumps' upper sides
        flower = pick(rng, _FLOWERS)
        r = 0.035 * float(np.clip(min(w, d, h), 0.5, 2.0)) + 0.02
        for k in range(int(rng.integers(8, 16))):
            c, radii = clumps[1 + k % (len(clumps) - 1)]
            u = rng.normal(size=3)
            u[2] = abs(u[2]) + 0.3
            p = c + 0.95 * radii * u / np.linalg.norm(u)
            lo = np.array([-hx + r, -hy + r, r])
            hi = np.array([hx - r, hy - r, h - r])
            asm.add(ellipsoid(np.clip(p, lo, hi), (r, r, 0.7 * r), segments=8, rings=4), flower)
    return asm


def _arc(
    cy: float, cz: float, ry: float, rz: float, a0: float, a1: float, n: int
) -> list[tuple[float, float]]:
    """Points of an elliptic arc in the (y, z) plane from angle `a0` to `a1`."""
    return [(cy + ry * math.cos(a), cz + rz * math.sin(a)) for a in np.linspace(a0, a1, n)]


def _hedge(rng: np.random.Generator, size: Size) -> Assembly:
    """A trimmed hedge along x: a box-like body with a flat, rounded or battered top and leafy bulges."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    color = pick(rng, _HEDGE)
    m = float(np.clip(0.1 * min(d, h), 0.04, 0.08))  # depth of the leafy bulges on the trimmed faces
    a, top = hy - m, h - m
    style = int(rng.integers(3))
    if style == 0:  # flat top with rounded edges
        rc = min(0.1, 0.4 * a)
        pts = [(-a, 0.0), (a, 0.0), *_arc(a - rc, top - rc, rc, rc, 0.0, 0.5 * math.pi, 4)]
        pts += _arc(-a + rc, top - rc, rc, rc, 0.5 * math.pi, math.pi, 4)
        vertical, top_half = top - rc, a - rc
    elif style == 1:  # rounded top
        rz = min(a, 0.5 * top)
        pts = [(-a, 0.0), (a, 0.0), *_arc(0.0, top - rz, a, rz, 0.0, math.pi, 9)]
        vertical, top_half = top - rz, 0.4 * a
    else:  # battered: narrower at the top, like a properly trimmed hedge
        vertical = 0.4 * top
        at, rc = 0.8 * a, min(0.08, 0.3 * a)
        pts = [(-a, 0.0), (a, 0.0), (a, vertical), *_arc(at - rc, top - rc, rc, rc, 0.0, 0.5 * math.pi, 3)]
        pts += [*_arc(-at + rc, top - rc, rc, rc, 0.5 * math.pi, math.pi, 3), (-a, vertical)]
        top_half = at - rc

    def crest(y: float) -> float:
        """Height of the body's top surface at `y` within the top's middle part."""
        if style != 1:
            return top
        rz = top - vertical
        return vertical + rz * math.sqrt(max(0.0, 1.0 - (y / a) ** 2))

    asm.add(
        extrude_along(np.array(pts), -hx, hx, axis="x"), shade(color, 0.85)
    )  # the shaded inside of the foliage
    n_side = int(np.clip(round(1.6 * w * max(h, 0.8) / 0.5), 3, 14))
    n_top = int(np.clip(round(1.6 * w / 0.6), 2, 9))
    for k in range(2 * n_side + n_top):
        rx = float(rng.uniform(0.12, 0.3))
        x = float(rng.uniform(-hx + rx, hx - rx))
        tone = shade(color, float(rng.uniform(0.92, 1.15)))
        if k < 2 * n_side:  # bulges on the vertical parts of the long sides reach the full depth
            sign = 1.0 if k % 2 == 0 else -1.0
            rz = min(float(rng.uniform(0.1, 0.22)), 0.45 * top)
            z = float(rng.uniform(rz, max(rz, min(vertical, h - rz))))
            asm.add(_blob(rng, (x, sign * a, z), (rx, m, rz), segments=8, rings=4, jitter=0.2), tone)
        else:  # bulges on the top; the first sits on the crest and reaches the full height
            ry = min(float(rng.uniform(0.1, 0.25)), top_half)
            y = 0.0 if k == 2 * n_side else float(rng.uniform(-1.0, 1.0)) * (top_half - ry)
            asm.add(_blob(rng, (x, y, crest(y)), (rx, ry, m), segments=8, rings=4, jitter=0.2), tone)
    return asm


def _flower_bed(rng: np.random.Generator, size: Size) -> Assembly:
    """A raised bed edged with timber, stone or steel, filled with soil and clumps of flowering plants."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    edge = ("wood", "stone", "steel")[int(rng.integers(3))]
    edge_color = pick(rng, _BED_EDGE[edge])
    rim = min(float(rng.uniform(0.18, 0.45)), h - 0.12)
    t = {"wood": 0.045, "stone": float(rng.uniform(0.1, 0.15)), "steel": 0.012}[edge]
    if edge == "stone":  # block wall under a coping that overhangs by 2 cm
        asm.box((-hx + 0.02, -hy + 0.02, 0.0), (hx - 0.02, -hy + t, rim - 0.05), edge_color)
        asm.box((-hx + 0.02, hy - t, 0.0), (hx - 0.02, hy - 0.02, rim - 0.05), edge_color)
        asm.box((-hx + 0.02, -hy + t, 0.0), (-hx + t, hy - t, rim - 0.05), edge_color)
        asm.box((hx - t, -hy + t, 0.0), (hx - 0.02, hy - t, rim - 0.05), edge_color)
        cap = shade(edge_color, 1.1)
        asm.box((-hx, -hy, rim - 0.05), (hx, -hy + t + 0.02, rim), cap)
        asm.box((-hx, hy - t - 0.02, rim - 0.05), (hx, hy, rim), cap)
        asm.box((-hx, -hy + t + 0.02, rim - 0.05), (-hx + t + 0.02, hy - t - 0.02, rim), cap)
        asm.box((hx - t - 0.02, -hy + t + 0.02, rim - 0.05), (hx, hy - t - 0.02, rim), cap)
        t += 0.02
    else:
        asm.box((-hx, -hy, 0.0), (hx, -hy + t, rim), edge_color)
        asm.box((-hx, hy - t, 0.0), (hx, hy, rim), edge_color)
        asm.box((-hx, -hy + t, 0.0), (-hx + t, hy - t, rim), edge_color)
        asm.box((hx - t, -hy + t, 0.0), (hx, hy - t, rim), edge_color)
        if edge == "wood":  # corner posts standing a little proud of the boards
            post = shade(edge_color, 0.85)
            for x, y in ((-hx, -hy), (hx - 0.07, -hy), (hx - 0.07, hy - 0.07), (-hx, hy - 0.07)):
                asm.box((x, y, 0.0), (x + 0.07, y + 0.07, rim + 0.03), post)
    soil_top = rim - 0.04
    asm.box((-hx + t, -hy + t, 0.0), (hx - t, hy - t, soil_top), pick(rng, "soil"))
    inner_w, inner_d = w - 2 * t - 0.04, d - 2 * t - 0.04
    spacing = max(0.22, math.sqrt(inner_w * inner_d / 22.0))
    nx, ny = max(1, int(inner_w / spacing)), max(1, int(inner_d / spacing))
    cw, cd = inner_w / nx, inner_d / ny
    spikes = rng.uniform() < 0.3  # lavender / salvia spikes instead of flat flower heads
    scheme = int(rng.integers(3))  # 0 one colour per row, 1 random mix, 2 two-colour checkerboard
    colors = [pick(rng, _FLOWERS) for _ in range(3)]
    leaf = pick(rng, _LEAF)
    tallest = int(rng.integers(nx * ny))
    grow = h - soil_top  # room for the plants above the soil
    for i in range(nx):
        for j in range(ny):
            rx, ry = 0.5 * cw * float(rng.uniform(0.8, 1.0)), 0.5 * cd * float(rng.uniform(0.8, 1.0))
            cx = -0.5 * inner_w + (i + 0.5) * cw + float(rng.uniform(-0.12, 0.12)) * cw
            cy = -0.5 * inner_d + (j + 0.5) * cd + float(rng.uniform(-0.12, 0.12)) * cd
            cx = float(np.clip(cx, -0.5 * inner_w + rx, 0.5 * inner_w - rx))
            cy = float(np.clip(cy, -0.5 * inner_d + ry, 0.5 * inner_d - ry))
            color = (colors[j % 3], colors[int(rng.integers(3))], colors[(i + j) % 2])[scheme]
            plant_h = grow if i * ny + j == tallest else grow * float(rng.uniform(0.6, 0.95))
            mound = min(0.75 * plant_h, soil_top - 0.01)
            asm.add(
                _blob(rng, (cx, cy, soil_top), (rx, ry, mound), segments=8, rings=4, jitter=0.15),
                shade(leaf, float(rng.uniform(0.9, 1.1))),
            )
            top = soil_top + plant_h
            if spikes:
                asm.add(
                    frustum((cx, cy, top - 0.4 * plant_h), (cx, cy, top), 0.3 * rx, 0.005, sections=8), color
                )
            else:
                rz = min(0.05, 0.3 * plant_h)
                head = (0.65 * rx, 0.65 * ry, rz)
                asm.add(ellipsoid((cx, cy, top - rz), head, segments=8, rings=4), color)
    return asm


def _rock_points(rng: np.random.Generator, count: int, roughness: float) -> np.ndarray:
    """Jittered points around a unit sphere with a flattened base."""
    dirs = rng.normal(size=(count, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    pts = dirs * rng.uniform(1.0 - roughness, 1.0, (count, 1))
    pts[:, 2] = np.maximum(pts[:, 2], -float(rng.uniform(0.3, 0.5)))
    return pts


def _fit_points(pts: np.ndarray, lo: Sequence[float], hi: Sequence[float]) -> np.ndarray:
    """Map a point cloud's bounding box onto the box `lo`..`hi` (the rock is designed to fill it)."""
    p_lo, p_hi = pts.min(axis=0), pts.max(axis=0)
    return np.asarray(lo) + (pts - p_lo) / (p_hi - p_lo) * (np.asarray(hi) - np.asarray(lo))


def _boulder(rng: np.random.Generator, size: Size) -> Assembly:
    """A boulder: an irregular hull of jittered points (sometimes two lobes), pebbles and a moss patch."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    stone = pick(rng, _ROCK)
    angular = rng.uniform() < 0.5
    count, rough = (int(rng.integers(12, 17)), 0.35) if angular else (int(rng.integers(20, 30)), 0.15)
    if rng.uniform() < 0.35:  # two fused lobes, one lower
        a = hull(_fit_points(_rock_points(rng, count, rough), (-hx, -hy, 0.0), (0.4 * hx, 0.85 * hy, h)))
        low = float(rng.uniform(0.55, 0.8)) * h
        b = hull(_fit_points(_rock_points(rng, count, rough), (-0.35 * hx, -0.85 * hy, 0.0), (hx, hy, low)))
        asm.add(a, stone)
        asm.add(b, shade(stone, 0.94))
        main = a
    else:
        main = hull(_fit_points(_rock_points(rng, count, rough), (-hx, -hy, 0.0), (hx, hy, h)))
        asm.add(main, stone)
    for _ in range(int(rng.integers(2, 5))):  # pebbles broken off, lying at the foot
        r = float(rng.uniform(0.07, 0.14)) * min(w, d)
        sx, sy = rng.choice([-1.0, 1.0], 2)
        c = np.array([sx * (0.72 * hx), sy * (0.72 * hy)])
        c = np.clip(c + rng.uniform(-0.1, 0.1, 2) * np.array([hx, hy]), [-hx + r, -hy + r], [hx - r, hy - r])
        hz = min(0.7 * r, 0.3 * h)
        asm.add(
            hull(
                _fit_points(_rock_points(rng, 12, 0.2), (c[0] - r, c[1] - r, 0.0), (c[0] + r, c[1] + r, hz))
            ),
            shade(stone, float(rng.uniform(0.85, 1.1))),
        )
    if rng.uniform() < 0.5:  # moss on the upper faces: the top of the rock, thickened a little outwards
        v = main[0]
        centre = v.mean(axis=0)
        cap = v[v[:, 2] > v[:, 2].max() - 0.3 * h]
        cap = centre + (cap - centre) * 1.02
        pts = np.concatenate([cap, cap - (0.0, 0.0, 0.12 * h)])
        pts = np.clip(pts, (-hx, -hy, 0.0), (hx, hy, h))
        if len(cap) >= 3:
            asm.add(hull(pts), pick(rng, _MOSS))
    return asm


def _tree_stump(rng: np.random.Generator, size: Size) -> Assembly:
    """A felled tree's stump: a rough bark cylinder with root flares and a sawn or broken top."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    bark = pick(rng, "bark")
    r = min(hx, hy) * float(rng.uniform(0.5, 0.7))
    sawn = rng.uniform() < 0.65
    body_top = h - (0.01 if sawn else min(0.35 * h, 0.6 * r))
    body = frustum((0, 0, 0), (0, 0, body_top), 1.12 * r, r, sections=14)
    v = body[0].copy()
    ring = v[:28]
    ring[:, :2] *= rng.uniform(0.93, 1.03, (28, 1))  # rough, not quite round
    v[:28] = ring
    asm.add((v, body[1]), bark)
    roots = [0.0, 0.5 * math.pi, math.pi, 1.5 * math.pi]
    roots += [float(a) for a in rng.uniform(0.0, 2.0 * math.pi, int(rng.integers(1, 4)))]
    root_z = min(0.45 * body_top, 0.9 * r)
    for k, a in enumerate(roots):  # buttress flares: wedges from the trunk's foot down to the ground
        direction = np.array([math.cos(a), math.sin(a), 0.0])
        side = np.array([-math.sin(a), math.cos(a), 0.0])
        if k < 4:  # the four axis roots reach the footprint's edges
            end = np.array([math.cos(a) * hx, math.sin(a) * hy, 0.0]).round(12)
        else:
            end = float(rng.uniform(0.6, 0.85)) * np.array([hx * math.cos(a), hy * math.sin(a), 0.0])
        start = 0.6 * r * direction
        t0, t1 = float(rng.uniform(0.4, 0.6)) * r, 0.15 * r
        pts = [start + s * 0.5 * t0 * side + (0, 0, z) for s in (-1, 1) for z in (0.0, root_z)]
        pts += [end + s * 0.5 * t1 * side for s in (-1, 1)]
        pts.append(end - 0.3 * t1 * direction + (0, 0, 0.6 * t1))
        asm.add(hull(pts), shade(bark, 0.92))
    if sawn:  # a pale cut face with a darker heartwood, slightly proud of the bark
        wood = pick(rng, "light_wood") if rng.uniform() < 0.6 else (150, 146, 136)  # fresh or weathered
        asm.add(cylinder((0, 0, body_top - 0.01), (0, 0, h - 0.003), 0.94 * r, sections=14), wood)
        asm.add(cylinder((0, 0, h - 0.01), (0, 0, h), 0.45 * r, sections=14), shade(wood, 0.8))
    else:  # splintered: jagged spikes standing on the rim, the tallest reaching the top
        wood = pick(rng, "light_wood")
        for k in range(int(rng.integers(4, 7))):
            a = float(rng.uniform(0.0, 2.0 * math.pi))
            tip_z = h if k == 0 else body_top + float(rng.uniform(0.3, 0.9)) * (h - body_top)
            base = [
                (0.9 * r * math.cos(a + s), 0.9 * r * math.sin(a + s), body_top - 0.02) for s in (-0.5, 0.5)
            ]
            base.append((0.5 * r * math.cos(a), 0.5 * r * math.sin(a), body_top - 0.02))
            tip = (0.75 * r * math.cos(a), 0.75 * r * math.sin(a), tip_z)
            asm.add(hull([*base, tip]), wood if k % 2 else shade(bark, 1.1))
    if rng.uniform() < 0.35:  # a few bracket mushrooms on the bark
        cap = pick(rng, ((196, 150, 96), (226, 216, 196), (170, 90, 50)))
        for _ in range(int(rng.integers(2, 4))):
            a = float(rng.uniform(0.0, 2.0 * math.pi))
            z = float(rng.uniform(0.25, 0.7)) * body_top
            c = (1.02 * r * math.cos(a), 1.02 * r * math.sin(a), z)
            asm.add(ellipsoid(c, (0.2 * r, 0.2 * r, 0.05 * r), segments=8, rings=4), cap)
    return asm


# ------------------------------------------------------------------------------------------- animals


def _ear(base_y: float, x: float, z: float, tip_z: float, width: float, lean: float) -> Solid:
    """A pointed, upright ear: a thin triangular pyramid whose tip is at height `tip_z`."""
    return hull(
        [
            (x - 0.5 * width, base_y, z),
            (x + 0.5 * width, base_y, z),
            (x, base_y - 0.6 * width, z),
            (x + lean, base_y - 0.1 * width, tip_z),
        ]
    )


def _quadruped(rng: np.random.Generator, size: Size, dog: bool) -> Assembly:
    """A standing cat or dog facing +y: torso, chest, neck, head, muzzle, ears, jointed legs and tail."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    coat = pick(rng, _DOG_FUR if dog else _CAT_FUR)
    accent = pick(rng, _FUR_ACCENT) if rng.uniform() < 0.5 else coat  # white chest and socks
    dark = shade(coat, 0.75)
    floppy = dog and rng.uniform() < 0.55
    ear_h = 0.0 if floppy else (0.12 if dog else 0.13) * h
    # head and muzzle, from the nose tip at +y backwards
    head_r = np.array(
        [(0.55 if dog else 0.62) * hx, (0.07 if dog else 0.075) * d, (0.095 if dog else 0.11) * h]
    )
    head_z = h - ear_h * 0.7 - head_r[2]
    nose_r = np.array([0.22 * head_r[0], 0.015 * d, 0.018 * h])
    snout_r = np.array([0.6 * head_r[0], (0.06 if dog else 0.03) * d, 0.6 * head_r[2]])
    nose_y = hy - nose_r[1]
    snout_y = nose_y - 0.8 * snout_r[1]
    head_y = snout_y - 0.5 * snout_r[1] - 0.65 * head_r[1]
    snout_z = head_z - 0.4 * head_r[2]
    asm.add(ellipsoid((0, head_y, head_z), head_r, segments=12, rings=6), coat)
    asm.add(ellipsoid((0, snout_y, snout_z), snout_r, segments=12, rings=6), accent if dog else coat)
    asm.add(
        ellipsoid((0, nose_y, snout_z + 0.3 * snout_r[2]), nose_r, segments=8, rings=4),
        _NOSE_DOG if dog else _NOSE_CAT,
    )
    for sx in (-1.0, 1.0):
        eye = (sx * 0.45 * head_r[0], head_y + 0.75 * head_r[1], head_z + 0.25 * head_r[2])
        asm.add(
            ellipsoid(eye, (0.12 * head_r[0], 0.2 * head_r[1], 0.12 * head_r[2]), segments=8, rings=4), _EYE
        )
        if floppy:  # hanging ears along the sides of the head
            ear = (sx * 1.0 * head_r[0], head_y - 0.2 * head_r[1], head_z - 0.5 * head_r[2])
            er = (min(0.2 * head_r[0], hx - head_r[0]), 0.55 * head_r[1], 1.1 * head_r[2])
            asm.add(ellipsoid(ear, er, segments=8, rings=4), dark)
        else:
            x = sx * 0.55 * head_r[0]
            base_z = head_z + 0.6 * head_r[2]
            asm.add(
                _ear(head_y - 0.1 * head_r[1], x, base_z, h, 0.5 * head_r[0], sx * 0.12 * head_r[0]), coat
            )
    # torso between the rump and the chest
    withers = 0.74 * h  # head up, the ear tips are about 1.35 times the shoulder height
    torso_rz = (0.19 if dog else 0.17) * h
    torso_z = withers - torso_rz
    tail_back = (0.1 if dog else 0.12) * d
    rump_y = -hy + tail_back
    chest_y = head_y - (0.1 if dog else 0.06) * d
    torso_y, torso_ry = 0.5 * (rump_y + chest_y), 0.5 * (chest_y - rump_y)
    asm.add(ellipsoid((0, torso_y, torso_z), (0.9 * hx, torso_ry, torso_rz), segments=12, rings=6), coat)
    asm.add(
        ellipsoid(
            (0, chest_y - 0.35 * torso_ry, torso_z - 0.1 * torso_rz), (hx, 0.45 * torso_ry, 1.05 * torso_rz)
        ),
        accent,
    )
    asm.add(
        ellipsoid(
            (0, rump_y + 0.35 * torso_ry, torso_z + 0.05 * torso_rz), (0.95 * hx, 0.4 * torso_ry, torso_rz)
        ),
        coat,
    )
    neck0 = np.array([0.0, chest_y - 0.3 * torso_ry, torso_z + 0.4 * torso_rz])
    neck1 = np.array([0.0, head_y - 0.3 * head_r[1], head_z - 0.3 * head_r[2]])
    neck_r0, neck_r1 = min(0.75 * torso_rz, 0.8 * hx), min(0.85 * head_r[2], head_r[0])
    asm.add(frustum(neck0, neck1, neck_r0, neck_r1, sections=12), coat)
    if dog and rng.uniform() < 0.5:  # a collar around the neck
        axis = (neck1 - neck0) / np.linalg.norm(neck1 - neck0)
        c = neck0 + 0.65 * (neck1 - neck0)
        rc = neck_r0 + 0.65 * (neck_r1 - neck_r0) + 0.006
        asm.add(frustum(c - 0.012 * axis, c + 0.012 * axis, rc, rc, sections=12), pick(rng, _COLLAR))
    # legs: straight front legs, angled hind legs (stifle forward, hock back), paws on the ground
    leg_r = (0.09 if dog else 0.075) * w
    paw = np.array([1.2 * leg_r, 1.7 * leg_r, 0.8 * leg_r])
    x_leg = hx - 1.3 * leg_r
    front_y = chest_y - 0.3 * torso_ry
    hind_y = rump_y + 0.4 * torso_ry
    for sx in (-1.0, 1.0):
        x = sx * min(0.5 * hx, x_leg)
        pts = [(x, front_y, torso_z), (x, front_y + 0.01 * d, 0.3 * h), (x, front_y, paw[2])]
        asm.add_all(_tube(pts, (1.4 * leg_r, leg_r, 0.85 * leg_r), sections=8), coat)
        asm.add(ellipsoid((x, front_y + 0.4 * paw[1], paw[2]), paw, segments=8, rings=4), accent)
        pts = [
            (x, hind_y, torso_z),
            (x, hind_y + 0.06 * d, 0.36 * h),
            (x, hind_y - 0.04 * d, 0.15 * h),
            (x, hind_y - 0.02 * d, paw[2]),
        ]
        asm.add_all(_tube(pts, (1.7 * leg_r, 1.1 * leg_r, 0.8 * leg_r, 0.8 * leg_r), sections=8), coat)
        asm.add(ellipsoid((x, hind_y - 0.02 * d + 0.4 * paw[1], paw[2]), paw, segments=8, rings=4), accent)
    # tail from the top of the rump, its tip reaching -y
    root = np.array([0.0, rump_y + 0.05 * torso_ry, torso_z + 0.55 * torso_rz])
    style = int(rng.integers(3))
    tail_r = (0.05 if dog else 0.06) * w
    if style == 0:  # raised
        bend = [
            (0.0, -0.5 * tail_back, 0.12 * h),
            (0.0, -0.85 * tail_back, 0.22 * h),
            (0.0, -tail_back, 0.28 * h),
        ]
    elif style == 1:  # hanging down
        bend = [
            (0.0, -0.5 * tail_back, -0.05 * h),
            (0.0, -0.85 * tail_back, -0.18 * h),
            (0.0, -tail_back, -0.3 * h),
        ]
    else:  # held out and curving up at the tip
        bend = [
            (0.0, -0.55 * tail_back, 0.02 * h),
            (0.0, -0.9 * tail_back, 0.06 * h),
            (0.0, -tail_back, 0.14 * h),
        ]
    lift = 1.0 if dog else 1.1  # a cat's tail is longer: it rises or hangs further
    pts = [root] + [root + np.array(b) * (1.0, 1.0, lift) for b in bend]
    tail = _tube(pts, (1.2 * tail_r, tail_r, 0.85 * tail_r, 0.5 * tail_r), sections=8)
    shift = -hy - min(float(s[0][:, 1].min()) for s in tail)
    asm.add_all((translate(s, (0.0, shift, 0.0)) for s in tail), dark if rng.uniform() < 0.3 else coat)
    return asm


def _sitting_cat(rng: np.random.Generator, size: Size) -> Assembly:
    """A cat sitting upright facing +y: haunches, upright chest, front legs, head, ears and a curled tail."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    coat = pick(rng, _CAT_FUR)
    accent = pick(rng, _FUR_ACCENT) if rng.uniform() < 0.4 else coat
    ear_h = 0.12 * h
    haunch = np.array([hx, 0.28 * d, 0.22 * h])
    haunch_c = np.array([0.0, -hy + haunch[1], haunch[2]])
    asm.add(ellipsoid(haunch_c, haunch, segments=12, rings=6), coat)
    paw = np.array([0.16 * hx, 0.09 * d, 0.035 * h])
    paw_y = hy - paw[1]
    leg_r = 0.12 * hx
    chest = np.array([0.7 * hx, 0.17 * d, 0.27 * h])  # upright: the chest rises over the front paws
    chest_c = np.array([0.0, hy - 0.3 * d, 0.45 * h])
    asm.add(ellipsoid(chest_c, chest, segments=12, rings=6), accent)
    # the back: an ellipsoid tilted up from the haunches to the shoulders
    p0, p1 = haunch_c + np.array([0.0, 0.0, 0.05 * h]), chest_c + np.array([0.0, -0.05 * d, 0.12 * h])
    mid, length = 0.5 * (p0 + p1), float(np.linalg.norm(p1 - p0))
    back = ellipsoid(mid, (0.85 * hx, 0.6 * length, 0.17 * h), segments=12, rings=6)
    asm.add(rotate(back, "x", math.atan2(p1[2] - p0[2], p1[1] - p0[1]), about=mid), coat)
    for sx in (-1.0, 1.0):
        x = sx * 0.35 * hx
        top = (x, chest_c[1] + 0.55 * chest[1], 0.32 * h)
        asm.add(frustum(top, (x, paw_y - 0.3 * paw[1], paw[2]), leg_r, 0.85 * leg_r, sections=8), coat)
        asm.add(ellipsoid((x, paw_y, paw[2]), paw, segments=8, rings=4), accent)
        hind = (sx * 0.7 * hx, haunch_c[1] + 0.75 * haunch[1], paw[2])
        asm.add(ellipsoid(hind, (0.22 * hx, 0.12 * d, paw[2]), segments=8, rings=4), coat)
    head_r = np.array([0.55 * hx, 0.13 * d, 0.13 * h])
    head_c = np.array([0.0, chest_c[1] + 0.02 * d, h - 0.7 * ear_h - head_r[2]])
    asm.add(ellipsoid(head_c, head_r, segments=12, rings=6), coat)
    muzzle_r = np.array([0.5 * head_r[0], 0.35 * head_r[1], 0.45 * head_r[2]])
    muzzle_c = head_c + np.array([0.0, 0.85 * head_r[1], -0.4 * head_r[2]])
    asm.add(ellipsoid(muzzle_c, muzzle_r, segments=8, rings=4), accent)
    nose = muzzle_c + np.array([0.0, 0.9 * muzzle_r[1], 0.5 * muzzle_r[2]])
    asm.add(
        ellipsoid(nose, (0.18 * muzzle_r[0], 0.2 * muzzle_r[1], 0.2 * muzzle_r[2]), segments=8, rings=4),
        _NOSE_CAT,
    )
    for sx in (-1.0, 1.0):
        eye = head_c + np.array([sx * 0.45 * head_r[0], 0.78 * head_r[1], 0.25 * head_r[2]])
        asm.add(
            ellipsoid(eye, (0.13 * head_r[0], 0.15 * head_r[1], 0.13 * head_r[2]), segments=8, rings=4), _EYE
        )
        x = sx * 0.55 * head_r[0]
        asm.add(
            _ear(
                head_c[1] - 0.1 * head_r[1],
                x,
                head_c[2] + 0.6 * head_r[2],
                h,
                0.5 * head_r[0],
                sx * 0.1 * head_r[0],
            ),
            coat,
        )
    # tail lying on the ground, curled from behind around one side towards the front paws
    side = 1.0 if rng.uniform() < 0.5 else -1.0
    tail_r = 0.1 * hx
    reach_x, reach_y = hx - 1.1 * tail_r, haunch[1] - 1.1 * tail_r
    sweep = float(rng.uniform(0.3, 0.9))
    angles = np.linspace(-0.5 * math.pi, sweep, 6)
    pts = [
        (
            side * reach_x * math.cos(a),
            haunch_c[1] + (reach_y + 0.1 * d * max(a, 0.0)) * math.sin(a),
            1.1 * tail_r,
        )
        for a in angles
    ]
    pts = [(x, min(y, hy - 1.1 * tail_r), z) for x, y, z in pts]
    radii = np.linspace(1.1 * tail_r, 0.8 * tail_r, len(pts))
    asm.add_all(_tube(pts, radii, sections=8), shade(coat, 0.85) if rng.uniform() < 0.4 else coat)
    return asm


def _cat(rng: np.random.Generator, size: Size) -> Assembly:
    """A domestic cat, sitting upright when its box is compact, else standing with its tail up or out."""
    if size[1] < 1.35 * size[2]:
        return _sitting_cat(rng, size)
    return _quadruped(rng, size, dog=False)


def _dog(rng: np.random.Generator, size: Size) -> Assembly:
    """A medium-sized dog standing, with pricked or floppy ears, a raised, hanging or level tail."""
    return _quadruped(rng, size, dog=True)


ASSETS: tuple[Asset, ...] = (
    Asset(
        "deciduous_tree",
        (3.0, 3.0, 4.0),  # a young lime or maple
        (12.0, 12.0, 15.0),  # a mature oak, plane or chestnut in a park
        "floor",
        None,
        0.0,
        "wood",
        _deciduous_tree,
        contexts=("park", "street", "plaza"),
    ),
    Asset(
        "conifer_tree",
        (1.8, 1.8, 4.0),  # spruce / fir crowns are a third to a half of the height wide
        (6.5, 6.5, 15.0),
        "floor",
        None,
        0.0,
        "wood",
        _conifer_tree,
        contexts=("park", "plaza"),
    ),
    Asset(
        "palm_tree",
        (3.0, 3.0, 4.0),  # date and Canary palms: fronds 2-5 m long, 4-12 m tall in streets
        (8.0, 8.0, 12.0),
        "floor",
        None,
        0.0,
        "wood",
        _palm_tree,
        contexts=("street", "park", "plaza"),
    ),
    Asset(
        "street_tree",
        (1.6, 1.6, 4.0),  # pit grates are 1.2 m (4 ft) or 1.5 m square; the crown starts over 2-2.6 m
        (4.0, 4.0, 7.5),
        "floor",
        None,
        0.0,
        "wood",
        _street_tree,
        contexts=("street", "plaza"),
    ),
    Asset(
        "birch_tree",
        (2.5, 2.5, 5.0),  # silver birch: narrow, airy crown
        (7.0, 7.0, 15.0),
        "floor",
        None,
        0.0,
        "wood",
        _birch_tree,
        contexts=("park", "street", "plaza"),
    ),
    Asset(
        "bush",
        (0.5, 0.5, 0.4),
        (2.5, 2.5, 1.8),
        "floor",
        None,
        0.0,
        "plant",
        _bush,
        contexts=("park", "plaza", "street", "frontage"),
    ),
    Asset(
        "hedge",
        (1.2, 0.4, 0.5),  # a trimmed box/privet/yew/beech hedge segment, x is its length
        (6.0, 1.2, 2.0),
        "floor",
        None,
        0.0,
        "plant",
        _hedge,
        contexts=("park", "street", "frontage"),
    ),
    Asset(
        "flower_bed",
        (1.0, 0.6, 0.3),  # raised beds: 0.2-0.45 m walls, plants up to 0.35 m above the soil
        (3.0, 1.5, 0.8),
        "floor",
        None,
        0.3,
        "plant",
        _flower_bed,
        contexts=("park", "plaza", "frontage"),
    ),
    Asset(
        "boulder",
        (0.4, 0.35, 0.25),  # landscaping boulders and rocks
        (2.2, 1.8, 1.4),
        "floor",
        None,
        0.0,
        "stone",
        _boulder,
        contexts=("park", "plaza"),
    ),
    Asset(
        "tree_stump",
        (0.35, 0.35, 0.15),  # footprint includes the root flares
        (1.2, 1.2, 0.8),
        "floor",
        None,
        0.0,
        "wood",
        _tree_stump,
        contexts=("park",),
    ),
    Asset(
        "cat",
        (0.13, 0.30, 0.24),  # body 0.45 m, 0.23-0.25 m at the shoulder; sitting 0.3-0.38 m tall
        (0.22, 0.62, 0.40),
        "floor",
        None,
        0.0,
        "fabric",
        _cat,
        contexts=("park", "street"),
    ),
    Asset(
        "dog",
        (0.22, 0.65, 0.50),  # medium breeds (border collie, labrador): 0.46-0.57 m at the withers
        (0.36, 1.10, 0.85),
        "floor",
        None,
        0.0,
        "fabric",
        _dog,
        contexts=("park", "street"),
    ),
)
