"""Furniture fittings shared by several categories: legs, handles, knobs, drawer and door fronts, casters,
rows of upright books.

Each helper adds closed parts to an :class:`~navverse.assets.parts.Assembly` in the floor frame
(front towards +y). Fronts are built on a carcass face at ``y = y_face`` and stick out towards +y by
at most ``FRONT_THICKNESS + HANDLE_DEPTH``, which builders reserve in their depth budget.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from navverse.assets.materials import RGB, pick, shade
from navverse.assets.parts import Assembly, box, cylinder, frustum

__all__ = [
    "FRONT_THICKNESS",
    "HANDLE_DEPTH",
    "bar_handle",
    "caster",
    "corners",
    "door_fronts",
    "drawer_fronts",
    "knob",
    "legs",
    "upright_books",
]

FRONT_THICKNESS = 0.018
"""Thickness of drawer and door fronts, m."""
HANDLE_DEPTH = 0.032
"""How far a bar handle (or knob) sticks out of the face it is mounted on, m."""


def corners(width: float, depth: float, inset: float) -> list[tuple[float, float]]:
    """``(x, y)`` of four points `inset` from the corners of a centred ``width`` x ``depth`` rectangle."""
    hx, hy = 0.5 * width - inset, 0.5 * depth - inset
    return [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)]


def legs(
    asm: Assembly,
    positions: Sequence[tuple[float, float]],
    z0: float,
    z1: float,
    thickness: float,
    color: RGB,
    *,
    round_legs: bool = False,
    taper: float = 1.0,
) -> None:
    """Vertical legs centred on `positions`, from `z0` to `z1`.

    Parameters
    ----------
    round_legs : bool
        Cylinders (12 sections) instead of square posts.
    taper : float
        Bottom size relative to the top (round legs only), e.g. 0.6 for tapered legs.
    """
    half = 0.5 * thickness
    for x, y in positions:
        if round_legs:
            asm.add(frustum((x, y, z0), (x, y, z1), half * taper, half, sections=12), color)
        else:
            asm.box((x - half, y - half, z0), (x + half, y + half, z1), color)


def bar_handle(
    asm: Assembly, x: float, z: float, y_face: float, length: float, color: RGB, *, vertical: bool = False
) -> None:
    """A bar handle centred at ``(x, z)`` on the face ``y = y_face``: two posts and a grip."""
    grip = 0.012
    post_end = y_face + HANDLE_DEPTH - grip
    half = 0.5 * length
    if vertical:
        for dz in (-half + 0.01, half - 0.01):
            asm.box((x - 0.005, y_face, z + dz - 0.005), (x + 0.005, post_end, z + dz + 0.005), color)
        asm.box((x - 0.006, post_end, z - half), (x + 0.006, y_face + HANDLE_DEPTH, z + half), color)
    else:
        for dx in (-half + 0.01, half - 0.01):
            asm.box((x + dx - 0.005, y_face, z - 0.005), (x + dx + 0.005, post_end, z + 0.005), color)
        asm.box((x - half, post_end, z - 0.006), (x + half, y_face + HANDLE_DEPTH, z + 0.006), color)


def knob(asm: Assembly, x: float, z: float, y_face: float, color: RGB, *, radius: float = 0.014) -> None:
    """A round knob on the face ``y = y_face``, sticking out by ``HANDLE_DEPTH``."""
    asm.add(cylinder((x, y_face, z), (x, y_face + HANDLE_DEPTH, z), radius, sections=12), color)


def drawer_fronts(
    asm: Assembly,
    x0: float,
    x1: float,
    z0: float,
    z1: float,
    y_face: float,
    *,
    rows: int,
    cols: int,
    color: RGB,
    handle_color: RGB,
    handle: str = "bar",
    gap: float = 0.006,
) -> None:
    """A grid of drawer fronts on the face ``y = y_face`` covering ``[x0, x1] x [z0, z1]``.

    Parameters
    ----------
    handle : {"bar", "knob", "none"}
        Hardware centred on each front (near its top for tall fronts).
    """
    widths = (x1 - x0) / cols
    heights = (z1 - z0) / rows
    for r in range(rows):
        for c in range(cols):
            fx0, fz0 = x0 + c * widths + 0.5 * gap, z0 + r * heights + 0.5 * gap
            fx1, fz1 = fx0 + widths - gap, fz0 + heights - gap
            asm.box((fx0, y_face, fz0), (fx1, y_face + FRONT_THICKNESS, fz1), color)
            cx, cz = 0.5 * (fx0 + fx1), min(0.5 * (fz0 + fz1), fz1 - 0.08)
            face = y_face + FRONT_THICKNESS
            if handle == "bar":
                bar_handle(asm, cx, cz, face, min(0.4 * (fx1 - fx0), 0.16), handle_color)
            elif handle == "knob":
                knob(asm, cx, cz, face, handle_color)


def door_fronts(
    asm: Assembly,
    x0: float,
    x1: float,
    z0: float,
    z1: float,
    y_face: float,
    *,
    count: int,
    color: RGB,
    handle_color: RGB,
    handle_z: float | None = None,
    gap: float = 0.005,
) -> None:
    """`count` side-by-side doors on ``y = y_face`` with vertical bar handles beside their meeting edges."""
    width = (x1 - x0) / count
    handle_len = min(0.5 * (z1 - z0), 0.3)
    hz = 0.5 * (z0 + z1) if handle_z is None else handle_z
    hz = float(np.clip(hz, z0 + 0.5 * handle_len + 0.01, z1 - 0.5 * handle_len - 0.01))
    face = y_face + FRONT_THICKNESS
    for c in range(count):
        dx0, dx1 = x0 + c * width + 0.5 * gap, x0 + (c + 1) * width - 0.5 * gap
        asm.box((dx0, y_face, z0 + 0.5 * gap), (dx1, face, z1 - 0.5 * gap), color)
        # hinges alternate, so neighbouring doors meet with their handles side by side
        hx = dx1 - 0.04 if c % 2 == 0 else dx0 + 0.04
        if count == 1:
            hx = dx1 - 0.04
        bar_handle(asm, hx, hz, face, handle_len, handle_color, vertical=True)


def caster(asm: Assembly, x: float, y: float, radius: float, color: RGB, fork_color: RGB) -> float:
    """A swivel caster standing on the floor at ``(x, y)``; returns the height of its top plate."""
    width = 0.6 * radius
    asm.add(cylinder((x - 0.5 * width, y, radius), (x + 0.5 * width, y, radius), radius, sections=12), color)
    top = 2.0 * radius + 0.02
    asm.box(
        (x - 0.5 * width - 0.006, y - 0.3 * radius, radius),
        (x + 0.5 * width + 0.006, y + 0.3 * radius, top),
        fork_color,
    )
    return top


def upright_books(
    asm: Assembly,
    rng: np.random.Generator,
    x0: float,
    x1: float,
    y_back: float,
    max_depth: float,
    z0: float,
    max_height: float,
    *,
    fill: float = 0.75,
) -> None:
    """Books standing on a shelf between ``x0`` and ``x1``, their backs at ``y_back``.

    Runs of books with occasional gaps fill about `fill` of the width; each book is one coloured box.
    """
    x = x0 + float(rng.uniform(0.0, 0.15)) * (x1 - x0) * (1.0 - fill)
    while x < x1 - 0.02:
        thick = float(rng.uniform(0.02, 0.055))
        if x + thick > x1:
            break
        if rng.uniform() < 1.0 - fill:
            x += thick * 1.5
            continue
        height = max_height * float(rng.uniform(0.65, 0.95))
        depth = max_depth * float(rng.uniform(0.7, 1.0))
        color = shade(pick(rng, "book"), float(rng.uniform(0.85, 1.1)))
        asm.add(box((x, y_back, z0), (x + thick, y_back + depth, z0 + height)), color)
        x += thick + 0.001
