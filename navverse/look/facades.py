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

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

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
        row = self.rows.take(frame, axis=0)
        s = (points[:, 0] - row[:, SX]) * row[:, DX] + (points[:, 1] - row[:, SY]) * row[:, DY]
        h = points[:, 2] - row[:, BASE]
        style = row[:, STYLE].astype(np.intp)
        storey = row[:, STOREY]
        bays = np.maximum(1.0, np.round(row[:, LENGTH] / _BAY[style]))
        bay = row[:, LENGTH] / bays
        centred = s - (np.floor(s / bay) + 0.5) * bay
        level = np.floor(h / storey)
        in_storey = h - level * storey
        width = np.minimum(_WINDOW_W[style], bay - 0.6)
        sill, top = _SILL[style], _SILL[style] + _WINDOW_H[style]
        storeyed = ((level >= 1) | ~_SHOP[style]) & (h < row[:, HEIGHT] - _TOP_CLEAR) & (width > 0.3)
        across = np.abs(centred)
        glass = storeyed & (across < 0.5 * width) & (in_storey > sill) & (in_storey < top)
        framed = storeyed & (across < 0.5 * width + _FRAME) & (in_storey > sill - _FRAME)
        framed &= (in_storey < top + _FRAME) & ~glass
        shop_top = np.minimum(storey - 0.7, 3.2)
        glass |= (level < 1) & _SHOP[style] & (across < 0.5 * bay - 0.3) & (h > 0.5) & (h < shop_top)
        door = np.zeros(len(frame), dtype=bool)
        for k in range(DOORS_PER_FACADE):
            at, door_width = row[:, _DOOR0 + 2 * k], row[:, _DOOR0 + 2 * k + 1]
            with np.errstate(invalid="ignore"):
                door |= (np.abs(s - at) < 0.5 * door_width) & (h < _DOOR_HEIGHT)
        overlay = np.full(len(frame), -1, dtype=np.int8)
        for name, mask in (("plinth", h < _PLINTH), ("frame", framed), ("glass", glass), ("door", door)):
            overlay[mask] = _OVERLAYS.index(name)  # later ones win
        return FacadePaint(s=s, h=h, wall=_WALLS.take(style), overlay=overlay)


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
