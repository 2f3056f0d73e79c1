"""A neighbourhood of a populated city made busier: more street objects, parked cars and storefronts.

The paper densifies the surroundings of an indoor-to-outdoor scene's anchor so that the outdoor part
of an episode has things to find and to avoid. :func:`densify_neighbourhood` does it for any region
of a populated city scene:

1. **Storefronts** on the road-facing facades of the region, until it holds the number asked
   (:func:`~navverse.city.places.storefronts.densify_storefronts`; each clears the street in front of its
   door).
2. **Street objects** from the zone grammar (:func:`~navverse.city.street_life.objects.plan_street_objects`
   with the sidewalk zones clipped to the region; mapped furniture is already standing).
3. **Parked cars** in the free street slots of the region
(:func:`~navverse.city.street_life.parking.street_slots`).

A new object or car keeps the city's ``gap`` (:class:`~navverse.city.street_life.zones.ZoneSettings`)
from every object already in the scene, from the buildings, from
the ``keep_clear`` areas the caller names (an exit's doorway, say) and from the approach of every
storefront door. Of those that fit, ``objects_nearby`` and ``cars_nearby`` are drawn with the
generator, so the same scene, region and seed give the same result. What is added follows the city's
own population and storefront settings (excluded categories, zone widths, storefront categories).
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Annotated

import numpy as np
import shapely
from pydantic import Field
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.base import BaseGeometry

from navverse.city.geometry.street_plan import StreetPlan
from navverse.city.map import CityMap
from navverse.city.places.storefronts import StorefrontSettings, densify_storefronts
from navverse.city.street_life.objects import GRAMMAR, Placement, footprint, plan_street_objects
from navverse.city.street_life.parking import Slot, slot_polygon, street_slots
from navverse.city.street_life.populate import CAR_TYPES, PopulateSettings, stand_objects
from navverse.city.street_life.zones import StreetZones, street_zones
from navverse.scene.annotations import ObjectAnnotation, StorefrontAnnotation
from navverse.scene.compose import object_parts, replace_parts
from navverse.scene.geometry import Scene
from navverse.scene.heights import SurfaceHeights
from navverse.settings import Settings

__all__ = [
    "Densified",
    "DensifySettings",
    "ExitGoals",
    "base_footprint",
    "densify_neighbourhood",
    "things_near",
]

_DOOR_APPROACH = 3.0  # length of the corridor kept free straight out of a storefront's door (m)


class DensifySettings(Settings):
    """How much a neighbourhood gains (the i2o stages densify the neighbourhood of the exit)."""

    storefronts_nearby: Annotated[int, Field(ge=0, le=200)] = 8
    """Storefronts the region should hold in the end (those standing count)."""
    objects_nearby: Annotated[int, Field(ge=0, le=1000)] = 30
    """Most street objects added."""
    cars_nearby: Annotated[int, Field(ge=0, le=500)] = 8
    """Most parked cars added."""
    nearby_radius: Annotated[float, Field(gt=0.0, le=200.0)] = 50.0
    """Radius of the neighbourhood densified around a point (:meth:`region_around`), m."""

    def region_around(self, x: float, y: float) -> BaseGeometry:
        """The disc of ``nearby_radius`` around ``(x, y)``: the region to densify."""
        return Point(x, y).buffer(self.nearby_radius, quad_segs=16)


class ExitGoals(Settings):
    """What a generated building's exit must open onto (``generate_i2o``): things to find outside."""

    exit_goals: Annotated[int, Field(ge=0, le=1000)] = 4
    """Street objects, parked cars and storefronts (their signs) that must stand within
    ``exit_goals_radius`` of the exit once its neighbourhood is densified; a generated building
    whose exit opens onto fewer is moved to the next facade that takes it, and when none of those
    tried has as many, to the one with the most (0: the first facade that takes it)."""
    exit_goals_radius: Annotated[float, Field(gt=0.0, le=200.0)] = 30.0
    """Radius around the exit in which ``exit_goals`` are counted, m."""


def things_near(scene: Scene, x: float, y: float, radius: float) -> int:
    """Objects of `scene` (street objects, parked cars, storefronts' signs) outside its indoor region
    whose centre is within `radius` of ``(x, y)``: the goals an exit there opens onto."""
    indoor = shapely.union_all([Polygon(p) for p in scene.annotations.indoor_polygons])
    centres = [o.center for o in scene.annotations.objects]
    if not centres:
        return 0
    xy = np.asarray(centres, dtype=np.float64)[:, :2]
    close = np.hypot(xy[:, 0] - x, xy[:, 1] - y) <= radius
    return int((close & ~shapely.contains_xy(indoor, xy[:, 0], xy[:, 1])).sum())


@dataclass(frozen=True)
class Densified:
    """A densified scene and what was added (``objects`` and ``cars`` by category, ``storefronts``
    as counted by :func:`~navverse.city.places.storefronts.densify_storefronts`, ``candidates``: the
    placements and slots that fitted before the draw)."""

    scene: Scene
    counts: dict


def _clip(zones: StreetZones, region: BaseGeometry) -> StreetZones:
    """The zones objects and cars may be added to, cut to `region` (walkways and junctions whole)."""
    return replace(
        zones,
        furniture=zones.furniture.intersection(region),
        frontage=zones.frontage.intersection(region),
        verge=zones.verge.intersection(region),
        parking=zones.parking.intersection(region),
        curbside=zones.curbside.intersection(region),
    )


def base_footprint(obj: ObjectAnnotation) -> Polygon:
    """Where a standing object meets the ground: its base (a tree's trunk, a lamp's post; see
    :data:`~navverse.city.street_life.objects.BASE_FOOTPRINT`), else its box's footprint."""
    return footprint(obj.category, obj.size, obj.center[0], obj.center[1], obj.yaw + math.pi / 2.0)


def _door_approach(store: StorefrontAnnotation) -> BaseGeometry:
    """The ground kept free in front of a storefront's door: a corridor straight out of it."""
    x, y = store.entrance[0], store.entrance[1]
    out = (x + _DOOR_APPROACH * math.cos(store.facing), y + _DOOR_APPROACH * math.sin(store.facing))
    return LineString([(x, y), out]).buffer(max(store.door_width or 1.0, 1.0) / 2.0 + 0.3)


def _taken(scene: Scene, keep_clear: Sequence[BaseGeometry], gap: float) -> BaseGeometry:
    """Everything a new footprint must keep `gap` from: objects, buildings, doors, `keep_clear`."""
    annotations = scene.annotations
    shapes: list[BaseGeometry] = [base_footprint(o) for o in annotations.objects]
    shapes += [Polygon(b.footprint) for b in annotations.buildings]
    shapes += [_door_approach(s) for s in annotations.storefronts]
    shapes += [g for g in keep_clear if not g.is_empty]
    return shapely.union_all([s.buffer(gap) for s in shapes]) if shapes else Polygon()


def _draw(items: list, count: int, rng: np.random.Generator) -> list:
    """`count` of `items` drawn without replacement, in their own order."""
    if len(items) <= count:
        return items
    keep = sorted(rng.choice(len(items), size=count, replace=False).tolist())
    return [items[k] for k in keep]


def _free_placements(
    placements: Sequence[Placement], taken: BaseGeometry, region: BaseGeometry
) -> list[Placement]:
    """The planned placements inside `region` whose footprint stays clear of `taken`."""
    from navverse.assets.library import asset

    free = []
    for p in placements:
        shape = footprint(p.category, asset(p.category).size_max, p.x, p.y, p.heading)
        if region.contains(Point(p.x, p.y)) and not taken.intersects(shape):
            free.append(p)
    return free


def _free_slots(slots: Sequence[Slot], taken: BaseGeometry, region: BaseGeometry) -> list[Slot]:
    """The slots inside `region` clear of `taken`."""
    return [s for s in slots if region.contains(Point(s.x, s.y)) and not taken.intersects(slot_polygon(s))]


def densify_neighbourhood(
    scene: Scene,
    city: CityMap,
    plan: StreetPlan,
    rng: np.random.Generator,
    *,
    region: BaseGeometry,
    keep_clear: Sequence[BaseGeometry] = (),
    settings: DensifySettings,
    populate: PopulateSettings,
    storefronts: StorefrontSettings,
) -> Densified:
    """Add street objects, parked cars and storefronts inside `region` of a populated city scene.

    Parameters
    ----------
    scene : Scene
        The populated city scene (or an i2o scene made from one).
    city : CityMap
        The map the city was made from.
    plan : StreetPlan
        Its street plan.
    rng : numpy.random.Generator
        The only source of randomness.
    region : BaseGeometry
        Where to add (e.g. a 50 m disc around an exit).
    keep_clear : sequence of BaseGeometry
        Areas no new object or car may cover.
    settings : DensifySettings
        How many of each.
    populate, storefronts : PopulateSettings, StorefrontSettings
        The settings the city was populated and given storefronts with (excluded categories, zone
        widths, storefront sizes and categories): what is added follows the city's own rules.

    Returns
    -------
    Densified
        The scene with the new objects after its own, and the counts.
    """
    from navverse.assets.library import asset

    excluded = populate.excluded
    zones = _clip(street_zones(city, plan, populate), region)
    counts: dict = {}
    if settings.storefronts_nearby:  # first: a storefront clears the objects in front of its door
        shops = densify_storefronts(
            scene, plan, rng, storefronts, region=region, count=settings.storefronts_nearby
        )
        scene, counts["storefronts"] = shops.scene, shops.counts
    taken = _taken(scene, keep_clear, populate.gap)
    planned = plan_street_objects(
        city.model_copy(update={"furniture": []}),
        plan,
        zones,
        lambda category: asset(category).size_max,
        rng,
        settings=populate,
        grammar=tuple(rule for rule in GRAMMAR if rule.category not in excluded),
        excluded=excluded,
    )
    placements = _free_placements(planned.placements, taken, region)
    car_types = {k: v for k, v in CAR_TYPES.items() if k not in excluded}
    slots = street_slots(city, zones, rng, settings=populate) if car_types else []
    slots = _free_slots(slots, taken, region)
    candidates = {"objects": len(placements), "cars": len(slots)}
    placements = _draw(placements, settings.objects_nearby, rng)
    slots = _draw(slots, settings.cars_nearby, rng)
    parts = stand_objects(placements, slots, car_types, SurfaceHeights(scene), rng)
    scene = replace_parts(scene, objects=[*object_parts(scene), *parts])
    counts["objects"] = dict(sorted(Counter(p.category for p in parts if p.source != "parking").items()))
    counts["cars"] = dict(sorted(Counter(p.category for p in parts if p.source == "parking").items()))
    counts["candidates"] = candidates
    return Densified(scene=scene, counts=counts)
