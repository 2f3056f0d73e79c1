"""The rooms a look lights: one lamp under each room's ceiling, and which room a point is in.

Indoor light comes from the rooms' lamps, not the sky: a point inside an indoor building takes its
room's lamp (with a shadow) and the light the room bounces around, while the sky's light is for points
in the open. Which room a point is in is read from a raster of the rooms' floor polygons
(:data:`ROOM_CELL` cells), each grown by :data:`ROOM_MARGIN` so that the doorways between rooms count
as in a room; where grown rooms overlap, the first room wins. A wall's face belongs to the room it
faces: callers lift a hit off its surface before asking.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numba import njit
from shapely.geometry import Polygon

from navverse.scene.annotations import SceneAnnotations

__all__ = ["LAMP_BELOW_CEILING", "ROOM_CELL", "ROOM_MARGIN", "RoomLights", "room_lights"]

ROOM_CELL = 0.1
"""Side of a room-raster cell in meters."""
ROOM_MARGIN = 0.12
"""How far a room's polygon is grown in the raster (meters): over half the walls between rooms, so the
floor of a doorway belongs to a room, but not out to the outer faces of outer walls."""
LAMP_BELOW_CEILING = 0.3
"""How far below the ceiling a room's lamp hangs (meters)."""


@dataclass(frozen=True)
class RoomLights:
    """The lamps of a scene's rooms and a raster of which room covers each place.

    Attributes
    ----------
    lamps : ndarray of float64, shape (R, 3)
        World position of each room's lamp.
    floors, ceilings : ndarray of float64, shape (R,)
        World height of each room's floor and ceiling.
    origin : ndarray, shape (2,)
        World xy of the raster's lower-left corner.
    raster : ndarray of int32, shape (rows, cols)
        Room index per cell (row = y, col = x), ``-1`` outside every room.
    room_types : tuple of str
        Each room's type.
    """

    lamps: np.ndarray
    floors: np.ndarray
    ceilings: np.ndarray
    origin: np.ndarray
    raster: np.ndarray
    room_types: tuple[str, ...] = ()

    @property
    def empty(self) -> bool:
        """Whether the scene has no room."""
        return len(self.lamps) == 0

    def room_at(self, points: np.ndarray, *, lift: np.ndarray | None = None) -> np.ndarray:
        """Index of the room holding each of `points` ((N, 3) world), ``-1`` where none does.

        A point above a room's ceiling or below its floor (by more than 10 cm) is in no room. With
        `lift` ((N, 3)), each point is first moved by it.
        """
        room = np.full(len(points), -1, dtype=np.int32)
        if not self.empty:
            offset = np.zeros((1, 3)) if lift is None else np.asarray(lift, dtype=np.float64)
            _rooms_at(
                np.ascontiguousarray(points, dtype=np.float64), offset, self.raster, self.origin,
                self.floors, self.ceilings, room,
            )  # fmt: skip
        return room


@njit(cache=True, nogil=True)
def _rooms_at(
    points: np.ndarray,
    lift: np.ndarray,
    raster: np.ndarray,
    origin: np.ndarray,
    floors: np.ndarray,
    ceilings: np.ndarray,
    room: np.ndarray,
) -> None:
    """The raster's room under each point moved by its `lift` (one row: the same for all), kept where
    the point is within 10 cm of that room's floor-to-ceiling span."""
    rows, cols = raster.shape
    same = lift.shape[0] == 1
    for k in range(points.shape[0]):
        d = 0 if same else k
        x = points[k, 0] + lift[d, 0]
        y = points[k, 1] + lift[d, 1]
        z = points[k, 2] + lift[d, 2]
        col = math.floor((x - origin[0]) / ROOM_CELL)
        row = math.floor((y - origin[1]) / ROOM_CELL)
        if col < 0 or col >= cols or row < 0 or row >= rows:
            continue
        r = raster[int(row), int(col)]
        if r >= 0 and floors[r] - 0.1 <= z <= ceilings[r] + 0.1:
            room[k] = r


def room_lights(annotations: SceneAnnotations) -> RoomLights:
    """The lamps and the room raster of the indoor buildings of a scene.

    Parameters
    ----------
    annotations : SceneAnnotations
        The scene's annotations; rooms of buildings not marked ``indoor`` are ignored.

    Returns
    -------
    RoomLights
    """
    polygons: list[Polygon] = []
    lamps, floors, ceilings, types = [], [], [], []
    for building in annotations.buildings:
        if not building.indoor:
            continue
        for room in building.rooms:
            polygon = shapely.make_valid(Polygon(room.polygon))
            if polygon.is_empty or polygon.area <= 0.0:
                continue
            floor = building.base_height + room.floor_height
            ceiling = building.base_height + building.height
            spot = polygon.centroid if polygon.contains(polygon.centroid) else polygon.representative_point()
            lamps.append((spot.x, spot.y, max(floor + 0.5, ceiling - LAMP_BELOW_CEILING)))
            floors.append(floor)
            ceilings.append(ceiling)
            types.append(room.room_type)
            polygons.append(polygon.buffer(ROOM_MARGIN, join_style="mitre"))
    if not polygons:
        return RoomLights(
            np.zeros((0, 3)), np.zeros(0), np.zeros(0), np.zeros(2), np.full((1, 1), -1, np.int32)
        )
    lo = np.min([p.bounds[:2] for p in polygons], axis=0)
    hi = np.max([p.bounds[2:] for p in polygons], axis=0)
    origin = np.floor(lo / ROOM_CELL) * ROOM_CELL
    cols, rows = (np.ceil((hi - origin) / ROOM_CELL).astype(int) + 1).tolist()
    xs = origin[0] + (np.arange(cols) + 0.5) * ROOM_CELL
    ys = origin[1] + (np.arange(rows) + 0.5) * ROOM_CELL
    grid_x, grid_y = np.meshgrid(xs, ys)
    raster = np.full((rows, cols), -1, dtype=np.int32)
    for index in reversed(range(len(polygons))):  # the first room is written last: it wins overlaps
        x0, y0, x1, y1 = polygons[index].bounds
        c0, c1 = int((x0 - origin[0]) / ROOM_CELL), int(np.ceil((x1 - origin[0]) / ROOM_CELL)) + 1
        r0, r1 = int((y0 - origin[1]) / ROOM_CELL), int(np.ceil((y1 - origin[1]) / ROOM_CELL)) + 1
        window = (slice(max(r0, 0), min(r1, rows)), slice(max(c0, 0), min(c1, cols)))
        inside = shapely.contains_xy(polygons[index], grid_x[window], grid_y[window])
        raster[window][inside] = index
    return RoomLights(
        lamps=np.asarray(lamps, dtype=np.float64),
        floors=np.asarray(floors, dtype=np.float64),
        ceilings=np.asarray(ceilings, dtype=np.float64),
        origin=origin,
        raster=raster,
        room_types=tuple(types),
    )
