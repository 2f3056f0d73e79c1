"""Procedural buildings: building programs, floorplans, structure, furnishing, and the assembled scene.

>>> scene = generate_building("office", np.random.default_rng(0), scene_id="office-0")  # doctest: +SKIP
"""

from navverse.indoor.building import (
    BuildingOptions,
    BuildingSettings,
    ExtraFurniture,
    describe_rooms,
    generate_building,
)
from navverse.indoor.floorplan import WALL_THICKNESS, Door, Exit, Floorplan, Rect, Room, generate_floorplan
from navverse.indoor.programs import BUILDING_TYPES, PROGRAMS, ROOM_FURNITURE, BuildingProgram, Furniture

__all__ = [
    "BUILDING_TYPES",
    "PROGRAMS",
    "ROOM_FURNITURE",
    "WALL_THICKNESS",
    "BuildingOptions",
    "BuildingProgram",
    "BuildingSettings",
    "Door",
    "Exit",
    "ExtraFurniture",
    "Floorplan",
    "Furniture",
    "Rect",
    "Room",
    "describe_rooms",
    "generate_building",
    "generate_floorplan",
]
