"""Street life: parked cars and street objects stood in a city scene."""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator, Field

from pipeline import Params, StageContext, stage


def _categories(names: list[str]) -> list[str]:
    from navverse.assets.library import categories

    known = set(categories())
    unknown = sorted(set(names) - known)
    if unknown:
        listed = ", ".join(sorted(known))
        raise ValueError(
            f"unknown object categories {', '.join(unknown)}; the object library knows: {listed}"
        )
    return sorted(set(names))


def _groups(names: list[str] | None) -> list[str] | None:
    if names is None:
        return None
    from navverse.city.context_groups import GROUPS

    known = {g.name for g in GROUPS}
    unknown = sorted(set(names) - known)
    if unknown:
        raise ValueError(f"unknown contextual groups {', '.join(unknown)}; known: {', '.join(sorted(known))}")
    return sorted(set(names))


class PopulateParams(Params):
    """Parameters of :func:`populate`.

    ``cars_per_km2`` and ``objects_per_km2`` cap the parked cars and the street objects (mapped
    furniture first, then the zone grammar) per km² of the city's window; ``exclude`` names object
    categories never placed; ``lot_share`` is the share of cars parked in parking lots when there
    are lots and street slots; ``clear_width`` is the walkway kept clear on sidewalks wide enough
    (else ``min_clear``, else the whole sidewalk). ``group_objects_per_km2`` caps the objects of
    contextual groups (bus stop waits, picnics, roadworks...), ``groups`` names the ones to place
    (default all 30), ``group_spacing`` is the least distance between two groups.
    """

    cars_per_km2: Annotated[float, Field(ge=0.0, le=5000.0)] = 200.0
    objects_per_km2: Annotated[float, Field(ge=0.0, le=20000.0)] = 1000.0
    exclude: Annotated[list[str], AfterValidator(_categories)] = []
    lot_share: Annotated[float, Field(ge=0.0, le=1.0)] = 0.4
    clear_width: Annotated[float, Field(ge=0.8, le=5.0)] = 1.5
    min_clear: Annotated[float, Field(ge=0.8, le=5.0)] = 1.3
    group_objects_per_km2: Annotated[float, Field(ge=0.0, le=20000.0)] = 300.0
    groups: Annotated[list[str] | None, AfterValidator(_groups)] = None
    group_spacing: Annotated[float, Field(ge=0.0, le=500.0)] = 8.0


@stage(
    name="populate",
    inputs=["city_map", "street_geometry"],
    outputs=["populated_geometry"],
    passthrough={"populated_geometry": "street_geometry"},
)
def populate(ctx: StageContext, params: PopulateParams) -> None:
    """The city scene with parked cars, mapped street furniture, sidewalk objects by zone and groups."""
    from navverse.city.populate import PopulateSettings, populate_city
    from navverse.city.street_zones import ZoneSettings
    from stages._city_step import read_city_step, write_city_step

    city, scene, plan = read_city_step(ctx, "street_geometry")
    settings = PopulateSettings(
        cars_per_km2=params.cars_per_km2,
        objects_per_km2=params.objects_per_km2,
        excluded=frozenset(params.exclude),
        lot_share=params.lot_share,
        group_objects_per_km2=params.group_objects_per_km2,
        groups=None if params.groups is None else frozenset(params.groups),
        group_spacing=params.group_spacing,
        zones=ZoneSettings(clear_width=params.clear_width, min_clear=params.min_clear),
    )
    result = populate_city(scene, city, plan, ctx.rng, settings)
    counts = result.counts
    write_city_step(ctx, result.scene, plan, counts)
    ctx.log.info(
        "populated %s: %d cars, %d street objects, %d groups, %d mapped objects skipped",
        ctx.target, sum(counts["cars"].values()),
        counts["sources"].get("map", 0) + counts["sources"].get("grammar", 0), sum(counts["groups"].values()),
        sum(counts["skipped"].values()),
    )  # fmt: skip
