"""Clipping a segment to an axis-aligned rectangle (Liang–Barsky), shared by the OSM reader and the
synthetic street networks.

:func:`clip_segment` gives the parameters ``(t0, t1)`` of the part of segment ``a``→``b`` inside the
closed rectangle; a caller places the clipped end points itself, as ``a + t * (b - a)``, and keeps an
end point inside as it is (``t0 == 0``, ``t1 == 1``), so the same segment always clips to the same
numbers.
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["Rect", "clip_segment"]

Rect = tuple[float, float, float, float]
"""``(min_x, min_y, max_x, max_y)``."""


def clip_segment(a: Sequence[float], b: Sequence[float], rect: Rect) -> tuple[float, float] | None:
    """Parameters ``(t0, t1)`` of the part of segment a→b inside ``rect`` (Liang–Barsky), or None.

    Parameters
    ----------
    a, b : sequence of float
        The segment's end points (x, y): tuples or arrays.
    rect : (min_x, min_y, max_x, max_y)
        The closed rectangle.

    Returns
    -------
    (float, float) or None
        ``0 <= t0 <= t1 <= 1``, the part inside being ``a + t * (b - a)`` for ``t`` in ``[t0, t1]``;
        None when the segment misses the rectangle.
    """
    t0, t1 = 0.0, 1.0
    dx, dy = b[0] - a[0], b[1] - a[1]
    for p, q in ((-dx, a[0] - rect[0]), (dx, rect[2] - a[0]), (-dy, a[1] - rect[1]), (dy, rect[3] - a[1])):
        if p == 0.0:
            if q < 0.0:
                return None
            continue
        t = q / p
        if p < 0.0:
            t0 = max(t0, t)
        else:
            t1 = min(t1, t)
        if t0 > t1:
            return None
    return t0, t1
