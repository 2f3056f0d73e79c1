"""Building programs: which rooms a building type has, how large, how they connect, what they hold.

A building is laid out around a *spine*: a corridor, a living room or a main hall that runs the length
of the footprint and touches the exterior where the entrance is. The other rooms line one or both
sides of the spine, each with a doorway onto it (see :mod:`navverse.indoor.floorplan`). Each room
type lists its furniture (see :mod:`navverse.indoor.furnish`); categories name assets of
:mod:`navverse.assets`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Literal

__all__ = [
    "BUILDING_TYPES",
    "PROGRAMS",
    "ROOM_FURNITURE",
    "BuildingProgram",
    "Furniture",
    "RoomSpec",
    "SpineSpec",
]

Range = tuple[float, float]
Mode = Literal["auto", "wall", "free", "corner", "rows", "table_group", "desk_group"]


@dataclass(frozen=True)
class Furniture:
    """One furniture rule of a room type.

    Parameters
    ----------
    category : str
        Asset category.
    count : tuple of int
        Inclusive range of how many to try to place (fewer if they do not fit).
    mode : str
        ``auto``: by the asset's own placement (floor -> free, wall -> against a wall, surface -> on a
        carrier, wall_mounted -> on a wall); ``corner``: against a wall, pushed into a corner;
        ``rows``: a block of rows with aisles in the middle of the room, each piece with ``seat`` in
        front and ``on_top`` on it; ``table_group``: the table with ``seat`` around it;
        ``desk_group``: the desk against a wall with ``seat`` in front and ``on_top`` on it.
    seat : str
        Seat category of groups.
    seats : tuple of int
        Range of seats around a table group.
    on : tuple of str
        For surface items: categories that may carry it (empty: any with a support area).
    on_top : str
        For desk groups and rows: an item placed on each piece.
    chance : float
        Probability that the rule is used at all.
    spacing : float
        For rows: the gap between neighbouring pieces of a row (m).
    alternate : bool
        For rows: every other row faces the other way (shelves facing each other across an aisle).
    near_entrance : bool
        For wall pieces: on the wall with the building's entrance first (checkouts, a counter).
    """

    category: str
    count: tuple[int, int] = (1, 1)
    mode: Mode = "auto"
    seat: str = ""
    seats: tuple[int, int] = (2, 4)
    on: tuple[str, ...] = ()
    on_top: str = ""
    chance: float = 1.0
    spacing: float = 0.05
    alternate: bool = False
    near_entrance: bool = False


@dataclass(frozen=True)
class RoomSpec:
    """A room type of a building program: how many, how large (m², and the narrowest side, m), and
    whether it sits by the entrance (a reception, a hallway)."""

    room_type: str
    count: tuple[int, int]
    area: Range
    min_width: float = 3.2
    near_entrance: bool = False


@dataclass(frozen=True)
class SpineSpec:
    """The spine: its room type, its width across the building (m), and which sides hold rooms."""

    room_type: str
    width: Range
    sides: Literal["both", "back"]


@dataclass(frozen=True)
class BuildingProgram:
    """A building type: footprint, spine, side rooms and entrances.

    ``length`` is the footprint along the spine and ``side_depth`` the depth of the rooms off it. With
    ``sides="back"`` the spine is a hall along the front and rooms line the back; the entrance is in
    the front wall. Otherwise the entrance is at an end of the spine (``exits`` of them).
    """

    building_type: str
    length: Range
    side_depth: Range
    spine: SpineSpec
    rooms: tuple[RoomSpec, ...]
    exits: int = 1
    ceiling_height: Range = (2.7, 3.0)
    door_width: Range = (1.5, 1.8)
    exit_width: Range = (1.8, 2.4)
    description: str = ""
    tags: tuple[str, ...] = field(default=())


def _furniture(**rooms: tuple[Furniture, ...]) -> Mapping[str, tuple[Furniture, ...]]:
    return MappingProxyType(dict(rooms))


F = Furniture

ROOM_FURNITURE: Mapping[str, tuple[Furniture, ...]] = _furniture(
    living_room=(
        F("sofa", (1, 1), "wall"),
        F("tv_stand", (1, 1), "wall"),
        F("tv", (1, 1), on=("tv_stand",)),
        F("coffee_table", (1, 1), "free"),
        F("armchair", (1, 2), "free"),
        F("bookshelf", (1, 2), "wall"),
        F("rug", (1, 1), "free", chance=0.7),
        F("potted_plant", (1, 2), "corner"),
        F("lamp", (1, 1), on=("coffee_table", "bookshelf")),
        F("piano", (1, 1), "wall", chance=0.3),
        F("dining_table", (1, 1), "table_group", seat="chair", seats=(2, 4), chance=0.6),
    ),
    kitchen=(
        F("kitchen_counter", (2, 3), "wall"),
        F("sink", (1, 1), "wall"),
        F("fridge", (1, 1), "wall"),
        F("oven", (1, 1), "wall"),
        F("microwave", (1, 1), on=("kitchen_counter",)),
        F("dining_table", (1, 1), "table_group", seat="chair", seats=(2, 4), chance=0.7),
        F("trash_can", (1, 1), "corner"),
    ),
    bedroom=(
        F("bed", (1, 1), "wall"),
        F("nightstand", (1, 2), "wall"),
        F("lamp", (1, 2), on=("nightstand", "dresser", "desk")),
        F("wardrobe", (1, 1), "wall"),
        F("dresser", (0, 1), "wall"),
        F("desk", (1, 1), "desk_group", seat="office_chair", on_top="laptop", chance=0.5),
        F("rug", (1, 1), "free", chance=0.5),
        F("potted_plant", (0, 1), "corner"),
        F("curtain", (1, 1), chance=0.6),
    ),
    bathroom=(
        F("toilet", (1, 1), "wall"),
        F("sink", (1, 1), "wall"),
        F("bathtub", (1, 1), "corner", chance=0.6),
        F("shower", (1, 1), "corner", chance=0.6),
        F("washing_machine", (1, 1), "wall", chance=0.5),
        F("trash_can", (1, 1), "corner"),
    ),
    hallway=(
        F("coat_rack", (1, 1), "wall"),
        F("potted_plant", (1, 2), "corner"),
        F("bench", (0, 1), "wall"),
    ),
    corridor=(
        F("potted_plant", (1, 3), "corner"),
        F("trash_can", (1, 2), "wall"),
        F("bench", (1, 2), "wall"),
        F("water_dispenser", (1, 1), "wall"),
        F("vending_machine", (0, 1), "wall"),
    ),
    reception=(
        F("reception_desk", (1, 1), "wall"),
        F("office_chair", (1, 1), "free"),
        F("monitor", (1, 1), on=("reception_desk",)),
        F("armchair", (2, 3), "wall"),
        F("coffee_table", (1, 1), "free"),
        F("potted_plant", (2, 3), "corner"),
        F("water_dispenser", (1, 1), "wall"),
        F("coat_rack", (1, 1), "wall"),
    ),
    open_office=(
        F("desk", (4, 10), "rows", seat="office_chair", on_top="monitor", spacing=0.3),
        F("desk", (1, 2), "desk_group", seat="office_chair", on_top="laptop"),
        F("cabinet", (1, 2), "wall"),
        F("printer", (1, 1), on=("cabinet",)),
        F("bookshelf", (1, 2), "wall"),
        F("whiteboard", (1, 1)),
        F("potted_plant", (2, 3), "corner"),
        F("trash_can", (1, 2), "corner"),
    ),
    private_office=(
        F("desk", (1, 1), "desk_group", seat="office_chair", on_top="monitor"),
        F("bookshelf", (1, 2), "wall"),
        F("cabinet", (1, 1), "wall"),
        F("armchair", (1, 1), "free"),
        F("potted_plant", (1, 1), "corner"),
        F("lamp", (1, 1), on=("cabinet", "bookshelf")),
    ),
    meeting_room=(
        F("dining_table", (1, 1), "table_group", seat="office_chair", seats=(4, 8)),
        F("whiteboard", (1, 1)),
        F("tv", (1, 1), on=("cabinet",)),
        F("cabinet", (1, 1), "wall"),
        F("potted_plant", (1, 2), "corner"),
    ),
    kitchenette=(
        F("kitchen_counter", (1, 2), "wall"),
        F("fridge", (1, 1), "wall"),
        F("microwave", (1, 1), on=("kitchen_counter",)),
        F("water_dispenser", (1, 1), "wall"),
        F("vending_machine", (0, 1), "wall"),
        F("cafe_table", (1, 2), "table_group", seat="chair", seats=(2, 3)),
        F("trash_can", (1, 1), "corner"),
    ),
    restroom=(
        F("toilet", (2, 3), "wall"),
        F("sink", (1, 2), "wall"),
        F("trash_can", (1, 1), "corner"),
    ),
    sales_floor=(
        F("grocery_shelf", (14, 24), "rows", spacing=0.02, alternate=True),
        F("checkout_counter", (2, 3), "wall", near_entrance=True),
        F("refrigerated_display", (3, 5), "wall"),
        F("shopping_cart", (3, 6), "free"),
        F("vending_machine", (0, 1), "wall"),
        F("trash_can", (1, 2), "corner"),
        F("potted_plant", (0, 2), "corner"),
    ),
    storage=(
        F("shelf_rack", (2, 4), "wall"),
        F("cabinet", (1, 2), "wall"),
        F("trash_can", (1, 1), "corner"),
    ),
    back_office=(
        F("desk", (1, 1), "desk_group", seat="office_chair", on_top="monitor"),
        F("cabinet", (1, 2), "wall"),
        F("printer", (1, 1), on=("cabinet",)),
        F("water_dispenser", (0, 1), "wall"),
    ),
    patient_room=(
        F("hospital_bed", (1, 2), "wall"),
        F("iv_stand", (1, 2), "free"),
        F("nightstand", (1, 2), "wall"),
        F("armchair", (1, 1), "free"),
        F("curtain", (1, 1)),
        F("sink", (1, 1), "wall"),
        F("trash_can", (1, 1), "corner"),
        F("tv", (1, 1), on=("nightstand",), chance=0.5),
    ),
    nurse_station=(
        F("reception_desk", (1, 1), "wall"),
        F("office_chair", (1, 2), "free"),
        F("monitor", (1, 2), on=("reception_desk", "cabinet")),
        F("medical_cart", (1, 2), "free"),
        F("cabinet", (1, 2), "wall"),
        F("printer", (1, 1), on=("cabinet",)),
        F("water_dispenser", (1, 1), "wall"),
    ),
    supply_room=(
        F("shelf_rack", (2, 3), "wall"),
        F("medical_cart", (1, 2), "free"),
        F("cabinet", (1, 1), "wall"),
    ),
    dining_area=(
        F("cafe_table", (4, 9), "table_group", seat="chair", seats=(2, 4)),
        F("checkout_counter", (1, 1), "wall"),
        F("bar_stool", (2, 4), "wall"),
        F("coat_rack", (1, 1), "wall"),
        F("potted_plant", (2, 3), "corner"),
        F("trash_can", (1, 1), "corner"),
        F("piano", (1, 1), "wall", chance=0.2),
    ),
    cafe_kitchen=(
        F("kitchen_counter", (2, 4), "wall"),
        F("oven", (1, 2), "wall"),
        F("fridge", (1, 2), "wall"),
        F("sink", (1, 1), "wall"),
        F("shelf_rack", (0, 1), "wall"),
        F("microwave", (1, 1), on=("kitchen_counter",)),
        F("trash_can", (1, 1), "corner"),
    ),
    classroom=(
        F("school_desk", (8, 20), "rows", seat="chair", spacing=0.35),
        F("desk", (1, 1), "desk_group", seat="office_chair", on_top="laptop"),
        F("whiteboard", (1, 1)),
        F("bookshelf", (1, 2), "wall"),
        F("cabinet", (0, 1), "wall"),
        F("potted_plant", (0, 1), "corner"),
        F("trash_can", (1, 1), "corner"),
    ),
    teachers_room=(
        F("dining_table", (1, 1), "table_group", seat="chair", seats=(4, 6)),
        F("desk", (1, 2), "desk_group", seat="office_chair", on_top="monitor"),
        F("bookshelf", (1, 2), "wall"),
        F("printer", (1, 1), on=("cabinet",)),
        F("cabinet", (1, 1), "wall"),
        F("water_dispenser", (1, 1), "wall"),
        F("coat_rack", (1, 1), "wall"),
    ),
)
"""Furniture rules by room type, in placement order (large pieces first)."""


PROGRAMS: Mapping[str, BuildingProgram] = MappingProxyType(
    {
        p.building_type: p
        for p in (
            BuildingProgram(
                "apartment",
                length=(14.0, 20.0),
                side_depth=(4.0, 5.0),
                spine=SpineSpec("living_room", (4.2, 5.2), "both"),
                rooms=(
                    RoomSpec("kitchen", (1, 1), (12.0, 18.0)),
                    RoomSpec("bedroom", (1, 3), (12.0, 18.0)),
                    RoomSpec("bathroom", (1, 2), (9.0, 12.0), min_width=3.0),
                    RoomSpec("hallway", (1, 1), (9.0, 12.0), min_width=3.0, near_entrance=True),
                ),
                description="a flat: living room through the middle, kitchen, bedrooms and bathrooms off it",
            ),
            BuildingProgram(
                "office",
                length=(22.0, 32.0),
                side_depth=(4.5, 6.5),
                spine=SpineSpec("corridor", (2.6, 3.2), "both"),
                rooms=(
                    RoomSpec("reception", (1, 1), (18.0, 26.0), near_entrance=True),
                    RoomSpec("open_office", (1, 2), (30.0, 45.0)),
                    RoomSpec("meeting_room", (1, 2), (16.0, 24.0)),
                    RoomSpec("private_office", (1, 3), (12.0, 16.0)),
                    RoomSpec("kitchenette", (1, 1), (14.0, 20.0)),
                    RoomSpec("restroom", (1, 2), (10.0, 14.0)),
                ),
                exits=2,
                description="an office floor: a corridor with offices, meeting rooms, a kitchenette",
            ),
            BuildingProgram(
                "grocery",
                length=(20.0, 30.0),
                side_depth=(4.0, 5.0),
                spine=SpineSpec("sales_floor", (12.0, 16.0), "back"),
                rooms=(
                    RoomSpec("storage", (1, 2), (18.0, 30.0)),
                    RoomSpec("back_office", (1, 1), (12.0, 16.0)),
                    RoomSpec("restroom", (1, 1), (10.0, 13.0)),
                ),
                exits=2,
                ceiling_height=(3.5, 4.0),
                description="a grocery store: aisles of shelves, chillers and checkouts, storage at the back",
            ),
            BuildingProgram(
                "hospital_ward",
                length=(24.0, 34.0),
                side_depth=(4.5, 5.5),
                spine=SpineSpec("corridor", (2.8, 3.4), "both"),
                rooms=(
                    RoomSpec("patient_room", (4, 8), (16.0, 22.0), min_width=3.6),
                    RoomSpec("nurse_station", (1, 1), (16.0, 22.0), near_entrance=True),
                    RoomSpec("supply_room", (1, 1), (12.0, 16.0)),
                    RoomSpec("restroom", (1, 1), (10.0, 14.0)),
                ),
                exits=2,
                description="a hospital ward: patient rooms along a corridor, a nurse station, supplies",
            ),
            BuildingProgram(
                "cafe",
                length=(14.0, 22.0),
                side_depth=(4.0, 5.0),
                spine=SpineSpec("dining_area", (8.0, 11.0), "back"),
                rooms=(
                    RoomSpec("cafe_kitchen", (1, 1), (20.0, 30.0)),
                    RoomSpec("restroom", (1, 2), (10.0, 13.0)),
                    RoomSpec("storage", (0, 1), (10.0, 14.0)),
                ),
                exits=1,
                ceiling_height=(3.0, 3.5),
                description="a cafe: tables and a counter in the dining room, kitchen and restrooms behind",
            ),
            BuildingProgram(
                "school",
                length=(24.0, 34.0),
                side_depth=(6.0, 7.5),
                spine=SpineSpec("corridor", (2.8, 3.4), "both"),
                rooms=(
                    RoomSpec("classroom", (3, 6), (40.0, 55.0), min_width=5.5),
                    RoomSpec("teachers_room", (1, 1), (24.0, 32.0)),
                    RoomSpec("restroom", (1, 2), (12.0, 16.0)),
                ),
                exits=2,
                ceiling_height=(3.0, 3.3),
                description="a school floor: classrooms with rows of desks along a corridor",
            ),
        )
    }
)
"""The building programs by type."""

BUILDING_TYPES: tuple[str, ...] = tuple(PROGRAMS)
"""The building types, in a fixed order."""
