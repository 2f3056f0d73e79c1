"""Home furniture that fits no other group: the bed and the upright piano.

The bed's headboard is at -y (against the wall); the piano's keyboard faces +y.
"""

from __future__ import annotations

import numpy as np

from navverse.assets.fittings import corners, legs
from navverse.assets.materials import pick, shade
from navverse.assets.parts import Assembly, ellipsoid, rounded_prism
from navverse.assets.spec import Asset, Size

__all__ = ["ASSETS"]


def _bed(rng: np.random.Generator, size: Size) -> Assembly:
    """Frame on legs, mattress, headboard, pillows, a blanket with a turned-down sheet, maybe a footboard."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    wood = pick(rng, "wood")
    upholstered = rng.uniform() < 0.4
    head = pick(rng, "fabric") if upholstered else wood
    head_t = 0.07
    leg_h = float(rng.uniform(0.08, 0.15))
    frame_top = leg_h + 0.18
    footboard = rng.uniform() < 0.35
    foot = hy - (0.04 if footboard else 0.0)
    y0 = -hy + head_t
    asm.box((-hx, -hy, 0.0), (hx, y0, h), head)
    if footboard:
        asm.box((-hx, foot, 0.0), (hx, hy, frame_top + 0.22), head)
    legs(asm, corners(w, d, 0.1), 0.0, leg_h + 0.01, 0.06, shade(wood, 0.8))
    asm.box((-hx, y0, leg_h), (hx, foot, frame_top), wood)
    mattress_top = frame_top + float(rng.uniform(0.17, 0.24))
    asm.add(
        rounded_prism((0.0, 0.5 * (y0 + foot)), w - 0.04, foot - y0 - 0.02, 0.05, frame_top, mattress_top),
        (244, 244, 240),
    )
    bedding = pick(rng, "bedding")
    blanket_y0 = y0 + 0.4 * (foot - y0)
    asm.box(
        (-hx + 0.005, blanket_y0, frame_top + 0.06), (hx - 0.005, foot - 0.005, mattress_top + 0.03), bedding
    )
    sheet = (246, 246, 244) if bedding[0] < 235 else (214, 222, 230)
    asm.box(
        (-hx + 0.004, blanket_y0 - 0.02, frame_top + 0.07),
        (hx - 0.004, blanket_y0 + 0.25, mattress_top + 0.035),
        sheet,
    )
    pillows = 1 if w < 1.25 else 2
    pitch = (w - 0.12) / pillows
    for k in range(pillows):
        cx = -0.5 * (w - 0.12) + (k + 0.5) * pitch
        asm.add(ellipsoid((cx, y0 + 0.22, mattress_top + 0.04), (0.5 * pitch - 0.03, 0.18, 0.07)), sheet)
    return asm


def _piano(rng: np.random.Generator, size: Size) -> Assembly:
    """An upright piano: tall case, key bed with white and black keys, fallboard, music desk, legs, pedals."""
    w, d, h = size
    hx, hy = 0.5 * w, 0.5 * d
    asm = Assembly()
    case = [(22, 22, 24), (22, 22, 24), (74, 44, 30), (110, 60, 40), (240, 240, 236)][int(rng.integers(5))]
    body_y1 = -hy + float(np.clip(0.55 * d, 0.28, 0.36))
    key_z = float(rng.uniform(0.7, 0.74))
    asm.box((-hx, -hy, 0.0), (hx, body_y1, h - 0.02), case)
    asm.box((-hx, -hy, h - 0.02), (hx, body_y1 + 0.02, h), shade(case, 1.1))
    asm.box((-hx, body_y1 - 0.01, key_z - 0.09), (hx, hy, key_z - 0.01), case)
    cheek = 0.06
    for x0 in (-hx, hx - cheek):
        asm.box((x0, body_y1 - 0.01, key_z - 0.09), (x0 + cheek, hy - 0.01, key_z + 0.07), case)
    keys_x0, keys_x1 = -hx + cheek, hx - cheek
    kb_y1 = hy - 0.02
    kb_y0 = kb_y1 - 0.15
    asm.box((keys_x0, kb_y0, key_z - 0.01), (keys_x1, kb_y1, key_z + 0.015), (246, 244, 236))
    whites = 52
    kw = (keys_x1 - keys_x0) / whites
    for i in range(whites - 1):
        if i % 7 in (0, 2, 3, 5, 6):  # sharps after A, C, D, F, G (the keyboard starts at A)
            x = keys_x0 + (i + 1) * kw
            asm.box(
                (x - 0.28 * kw, kb_y0, key_z + 0.015),
                (x + 0.28 * kw, kb_y0 + 0.09, key_z + 0.03),
                (18, 18, 20),
            )
    asm.box((keys_x0, body_y1 - 0.01, key_z + 0.015), (keys_x1, kb_y0, key_z + 0.13), shade(case, 0.9))
    asm.box((-0.3 * w, body_y1, key_z + 0.16), (0.3 * w, body_y1 + 0.025, key_z + 0.34), shade(case, 1.15))
    for x in (-hx + 0.03, hx - 0.03):
        asm.box((x - 0.025, hy - 0.09, 0.03), (x + 0.025, hy - 0.04, key_z - 0.09), case)
        asm.box((x - 0.03, body_y1 - 0.01, 0.0), (x + 0.03, hy - 0.03, 0.04), case)
    for k in range(3):
        x = (k - 1) * 0.06
        asm.box((x - 0.015, body_y1, 0.05), (x + 0.015, body_y1 + 0.07, 0.065), (196, 160, 80))
    return asm


ASSETS: tuple[Asset, ...] = (
    Asset(
        "bed", (0.90, 1.95, 0.80), (1.90, 2.20, 1.20), "wall", None, 0.6, "fabric", _bed, contexts=("home",)
    ),
    Asset(
        "piano",
        (1.40, 0.55, 1.10),
        (1.55, 0.66, 1.30),
        "wall",
        None,
        0.8,
        "wood",
        _piano,
        contexts=("home", "school"),
    ),
)
