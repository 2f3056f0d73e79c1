"""Storage furniture: bookshelf, wardrobe, dresser, nightstand, cabinet, filing cabinet, locker, tv stand.

Carcasses stand with their backs at -y; doors, drawers and open compartments face +y. Open
compartments are boolean cut-outs (manifold3d), so a carcass stays one watertight solid.
"""

from __future__ import annotations

import numpy as np

from navverse.assets.fittings import (
    FRONT_THICKNESS,
    HANDLE_DEPTH,
    bar_handle,
    corners,
    door_fronts,
    drawer_fronts,
    legs,
    upright_books,
)
from navverse.assets.materials import pick, shade
from navverse.assets.parts import Assembly, box, difference
from navverse.assets.spec import Asset, Size, SupportArea, top_support

__all__ = ["ASSETS"]

_FRONT = FRONT_THICKNESS + HANDLE_DEPTH


def _bookshelf(rng: np.random.Generator, size: Size) -> Assembly:
    """An open carcass with shelves (cut-outs) filled with rows of books."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wood = pick(rng, "wood") if rng.uniform() < 0.7 else pick(rng, "painted")
    t = float(rng.uniform(0.018, 0.028))
    back = 0.01
    plinth = 0.06
    rows = int(np.clip(round((h - plinth) / 0.34), 3, 7))
    cols = 1 if w < 0.85 else 2
    row_h = (h - plinth - t) / rows
    col_w = (w - t) / cols
    cuts = []
    cells = []
    for r in range(rows):
        for c in range(cols):
            x0, x1 = -hx + t + c * col_w, -hx + (c + 1) * col_w
            z0, z1 = plinth + r * row_h + t, plinth + (r + 1) * row_h
            cuts.append(box((x0, -hy + back, z0), (x1, hy + 0.01, z1)))
            cells.append((x0, x1, z0, z1))
    asm.add(difference(box((-hx, -hy, 0.0), (hx, hy, h)), *cuts), wood)
    for x0, x1, z0, z1 in cells:
        if rng.uniform() < 0.85:
            upright_books(
                asm, rng, x0 + 0.01, x1 - 0.01, -hy + back + 0.01, d - back - 0.04, z0, z1 - z0 - 0.02
            )
    return asm


def _wardrobe(rng: np.random.Generator, size: Size) -> Assembly:
    """A tall carcass with two to four doors, long handles, plinth and cornice; a door may be a mirror."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wood = pick(rng, "wood") if rng.uniform() < 0.6 else pick(rng, "painted")
    face = hy - _FRONT
    cornice = 0.04
    asm.box((-hx, -hy, 0.0), (hx, face, h - cornice), wood)
    asm.box((-hx, -hy, h - cornice), (hx, hy - HANDLE_DEPTH, h), shade(wood, 0.9))
    asm.box((-hx + 0.02, face, 0.0), (hx - 0.02, face + 0.005, 0.08), shade(wood, 0.6))
    count = int(np.clip(round(w / 0.5), 2, 4))
    door_fronts(
        asm,
        -hx,
        hx,
        0.08,
        h - cornice,
        face,
        count=count,
        color=shade(wood, 1.04),
        handle_color=pick(rng, "chrome"),
        handle_z=1.05,
    )
    if rng.uniform() < 0.35:
        width = w / count
        asm.box(
            (-hx + 0.05, face + FRONT_THICKNESS, 0.25),
            (-hx + width - 0.08, face + FRONT_THICKNESS + 0.004, h - cornice - 0.2),
            pick(rng, "glass"),
        )
    return asm


def _dresser(rng: np.random.Generator, size: Size) -> Assembly:
    """A chest of drawers (one or two columns) under an overhanging top, on a plinth or short legs."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wood = pick(rng, "wood") if rng.uniform() < 0.7 else pick(rng, "painted")
    face = hy - _FRONT
    base = float(rng.choice([0.06, 0.12]))
    top_t = 0.025
    asm.box((-hx, -hy, h - top_t), (hx, hy - HANDLE_DEPTH, h), shade(wood, 0.95))
    asm.box((-hx + 0.01, -hy, base), (hx - 0.01, face, h - top_t), wood)
    if base > 0.1:
        legs(asm, corners(w - 0.02, d - _FRONT, 0.03), 0.0, base, 0.04, shade(wood, 0.8))
    else:
        asm.box((-hx + 0.03, -hy + 0.02, 0.0), (hx - 0.03, face - 0.02, base), shade(wood, 0.7))
    rows = int(np.clip(round((h - base - top_t) / 0.2), 3, 5))
    drawer_fronts(
        asm,
        -hx + 0.01,
        hx - 0.01,
        base,
        h - top_t,
        face,
        rows=rows,
        cols=1 if w < 1.0 else 2,
        color=shade(wood, 1.05),
        handle_color=pick(rng, "brass" if rng.uniform() < 0.4 else "chrome"),
        handle="knob" if rng.uniform() < 0.4 else "bar",
    )
    return asm


def _nightstand(rng: np.random.Generator, size: Size) -> Assembly:
    """A small cabinet on legs with one or two drawers and sometimes an open niche."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wood = pick(rng, "wood") if rng.uniform() < 0.7 else pick(rng, "painted")
    face = hy - _FRONT
    leg_h = float(rng.uniform(0.08, 0.16))
    legs(
        asm,
        corners(w, d - _FRONT, 0.03),
        0.0,
        leg_h + 0.01,
        0.035,
        shade(wood, 0.8),
        round_legs=True,
        taper=0.6,
    )
    niche = rng.uniform() < 0.5
    body_h = h - leg_h
    split = leg_h + (0.5 * body_h if niche else 0.0)
    carcass = box((-hx, -hy, leg_h), (hx, face, h))
    if niche:
        carcass = difference(
            carcass, box((-hx + 0.02, -hy + 0.02, leg_h + 0.02), (hx - 0.02, face + 0.01, split))
        )
    asm.add(carcass, wood)
    drawer_fronts(
        asm,
        -hx + 0.01,
        hx - 0.01,
        split + 0.01,
        h - 0.01,
        face,
        rows=1 if niche or body_h < 0.3 else 2,
        cols=1,
        color=shade(wood, 1.05),
        handle_color=pick(rng, "brass"),
        handle="knob" if rng.uniform() < 0.5 else "bar",
    )
    return asm


def _cabinet(rng: np.random.Generator, size: Size) -> Assembly:
    """A storage cabinet with two doors; tall ones get a second pair of doors above."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    color = pick(rng, "painted") if rng.uniform() < 0.5 else pick(rng, "wood")
    face = hy - _FRONT
    asm.box((-hx, -hy, 0.0), (hx, face, h), color)
    asm.box((-hx + 0.02, face, 0.0), (hx - 0.02, face + 0.004, 0.07), shade(color, 0.55))
    handles = pick(rng, "chrome")
    count = 1 if w < 0.55 else 2
    if h > 1.3:
        split = 0.9
        door_fronts(
            asm, -hx, hx, 0.07, split, face, count=count, color=shade(color, 1.04), handle_color=handles
        )
        door_fronts(
            asm,
            -hx,
            hx,
            split,
            h - 0.02,
            face,
            count=count,
            color=shade(color, 1.04),
            handle_color=handles,
            handle_z=split + 0.25,
        )
    else:
        door_fronts(
            asm, -hx, hx, 0.07, h - 0.02, face, count=count, color=shade(color, 1.04), handle_color=handles
        )
    return asm


def _cabinet_supports(size: Size) -> list[SupportArea]:
    return top_support(front_margin=_FRONT)(size) if size[2] <= 1.3 else []


def _filing_cabinet(rng: np.random.Generator, size: Size) -> Assembly:
    """A metal cabinet of two to four deep drawers, each with a handle and a label holder."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    metal = pick(rng, "metal") if rng.uniform() < 0.7 else pick(rng, "painted")
    face = hy - _FRONT
    asm.box((-hx, -hy, 0.0), (hx, face, h), metal)
    rows = int(np.clip(round(h / 0.32), 2, 4))
    drawer_fronts(
        asm,
        -hx + 0.01,
        hx - 0.01,
        0.03,
        h - 0.01,
        face,
        rows=rows,
        cols=1,
        color=shade(metal, 1.06),
        handle_color=shade(metal, 0.7),
    )
    pitch = (h - 0.04) / rows
    for r in range(rows):
        z = 0.03 + (r + 1) * pitch - 0.045
        asm.box(
            (-0.04, face + FRONT_THICKNESS, z - 0.015),
            (0.04, face + FRONT_THICKNESS + 0.004, z + 0.015),
            (240, 240, 236),
        )
    return asm


def _locker(rng: np.random.Generator, size: Size) -> Assembly:
    """A bank of steel lockers: one to four columns of one or two tiers, with vents and handles."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    body = pick(rng, "metal")
    door = pick(rng, "accent") if rng.uniform() < 0.5 else shade(body, 1.08)
    dark = shade(body, 0.35)
    face = hy - FRONT_THICKNESS - 0.02
    asm.box((-hx, -hy, 0.0), (hx, face, h), body)
    asm.box((-hx + 0.01, face, 0.0), (hx - 0.01, face + 0.004, 0.1), dark)
    cols = max(1, round(w / 0.3))
    tiers = 1 if rng.uniform() < 0.5 else 2
    cw = (w - 0.02) / cols
    th = (h - 0.12) / tiers
    for c in range(cols):
        for t in range(tiers):
            x0, x1 = -hx + 0.01 + c * cw + 0.003, -hx + 0.01 + (c + 1) * cw - 0.003
            z0, z1 = 0.1 + t * th + 0.003, 0.1 + (t + 1) * th - 0.003
            asm.box((x0, face, z0), (x1, face + FRONT_THICKNESS, z1), door)
            front = face + FRONT_THICKNESS
            for k in range(3):
                vz = z1 - 0.06 - 0.03 * k
                asm.box((x0 + 0.04, front, vz), (x1 - 0.04, front + 0.003, vz + 0.012), dark)
            hz = z0 + 0.55 * (z1 - z0) if tiers == 1 else 0.5 * (z0 + z1)
            asm.box((x1 - 0.05, front, hz - 0.06), (x1 - 0.03, front + 0.02, hz + 0.06), shade(body, 0.5))
    return asm


def _tv_stand(rng: np.random.Generator, size: Size) -> Assembly:
    """A low media unit: open compartments (cut-outs) beside door or drawer fronts, on short legs."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wood = pick(rng, "wood") if rng.uniform() < 0.6 else pick(rng, "painted")
    face = hy - _FRONT
    leg_h = float(rng.uniform(0.05, 0.12))
    legs(asm, corners(w, d - _FRONT, 0.05), 0.0, leg_h + 0.01, 0.04, pick(rng, "dark_metal"))
    cells = 3 if w > 1.4 else 2
    cw = (w - 0.02) / cells
    open_cell = int(rng.integers(cells))
    cut = box(
        (-hx + 0.02 + open_cell * cw, -hy + 0.02, leg_h + 0.02),
        (-hx + (open_cell + 1) * cw, face + 0.01, h - 0.02),
    )
    asm.add(difference(box((-hx, -hy, leg_h), (hx, face, h)), cut), wood)
    fronts = shade(wood, 1.06)
    for c in range(cells):
        if c == open_cell:
            continue
        x0, x1 = -hx + 0.01 + c * cw, -hx + 0.01 + (c + 1) * cw
        if rng.uniform() < 0.5:
            drawer_fronts(
                asm,
                x0,
                x1,
                leg_h + 0.01,
                h - 0.01,
                face,
                rows=2,
                cols=1,
                color=fronts,
                handle_color=shade(wood, 0.5),
            )
        else:
            asm.box((x0 + 0.003, face, leg_h + 0.01), (x1 - 0.003, face + FRONT_THICKNESS, h - 0.01), fronts)
            bar_handle(asm, 0.5 * (x0 + x1), h - 0.07, face + FRONT_THICKNESS, 0.12, shade(wood, 0.5))
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "bookshelf",
        (0.60, 0.28, 1.50),
        (1.20, 0.40, 2.20),
        "wall",
        None,
        0.6,
        "wood",
        _bookshelf,
        contexts=("home", "office", "school"),
    ),
    Asset(
        "wardrobe",
        (0.90, 0.55, 1.90),
        (2.00, 0.65, 2.30),
        "wall",
        None,
        0.8,
        "wood",
        _wardrobe,
        contexts=("home", "hospital"),
    ),
    Asset(
        "dresser",
        (0.80, 0.42, 0.75),
        (1.60, 0.55, 1.10),
        "wall",
        None,
        0.7,
        "wood",
        _dresser,
        supports=top_support(front_margin=HANDLE_DEPTH),
        contexts=("home",),
    ),
    Asset(
        "nightstand",
        (0.40, 0.35, 0.45),
        (0.55, 0.45, 0.65),
        "wall",
        None,
        0.4,
        "wood",
        _nightstand,
        supports=top_support(inset=0.02, front_margin=_FRONT),
        contexts=("home", "hospital"),
    ),
    Asset(
        "cabinet",
        (0.55, 0.40, 0.80),
        (1.20, 0.60, 2.00),
        "wall",
        None,
        0.7,
        "wood",
        _cabinet,
        supports=_cabinet_supports,
        contexts=("home", "office", "school", "hospital", "retail"),
    ),
    Asset(
        "filing_cabinet",
        (0.40, 0.45, 0.70),
        (0.50, 0.62, 1.35),
        "wall",
        None,
        0.8,
        "metal",
        _filing_cabinet,
        supports=top_support(inset=0.02, front_margin=_FRONT),
        contexts=("office", "school", "hospital"),
    ),
    Asset(
        "locker",
        (0.30, 0.40, 1.75),
        (1.20, 0.50, 1.95),
        "wall",
        None,
        0.7,
        "metal",
        _locker,
        contexts=("school", "office", "hospital"),
    ),
    Asset(
        "tv_stand",
        (1.20, 0.35, 0.40),
        (2.00, 0.50, 0.60),
        "wall",
        None,
        0.6,
        "wood",
        _tv_stand,
        supports=top_support(front_margin=_FRONT),
        contexts=("home", "office"),
    ),
)
