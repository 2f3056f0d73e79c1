"""A procedural building as a :class:`~navverse.scene.Scene`: floorplan, structure, furniture, annotations."""

from __future__ import annotations

from collections import Counter
from typing import Annotated, Literal

import numpy as np
from pydantic import AfterValidator, Field, model_validator

from navverse.errors import SceneError
from navverse.indoor.floorplan import Floorplan, depth_range, generate_floorplan
from navverse.indoor.furnish import Placement, furnish_room
from navverse.indoor.programs import BUILDING_TYPES, PROGRAMS, ROOM_FURNITURE, Furniture
from navverse.indoor.structure import SLAB, build_structure
from navverse.scene.annotations import (
    BuildingAnnotation,
    DoorAnnotation,
    ExitAnnotation,
    RoomAnnotation,
    SceneSource,
    footprint_facades,
    nearest_facade,
)
from navverse.scene.categories import CategoryRule, assign_category
from navverse.scene.compose import ObjectPart, assemble_scene
from navverse.scene.geometry import MeshData, Scene, Surface
from navverse.scene.naming import OBJECTS_ROOT, sanitize_identifier
from navverse.scene.terrain import terrain_classes
from navverse.settings import Settings

__all__ = ["BuildingOptions", "BuildingSettings", "BuildingType", "ExtraFurniture", "generate_building"]

BuildingType = Literal[BUILDING_TYPES]  # type: ignore[valid-type]
"""A building type: a key of :data:`~navverse.indoor.programs.PROGRAMS`."""


def _known_category(name: str) -> str:
    from navverse.assets.library import categories

    known = categories()
    if name not in known:
        raise ValueError(f"unknown object category {name!r} (known: {', '.join(known)})")
    return name


AssetCategory = Annotated[str, AfterValidator(_known_category)]
"""An object category of the asset library (:func:`navverse.assets.library.categories`)."""


class ExtraFurniture(Settings):
    """Furniture added to every room of a type: ``count`` of ``category``."""

    room_type: str
    """The room type (of the building's program) whose rooms get it."""
    category: AssetCategory
    """The asset category placed."""
    count: Annotated[int, Field(ge=1, le=20)] = 1
    """How many per room."""


class BuildingOptions(Settings):
    """What a recipe can change about a procedural building of a given type.

    ``length`` fixes the footprint along the building's spine and ``depth`` across it (m, within the
    program's range); either is drawn from the program when None. ``density`` scales furniture
    counts. ``exclude_categories`` and ``extra_furniture`` remove or add asset categories.
    ``category_rules`` (regexes over object prim names such as ``office_chair_0007`` or paths) give
    the annotated goal categories; objects matching a rule with ``category: null`` stay as
    unannotated geometry.
    """

    length: Annotated[float, Field(gt=6.0, le=120.0)] | None = None
    """Footprint length along the spine (m); drawn from the program when None."""
    depth: Annotated[float, Field(gt=3.0, le=60.0)] | None = None
    """Footprint depth across the spine (m), within the program's range
    (:func:`~navverse.indoor.floorplan.depth_range`); drawn when None."""
    density: Annotated[float, Field(gt=0.0, le=3.0)] = 1.0
    """Multiplies furniture counts."""
    exclude_categories: list[AssetCategory] = []
    """Asset categories never placed."""
    extra_furniture: list[ExtraFurniture] = []
    """Furniture added to every room of a type."""
    category_rules: list[CategoryRule] = []
    """Regexes over object prim names or paths giving annotated categories (default: the asset's);
    the first match wins, a rule without a category leaves the object unannotated."""


class BuildingSettings(BuildingOptions):
    """A building type and its options, checked together: the depth within the type's range, extra
    furniture only in room types the type has."""

    building_type: BuildingType
    """The program (rooms, sizes, furniture): a key of :data:`~navverse.indoor.programs.PROGRAMS`."""

    @model_validator(mode="after")
    def _room_types(self) -> BuildingSettings:
        program = PROGRAMS[self.building_type]
        if self.depth is not None:
            lo, hi = depth_range(program)
            if not lo <= self.depth <= hi:
                raise ValueError(
                    f"a {self.building_type} footprint is {lo:.1f}-{hi:.1f} m deep, not {self.depth} m"
                )
        known = [program.spine.room_type] + [r.room_type for r in program.rooms]
        for extra in self.extra_furniture:
            if extra.room_type not in known:
                rooms = ", ".join(known)
                raise ValueError(
                    f"a {self.building_type} has no room type {extra.room_type!r} (its rooms: {rooms})"
                )
        return self


def _spawn(rng: np.random.Generator) -> np.random.Generator:
    return np.random.default_rng(int(rng.integers(0, 2**63 - 1)))


def _furnish(plan: Floorplan, options: BuildingOptions, rng: np.random.Generator) -> list[Placement]:
    placements: list[Placement] = []
    excluded = set(options.exclude_categories)
    for room in plan.rooms:
        rules = ROOM_FURNITURE.get(room.room_type, ())
        rules = rules + tuple(
            Furniture(e.category, (e.count, e.count))
            for e in options.extra_furniture
            if e.room_type == room.room_type
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
    options: BuildingOptions | None = None,
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
    options : BuildingOptions, optional
        Recipe options (default: the defaults).
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
    options = options or BuildingOptions()
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
