"""The indoor_layout stage: a procedural, furnished building of a given type."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import AfterValidator, Field, model_validator

from navverse.indoor.programs import BUILDING_TYPES, PROGRAMS
from navverse.scene.categories import CategoryRule
from pipeline import Params, StageContext, stage

BuildingType = Literal[BUILDING_TYPES]  # type: ignore[valid-type]


def _known_category(name: str) -> str:
    from navverse.assets.library import categories

    known = categories()
    if name not in known:
        raise ValueError(f"unknown object category {name!r} (known: {', '.join(known)})")
    return name


AssetCategory = Annotated[str, AfterValidator(_known_category)]


class ExtraFurnitureParams(Params):
    """Furniture added to every room of a type."""

    room_type: str
    category: AssetCategory
    count: Annotated[int, Field(ge=1, le=20)] = 1


class IndoorLayoutParams(Params):
    """Parameters of :func:`indoor_layout`.

    ``building_type`` picks the program (rooms, sizes, furniture); ``length`` fixes the footprint
    along the building's spine and ``depth`` across it (m, within the program's range). ``density``
    scales furniture counts. ``exclude_categories`` and ``extra_furniture`` remove or add asset
    categories. ``category_rules`` (regexes over object prim
    names such as ``office_chair_0007`` or paths) give the annotated goal categories; objects matching
    a rule with ``category: null`` stay as unannotated geometry.
    """

    building_type: BuildingType
    length: Annotated[float, Field(gt=6.0, le=120.0)] | None = None
    depth: Annotated[float, Field(gt=3.0, le=60.0)] | None = None
    density: Annotated[float, Field(gt=0.0, le=3.0)] = 1.0
    exclude_categories: list[AssetCategory] = []
    extra_furniture: list[ExtraFurnitureParams] = []
    category_rules: list[CategoryRule] = []

    @model_validator(mode="after")
    def _room_types(self) -> IndoorLayoutParams:
        program = PROGRAMS[self.building_type]
        if self.depth is not None:
            from navverse.indoor.floorplan import depth_range

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


@stage(name="indoor_layout", outputs=["raw_geometry"])
def indoor_layout(ctx: StageContext, params: IndoorLayoutParams) -> None:
    """A furnished procedural building: scene.usdc, scene.json (rooms, doorways, exits, objects), bev.png."""
    import navverse
    from navverse.indoor import BuildingOptions, ExtraFurniture, describe_rooms, generate_building
    from navverse.scene import SceneSource, write_scene_dir
    from navverse.scene.categories import unmatched_rules

    options = BuildingOptions(
        length=params.length,
        depth=params.depth,
        density=params.density,
        exclude=tuple(params.exclude_categories),
        extra=tuple(ExtraFurniture(e.room_type, e.category, e.count) for e in params.extra_furniture),
        category_rules=tuple(params.category_rules),
    )
    source = SceneSource(recipe=ctx.recipe, recipe_hash=ctx.recipe_hash, toolkit_version=navverse.__version__)
    ctx.progress(0, 2, "layout")
    hits: list[int] = []
    scene = generate_building(
        params.building_type, ctx.rng, scene_id=ctx.target, options=options, source=source, rule_hits=hits
    )
    for warning in unmatched_rules(options.category_rules, hits):
        ctx.log.warning("%s", warning)
    ctx.progress(1, 2, "writing")
    write_scene_dir(scene, ctx.output)
    ctx.progress(2, 2, "done")
    ann = scene.annotations
    rooms = describe_rooms(scene)
    ctx.record(
        building_type=params.building_type,
        rooms=sum(rooms.values()),
        rooms_per_type=rooms,
        doors=len(ann.doors),
        exits=len(ann.exits),
        objects=len(ann.objects),
        categories=len(ann.statistics.objects_per_category),
        faces=ann.statistics.faces,
    )
    ctx.log.info(
        "%s %s: %d rooms, %d objects of %d categories, %d faces",
        params.building_type, ctx.target, sum(rooms.values()), len(ann.objects),
        len(ann.statistics.objects_per_category), ann.statistics.faces,
    )  # fmt: skip
