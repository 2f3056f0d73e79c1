"""Street life: parked cars and street objects stood in a city scene."""

from __future__ import annotations

from navverse.city.street_life.populate import PopulateSettings
from pipeline import Params, StageContext, stage


class PopulateParams(Params, PopulateSettings):
    """Parameters of :func:`populate`: those of :class:`navverse.city.street_life.populate.PopulateSettings`.

    ``cars_per_km2`` and ``objects_per_km2`` cap the parked cars and the street objects (mapped
    furniture first, then the zone grammar) per km² of the city's window; ``exclude`` names object
    categories never placed; ``lot_share`` is the share of cars parked in parking lots when there
    are lots and street slots; ``clear_width`` is the walkway kept clear on sidewalks wide enough
    (else ``min_clear``, else the whole sidewalk), and the other sidewalk zone widths and
    clearances are :class:`navverse.city.street_life.zones.ZoneSettings`'. ``group_objects_per_km2`` caps
    the objects of contextual groups (bus stop waits, picnics, roadworks...), ``groups`` names the
    ones to place (default all 30), ``group_spacing`` is the least distance between two groups.
    """


@stage(
    name="populate",
    inputs=["city_map", "street_geometry"],
    outputs=["populated_geometry"],
    passthrough={"populated_geometry": "street_geometry"},
    summary={
        "objects": "objects",
        "by source": "sources",
        "groups": "groups",
        "map objects skipped": "skipped",
    },
)
def populate(ctx: StageContext, params: PopulateParams) -> None:
    """The city scene with parked cars, mapped street furniture, sidewalk objects by zone and groups."""
    from navverse.city.street_life.populate import populate_city
    from stages._city_step import read_city_step, write_city_step

    city, scene, plan, carried = read_city_step(ctx, "street_geometry")
    settings = PopulateSettings.of(params)
    result = populate_city(scene, city, plan, ctx.rng, settings)
    counts = result.counts
    write_city_step(ctx, result.scene, plan, carried.model_copy(update={"populate": settings}), counts)
    ctx.log.info(
        "populated %s: %d cars, %d street objects, %d groups, %d mapped objects skipped",
        ctx.target, sum(counts["cars"].values()),
        counts["sources"].get("map", 0) + counts["sources"].get("grammar", 0), sum(counts["groups"].values()),
        sum(counts["skipped"].values()),
    )  # fmt: skip
