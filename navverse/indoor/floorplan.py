"""Floorplans: a rectangular footprint partitioned into a spine and the rooms along it, with doorways.

The building frame has its origin at the footprint's south-west corner, x along the spine. Walls are
centred on the partition lines (exterior walls on the footprint edge), so a room's free interior is
its partition rectangle shrunk by half a wall thickness on every side.

* ``sides="both"``: the spine (a corridor or living room) runs along x through the middle, rooms line
  the south and the north; the entrance is in the west (and, for two exits, the east) wall.
* ``sides="back"``: the spine is a hall along the south (front) side, rooms line the north (back);
  the entrances are in the south wall.

Every side room has one doorway onto the spine, so every room is connected.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from navverse.errors import SceneError
from navverse.indoor.programs import BuildingProgram

__all__ = ["WALL_THICKNESS", "Door", "Exit", "Floorplan", "Rect", "Room", "generate_floorplan"]

WALL_THICKNESS = 0.16
"""Wall thickness (m)."""
_GRID = 0.05  # partition lines are snapped to 5 cm
_DOOR_MARGIN = 0.35  # free wall between a doorway and a room corner (m)


@dataclass(frozen=True)
class Rect:
    """An axis-aligned rectangle ``[x0, x1] x [y0, y1]`` (m)."""

    x0: float
    y0: float
    x1: float
    y1: float

    @property
    def width(self) -> float:
        """Extent along x."""
        return self.x1 - self.x0

    @property
    def depth(self) -> float:
        """Extent along y."""
        return self.y1 - self.y0

    @property
    def area(self) -> float:
        """Area (m²)."""
        return self.width * self.depth

    def shrunk(self, margin: float) -> Rect:
        """The rectangle with ``margin`` removed on every side."""
        return Rect(self.x0 + margin, self.y0 + margin, self.x1 - margin, self.y1 - margin)

    def corners(self) -> list[tuple[float, float]]:
        """Corners counter-clockwise from (x0, y0)."""
        return [(self.x0, self.y0), (self.x1, self.y0), (self.x1, self.y1), (self.x0, self.y1)]


@dataclass(frozen=True)
class Room:
    """A room: id (>= 1), type and partition rectangle."""

    id: int
    room_type: str
    rect: Rect

    @property
    def interior(self) -> Rect:
        """The free floor inside the walls."""
        return self.rect.shrunk(WALL_THICKNESS / 2)


@dataclass(frozen=True)
class Door:
    """A doorway in the wall between two rooms.

    ``axis`` is the axis the wall runs along (``"x"``: the wall is a line of constant y); ``facing``
    is the yaw of the normal from ``rooms[0]`` into ``rooms[1]``.
    """

    id: int
    center: tuple[float, float]
    width: float
    axis: str
    rooms: tuple[int, int]
    facing: float


@dataclass(frozen=True)
class Exit:
    """A doorway in the exterior wall: the room it opens from and the outward yaw."""

    id: int
    center: tuple[float, float]
    width: float
    axis: str
    room: int
    facing: float


@dataclass(frozen=True)
class Floorplan:
    """A partitioned footprint: rooms (the spine first), doorways between them, exits."""

    footprint: Rect
    rooms: tuple[Room, ...]
    doors: tuple[Door, ...]
    exits: tuple[Exit, ...]
    ceiling_height: float
    building_type: str

    def room(self, room_id: int) -> Room:
        """The room with ``room_id``."""
        for room in self.rooms:
            if room.id == room_id:
                return room
        raise KeyError(room_id)

    @property
    def spine(self) -> Room:
        """The spine room."""
        return self.rooms[0]

    def doors_of(self, room_id: int) -> list[Door | Exit]:
        """Doorways and exits of a room."""
        doors: list[Door | Exit] = [d for d in self.doors if room_id in d.rooms]
        return doors + [e for e in self.exits if e.room == room_id]


def _snap(value: float) -> float:
    return round(value / _GRID) * _GRID


def _uniform(rng: np.random.Generator, bounds: tuple[float, float]) -> float:
    return float(rng.uniform(bounds[0], bounds[1]))


def _room_list(program: BuildingProgram, rng: np.random.Generator) -> list[tuple[str, float, float]]:
    """Side rooms to place: (room type, target area, minimum width), largest first."""
    rooms = []
    for spec in program.rooms:
        count = int(rng.integers(spec.count[0], spec.count[1] + 1))
        rooms += [(spec.room_type, _uniform(rng, spec.area), spec.min_width) for _ in range(count)]
    rooms.sort(key=lambda r: -r[1])
    return rooms


def _order_strip(
    program: BuildingProgram, strip: list[tuple[str, float, float]], rng: np.random.Generator
) -> list[tuple[str, float, float]]:
    """Shuffle a strip's rooms, then move the ones that belong by the entrance to its entrance end."""
    near = {spec.room_type for spec in program.rooms if spec.near_entrance}
    rng.shuffle(strip)
    return [r for r in strip if r[0] in near] + [r for r in strip if r[0] not in near]


def _split_strip(
    rooms: list[tuple[str, float, float]], length: float, depth: float
) -> list[tuple[str, float]]:
    """Widths along a strip for its rooms, proportional to their areas, dropping rooms that do not fit."""
    rooms = list(rooms)
    while rooms:
        widths = [area / depth for _, area, _ in rooms]
        scale = length / sum(widths)
        scaled = [w * scale for w in widths]
        narrow = [i for i, (w, r) in enumerate(zip(scaled, rooms, strict=True)) if w < r[2]]
        if not narrow:
            return [(r[0], w) for r, w in zip(rooms, scaled, strict=True)]
        rooms.pop(max(narrow, key=lambda i: (rooms[i][2] - scaled[i], i)))
    return []


def _cut(x0: float, widths: list[float], x1: float) -> list[tuple[float, float]]:
    """Consecutive intervals from x0 to x1 with these widths, cut lines snapped to the grid."""
    cuts = [x0]
    for w in widths[:-1]:
        cuts.append(_snap(cuts[-1] + w))
    cuts.append(x1)
    return list(itertools.pairwise(cuts))


def _door_along(rng: np.random.Generator, lo: float, hi: float, width: float) -> float | None:
    """A doorway centre on a wall segment [lo, hi], clear of its ends; None if it does not fit."""
    a, b = lo + _DOOR_MARGIN + width / 2, hi - _DOOR_MARGIN - width / 2
    if b < a:
        return None
    return _snap(_uniform(rng, (a, b))) if b - a > _GRID else (a + b) / 2


def depth_range(program: BuildingProgram) -> tuple[float, float]:
    """The footprint depths (across the spine, m) a program's floorplans can have."""
    sides = 2 if program.spine.sides == "both" else 1
    return (
        program.spine.width[0] + sides * program.side_depth[0],
        program.spine.width[1] + sides * program.side_depth[1],
    )


def _split_depth(program: BuildingProgram, depth: float) -> tuple[float, list[float]]:
    """The spine width and side depths that make a footprint `depth` deep."""
    sides = 2 if program.spine.sides == "both" else 1
    lo, hi = depth_range(program)
    if not lo - 1e-9 <= depth <= hi + 1e-9:
        raise SceneError(
            f"a {program.building_type} footprint is {lo:.1f}-{hi:.1f} m deep; {depth:.2f} m was asked"
        )
    # share the depth between spine and side rooms in proportion to where it lies in their ranges
    t = (depth - lo) / (hi - lo) if hi > lo else 0.0
    spine = _snap(program.spine.width[0] + t * (program.spine.width[1] - program.spine.width[0]))
    return spine, [_snap((depth - spine) / sides)] * sides


def generate_floorplan(
    program: BuildingProgram,
    rng: np.random.Generator,
    *,
    length: float | None = None,
    depth: float | None = None,
) -> Floorplan:
    """Partition a footprint for ``program``.

    Parameters
    ----------
    program : BuildingProgram
        The building type.
    rng : numpy.random.Generator
        The only randomness.
    length : float, optional
        Footprint length along the spine (m); sampled from the program by default.
    depth : float, optional
        Footprint depth across the spine (m), within :func:`depth_range`; sampled by default.

    Returns
    -------
    Floorplan

    Raises
    ------
    SceneError
        If no side room fits (footprint far too short for the program), or `depth` is outside the
        program's range.
    """
    length = _snap(length if length is not None else _uniform(rng, program.length))
    both = program.spine.sides == "both"
    if depth is None:  # the draws in this order: the same seed gives the same building as before
        spine_width = _snap(_uniform(rng, program.spine.width))
        rooms_wanted = _room_list(program, rng)
        depths = [_snap(_uniform(rng, program.side_depth)) for _ in range(2 if both else 1)]
    else:
        spine_width, depths = _split_depth(program, depth)
        rooms_wanted = _room_list(program, rng)

    # Distribute side rooms over the strips, largest first, onto the emptier strip.
    strips: list[list[tuple[str, float, float]]] = [[] for _ in depths]
    for room in rooms_wanted:
        load = [sum(r[1] for r in s) / (length * d) for s, d in zip(strips, depths, strict=True)]
        strips[int(np.argmin(load))].append(room)
    strips = [_order_strip(program, strip, rng) for strip in strips]  # room order from x = 0

    if both:
        south_depth, north_depth = depths
        spine = Rect(0.0, south_depth, length, south_depth + spine_width)
        strip_y = [(0.0, south_depth), (spine.y1, spine.y1 + north_depth)]
    else:
        spine = Rect(0.0, 0.0, length, spine_width)
        strip_y = [(spine_width, spine_width + depths[0])]
    footprint = Rect(0.0, 0.0, length, max(y1 for _, y1 in strip_y))

    rooms = [Room(1, program.spine.room_type, spine)]
    doors: list[Door] = []
    for (y0, y1), strip in zip(strip_y, strips, strict=True):
        placed = _split_strip(strip, length, y1 - y0)
        for (room_type, _), (x0, x1) in zip(placed, _cut(0.0, [w for _, w in placed], length), strict=True):
            room = Room(len(rooms) + 1, room_type, Rect(x0, y0, x1, y1))
            rooms.append(room)
            width = _snap(_uniform(rng, program.door_width))
            center_x = _door_along(rng, x0, x1, width)
            if center_x is None:
                raise SceneError(
                    f"room {room_type} ({x1 - x0:.2f} m wide) cannot hold a {width:.2f} m doorway"
                )
            on_spine_y = y0 if y0 >= spine.y1 - 1e-9 else y1
            into_room = math.pi / 2 if on_spine_y == y0 else -math.pi / 2
            doors.append(Door(len(doors) + 1, (center_x, on_spine_y), width, "x", (1, room.id), into_room))
    if len(rooms) == 1:
        raise SceneError(
            f"a {program.building_type} footprint {length:.1f} m long holds none of its rooms; make it longer"
        )

    exits: list[Exit] = []
    for k in range(program.exits):
        width = _snap(_uniform(rng, program.exit_width))
        if both:  # at the ends of the spine: west first, then east
            x = 0.0 if k % 2 == 0 else length
            y = _snap((spine.y0 + spine.y1) / 2)
            exits.append(Exit(k + 1, (x, y), width, "y", 1, math.pi if x == 0.0 else 0.0))
        else:  # in the front (south) wall, spread along it
            slot = length / (program.exits + 1)
            x = _door_along(rng, slot * (k + 1) - slot / 2, slot * (k + 1) + slot / 2, width)
            exits.append(
                Exit(k + 1, (x if x is not None else slot * (k + 1), 0.0), width, "x", 1, -math.pi / 2)
            )
    return Floorplan(
        footprint=footprint,
        rooms=tuple(rooms),
        doors=tuple(doors),
        exits=tuple(exits),
        ceiling_height=round(_uniform(rng, program.ceiling_height), 2),
        building_type=program.building_type,
    )
