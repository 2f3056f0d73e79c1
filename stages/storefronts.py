"""Storefronts: the places of a city's map set into its facades, with signs a robot can read."""

from __future__ import annotations

from navverse.city.places.storefronts import StorefrontSettings
from pipeline import Params, StageContext, stage


class StorefrontsParams(Params, StorefrontSettings):
    """Parameters of :func:`storefronts`: those of
    :class:`navverse.city.places.storefronts.StorefrontSettings`."""


@stage(
    name="storefronts",
    inputs=["city_map", "populated_geometry"],
    outputs=["geometry"],
    passthrough={"geometry": "populated_geometry"},
    summary={
        "storefronts": "categories",
        "map places": "places",
        "fill tries": "filled",
        "rejected": "rejected",
        "objects cleared": "objects_cleared",
    },
)
def storefronts(ctx: StageContext, params: StorefrontsParams) -> None:
    """The city scene with storefronts carved into its facades at the map's places (scene.json records)."""
    from navverse.city.places.storefronts import place_storefronts
    from stages._city_step import read_city_step, write_city_step

    city, scene, plan, carried = read_city_step(ctx, "populated_geometry")
    settings = StorefrontSettings.of(params)
    result = place_storefronts(scene, city, plan, ctx.rng, settings)
    counts = result.counts
    write_city_step(ctx, result.scene, plan, carried.model_copy(update={"storefronts": settings}), counts)
    ctx.log.info(
        "%s: %d storefronts placed (%d map places, %d added), %d rejected",
        ctx.target, counts["placed"], counts["places"], counts["filled"], sum(counts["rejected"].values()),
    )  # fmt: skip
