"""Sign-board images of storefronts: the shop name and a simple category icon, drawn with Pillow.

:func:`sign_image` returns a ``uint8 (H, W, 3)`` image in the orientation of
:class:`navverse.scene.geometry.Texture` (row 0 at the top). The image is a pure function of its
arguments (no randomness), so equal signs get equal pixels and :func:`texture_name` can name a texture
by its content. Icons are built from Pillow primitives only (lines, ellipses, polygons, rectangles);
:data:`ICONS` lists the categories that have one, every other category gets a shopping bag.
"""

from __future__ import annotations

import functools
import hashlib
import math
import re
from collections.abc import Callable

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from navverse.assets.materials import RGB

__all__ = ["ICONS", "sign_image", "texture_name"]

_Box = tuple[float, float, float]
"""``(left, top, size)`` of the square an icon is drawn into, pixels."""
_Icon = Callable[[ImageDraw.ImageDraw, _Box, RGB], None]


def _p(box: _Box, u: float, v: float) -> tuple[float, float]:
    """The pixel at fractions ``(u, v)`` of an icon square (u right, v down)."""
    left, top, size = box
    return left + u * size, top + v * size


def _rect(box: _Box, u0: float, v0: float, u1: float, v1: float) -> list[tuple[float, float]]:
    return [_p(box, u0, v0), _p(box, u1, v1)]


def _w(box: _Box, fraction: float) -> int:
    """A line width as a fraction of the icon size (at least one pixel)."""
    return max(1, round(fraction * box[2]))


def _cup(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.rounded_rectangle(_rect(b, 0.15, 0.4, 0.7, 0.9), radius=_w(b, 0.1), fill=c)
    d.ellipse(_rect(b, 0.58, 0.5, 0.9, 0.78), outline=c, width=_w(b, 0.07))
    for u in (0.3, 0.45, 0.6):
        d.line([_p(b, u, 0.1), _p(b, u - 0.05, 0.2), _p(b, u, 0.3)], fill=c, width=_w(b, 0.05))


def _fork_knife(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    for u in (0.2, 0.3, 0.4):
        d.line([_p(b, u, 0.1), _p(b, u, 0.4)], fill=c, width=_w(b, 0.05))
    d.rectangle(_rect(b, 0.18, 0.38, 0.42, 0.46), fill=c)
    d.line([_p(b, 0.3, 0.4), _p(b, 0.3, 0.9)], fill=c, width=_w(b, 0.08))
    d.polygon([_p(b, 0.65, 0.1), _p(b, 0.8, 0.2), _p(b, 0.8, 0.5), _p(b, 0.65, 0.5)], fill=c)
    d.line([_p(b, 0.7, 0.5), _p(b, 0.7, 0.9)], fill=c, width=_w(b, 0.08))


def _burger(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.chord(_rect(b, 0.1, 0.15, 0.9, 0.75), 180, 360, fill=c)
    d.rectangle(_rect(b, 0.1, 0.5, 0.9, 0.58), fill=c)
    d.rounded_rectangle(_rect(b, 0.1, 0.64, 0.9, 0.85), radius=_w(b, 0.06), fill=c)


def _glass(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.polygon([_p(b, 0.2, 0.1), _p(b, 0.8, 0.1), _p(b, 0.5, 0.5)], fill=c)
    d.line([_p(b, 0.5, 0.5), _p(b, 0.5, 0.85)], fill=c, width=_w(b, 0.06))
    d.line([_p(b, 0.3, 0.88), _p(b, 0.7, 0.88)], fill=c, width=_w(b, 0.07))


def _bank(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.polygon([_p(b, 0.1, 0.32), _p(b, 0.5, 0.08), _p(b, 0.9, 0.32)], fill=c)
    for u in (0.2, 0.4, 0.6, 0.8):
        d.rectangle(_rect(b, u - 0.05, 0.38, u + 0.05, 0.78), fill=c)
    d.rectangle(_rect(b, 0.08, 0.82, 0.92, 0.92), fill=c)


def _cross(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.rectangle(_rect(b, 0.37, 0.1, 0.63, 0.9), fill=c)
    d.rectangle(_rect(b, 0.1, 0.37, 0.9, 0.63), fill=c)


def _ring_cross(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.ellipse(_rect(b, 0.05, 0.05, 0.95, 0.95), outline=c, width=_w(b, 0.07))
    d.rectangle(_rect(b, 0.42, 0.22, 0.58, 0.78), fill=c)
    d.rectangle(_rect(b, 0.22, 0.42, 0.78, 0.58), fill=c)


def _cart(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.line(
        [_p(b, 0.05, 0.15), _p(b, 0.2, 0.15), _p(b, 0.3, 0.65), _p(b, 0.85, 0.65)], fill=c, width=_w(b, 0.06)
    )
    d.polygon([_p(b, 0.22, 0.25), _p(b, 0.92, 0.25), _p(b, 0.84, 0.55), _p(b, 0.28, 0.55)], fill=c)
    for u in (0.35, 0.78):
        d.ellipse(_rect(b, u - 0.07, 0.72, u + 0.07, 0.86), fill=c)


def _bag(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.arc(_rect(b, 0.33, 0.08, 0.67, 0.5), 180, 360, fill=c, width=_w(b, 0.06))
    d.polygon([_p(b, 0.18, 0.3), _p(b, 0.82, 0.3), _p(b, 0.9, 0.9), _p(b, 0.1, 0.9)], fill=c)


def _bread(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.ellipse(_rect(b, 0.05, 0.3, 0.95, 0.75), fill=c)
    for u in (0.3, 0.5, 0.7):
        d.line([_p(b, u - 0.06, 0.62), _p(b, u + 0.06, 0.42)], fill=(0, 0, 0), width=_w(b, 0.04))


def _shirt(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    outline = [(0.35, 0.1), (0.65, 0.1), (0.95, 0.3), (0.85, 0.45), (0.75, 0.4), (0.75, 0.9)]
    outline += [(0.25, 0.9), (0.25, 0.4), (0.15, 0.45), (0.05, 0.3)]
    d.polygon([_p(b, u, v) for u, v in outline], fill=c)


def _scissors(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    width = _w(b, 0.07)
    d.line([_p(b, 0.3, 0.62), _p(b, 0.85, 0.08)], fill=c, width=width)
    d.line([_p(b, 0.7, 0.62), _p(b, 0.15, 0.08)], fill=c, width=width)
    for u in (0.22, 0.78):
        d.ellipse(_rect(b, u - 0.14, 0.6, u + 0.14, 0.88), outline=c, width=width)


def _book(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.polygon([_p(b, 0.05, 0.2), _p(b, 0.48, 0.28), _p(b, 0.48, 0.88), _p(b, 0.05, 0.8)], fill=c)
    d.polygon([_p(b, 0.95, 0.2), _p(b, 0.52, 0.28), _p(b, 0.52, 0.88), _p(b, 0.95, 0.8)], fill=c)


def _flower(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.line([_p(b, 0.5, 0.45), _p(b, 0.5, 0.95)], fill=c, width=_w(b, 0.06))
    d.ellipse(_rect(b, 0.5, 0.62, 0.8, 0.76), fill=c)
    for k in range(6):
        a = k * math.pi / 3
        u, v = 0.5 + 0.2 * math.cos(a), 0.32 + 0.2 * math.sin(a)
        d.ellipse(_rect(b, u - 0.11, v - 0.11, u + 0.11, v + 0.11), fill=c)


def _hammer(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.line([_p(b, 0.25, 0.9), _p(b, 0.62, 0.35)], fill=c, width=_w(b, 0.1))
    d.polygon([_p(b, 0.4, 0.1), _p(b, 0.55, 0.0), _p(b, 0.95, 0.4), _p(b, 0.82, 0.5)], fill=c)


def _phone(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.rounded_rectangle(_rect(b, 0.28, 0.05, 0.72, 0.95), radius=_w(b, 0.08), fill=c)
    d.rectangle(_rect(b, 0.34, 0.14, 0.66, 0.78), fill=(0, 0, 0))
    d.ellipse(_rect(b, 0.45, 0.82, 0.55, 0.9), fill=(0, 0, 0))


def _envelope(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    width = _w(b, 0.06)
    d.rectangle(_rect(b, 0.05, 0.2, 0.95, 0.8), outline=c, width=width)
    d.line([_p(b, 0.05, 0.2), _p(b, 0.5, 0.55), _p(b, 0.95, 0.2)], fill=c, width=width)


def _cone(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.ellipse(_rect(b, 0.25, 0.05, 0.75, 0.5), fill=c)
    d.polygon([_p(b, 0.25, 0.4), _p(b, 0.75, 0.4), _p(b, 0.5, 0.95)], fill=c)


def _cleaver(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.polygon([_p(b, 0.1, 0.15), _p(b, 0.65, 0.15), _p(b, 0.65, 0.6), _p(b, 0.1, 0.6)], fill=c)
    d.ellipse(_rect(b, 0.15, 0.22, 0.25, 0.32), fill=(0, 0, 0))
    d.rectangle(_rect(b, 0.65, 0.3, 0.95, 0.42), fill=c)


def _spectacles(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    width = _w(b, 0.07)
    for u in (0.25, 0.75):
        d.ellipse(_rect(b, u - 0.2, 0.35, u + 0.2, 0.75), outline=c, width=width)
    d.arc(_rect(b, 0.4, 0.4, 0.6, 0.6), 200, 340, fill=c, width=width)


def _diamond(d: ImageDraw.ImageDraw, b: _Box, c: RGB) -> None:
    d.polygon(
        [_p(b, 0.25, 0.15), _p(b, 0.75, 0.15), _p(b, 0.95, 0.38), _p(b, 0.5, 0.92), _p(b, 0.05, 0.38)], fill=c
    )
    d.line([_p(b, 0.05, 0.38), _p(b, 0.95, 0.38)], fill=(0, 0, 0), width=_w(b, 0.03))


ICONS: dict[str, _Icon] = {
    "restaurant": _fork_knife,
    "cafe": _cup,
    "fast_food": _burger,
    "bar": _glass,
    "bank": _bank,
    "pharmacy": _cross,
    "supermarket": _cart,
    "convenience": _bag,
    "bakery": _bread,
    "clothes": _shirt,
    "hairdresser": _scissors,
    "books": _book,
    "florist": _flower,
    "hardware": _hammer,
    "electronics": _phone,
    "post_office": _envelope,
    "clinic": _ring_cross,
    "ice_cream": _cone,
    "butcher": _cleaver,
    "optician": _spectacles,
    "jewelry": _diamond,
    "shop": _bag,
}
"""Icon drawer per category (``draw(image_draw, (left, top, size), colour)``)."""


@functools.lru_cache(maxsize=64)
def _font(size: int) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    return ImageFont.load_default(size=size)


def _fit_font(
    draw: ImageDraw.ImageDraw, text: str, max_width: float, max_height: float
) -> ImageFont.ImageFont:
    """The largest default font (in 2 px steps) whose rendering of `text` fits the box."""
    size = max(8, int(max_height))
    while size > 8:
        left, top, right, bottom = draw.textbbox((0, 0), text, font=_font(size))
        if right - left <= max_width and bottom - top <= max_height:
            break
        size -= 2
    return _font(size)


def sign_image(
    text: str,
    category: str,
    *,
    background: RGB,
    foreground: RGB,
    aspect: float,
    height_px: int = 128,
    icons: int = 1,
    border: bool = False,
) -> np.ndarray:
    """Draw a sign board: the name centred between one or two category icons.

    Parameters
    ----------
    text : str
        The name; drawn in the default Pillow font, as large as fits.
    category : str
        Place category, choosing the icon from :data:`ICONS` (a bag when it has none).
    background, foreground : tuple of int
        Board and lettering colours.
    aspect : float
        Width over height of the board (> 0); the image keeps it, up to a width of 12 heights.
    height_px : int
        Image height in pixels.
    icons : int
        0 (text only), 1 (icon left of the text) or 2 (icons on both sides).
    border : bool
        Whether to draw a frame line inside the edge.

    Returns
    -------
    ndarray of uint8, shape (height_px, W, 3)
        Row 0 is the top of the board, column 0 its left edge as seen by a reader.
    """
    width_px = int(np.clip(round(aspect * height_px), height_px, 12 * height_px))
    image = Image.new("RGB", (width_px, height_px), background)
    draw = ImageDraw.Draw(image)
    pad = 0.12 * height_px
    if border:
        draw.rectangle(
            [pad / 3, pad / 3, width_px - pad / 3, height_px - pad / 3], outline=foreground, width=3
        )
    icon_size = height_px - 2.0 * pad
    icon = ICONS.get(category, _bag)
    slots = [pad, width_px - pad - icon_size][: max(0, min(icons, 2))]
    for left in slots:
        icon(draw, (left, pad, icon_size), foreground)
    text_left = pad + (icon_size + pad if slots else 0.0)
    text_right = width_px - pad - (icon_size + pad if len(slots) == 2 else 0.0)
    font = _fit_font(draw, text, text_right - text_left, 0.62 * height_px)
    centre = (0.5 * (text_left + text_right), 0.5 * height_px)
    draw.text(centre, text, fill=foreground, font=font, anchor="mm")
    return np.asarray(image, dtype=np.uint8).copy()


_NOT_IDENTIFIER = re.compile(r"[^A-Za-z0-9_]")


def texture_name(category: str, design: int, text: str, image: np.ndarray) -> str:
    """A USD identifier naming a sign texture by its content.

    ``sign_<category>_<design>_<hash>``, where the hash covers the text and the image pixels, so two
    signs share a name exactly when they show the same image.
    """
    digest = hashlib.sha1(text.encode("utf-8"))
    digest.update(repr(image.shape).encode())
    digest.update(np.ascontiguousarray(image).tobytes())
    return _NOT_IDENTIFIER.sub("_", f"sign_{category}_{design}_{digest.hexdigest()[:12]}")
