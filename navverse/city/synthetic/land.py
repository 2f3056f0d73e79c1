"""Land of synthetic cities: the river, its embankments, and what each block is used for.

The river (:func:`river`) is a band ``river_width`` wide along a gently bending centre line (two
sine waves of ``meander`` amplitude at most) that crosses the whole window, turned up to 20° from
one of the axes and shifted up to a quarter of the window off its centre. Streets stop at its
embankments except ``bridges`` of them (see :func:`~navverse.city.synthetic.streets.cut_at_water`); the
embankments are green strips ``embankment`` wide along both banks, cut by the bridges.

Each block is a park (``park_share``; a ``pond_share`` of parks hold an oval pond of at most
``pond_size`` of the park's area, a hole in the park), a paved square (``plaza_share``; in the
radial layout, the block at the centre is, unless the river took its ring road), a parking lot
(``parking_share``) or built up.
"""

from __future__ import annotations

import math

import numpy as np
from shapely import affinity
from shapely.geometry import LineString, Point, Polygon, box
from shapely.geometry.base import BaseGeometry

from navverse.city.synthetic.blocks import polygons_of
from navverse.city.synthetic.params import SyntheticCityParams
from navverse.city.synthetic.streets import XY, Window

__all__ = ["banks", "block_uses", "embankments", "keepout", "pond", "river"]


def river(
    rng: np.random.Generator,
    window: Window,
    params: SyntheticCityParams,
    *,
    avoid: list[XY],
    clearance: float,
) -> Polygon | None:
    """The river's water polygon in the window (the largest piece), or None without a river.

    Its shift off the window's centre is drawn again (up to 8 times) while its straight centre
    line passes closer than ``clearance`` to a point of ``avoid`` (the radial layout's centre);
    failing that, the draw passing farthest from them is used.
    """
    if params.river_width <= 0.0:
        return None
    min_x, min_y, max_x, max_y = window
    width, height = max_x - min_x, max_y - min_y
    along_y = bool(rng.uniform() < 0.5)
    turn = float(rng.uniform(-1.0, 1.0)) * math.radians(20.0) + (math.pi / 2.0 if along_y else 0.0)
    dx, dy = math.cos(turn), math.sin(turn)
    nx, ny = -dy, dx
    across = width if along_y else height
    mid_x, mid_y = (min_x + max_x) / 2.0, (min_y + max_y) / 2.0
    best, best_gap = 0.0, -math.inf
    for _ in range(8):
        shift = float(rng.uniform(-0.25, 0.25)) * across
        gap = min((abs((px - mid_x) * nx + (py - mid_y) * ny - shift) for px, py in avoid), default=math.inf)
        if gap > best_gap:
            best, best_gap = shift, gap
        if gap >= clearance:
            break
    cx, cy = mid_x + nx * best, mid_y + ny * best
    half = math.hypot(width, height) / 2.0 + params.river_width + params.meander
    s = np.arange(-half, half + 8.0, 8.0)
    amplitudes = params.meander * rng.uniform([0.6, 0.1], [1.0, 0.25])
    wavelengths = rng.uniform([700.0, 250.0], [1200.0, 400.0])
    phases = rng.uniform(0.0, 2.0 * math.pi, size=2)
    offset = sum(
        a * np.sin(2.0 * math.pi * s / w + p) for a, w, p in zip(amplitudes, wavelengths, phases, strict=True)
    )
    points = np.stack([cx + s * dx + offset * nx, cy + s * dy + offset * ny], axis=1)
    band = LineString(points).buffer(params.river_width / 2.0, cap_style="flat").intersection(box(*window))
    parts = polygons_of(band)
    return max(parts, key=lambda p: p.area) if parts else None


def block_uses(
    rng: np.random.Generator, blocks: list[Polygon], params: SyntheticCityParams, squares: list[XY]
) -> list[str]:
    """``park``, ``plaza``, ``parking`` or ``built`` for each block (one draw per block, in order)."""
    uses = []
    for block in blocks:
        draw = float(rng.uniform())
        if block.area <= 4.0 * params.block[0] * params.block[1] and any(
            block.contains(Point(p)) for p in squares
        ):
            uses.append("plaza")
        elif draw < params.park_share:
            uses.append("park")
        elif draw < params.park_share + params.plaza_share:
            uses.append("plaza")
        elif draw < params.park_share + params.plaza_share + params.parking_share:
            uses.append("parking")
        else:
            uses.append("built")
    return uses


def pond(rng: np.random.Generator, park: Polygon, params: SyntheticCityParams) -> Polygon | None:
    """An oval pond inside ``park`` (at least 5 m from its edge), or None when it does not fit or is
    not drawn (``pond_share``)."""
    if float(rng.uniform()) >= params.pond_share:
        return None
    target = params.pond_size * float(rng.uniform(0.5, 1.0)) * park.area
    inner = park.buffer(-5.0)
    parts = polygons_of(inner)
    if not parts:
        return None
    inner = max(parts, key=lambda p: p.area)
    if inner.area < 150.0:
        return None
    frame = inner.minimum_rotated_rectangle
    corners = list(frame.exterior.coords)
    sides = [math.dist(corners[0], corners[1]), math.dist(corners[1], corners[2])]
    angle = math.degrees(math.atan2(corners[1][1] - corners[0][1], corners[1][0] - corners[0][0]))
    scale = min(0.9, math.sqrt(4.0 * target / (math.pi * sides[0] * sides[1])))
    centre = inner.centroid if inner.contains(inner.centroid) else inner.representative_point()
    oval = affinity.rotate(
        affinity.scale(
            Point(centre.x, centre.y).buffer(0.5, quad_segs=12), sides[0] * scale, sides[1] * scale
        ),
        angle,
        origin=(centre.x, centre.y),
    )
    parts = polygons_of(oval.intersection(inner))
    if not parts:
        return None
    best = max(parts, key=lambda p: p.area).simplify(0.05)
    return best if isinstance(best, Polygon) and best.area >= 50.0 else None


def embankments(
    water: Polygon, params: SyntheticCityParams, streets: BaseGeometry, window: Window
) -> list[Polygon]:
    """The green strips along the river banks, cut by the bridges' streets."""
    if params.embankment <= 0.0:
        return []
    strip = water.buffer(params.embankment).difference(water).difference(streets).intersection(box(*window))
    return [p for p in polygons_of(strip) if p.area >= 5.0]


def keepout(water: Polygon | None, params: SyntheticCityParams) -> BaseGeometry:
    """Where no block reaches: the river and its embankments."""
    if water is None:
        return Polygon()
    return water.buffer(params.embankment + 0.01) if params.embankment > 0 else water.buffer(0.01)


def banks(water: Polygon, halves: dict[int, float], params: SyntheticCityParams) -> dict[int, Polygon]:
    """For each street rank, where its centre lines must stop: the water grown by the embankment and
    the street's half width (carriageway and sidewalk)."""
    return {rank: water.buffer(params.embankment + half + 0.5) for rank, half in halves.items()}
