"""Deterministic colours for names without an assigned colour (e.g. object categories)."""

from __future__ import annotations

import colorsys
import hashlib
from collections.abc import Sequence

import numpy as np

__all__ = ["RGB", "default_color", "lighten", "linear_to_srgb", "srgb_to_linear"]

RGB = tuple[int, int, int]


def default_color(name: str) -> RGB:
    """Return a stable, saturated colour for `name`.

    The hue comes from a SHA-256 digest of the name (not Python's salted ``hash``), so the same name
    gets the same colour in every process and on every machine.

    Parameters
    ----------
    name : str
        Any label, e.g. an object category.

    Returns
    -------
    tuple of int
        ``(r, g, b)`` in 0..255.
    """
    digest = hashlib.sha256(name.encode("utf-8")).digest()
    hue = int.from_bytes(digest[:2], "big") / 65536.0
    saturation = 0.55 + 0.35 * digest[2] / 255.0
    value = 0.70 + 0.25 * digest[3] / 255.0
    r, g, b = colorsys.hsv_to_rgb(hue, saturation, value)
    return (round(r * 255), round(g * 255), round(b * 255))


def lighten(color: RGB, amount: float) -> RGB:
    """Blend `color` towards white.

    Parameters
    ----------
    color : tuple of int
        ``(r, g, b)`` in 0..255.
    amount : float
        0 keeps the colour, 1 gives white.

    Returns
    -------
    tuple of int
        The lighter colour.
    """
    if not 0.0 <= amount <= 1.0:
        raise ValueError(f"amount must be in [0, 1], got {amount}")
    r, g, b = (round(c + (255 - c) * amount) for c in color)
    return (r, g, b)


def srgb_to_linear(values: np.ndarray | Sequence[float]) -> np.ndarray:
    """Linear RGB in [0, 1] (float32) of sRGB values in 0..255 (the standard transfer function)."""
    c = np.asarray(values, dtype=np.float64) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4).astype(np.float32)


def linear_to_srgb(values: np.ndarray | Sequence[float]) -> np.ndarray:
    """sRGB bytes of linear RGB values in [0, 1] (clipped)."""
    c = np.clip(np.asarray(values, dtype=np.float64), 0.0, 1.0)
    srgb = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1.0 / 2.4) - 0.055)
    return np.rint(srgb * 255.0).astype(np.uint8)
