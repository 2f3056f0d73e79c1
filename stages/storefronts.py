"""Storefronts: the places of a city's map set into its facades, with signs a robot can read."""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator, Field

from pipeline import Params, StageContext, stage


def _place_categories(names: list[str] | None) -> list[str] | None:
    if names is None:
        return None
    from navverse.assets.storefronts import PLACE_CATEGORIES

    unknown = sorted(set(names) - set(PLACE_CATEGORIES))
    if unknown:
        raise ValueError(
            f"unknown place categories {', '.join(unknown)}; known: {', '.join(PLACE_CATEGORIES)}"
        )
    return sorted(set(names))


class StorefrontsParams(Params):
    """Parameters of :func:`storefronts`.

    Every place of the map whose ``amenity``/``shop`` tag has a place category gets a storefront on
    the nearest road-facing facade (found by ray casting), ``height`` tall and up to ``max_width``
    wide (lower on a lower building), shifted sideways to fit and kept ``corner_margin`` from the
    facade's ends; it is accepted when its recess is carved, its door opens onto the sidewalk (across
    at most ``sidewalk_gap`` m of open ground) and its sign is seen from the walkable ground in front
    (within ``view_radius``) at ``camera_height``. ``fill_per_km2`` adds storefronts
    on road-facing facades where the map has fewer places (categories drawn from the synthetic
    cities' place table); ``categories`` limits the place categories placed.
    """

    height: Annotated[float, Field(ge=3.2, le=6.0)] = 3.6
    max_width: Annotated[float, Field(ge=4.0, le=20.0)] = 8.0
    corner_margin: Annotated[float, Field(ge=0.0, le=5.0)] = 0.4
    search_radius: Annotated[float, Field(gt=0.0, le=200.0)] = 40.0
    max_road_distance: Annotated[float, Field(gt=0.0, le=50.0)] = 30.0
    camera_height: Annotated[float, Field(gt=0.0, le=3.0)] = 0.6
    view_radius: Annotated[float, Field(ge=2.0, le=30.0)] = 15.0
    fill_per_km2: Annotated[float, Field(ge=0.0, le=2000.0)] = 0.0
    sidewalk_gap: Annotated[float, Field(ge=0.0, le=20.0)] = 6.0
    categories: Annotated[list[str] | None, AfterValidator(_place_categories)] = None


@stage(
    name="storefronts",
    inputs=["city_map", "populated_geometry"],
    outputs=["geometry"],
    passthrough={"geometry": "populated_geometry"},
)
def storefronts(ctx: StageContext, params: StorefrontsParams) -> None:
    """The city scene with storefronts carved into its facades at the map's places (scene.json records)."""
    from navverse.city.storefronts import StorefrontSettings, place_storefronts
    from stages._city_step import read_city_step, write_city_step

    city, scene, plan = read_city_step(ctx, "populated_geometry")
    settings = StorefrontSettings(
        height=params.height,
        max_width=params.max_width,
        corner_margin=params.corner_margin,
        search_radius=params.search_radius,
        max_road_distance=params.max_road_distance,
        camera_height=params.camera_height,
        view_radius=params.view_radius,
        fill_per_km2=params.fill_per_km2,
        sidewalk_gap=params.sidewalk_gap,
        categories=None if params.categories is None else frozenset(params.categories),
    )
    result = place_storefronts(scene, city, plan, ctx.rng, settings)
    counts = result.counts
    write_city_step(ctx, result.scene, plan, counts)
    ctx.log.info(
        "%s: %d storefronts placed (%d map places, %d added), %d rejected",
        ctx.target, counts["placed"], counts["places"], counts["filled"], sum(counts["rejected"].values()),
    )  # fmt: skip
