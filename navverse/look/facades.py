"""Facades: the frame of each building wall, and the windows, frames, doors and plinth painted on it.

A facade frame is a building's facade (its base segment from the scene's annotations) with the
building's base and height, its facade style (:data:`~navverse.look.materials.FACADE_STYLES`, by the
map's building type) and storey height (the map's levels when given, else the style's), and up to
:data:`DOORS_PER_FACADE` doors where the building has mapped entrances on it. On a hit, the point's
distance along the facade ``s`` and height above the base ``h`` place it: the facade is cut into
whole bays of about the style's bay width and into storeys; a window sits in the middle of each bay
at the style's sill height on every storey (on the ground floor of a shop or office, one wide shop
window per bay instead), framed; no window within 0.6 m of the top; doors at the entrances; a plinth
at the foot.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit

from navverse.look.materials import FACADE_STYLES, MATERIALS, material_index, srgb_to_linear
from navverse.scene.annotations import BuildingAnnotation

__all__ = [
    "BASE",
    "DOORS_PER_FACADE",
    "DX",
    "DY",
    "HEIGHT",
    "LENGTH",
    "OVERLAY_ALBEDO",
    "OVERLAY_NAMES",
    "STOREY",
    "STYLE",
    "SX",
    "SY",
    "FacadeFrames",
    "FacadePaint",
    "facade_frames",
]

DOORS_PER_FACADE = 2
"""Entrances drawn per facade (the first ones on it)."""
_STYLE_NAMES = tuple(FACADE_STYLES)
_WINDOW_W = np.array([s.window[0] for s in FACADE_STYLES.values()])
_WINDOW_H = np.array([s.window[1] for s in FACADE_STYLES.values()])
_SILL = np.array([s.sill for s in FACADE_STYLES.values()])
_BAY = np.array([s.bay for s in FACADE_STYLES.values()])
_SHOP = np.array([s.shop_front for s in FACADE_STYLES.values()])
_WALLS = np.array([material_index(s.wall) for s in FACADE_STYLES.values()], dtype=np.int32)
_PLINTH = 0.4  # m
_FRAME = 0.07  # m of frame around windows
_DOOR_HEIGHT = 2.3  # m
_TOP_CLEAR = 0.6  # m without windows under the roof line
# Columns of a frame row.
SX, SY, DX, DY, LENGTH, BASE, HEIGHT, STOREY, STYLE = range(9)
_DOOR0 = 9  # then (at, width) per door; NaN where there is none
_COLUMNS = _DOOR0 + 2 * DOORS_PER_FACADE
_OVERLAYS = ("glass", "frame", "door", "plinth")
_GLASS_OVERLAY, _FRAME_OVERLAY, _DOOR_OVERLAY, _PLINTH_OVERLAY = range(len(_OVERLAYS))
# Per style: window width, window height, sill, bay, shop front (0/1), wall material.
_STYLE_TABLE = np.column_stack([_WINDOW_W, _WINDOW_H, _SILL, _BAY, _SHOP, _WALLS]).astype(np.float64)


@dataclass(frozen=True)
class FacadePaint:
    """What facade hits show.

    Attributes
    ----------
    s, h : ndarray of float64, shape (K,)
        Distance along the facade from its start and height above the building's base (m): the wall
        material's surface coordinates.
    wall : ndarray of int32, shape (K,)
        The wall material (its index in :data:`~navverse.look.materials.MATERIAL_NAMES`) of each hit's
        facade style.
    overlay : ndarray of int8, shape (K,)
        Index into :data:`OVERLAY_NAMES` of the overlay at each hit, ``-1`` for bare wall.
    """

    s: np.ndarray
    h: np.ndarray
    wall: np.ndarray
    overlay: np.ndarray


OVERLAY_NAMES = _OVERLAYS
"""Materials painted over a facade's wall, by overlay index (each a :data:`MATERIALS` name)."""
OVERLAY_ALBEDO = np.stack([srgb_to_linear(MATERIALS[name].color) for name in _OVERLAYS], axis=1)
"""Linear albedo ``(3, 4)`` of each overlay."""


@dataclass(frozen=True, eq=False)
class FacadeFrames:
    """Every facade frame of a scene, one row each (see the module's docstring for the columns)."""

    rows: np.ndarray

    def paint(self, frame: np.ndarray, points: np.ndarray) -> FacadePaint:
        """Paint the hits at world `points` ``(K, 3)`` on facades `frame` ``(K,)`` (row indices)."""
        count = len(frame)
        s, h = np.empty(count), np.empty(count)
        wall = np.empty(count, dtype=np.int32)
        overlay = np.empty(count, dtype=np.int8)
        _paint_hits(
            self.rows, np.ascontiguousarray(frame, dtype=np.int64), np.ascontiguousarray(points, np.float64),
            _STYLE_TABLE, s, h, wall, overlay,
        )  # fmt: skip
        return FacadePaint(s=s, h=h, wall=wall, overlay=overlay)


@njit(cache=True, nogil=True)
def _paint_hits(
    rows: np.ndarray,
    frame: np.ndarray,
    points: np.ndarray,
    styles: np.ndarray,
    s_out: np.ndarray,
    h_out: np.ndarray,
    wall: np.ndarray,
    overlay: np.ndarray,
) -> None:
    """Per hit: its place ``(s, h)`` on its facade, the wall material and the overlay painted there
    (an index into ``_OVERLAYS``, -1 for none; a door over glass over a frame over the plinth)."""
    for k in range(frame.shape[0]):
        r = frame[k]
        s = (points[k, 0] - rows[r, SX]) * rows[r, DX] + (points[k, 1] - rows[r, SY]) * rows[r, DY]
        h = points[k, 2] - rows[r, BASE]
        style = int(rows[r, STYLE])
        window_w, window_h, sill, bay_width, shop = (
            styles[style, 0],
            styles[style, 1],
            styles[style, 2],
            styles[style, 3],
            styles[style, 4] > 0.0,
        )
        storey = rows[r, STOREY]
        bays = max(1.0, float(np.round(rows[r, LENGTH] / bay_width)))
        bay = rows[r, LENGTH] / bays
        across = abs(s - (math.floor(s / bay) + 0.5) * bay)
        level = math.floor(h / storey)
        in_storey = h - level * storey
        width = min(window_w, bay - 0.6)
        top = sill + window_h
        storeyed = (level >= 1 or not shop) and h < rows[r, HEIGHT] - _TOP_CLEAR and width > 0.3
        glass = storeyed and across < 0.5 * width and sill < in_storey < top
        framed = (
            storeyed
            and not glass
            and across < 0.5 * width + _FRAME
            and sill - _FRAME < in_storey < top + _FRAME
        )
        if level < 1 and shop and across < 0.5 * bay - 0.3 and 0.5 < h < min(storey - 0.7, 3.2):
            glass = True
        door = False
        for d in range(DOORS_PER_FACADE):
            at, door_width = rows[r, _DOOR0 + 2 * d], rows[r, _DOOR0 + 2 * d + 1]
            if abs(s - at) < 0.5 * door_width and h < _DOOR_HEIGHT:  # NaN (no door) compares False
                door = True
        painted = -1
        if door:
            painted = _DOOR_OVERLAY
        elif glass:
            painted = _GLASS_OVERLAY
        elif framed:
            painted = _FRAME_OVERLAY
        elif h < _PLINTH:
            painted = _PLINTH_OVERLAY
        s_out[k], h_out[k] = s, h
        wall[k] = int(styles[style, 5])
        overlay[k] = painted


def facade_frames(
    buildings: Sequence[BuildingAnnotation], styles: dict[int, tuple[str, float | None]]
) -> tuple[FacadeFrames, dict[tuple[int, int], int]]:
    """The frames of the buildings' facades.

    Parameters
    ----------
    buildings : sequence of BuildingAnnotation
        The scene's buildings.
    styles : dict
        By building id, its facade style name and its number of levels (None: by the style's storey
        height).

    Returns
    -------
    FacadeFrames
        One row per facade of a building in `styles`.
    dict
        The row of each ``(building id, facade id)``.
    """
    rows, index = [], {}
    for building in buildings:
        if building.id not in styles:
            continue
        style_name, levels = styles[building.id]
        style = FACADE_STYLES[style_name]
        storey = building.height / levels if levels and levels >= 1 else style.storey
        for facade in building.facades:
            (x0, y0), (x1, y1) = facade.segment
            length = float(np.hypot(x1 - x0, y1 - y0))
            dx, dy = (x1 - x0) / length, (y1 - y0) / length
            row = [x0, y0, dx, dy, length, building.base_height, building.height, storey]
            row += [_STYLE_NAMES.index(style_name)] + [np.nan] * (2 * DOORS_PER_FACADE)
            doors = [e for e in building.exits if e.facade == facade.id][:DOORS_PER_FACADE]
            for k, entrance in enumerate(doors):
                at = (entrance.center[0] - x0) * dx + (entrance.center[1] - y0) * dy
                row[_DOOR0 + 2 * k : _DOOR0 + 2 * k + 2] = [at, entrance.width]
            index[(building.id, facade.id)] = len(rows)
            rows.append(row)
    return FacadeFrames(np.asarray(rows, dtype=np.float64).reshape(-1, _COLUMNS)), index
