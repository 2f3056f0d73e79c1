"""Furnish the rooms of a floorplan: rule by rule, with rejection sampling and bounded retries.

Each candidate placement must lie inside the room, overlap no other footprint (a 1 cm gap is kept),
stay out of the zone in front of every doorway, leave its own front clearance free, and keep the
room connected for the robot (:class:`~navverse.indoor.occupancy.FreeSpace`): every doorway reachable
and nearly all free floor in one piece. Items of ``surface`` placement stand on the support areas of
furniture already placed; ``wall_mounted`` ones hang on walls above the floor.

Yaw follows the asset frame (:mod:`navverse.assets`): an object's front faces its local +y, so yaw 0
turns its front to world +y.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from shapely.geometry import Polygon, box

from navverse.assets.library import Asset, SupportArea, asset
from navverse.indoor.floorplan import WALL_THICKNESS, Floorplan, Room
from navverse.indoor.occupancy import FreeSpace, footprint_corners
from navverse.indoor.programs import Furniture
from navverse.scene.geometry import MeshData

__all__ = ["Placement", "furnish_room"]

_GAP = 0.01  # kept between footprints (m)
_TRIES = 40  # candidate positions per piece
_KEEPOUT_DEPTH = 1.3  # free floor in front of a doorway (m)
_ANCHOR_DEPTH = 0.8  # where the robot must be able to stand in front of a doorway (m)
_LOW = 0.08  # objects lower than this (rugs) do not block the robot (m)
_ROBOT_HEIGHT = 0.6  # wall-mounted items hanging lower than this are obstacles (m)
_SIDES = ("south", "east", "north", "west")
# Yaw that turns an object's front (local +y) away from the wall on that side, into the room.
_YAW_FROM_WALL = {"south": 0.0, "east": math.pi / 2, "north": math.pi, "west": -math.pi / 2}


@dataclass(frozen=True)
class Placement:
    """A placed object: asset category, bounding-box centre (world), size, yaw, local mesh, room."""

    category: str
    center: tuple[float, float, float]
    size: tuple[float, float, float]
    yaw: float
    mesh: MeshData
    room_id: int
    carrier: int | None = None  # index (in the room's placements) of the object it stands on


@dataclass
class _Surface:
    """A support area of a placed object, in world coordinates, and what already stands on it."""

    owner: int
    category: str
    top: float  # world z of the surface
    corners: np.ndarray  # (4, 2) world corners of the usable rectangle
    frame: tuple[float, float, float]  # owner centre x, y and yaw
    area: SupportArea
    items: list[Polygon] = field(default_factory=list)


class _Room:
    """The furnishing state of one room."""

    def __init__(self, plan: Floorplan, room: Room, rng: np.random.Generator) -> None:
        self.room = room
        self.rng = rng
        self.interior = room.interior
        self.bounds = box(self.interior.x0, self.interior.y0, self.interior.x1, self.interior.y1)
        anchors, self.keepouts = [], []
        for door in plan.doors_of(room.id):
            inward = self._inward(door.center, door.axis)
            cx, cy = door.center
            depth = WALL_THICKNESS / 2
            anchors.append(
                (cx + inward[0] * (depth + _ANCHOR_DEPTH), cy + inward[1] * (depth + _ANCHOR_DEPTH))
            )
            half = door.width / 2 + 0.15
            if door.axis == "x":
                y_far = cy + inward[1] * (depth + _KEEPOUT_DEPTH)
                self.keepouts.append(box(cx - half, min(cy, y_far), cx + half, max(cy, y_far)))
            else:
                x_far = cx + inward[0] * (depth + _KEEPOUT_DEPTH)
                self.keepouts.append(box(min(cx, x_far), cy - half, max(cx, x_far), cy + half))
        self.free = FreeSpace(self.interior, anchors)
        # Walls of this room that hold an exit of the building.
        self.entrance_sides = {
            ("south" if e.center[1] <= room.rect.y0 + 1e-6 else "north") if e.axis == "x"
            else ("west" if e.center[0] <= room.rect.x0 + 1e-6 else "east")
            for e in plan.exits if e.room == room.id
        }  # fmt: skip
        self.footprints: list[Polygon] = []
        self.mounted: list[Polygon] = []  # wall-mounted items, by their footprint on the wall side
        self.placed: list[Placement] = []
        self.surfaces: list[_Surface] = []

    def _inward(self, center: tuple[float, float], axis: str) -> tuple[float, float]:
        """Unit vector from a doorway on this room's boundary into the room."""
        mid_x = (self.room.rect.x0 + self.room.rect.x1) / 2
        mid_y = (self.room.rect.y0 + self.room.rect.y1) / 2
        if axis == "x":
            return (0.0, 1.0 if mid_y > center[1] else -1.0)
        return (1.0 if mid_x > center[0] else -1.0, 0.0)

    # ------------------------------------------------------------------ checks

    def _fits(self, poly: Polygon, *, clearance: Polygon | None = None) -> bool:
        if not self.bounds.buffer(1e-6).contains(poly):
            return False
        grown = poly.buffer(_GAP, join_style="mitre")
        if any(grown.intersects(k) for k in self.keepouts):
            return False
        if any(grown.intersects(f) for f in self.footprints):
            return False
        return clearance is None or not any(clearance.intersects(f) for f in self.footprints)

    def _commit(self, item: Placement, corners: np.ndarray, blocks: bool) -> bool:
        """Keep the placement if the room stays connected; True when kept."""
        cells = self.free.mask(corners) if blocks else np.zeros(self.free.blocked.shape, dtype=bool)
        if blocks and not self.free.connected_with(cells):
            return False
        self.free.block(cells)
        self.footprints.append(Polygon(corners))
        self.placed.append(item)
        self._add_surfaces(len(self.placed) - 1)
        return True

    def _add_surfaces(self, index: int) -> None:
        item = self.placed[index]
        spec = asset(item.category)
        bottom = item.center[2] - item.size[2] / 2
        for area in spec.support_areas(item.size):
            local = np.array([[area.x_min, area.y_min], [area.x_max, area.y_min], [area.x_max, area.y_max],
                              [area.x_min, area.y_max]])  # fmt: skip
            c, s = math.cos(item.yaw), math.sin(item.yaw)
            world = local @ np.array([[c, s], [-s, c]]) + np.asarray(item.center[:2])
            self.surfaces.append(
                _Surface(
                    index, item.category, bottom + area.height, world, (*item.center[:2], item.yaw), area
                )
            )

    # ------------------------------------------------------------------ placement modes

    def _make(self, spec: Asset) -> tuple[MeshData, tuple[float, float, float]]:
        size = spec.sample_size(self.rng)
        mesh = spec.build(self.rng, size)
        lo, hi = mesh.bounds()
        return mesh, tuple(float(v) for v in hi - lo)  # type: ignore[return-value]

    def place_floor(
        self,
        spec: Asset,
        center: tuple[float, float],
        yaw: float,
        *,
        mesh_size: tuple[MeshData, tuple[float, float, float]] | None = None,
        clearance: bool = True,
        reserve: float = 0.0,
    ) -> bool:
        """Stand ``spec`` on the floor at ``center`` turned by ``yaw``, if it fits.

        ``clearance`` checks the asset's front clearance (off for seats that face their table);
        ``reserve`` keeps a ring of that width around the footprint free of other footprints too (room
        for the chairs of a table).
        """
        mesh, size = mesh_size or self._make(spec)
        corners = footprint_corners(center, size, yaw)
        front_zone = None
        if clearance and spec.front_clearance > 0:
            front = np.array([-math.sin(yaw), math.cos(yaw)])
            depth = size[1] / 2 + spec.front_clearance / 2 + _GAP
            front_zone = Polygon(
                footprint_corners(np.asarray(center) + front * depth, (size[0], spec.front_clearance), yaw)
            )
        check = Polygon(footprint_corners(center, (size[0] + 2 * reserve, size[1] + 2 * reserve), yaw))
        if not self._fits(check if reserve else Polygon(corners), clearance=front_zone):
            return False
        item = Placement(spec.category, (center[0], center[1], size[2] / 2), size, yaw, mesh, self.room.id)
        return self._commit(item, corners, blocks=size[2] >= _LOW)

    def _wall_spot(
        self, side: str, size: tuple[float, float, float], where: str
    ) -> tuple[tuple[float, float], float]:
        """A centre against the wall on ``side`` for an object of ``size`` (back to the wall)."""
        r = self.interior
        along_lo, along_hi = (r.x0, r.x1) if side in ("south", "north") else (r.y0, r.y1)
        half = size[0] / 2 + _GAP
        if where == "corner":
            along = along_lo + half if self.rng.random() < 0.5 else along_hi - half
        else:
            along = float(self.rng.uniform(along_lo + half, max(along_lo + half, along_hi - half)))
        off = size[1] / 2 + _GAP
        center = {
            "south": (along, r.y0 + off),
            "north": (along, r.y1 - off),
            "west": (r.x0 + off, along),
            "east": (r.x1 - off, along),
        }[side]
        return center, _YAW_FROM_WALL[side]

    def _sides_by_length(self, *, entrance_first: bool = False) -> list[str]:
        r = self.interior
        lengths = {"south": r.width, "north": r.width, "east": r.depth, "west": r.depth}
        weights = np.array([lengths[s] for s in _SIDES])
        sides = [_SIDES[i] for i in self.rng.choice(4, size=4, replace=False, p=weights / weights.sum())]
        if entrance_first and self.entrance_sides:
            sides = [s for s in sides if s in self.entrance_sides] + [
                s for s in sides if s not in self.entrance_sides
            ]
        return sides

    def place_wall(
        self, spec: Asset, *, where: str = "wall", mesh_size=None, near_entrance: bool = False
    ) -> int | None:
        """Stand ``spec`` against a wall (or in a corner; on the entrance wall first when asked)."""
        mesh, size = mesh_size or self._make(spec)
        for _ in range(_TRIES // 4):
            for side in self._sides_by_length(entrance_first=near_entrance):
                center, yaw = self._wall_spot(side, size, where)
                if self.place_floor(spec, center, yaw, mesh_size=(mesh, size)):
                    return len(self.placed) - 1
        return None

    def place_free(
        self, spec: Asset, *, mesh_size=None, reserve: float = 0.0, tilt: float = 0.25
    ) -> int | None:
        """Stand ``spec`` somewhere in the room, aligned with the walls to within ``tilt`` rad."""
        mesh, size = mesh_size or self._make(spec)
        r = self.interior
        reach = math.hypot(size[0], size[1]) / 2 + reserve
        if r.width < 2 * reach or r.depth < 2 * reach:
            return None
        for _ in range(_TRIES):
            center = (float(self.rng.uniform(r.x0 + reach, r.x1 - reach)),
                      float(self.rng.uniform(r.y0 + reach, r.y1 - reach)))  # fmt: skip
            yaw = float(self.rng.integers(4)) * math.pi / 2 + float(self.rng.uniform(-tilt, tilt))
            if self.place_floor(spec, center, yaw, mesh_size=(mesh, size), reserve=reserve):
                return len(self.placed) - 1
        return None

    def place_on(self, spec: Asset, carriers: tuple[str, ...], *, only: int | None = None) -> bool:
        """Stand a small item on a support area of a placed object (of ``carriers`` categories)."""
        options = [
            s for s in self.surfaces
            if (only is None or s.owner == only) and (not carriers or s.category in carriers)
        ]  # fmt: skip
        if not options:
            return False
        mesh, size = self._make(spec)
        for _ in range(_TRIES // 2):
            surface = options[int(self.rng.integers(len(options)))]
            area = surface.area
            room_x, room_y = area.x_max - area.x_min - size[0], area.y_max - area.y_min - size[1]
            if room_x < 0 or room_y < 0:
                continue
            lx = area.x_min + size[0] / 2 + float(self.rng.uniform(0, room_x))
            ly = area.y_min + size[1] / 2 + float(self.rng.uniform(0, room_y))
            ox, oy, oyaw = surface.frame
            c, s = math.cos(oyaw), math.sin(oyaw)
            center = (ox + c * lx - s * ly, oy + s * lx + c * ly)
            footprint = Polygon(footprint_corners(center, size, oyaw))
            if any(footprint.buffer(_GAP).intersects(p) for p in surface.items):
                continue
            surface.items.append(footprint)
            item = Placement(
                spec.category, (center[0], center[1], surface.top + size[2] / 2), size, oyaw, mesh,
                self.room.id, carrier=surface.owner,
            )  # fmt: skip
            self.placed.append(item)
            self._add_surfaces(len(self.placed) - 1)
            return True
        return False

    def place_mounted(self, spec: Asset) -> bool:
        """Hang ``spec`` on a wall, its bottom at the asset's mount height, clear of doorways."""
        mesh, size = self._make(spec)
        low, high = spec.mount_height or (1.0, 1.2)
        for _ in range(_TRIES // 4):
            for side in self._sides_by_length():
                center, yaw = self._wall_spot(side, size, "wall")
                poly = Polygon(footprint_corners(center, size, yaw))
                grown = poly.buffer(_GAP, join_style="mitre")
                if not self.bounds.buffer(1e-6).contains(poly) or any(
                    grown.intersects(k) for k in self.keepouts
                ):
                    continue
                if any(grown.intersects(m) for m in self.mounted):
                    continue
                bottom = float(self.rng.uniform(low, high))
                item = Placement(spec.category, (center[0], center[1], bottom + size[2] / 2), size, yaw, mesh,
                                 self.room.id)  # fmt: skip
                if bottom < _ROBOT_HEIGHT:  # it hangs low enough to be in the robot's way (a curtain)
                    corners = footprint_corners(center, size, yaw)
                    if not self._fits(Polygon(corners)) or not self._commit(item, corners, blocks=True):
                        continue
                else:
                    self.placed.append(item)
                self.mounted.append(poly)
                return True
        return False

    def attach(self, index: int, rule: Furniture) -> int:
        """Complete a placed piece into a unit: ``rule.seat`` in front facing it, ``rule.on_top`` on it."""
        piece = self.placed[index]
        placed = 0
        if rule.seat:
            seat = asset(rule.seat)
            mesh, size = self._make(seat)
            front = np.array([-math.sin(piece.yaw), math.cos(piece.yaw)])
            center = np.asarray(piece.center[:2]) + front * (piece.size[1] / 2 + size[1] / 2 + 0.05)
            placed += self.place_floor(seat, (float(center[0]), float(center[1])), piece.yaw + math.pi,
                                       mesh_size=(mesh, size), clearance=False)  # fmt: skip
        if rule.on_top:
            placed += self.place_on(asset(rule.on_top), (), only=index)
        return placed

    def place_table_group(self, spec: Asset, rule: Furniture) -> int:
        """A table in the open with seats spread along its long sides (and ends), facing it."""
        seat = asset(rule.seat)
        seat_mesh, seat_size = self._make(seat)
        index = self.place_free(spec, reserve=seat_size[1] + 0.1, tilt=0.0)
        if index is None:
            return 0
        table = self.placed[index]
        wanted = int(self.rng.integers(rule.seats[0], rule.seats[1] + 1))
        long_x = table.size[0] >= table.size[1]
        long_len, short_len = (table.size[0], table.size[1]) if long_x else (table.size[1], table.size[0])
        per_side = min(max(1, (wanted + 1) // 2), max(1, int(long_len // (seat_size[0] + 0.1))))
        ends = min(2, max(0, wanted - 2 * per_side)) if short_len >= seat_size[0] else 0
        slots: list[tuple[float, float]] = []  # (along the long side, across) in table units
        for side in (1.0, -1.0):
            slots += [((i + 0.5) / per_side - 0.5, side) for i in range(per_side)]
        slots += [(side, 0.0) for side in (1.0, -1.0)][:ends]
        c, s = math.cos(table.yaw), math.sin(table.yaw)
        placed = 1
        for along, across in slots[:wanted]:
            if across:
                a, b = along * long_len, across * (short_len / 2 + seat_size[1] / 2 + 0.05)
            else:
                a, b = along * (long_len / 2 + seat_size[1] / 2 + 0.05), 0.0
            lx, ly = (a, b) if long_x else (b, a)
            center = (table.center[0] + c * lx - s * ly, table.center[1] + s * lx + c * ly)
            # Face the table: the seat's front (+y) points from the seat to the table.
            yaw = math.atan2(-(table.center[0] - center[0]), table.center[1] - center[1])
            placed += self.place_floor(seat, center, yaw, mesh_size=(seat_mesh, seat_size), clearance=False)
        return placed

    def place_desk_group(self, spec: Asset, rule: Furniture) -> int:
        """A desk against a wall with its seat and item: how many pieces were placed."""
        index = self.place_wall(spec)
        return 0 if index is None else 1 + self.attach(index, rule)

    def place_rows(self, spec: Asset, rule: Furniture, count: int) -> int:
        """A block of rows with aisles, centred in the room (shelves, desks): how many pieces placed."""
        mesh, size = self._make(spec)
        seat_depth = 0.0
        if rule.seat:
            seat_depth = self._make(asset(rule.seat))[1][1] + 0.1
        r = self.interior.shrunk(0.9)  # aisles along the walls too
        along_x = r.width >= r.depth
        length, across = (r.width, r.depth) if along_x else (r.depth, r.width)
        aisle = float(self.rng.uniform(1.5, 1.8))
        pitch = size[1] + seat_depth + aisle
        max_rows = int((across + aisle) // pitch)
        per_row_max = int((length + rule.spacing) // (size[0] + rule.spacing))
        if max_rows < 1 or per_row_max < 1 or count < 1:
            return 0
        # Rows about 60 % of the longest possible, so the block has several rows and cross aisles.
        rows = min(max_rows, max(1, math.ceil(count / max(1.0, 0.6 * per_row_max))))
        per_row = min(per_row_max, math.ceil(count / rows))
        block_len = per_row * (size[0] + rule.spacing) - rule.spacing
        block_depth = rows * pitch - aisle
        start_along = (length - block_len) / 2
        start_across = (across - block_depth) / 2
        base = 0.0 if along_x else -math.pi / 2
        placed = 0
        for row in range(rows):
            yaw = base + (math.pi if rule.alternate and row % 2 else 0.0)
            # The piece sits at the back of its row's band, its seat (if any) in front of it.
            flip = rule.alternate and row % 2
            offset = start_across + row * pitch + (size[1] / 2 + seat_depth if flip else size[1] / 2)
            for k in range(per_row):
                if placed >= count:
                    return placed
                t = start_along + k * (size[0] + rule.spacing) + size[0] / 2
                center = (r.x0 + t, r.y0 + offset) if along_x else (r.x0 + offset, r.y0 + t)
                if self.place_floor(spec, center, yaw, mesh_size=(mesh, size), clearance=False):
                    placed += 1
                    self.attach(len(self.placed) - 1, rule)
        return placed


def _count(rule: Furniture, rng: np.random.Generator, density: float) -> int:
    lo, hi = rule.count
    n = int(rng.integers(lo, hi + 1))
    return max(0, round(n * density))


def furnish_room(
    plan: Floorplan,
    room: Room,
    rules: tuple[Furniture, ...],
    rng: np.random.Generator,
    *,
    density: float = 1.0,
    allowed: Callable[[str], bool] = lambda category: True,
) -> list[Placement]:
    """Furnish one room of a floorplan.

    Parameters
    ----------
    plan : Floorplan
        The building (for the room's doorways).
    room : Room
        The room to furnish.
    rules : tuple of Furniture
        Its furniture rules, in order.
    rng : numpy.random.Generator
        The only randomness.
    density : float
        Multiplies the counts of every rule.
    allowed : callable
        Whether a category may be placed (recipes can exclude categories).

    Returns
    -------
    list of Placement
        What was placed, in order; carriers refer to indices in this list.
    """
    state = _Room(plan, room, rng)
    for rule in rules:
        if not allowed(rule.category) or (rule.seat and not allowed(rule.seat)):
            continue
        if rule.chance < 1.0 and rng.random() >= rule.chance:
            continue
        count = _count(rule, rng, density)
        spec = asset(rule.category)
        if rule.mode == "rows":
            state.place_rows(spec, rule, count)
            continue
        for _ in range(count):
            if rule.mode == "table_group":
                state.place_table_group(spec, rule)
            elif rule.mode == "desk_group":
                state.place_desk_group(spec, rule)
            elif rule.mode in ("wall", "corner"):
                state.place_wall(spec, where=rule.mode, near_entrance=rule.near_entrance)
            elif rule.mode == "free":
                state.place_free(spec)
            elif spec.placement == "surface":
                state.place_on(spec, rule.on)
            elif spec.placement == "wall_mounted":
                state.place_mounted(spec)
            elif spec.placement == "wall":
                state.place_wall(spec)
            else:
                state.place_free(spec)
    return state.placed
