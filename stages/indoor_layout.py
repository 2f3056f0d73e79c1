"""The indoor_layout stage: a procedural, furnished building of a given type."""

from __future__ import annotations

from navverse.indoor.building import BuildingSettings
from pipeline import Params, StageContext, stage


class IndoorLayoutParams(Params, BuildingSettings):
    """Parameters of :func:`indoor_layout`: those of :class:`navverse.indoor.building.BuildingSettings`,
    a building type (its program: rooms, sizes, furniture) and the options of its footprint, its
    furniture and its goal categories."""


@stage(
    name="indoor_layout",
    outputs=["raw_geometry"],
    summary={
        "building": "building_type",
        "rooms": "rooms_per_type",
        "doors": "doors",
        "exits": "exits",
        "objects": "objects",
        "faces": "faces",
    },
)
def indoor_layout(ctx: StageContext, params: IndoorLayoutParams) -> None:
    """A furnished procedural building: scene.usdc, scene.json (rooms, doorways, exits, objects), bev.png."""
    import navverse
    from navverse.indoor import BuildingOptions, describe_rooms, generate_building
    from navverse.scene.annotations import SceneSource
    from navverse.scene.categories import unmatched_rules
    from navverse.scene.directory import write_scene_dir

    options = BuildingOptions.of(params)
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
