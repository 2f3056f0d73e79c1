"""Indoor-to-outdoor assembly: a building (linked, or generated to fit) joined to a city through a door
in a road-facing facade."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, NamedTuple

from pydantic import AfterValidator

from navverse.city.i2o.assembly import AssemblySettings
from navverse.city.i2o.densify import DensifySettings, ExitGoals
from pipeline import Input, Params, StageContext, stage

if TYPE_CHECKING:
    from navverse.city.city_settings import CitySettings
    from navverse.city.geometry.street_plan import StreetPlan
    from navverse.city.i2o.assembly import I2OAssembly
    from navverse.city.i2o.densify import Densified
    from navverse.city.map import CityMap
    from navverse.scene.geometry import Scene


def _building_type(name: str) -> str:
    from navverse.indoor.programs import PROGRAMS

    if name not in PROGRAMS:
        raise ValueError(f"unknown building type {name!r}; choose from: {', '.join(PROGRAMS)}")
    return name


_I2O_SUMMARY = {
    "city": "city",
    "building": "building",
    "facade": "facade",
    "placements fit": "candidates",
    "refused": "refused",
    "storefronts nearby": "densified.storefronts.placed",
    "objects nearby": "densified.objects",
    "cars nearby": "densified.cars",
}
"""What the build summary says an i2o scene was made of (its stats: :func:`_finish`)."""


class AssembleI2OParams(Params, AssemblySettings, DensifySettings):
    """Parameters of :func:`assemble_i2o`: those of :class:`navverse.city.i2o.assembly.AssemblySettings` and
    :class:`navverse.city.i2o.densify.DensifySettings`.

    The recipe links the pair: ``city`` (the ``geometry`` of a city target, after its storefronts)
    and ``building`` (the ``geometry`` of an indoor building target); when a link's globs match
    several targets, the target's seed draws one of each (``seeds: [0, 1, 2]`` makes three pairs); a
    drawn city with no room for the building passes it to the next linked city (in scene-id order, the
    record's ``cities_refused`` says why each was passed over).
    The building's exit (``exit``, by default its first) is set into the road-facing facade chosen
    (or ``facade``, a city facade id) with ``exit_margin`` of facade on each side and the sidewalk
    within ``sidewalk_gap`` in front; the building must fit clear of streets and other buildings.
    ``clear_depth`` of street in front of the exit is cleared of objects. Then the neighbourhood
    within ``nearby_radius`` of the exit is densified, as the paper does around the anchor: up to
    ``objects_nearby`` street objects and ``cars_nearby`` parked cars are added where they fit (clear
    of the doorway, of storefront doors and of what stands), and storefronts on road-facing facades
    until ``storefronts_nearby`` stand there, so that PlaceNav has places near the building; what is
    added follows the city's own population and storefront settings (``city_settings.json``).
    """


@stage(
    name="assemble_i2o",
    inputs=[Input("city", artifact="geometry", many=True), Input("building", artifact="geometry", many=True)],
    outputs=["geometry"],
    summary=_I2O_SUMMARY,
)
def assemble_i2o(ctx: StageContext, params: AssembleI2OParams) -> None:
    """An i2o scene: the linked building set into the linked city at a road-facing facade."""
    from navverse.city.i2o.assembly import assemble_i2o as assemble
    from navverse.scene.directory import read_scene

    cities = _in_turn(ctx, "city")
    building = read_scene(_draw(ctx, "building"))
    settings = AssemblySettings.of(params)
    ctx.progress(1, 3, "assembling")
    joined = _join(
        ctx,
        cities,
        lambda city, plan: [assemble(city, plan, building, scene_id=ctx.target, settings=settings)],
    )
    _finish(ctx, joined, _densify(ctx, params, joined), building=building.scene_id)


class GenerateI2OParams(AssembleI2OParams, ExitGoals):
    """Parameters of :func:`generate_i2o`: those of :func:`assemble_i2o`, the ``building_type`` of
    the procedural building generated to fit the city (``exit`` and ``facade`` are chosen with it)
    and what its exit must open onto (:class:`navverse.city.i2o.densify.ExitGoals`: ``exit_goals``
    objects within ``exit_goals_radius`` once densified, else the next facade is tried)."""

    building_type: Annotated[str, AfterValidator(_building_type)]
    """Program of the generated building: a building type of :data:`navverse.indoor.programs.PROGRAMS`
    (e.g. ``apartment``, ``office``, ``cafe``); its footprint ranges decide the road-facing facade."""


@stage(
    name="generate_i2o",
    inputs=[Input("city", artifact="geometry", many=True)],
    outputs=["geometry"],
    summary=_I2O_SUMMARY,
)
def generate_i2o(ctx: StageContext, params: GenerateI2OParams) -> None:
    """An i2o scene: a procedural building sized to a road-facing city building, set in its place."""
    import itertools

    from navverse.city.i2o.assembly import generated_fits
    from navverse.city.i2o.densify import things_near

    cities = _in_turn(ctx, "city")
    settings = AssemblySettings.of(params)
    ctx.progress(1, 3, "generating")
    joined = _join(
        ctx,
        cities,
        lambda city, plan: generated_fits(
            city, plan, params.building_type, ctx.rng, scene_id=ctx.target, settings=settings
        ),
    )
    # The first join whose exit opens onto enough things to find once densified, else the richest.
    best: tuple[int, _Joined, Densified] | None = None
    passed = 0
    for result in itertools.chain([joined.result], joined.more):  # lazily: a join draws from ctx.rng
        candidate = joined._replace(result=result, more=iter(()))
        nearby = _densify(ctx, params, candidate)
        anchor = result.scene.annotations.indoor_anchor
        found = things_near(nearby.scene, anchor[0], anchor[1], params.exit_goals_radius)
        if best is None or found > best[0]:
            best = (found, candidate, nearby)
        if found >= params.exit_goals:
            break
        ctx.log.info(
            "%s: facade %d opens onto %d things within %.0f m, fewer than %d: passed over",
            ctx.target, result.record["facade"], found, params.exit_goals_radius, params.exit_goals,
        )  # fmt: skip
        passed += 1
    assert best is not None
    found, chosen, nearby = best
    _finish(ctx, chosen, nearby, building=params.building_type, exit_goals={"found": found, "passed": passed})


class _Joined(NamedTuple):
    """An assembled i2o scene with the city it was joined to: the map the city was made from, its
    street plan and the settings it was built with."""

    result: I2OAssembly
    city: Scene
    city_map: CityMap
    plan: StreetPlan
    carried: CitySettings
    cities_refused: dict[str, str]
    """Linked cities tried before it, with the reason each refused."""
    more: Iterator[I2OAssembly]
    """The further joins with the same city, in turn (none for a linked building)."""


def _join(
    ctx: StageContext, cities: list[Path], assemble: Callable[[Scene, StreetPlan], Iterable[I2OAssembly]]
) -> _Joined:
    """Assemble with the first of `cities` (in turn) that takes the building (`assemble` gives the
    joins with a city in turn; the first is taken, the others are kept in ``more``).

    Raises
    ------
    AssemblyError
        If none of them does: every city's reason.
    """
    from navverse.city.i2o.assembly import AssemblyError

    refusals: dict[str, str] = {}
    for city_dir in cities:
        city, city_map, plan, carried = _read_city(city_dir)
        try:
            joins = iter(assemble(city, plan))
            result = next(joins)
        except AssemblyError as exc:
            ctx.log.info("%s: %s refused: %s", ctx.target, city.scene_id, exc)
            refusals[city.scene_id] = str(exc)
            continue
        return _Joined(result, city, city_map, plan, carried, refusals, joins)
    if len(refusals) == 1:
        raise AssemblyError(next(iter(refusals.values())))
    raise AssemblyError(
        f"none of the {len(refusals)} linked cities takes the building; link another city:\n  "
        + "\n  ".join(f"{city}: {reason}" for city, reason in refusals.items())
    )


def _read_city(city_dir: Path) -> tuple[Scene, CityMap, StreetPlan, CitySettings]:
    """A linked city scene, the map it was made from, its street plan and the settings it was built
    with (all in its directory)."""
    from navverse.city.city_settings import CITY_SETTINGS_FILE, load_city_settings
    from navverse.city.geometry.street_plan import STREET_PLAN_FILE, load_street_plan
    from navverse.city.i2o.assembly import AssemblyError
    from navverse.city.map import read_city_map
    from navverse.scene.directory import read_scene
    from stages.city import CITY_MAP_FILE

    needed = (CITY_MAP_FILE, STREET_PLAN_FILE, CITY_SETTINGS_FILE)
    missing = [name for name in needed if not (city_dir / name).is_file()]
    if missing:
        raise AssemblyError(
            f"the linked city {city_dir} has no {' or '.join(missing)}: link the `geometry` of a city "
            "target (built by its storefronts stage), not another scene"
        )
    city_map = read_city_map(city_dir / CITY_MAP_FILE)
    plan = load_street_plan(city_dir / STREET_PLAN_FILE)
    return read_scene(city_dir), city_map, plan, load_city_settings(city_dir / CITY_SETTINGS_FILE)


def _densify(ctx: StageContext, params: AssembleI2OParams, joined: _Joined) -> Densified:
    """The joined scene with the neighbourhood of its exit densified by the city's own settings."""
    from shapely.geometry import Point

    from navverse.city.i2o.densify import densify_neighbourhood

    result = joined.result
    anchor = result.scene.annotations.indoor_anchor
    doorway = Point(anchor[0], anchor[1]).buffer(params.clear_depth + 1.5)
    densify = DensifySettings.of(params)
    return densify_neighbourhood(
        result.scene,
        joined.city_map,
        joined.plan,
        ctx.rng,
        region=densify.region_around(anchor[0], anchor[1]),
        keep_clear=[doorway],
        settings=densify,
        populate=joined.carried.effective_populate,
        storefronts=joined.carried.effective_storefronts,
    )


def _finish(ctx: StageContext, joined: _Joined, nearby: Densified, *, building: str, **record) -> None:
    """Write the densified scene and the map of the street around it, and record how it was made."""
    from navverse.city.map import write_city_map
    from navverse.scene.directory import write_scene_dir
    from stages.city import CITY_MAP_FILE

    result = joined.result
    ctx.progress(2, 3, "writing")
    write_scene_dir(nearby.scene, ctx.output)
    write_city_map(joined.city_map, ctx.output / CITY_MAP_FILE)  # the street around: its look needs the map
    ctx.progress(3, 3, "done")
    city = joined.city.scene_id
    ctx.record(
        city=city,
        building=building,
        cities_refused=joined.cities_refused,
        densified=nearby.counts,
        **result.record,
        **record,
    )
    ctx.log.info(
        "%s: %s joined to %s at facade %d (%d placements fit), step %.3f m",
        ctx.target, building, city, result.record["facade"], result.record["candidates"],
        result.record["step"],
    )  # fmt: skip


def _in_turn(ctx: StageContext, name: str) -> list[Path]:
    """The linked scene directories of input `name` in the order they are tried: the one drawn with
    the target's seed (the only one, or a draw among several ordered by scene id, so the draw does not
    depend on where artifacts are stored), then the others after it in scene-id order, so a city with
    no room for the building passes it to another city of the same link."""
    from navverse.scene.directory import read_annotations

    linked = sorted(ctx.inputs[name], key=lambda path: read_annotations(path).scene_id)
    first = int(ctx.rng.integers(len(linked))) if len(linked) > 1 else 0
    return linked[first:] + linked[:first]


def _draw(ctx: StageContext, name: str) -> Path:
    """The linked scene directory of input `name` drawn with the target's seed (:func:`_in_turn`)."""
    return _in_turn(ctx, name)[0]
