"""Indoor-to-outdoor assembly: a building (linked, or generated to fit) joined to a city through a door
in a road-facing facade."""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator, Field

from pipeline import Input, Params, StageContext, stage


def _building_type(name: str) -> str:
    from navverse.indoor.programs import PROGRAMS

    if name not in PROGRAMS:
        raise ValueError(f"unknown building type {name!r}; choose from: {', '.join(PROGRAMS)}")
    return name


class AssembleI2OParams(Params):
    """Parameters of :func:`assemble_i2o`.

    The recipe links the pair: ``city`` (the ``geometry`` of a city target, after its storefronts)
    and ``building`` (the ``geometry`` of an indoor building target); when a link's globs match
    several targets, the target's seed draws one of each (``seeds: [0, 1, 2]`` makes three pairs).
    The building's exit (``exit``, by default its first) is set into the road-facing facade chosen
    (or ``facade``, a city facade id) with ``exit_margin`` of facade on each side and the sidewalk
    within ``sidewalk_gap`` in front; the building must fit clear of streets and other buildings.
    ``clear_depth`` of street in front of the exit is cleared of objects. Then the neighbourhood
    within ``nearby_radius`` of the exit is densified, as the paper does around the anchor: up to
    ``objects_nearby`` street objects and ``cars_nearby`` parked cars are added where they fit (clear
    of the doorway, of storefront doors and of what stands), and storefronts on road-facing facades
    until ``storefronts_nearby`` stand there, so that PlaceNav has places near the building.
    """

    max_road_distance: Annotated[float, Field(gt=0.0, le=50.0)] = 30.0
    sidewalk_gap: Annotated[float, Field(ge=0.0, le=20.0)] = 6.0
    exit_margin: Annotated[float, Field(ge=0.0, le=5.0)] = 0.5
    clear_depth: Annotated[float, Field(ge=0.0, le=10.0)] = 2.0
    facade: Annotated[int, Field(ge=1, le=10_000_000)] | None = None
    exit: Annotated[int, Field(ge=1, le=10_000)] | None = None
    storefronts_nearby: Annotated[int, Field(ge=0, le=200)] = 8
    objects_nearby: Annotated[int, Field(ge=0, le=1000)] = 30
    cars_nearby: Annotated[int, Field(ge=0, le=500)] = 8
    nearby_radius: Annotated[float, Field(gt=0.0, le=200.0)] = 50.0


@stage(
    name="assemble_i2o",
    inputs=[Input("city", artifact="geometry", many=True), Input("building", artifact="geometry", many=True)],
    outputs=["geometry"],
)
def assemble_i2o(ctx: StageContext, params: AssembleI2OParams) -> None:
    """An i2o scene: the linked building set into the linked city at a road-facing facade."""
    from navverse.city.i2o import assemble_i2o as assemble
    from navverse.scene import read_scene

    city, city_map, plan = _read_city(ctx)
    building = read_scene(_draw(ctx, "building"))
    ctx.progress(1, 3, "assembling")
    result = assemble(city, plan, building, scene_id=ctx.target, settings=_settings(params))
    _finish(ctx, params, result, city_map, plan, city=city.scene_id, building=building.scene_id)


class GenerateI2OParams(AssembleI2OParams):
    """Parameters of :func:`generate_i2o`: those of :func:`assemble_i2o` and the ``building_type`` of
    the procedural building generated to fit the city (``exit`` and ``facade`` are chosen with it)."""

    building_type: Annotated[str, AfterValidator(_building_type)]


@stage(name="generate_i2o", inputs=[Input("city", artifact="geometry", many=True)], outputs=["geometry"])
def generate_i2o(ctx: StageContext, params: GenerateI2OParams) -> None:
    """An i2o scene: a procedural building sized to a road-facing city building, set in its place."""
    from navverse.city.i2o import generate_i2o as generate

    city, city_map, plan = _read_city(ctx)
    ctx.progress(1, 3, "generating")
    result = generate(
        city, plan, params.building_type, ctx.rng, scene_id=ctx.target, settings=_settings(params)
    )
    _finish(ctx, params, result, city_map, plan, city=city.scene_id, building=params.building_type)


def _read_city(ctx: StageContext):
    """The linked city scene, the map it was made from and its street plan (all in its directory)."""
    from navverse.city.i2o import AssemblyError
    from navverse.city.map import read_city_map
    from navverse.city.street_plan import STREET_PLAN_FILE, load_street_plan
    from navverse.scene import read_scene
    from stages.city import CITY_MAP_FILE

    ctx.progress(0, 3, "reading")
    city_dir = _draw(ctx, "city")
    missing = [name for name in (CITY_MAP_FILE, STREET_PLAN_FILE) if not (city_dir / name).is_file()]
    if missing:
        raise AssemblyError(
            f"the linked city {city_dir} has no {' or '.join(missing)}: link the `geometry` of a city "
            "target (built by its storefronts stage), not another scene"
        )
    city_map = read_city_map(city_dir / CITY_MAP_FILE)
    return read_scene(city_dir), city_map, load_street_plan(city_dir / STREET_PLAN_FILE)


def _settings(params: AssembleI2OParams):
    from navverse.city.i2o import AssemblySettings

    return AssemblySettings(
        max_road_distance=params.max_road_distance,
        sidewalk_gap=params.sidewalk_gap,
        exit_margin=params.exit_margin,
        clear_depth=params.clear_depth,
        facade=params.facade,
        exit=params.exit,
    )


def _finish(
    ctx: StageContext, params: AssembleI2OParams, result, city_map, plan, *, city: str, building: str
) -> None:
    """Densify the neighbourhood of the exit, write the scene and record how it was made."""
    from shapely.geometry import Point

    from navverse.city.densify import DensifySettings, densify_neighbourhood
    from navverse.scene import write_scene_dir

    anchor = result.scene.annotations.indoor_anchor
    doorway = Point(anchor[0], anchor[1]).buffer(params.clear_depth + 1.5)
    nearby = densify_neighbourhood(
        result.scene,
        city_map,
        plan,
        ctx.rng,
        region=Point(anchor[0], anchor[1]).buffer(params.nearby_radius, quad_segs=16),
        keep_clear=[doorway],
        settings=DensifySettings(
            objects=params.objects_nearby, cars=params.cars_nearby, storefronts=params.storefronts_nearby
        ),
    )
    ctx.progress(2, 3, "writing")
    write_scene_dir(nearby.scene, ctx.output)
    ctx.progress(3, 3, "done")
    ctx.record(city=city, building=building, densified=nearby.counts, **result.record)
    ctx.log.info(
        "%s: %s joined to %s at facade %d (%d placements fit), step %.3f m",
        ctx.target, building, city, result.record["facade"], result.record["candidates"],
        result.record["step"],
    )  # fmt: skip


def _draw(ctx: StageContext, name: str):
    """The linked scene directory of input `name`: the only one, or one drawn with the target's seed
    among several (ordered by scene id, so the draw does not depend on where artifacts are stored)."""
    from navverse.scene import read_annotations

    linked = sorted(ctx.inputs[name], key=lambda path: read_annotations(path).scene_id)
    return linked[int(ctx.rng.integers(len(linked)))] if len(linked) > 1 else linked[0]
