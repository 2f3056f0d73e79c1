"""A procedural building as a :class:`~navverse.scene.Scene`: floorplan, structure, furniture, annotations."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from navverse.errors import SceneError
from navverse.indoor.floorplan import Floorplan, generate_floorplan
from navverse.indoor.furnish import Placement, furnish_room
from navverse.indoor.programs import PROGRAMS, ROOM_FURNITURE, Furniture
from navverse.indoor.structure import SLAB, build_structure
from navverse.scene import (
    BuildingAnnotation,
    DoorAnnotation,
    ExitAnnotation,
    MeshData,
    ObjectPart,
    RoomAnnotation,
    Scene,
    SceneSource,
    Surface,
    assemble_scene,
    footprint_facades,
    nearest_facade,
    terrain_classes,
)
from navverse.scene.categories import CategoryRule, assign_category
from navverse.scene.naming import OBJECTS_ROOT, sanitize_identifier

__all__ = ["BuildingOptions", "ExtraFurniture", "generate_building"]


@dataclass(frozen=True)
class ExtraFurniture:
    """Furniture a recipe adds to every room of a type: ``count`` of ``category``."""

    room_type: str
    category: str
    count: int = 1


@dataclass(frozen=True)
class BuildingOptions:
    """What a recipe can change about a procedural building.

    Attributes
    ----------
    length : float or None
        Footprint length along the spine (m); sampled from the program when None.
    depth : float or None
        Footprint depth across the spine (m), within the program's range
        (:func:`~navverse.indoor.floorplan.depth_range`); sampled when None.
    density : float
        Multiplies furniture counts.
    exclude : tuple of str
        Asset categories never placed.
    extra : tuple of ExtraFurniture
        Furniture added to rooms of a type.
    category_rules : tuple of CategoryRule
        Regexes over object prim names/paths giving annotated categories (default: the asset's).
    """

    length: float | None = None
    depth: float | None = None
    density: float = 1.0
    exclude: tuple[str, ...] = ()
    extra: tuple[ExtraFurniture, ...] = ()
    category_rules: tuple[CategoryRule, ...] = ()


def _spawn(rng: np.random.Generator) -> np.random.Generator:
    return np.random.default_rng(int(rng.integers(0, 2**63 - 1)))


def _furnish(plan: Floorplan, options: BuildingOptions, rng: np.random.Generator) -> list[Placement]:
    placements: list[Placement] = []
    excluded = set(options.exclude)
    for room in plan.rooms:
        rules = ROOM_FURNITURE.get(room.room_type, ())
        rules = rules + tuple(
            Furniture(e.category, (e.count, e.count)) for e in options.extra if e.room_type == room.room_type
        )
        placements += furnish_room(
            plan, room, rules, _spawn(rng), density=options.density, allowed=lambda c: c not in excluded
        )
    return placements


def generate_building(
    building_type: str,
    rng: np.random.Generator,
    *,
    scene_id: str,
    options: BuildingOptions = BuildingOptions(),
    source: SceneSource | None = None,
    rule_hits: list[int] | None = None,
) -> Scene:
    """Generate a furnished building of ``building_type`` as a scene.

    Parameters
    ----------
    building_type : str
        A key of :data:`~navverse.indoor.programs.PROGRAMS`.
    rng : numpy.random.Generator
        The only randomness: the same seed gives the same scene.
    scene_id : str
        The scene's id.
    options : BuildingOptions
        Recipe options.
    source : SceneSource, optional
        Recorded in the annotations.
    rule_hits : list of int, optional
        Filled with the objects each of ``options.category_rules`` matched (one counter per rule).

    Returns
    -------
    Scene
        Terrain surfaces (floor, walls, ceiling, aprons), objects, rooms, doorways and exits.

    Raises
    ------
    SceneError
        On an unknown building type.
    """
    if building_type not in PROGRAMS:
        raise SceneError(f"unknown building type {building_type!r}; choose from: {', '.join(PROGRAMS)}")
    plan = generate_floorplan(
        PROGRAMS[building_type], _spawn(rng), length=options.length, depth=options.depth
    )
    surfaces = build_structure(plan)
    placements = _furnish(plan, options, _spawn(rng))

    objects: list[ObjectPart] = []
    dropped: list[MeshData] = []
    hits = [0] * len(options.category_rules)
    for item in placements:
        name = f"{sanitize_identifier(item.category)}_{len(objects) + 1:04d}"  # its prim name, if annotated
        category = assign_category(
            options.category_rules, name=name, path=f"{OBJECTS_ROOT}/{name}", default=item.category, hits=hits
        )
        if category is None:
            dropped.append(item.mesh.transformed(item.center, item.yaw))
            continue
        objects.append(
            ObjectPart(
                category=category,
                mesh=item.mesh,
                center=item.center,
                yaw=item.yaw,
                size=item.size,
                kind=item.category,
            )
        )
    if dropped:
        surfaces.append(Surface("unannotated", "obstacle", MeshData.concatenate(dropped)))
    if rule_hits is not None:
        rule_hits[:] = hits

    classes = ["floor", "wall", "ceiling"] + (["sidewalk"] if plan.exits else [])
    classes += ["obstacle"] if dropped else []
    return assemble_scene(
        scene_id=scene_id,
        scene_type="indoor",
        surfaces=surfaces,
        objects=objects,
        buildings=[_building_annotation(plan)],
        terrain_classes=terrain_classes(classes),
        source=source,
    )


def _building_annotation(plan: Floorplan) -> BuildingAnnotation:
    """The generated building: its footprint, rooms, doorways, exits (each in its facade) and facades."""
    height = plan.ceiling_height + SLAB
    facades = footprint_facades(plan.footprint.corners(), height=height)
    return BuildingAnnotation(
        id=1,
        footprint=plan.footprint.corners(),
        base_height=0.0,
        height=height,
        indoor=True,
        rooms=[RoomAnnotation(id=r.id, room_type=r.room_type, polygon=r.rect.corners()) for r in plan.rooms],
        doors=[
            DoorAnnotation(id=d.id, center=(*d.center, 0.0), width=d.width, facing=d.facing, rooms=d.rooms)
            for d in plan.doors
        ],
        exits=[
            ExitAnnotation(
                id=e.id,
                center=(*e.center, 0.0),
                width=e.width,
                facing=e.facing,
                facade=nearest_facade(facades, e.center).id,
            )
            for e in plan.exits
        ],
        facades=facades,
    )


def describe_rooms(scene: Scene) -> dict[str, int]:
    """Rooms per type of a generated building (for logs)."""
    return dict(Counter(r.room_type for r in scene.annotations.rooms))
