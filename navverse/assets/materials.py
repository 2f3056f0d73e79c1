"""Colour palettes of the object library and the physical materials an asset can be made of.

A *palette* is a list of base sRGB colours (wood tones, fabrics, metals, ...): one of the named
:data:`PALETTES` or a family's own tuple of colours (car paints, hydrant bonnets, ...). Every builder
draws its colours with :func:`pick`, which chooses a base colour and varies its brightness slightly, so
two chairs of the same seed are identical and two seeds rarely are. Randomness comes only from the
``numpy.random.Generator`` passed in.

``PHYSICAL_MATERIALS`` are the names an :class:`~navverse.assets.library.Asset` may give as its
dominant material (what friction and a renderer's material will later be keyed on); palettes are a
finer, purely visual split.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["PALETTES", "PHYSICAL_MATERIALS", "RGB", "pick", "shade"]

RGB = tuple[int, int, int]

PHYSICAL_MATERIALS: frozenset[str] = frozenset(
    {"wood", "fabric", "leather", "metal", "plastic", "ceramic", "glass", "stone", "paper", "plant", "rubber"}
)
"""Dominant materials an asset may declare."""

PALETTES: dict[str, tuple[RGB, ...]] = {
    # wood: oak, walnut, cherry, maple, birch, ash grey, mahogany, pine, wenge
    "wood": (
        (176, 132, 84),
        (110, 74, 48),
        (150, 82, 52),
        (206, 170, 122),
        (222, 196, 156),
        (150, 138, 124),
        (112, 52, 38),
        (214, 176, 118),
        (72, 52, 40),
    ),
    "light_wood": ((222, 196, 156), (206, 170, 122), (214, 176, 118), (196, 160, 112)),
    "dark_wood": ((110, 74, 48), (72, 52, 40), (112, 52, 38), (90, 62, 44)),
    # painted or laminated panels
    "painted": (
        (240, 238, 232),
        (222, 222, 218),
        (170, 172, 170),
        (60, 72, 96),
        (150, 166, 140),
        (94, 98, 104),
        (200, 184, 160),
        (240, 232, 214),
    ),
    "fabric": (
        (128, 128, 132),
        (196, 182, 160),
        (52, 64, 100),
        (98, 108, 70),
        (40, 110, 116),
        (196, 150, 50),
        (150, 70, 58),
        (64, 64, 70),
        (226, 218, 200),
        (120, 90, 130),
    ),
    "leather": ((36, 32, 30), (100, 62, 40), (160, 108, 64), (98, 34, 34)),
    "bedding": (
        (246, 246, 244),
        (214, 218, 222),
        (176, 196, 218),
        (226, 212, 186),
        (176, 194, 168),
        (226, 190, 186),
    ),
    "metal": ((150, 154, 160), (186, 190, 194), (92, 96, 102), (52, 54, 58), (120, 126, 134)),
    "chrome": ((204, 208, 212), (222, 224, 228), (186, 190, 196)),
    "dark_metal": ((42, 44, 48), (62, 64, 70), (30, 30, 32)),
    "stainless": ((196, 198, 200), (176, 180, 184), (214, 214, 212)),
    "brass": ((196, 160, 80), (176, 140, 64)),
    "plastic": (
        (236, 236, 232),
        (150, 152, 156),
        (40, 40, 44),
        (40, 90, 170),
        (190, 48, 42),
        (50, 140, 80),
        (232, 190, 40),
        (232, 120, 40),
    ),
    "white_plastic": ((242, 242, 238), (232, 232, 228), (224, 226, 228)),
    "dark_plastic": ((34, 34, 38), (52, 52, 56), (70, 70, 74)),
    "ceramic": ((248, 248, 246), (240, 236, 226), (226, 228, 230)),
    "pot": ((196, 106, 66), (170, 90, 60), (230, 226, 216), (60, 60, 64), (120, 140, 150), (160, 150, 130)),
    "glass": ((186, 214, 222), (170, 200, 212), (200, 222, 226)),
    "screen": ((22, 26, 34), (16, 20, 28), (28, 32, 44)),
    "foliage": ((58, 110, 48), (74, 130, 56), (44, 92, 52), (96, 140, 60), (38, 80, 40)),
    "bark": ((96, 70, 48), (80, 60, 44), (120, 92, 64)),
    "soil": ((64, 46, 34), (52, 38, 28)),
    "paper": ((248, 246, 238), (240, 236, 220), (252, 252, 250)),
    "rubber": ((30, 30, 32), (44, 44, 46)),
    "stone": ((232, 230, 226), (120, 118, 116), (40, 40, 42), (200, 190, 170), (170, 164, 156)),
    "book": (
        (150, 40, 40),
        (40, 70, 130),
        (40, 100, 60),
        (200, 160, 60),
        (90, 50, 90),
        (30, 30, 34),
        (220, 210, 190),
        (200, 90, 40),
        (60, 130, 150),
    ),
    # saturated packaging colours for products on retail shelves
    "packaging": (
        (220, 40, 40),
        (240, 200, 40),
        (40, 110, 200),
        (40, 160, 80),
        (240, 130, 30),
        (236, 236, 236),
        (150, 60, 160),
        (120, 70, 40),
        (30, 30, 30),
        (0, 150, 170),
    ),
    "brand": ((200, 30, 40), (30, 80, 170), (30, 30, 34), (236, 236, 236), (20, 130, 70), (240, 140, 20)),
    "medical": ((236, 238, 240), (180, 210, 230), (200, 226, 214), (226, 230, 236)),
    "accent": ((200, 60, 50), (40, 110, 190), (240, 180, 40), (60, 150, 90), (120, 70, 160), (30, 150, 160)),
}
"""Base colours per palette name."""


def shade(color: RGB, factor: float) -> RGB:
    """Scale a colour's brightness.

    Parameters
    ----------
    color : tuple of int
        ``(r, g, b)`` in 0..255.
    factor : float
        Multiplier (> 1 brightens, < 1 darkens); results are clipped to 0..255.

    Returns
    -------
    tuple of int
        The scaled colour.
    """
    r, g, b = (int(np.clip(round(c * factor), 0, 255)) for c in color)
    return (r, g, b)


def pick(
    rng: np.random.Generator,
    palette: str | Sequence[RGB],
    *,
    variation: float = 0.06,
    brightness: tuple[float, float] | None = None,
) -> RGB:
    """Draw a colour from a palette and vary its brightness.

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of randomness (two draws: the base colour, then the brightness factor).
    palette : str or sequence of tuple of int
        Key of :data:`PALETTES`, or the base colours themselves (a family's own palette).
    variation : float
        The brightness factor is ``1 + uniform(-variation, variation)``.
    brightness : (float, float), optional
        The brightness factor's range ``(low, high)``, drawn as ``uniform(low, high)`` in place of
        `variation`. The two forms of the same range can differ in the last bit of the factor, and so
        in a rounded channel: a builder keeps the form its colours were made with.

    Returns
    -------
    tuple of int
        ``(r, g, b)`` in 0..255.

    Raises
    ------
    KeyError
        If the palette is unknown (a programming error in a builder).
    """
    colors = PALETTES[palette] if isinstance(palette, str) else palette
    base = colors[int(rng.integers(len(colors)))]
    if brightness is not None:
        return shade(base, float(rng.uniform(*brightness)))
    return shade(base, 1.0 + float(rng.uniform(-variation, variation)))
