"""Street life: a city scene with parked cars and street objects standing on it.

:func:`populate_city` lays the street zones (:mod:`navverse.city.street_life.zones`), plans the street
objects (:mod:`navverse.city.street_life.objects`: mapped furniture, then the zone grammar) within a
budget of ``objects_per_km2``, picks parking slots (:mod:`navverse.city.street_life.parking`) for up to
``cars_per_km2`` cars, builds every object from the object library, stands it on the scene's
surface (a vertical ray cast at its position) and adds it to the scene with its zone and source.

Footprints are planned with each category's largest size (``size_max``), so the object built,
whose size is drawn within the category's range, never reaches beyond its footprint. A car's size
is drawn and then shrunk, within its category's range, to fit its slot; a body type whose smallest
car does not fit is not drawn for that slot.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Annotated

import numpy as np
import shapely
from pydantic import AfterValidator, Field

from navverse.assets.library import SupportArea, asset, make_object
from navverse.city.geometry.street_plan import StreetPlan
from navverse.city.map import CityMap
from navverse.city.street_life.groups import GroupPlan, plan_groups
from navverse.city.street_life.objects import GRAMMAR, Placement, footprint, plan_street_objects
from navverse.city.street_life.parking import Slot, lot_slots, slot_polygon, street_slots
from navverse.city.street_life.zones import StreetZones, ZoneSettings, street_zones, walkway_clearance
from navverse.scene.compose import ObjectPart, object_parts, replace_parts
from navverse.scene.geometry import Scene
from navverse.scene.heights import SurfaceHeights

__all__ = ["CAR_TYPES", "PopulateSettings", "Population", "populate_city", "stand_objects"]

CAR_TYPES: dict[str, float] = {
    "sedan": 0.38,
    "hatchback": 0.22,
    "suv": 0.24,
    "van": 0.08,
    "pickup_truck": 0.08,
}
"""Body types of parked cars and their shares (a drawn type that does not fit a slot is redrawn)."""


def _known_categories(names: list[str]) -> list[str]:
    from navverse.assets.library import categories

    known = set(categories())
    unknown = sorted(set(names) - known)
    if unknown:
        listed = ", ".join(sorted(known))
        raise ValueError(
            f"unknown object categories {', '.join(unknown)}; the object library knows: {listed}"
        )
    return sorted(set(names))


def _known_groups(names: list[str] | None) -> list[str] | None:
    if names is None:
        return None
    from navverse.city.street_life.group_catalogue import GROUPS

    known = {g.name for g in GROUPS}
    unknown = sorted(set(names) - known)
    if unknown:
        raise ValueError(f"unknown contextual groups {', '.join(unknown)}; known: {', '.join(sorted(known))}")
    return sorted(set(names))


class PopulateSettings(ZoneSettings):
    """How densely a city is populated, and with what: the densities and exclusions below and the
    sidewalk zone widths of :class:`~navverse.city.street_life.zones.ZoneSettings` (``clear_width`` is the
    walkway kept clear on sidewalks wide enough, else ``min_clear``, else the whole sidewalk)."""

    cars_per_km2: Annotated[float, Field(ge=0.0, le=5000.0)] = 200.0
    """Most parked cars per km² of the window."""
    objects_per_km2: Annotated[float, Field(ge=0.0, le=20000.0)] = 1000.0
    """Most street objects (mapped furniture first, then the zone grammar) per km² of the window."""
    exclude: Annotated[list[str], AfterValidator(_known_categories)] = []
    """Object categories never placed."""
    lot_share: Annotated[float, Field(ge=0.0, le=1.0)] = 0.4
    """Share of the cars parked in parking lots when both lots and street slots are free."""
    group_objects_per_km2: Annotated[float, Field(ge=0.0, le=20000.0)] = 300.0
    """Most objects of contextual groups (bus stop waits, picnics, roadworks...) per km², besides the
    street objects."""
    groups: Annotated[list[str] | None, AfterValidator(_known_groups)] = None
    """The contextual groups to place (:data:`~navverse.city.street_life.group_catalogue.GROUPS` names);
    None: all."""
    group_spacing: Annotated[float, Field(ge=0.0, le=500.0)] = 8.0
    """Least distance between two groups (m)."""

    @property
    def excluded(self) -> frozenset[str]:
        """``exclude`` as a set."""
        return frozenset(self.exclude)


@dataclass(frozen=True)
class Population:
    """A populated scene and what was placed.

    Attributes
    ----------
    scene : Scene
        The scene with the new objects after its own.
    counts : dict
        ``cars`` by zone, ``objects`` by category, ``zones`` (objects by zone), ``sources`` (by what
        placed them), ``skipped`` (mapped furniture not placed, by reason), ``walkway_clearance_m``
        (``min``, ``median`` and ``transects`` of the clear walkway width measured across every
        sidewalk with the objects standing: :func:`~navverse.city.street_life.zones.walkway_clearance`).
    """

    scene: Scene
    counts: dict[str, dict[str, float]]


def _largest(category: str) -> tuple[float, float, float]:
    return asset(category).size_max


def _car_size(category: str, slot: Slot, rng: np.random.Generator) -> tuple[float, float, float] | None:
    """A drawn size of a car of ``category`` shrunk to fit ``slot`` (width, length, height), or None."""
    spec = asset(category)
    lo = spec.size_min
    if lo[0] > slot.width or lo[1] > slot.length:
        return None
    drawn = spec.sample_size(rng)
    return (min(drawn[0], slot.width), min(drawn[1], slot.length), drawn[2])


def _choose_slots(
    street: list[Slot], lots: list[Slot], count: int, share: float, rng: np.random.Generator
) -> list[Slot]:
    """``count`` slots: ``share`` of them from the lots, the rest from the street (or what there is)."""
    from_lots = min(len(lots), round(count * share)) if street else min(len(lots), count)
    from_street = min(len(street), count - from_lots)
    from_lots = min(len(lots), count - from_street)
    chosen = []
    for pool, n in ((street, from_street), (lots, from_lots)):
        if n > 0:
            chosen += [pool[i] for i in sorted(rng.choice(len(pool), size=n, replace=False).tolist())]
    return chosen


def populate_city(
    scene: Scene,
    city: CityMap,
    plan: StreetPlan,
    rng: np.random.Generator,
    settings: PopulateSettings | None = None,
) -> Population:
    """Stand parked cars and street objects in a city scene.

    Parameters
    ----------
    scene : Scene
        The city scene (``city_geometry``), with its own objects if any.
    city : CityMap
        The map it was made from.
    plan : StreetPlan
        The plan it was made from (``street_plan.json``).
    rng : numpy.random.Generator
        The only source of randomness.
    settings : PopulateSettings, optional
        Densities and exclusions.

    Returns
    -------
    Population
        The populated scene and its counts.
    """
    settings = settings or PopulateSettings()
    x0, y0, x1, y1 = city.window
    area_km2 = (x1 - x0) * (y1 - y0) / 1e6
    zones = street_zones(city, plan, settings)
    grammar = tuple(rule for rule in GRAMMAR if rule.category not in settings.excluded)
    street = plan_street_objects(
        city,
        plan,
        zones,
        _largest,
        rng,
        settings=settings,
        grammar=grammar,
        excluded=settings.excluded,
        budget=math.floor(settings.objects_per_km2 * area_km2),
    )
    car_types = {k: v for k, v in CAR_TYPES.items() if k not in settings.excluded}
    slots: list[Slot] = []
    if car_types:
        free_street = street_slots(city, zones, rng, settings=settings)
        free_lots = lot_slots(plan.classes["parking"])
        count = math.floor(settings.cars_per_km2 * area_km2)
        slots = _choose_slots(free_street, free_lots, count, settings.lot_share, rng)

    groups = plan_groups(
        city,
        plan,
        zones,
        street.placements,
        _largest,
        _supports,
        rng,
        budget=math.floor(settings.group_objects_per_km2 * area_km2),
        min_spacing=settings.group_spacing,
        gap=settings.gap,
        excluded=settings.excluded,
        selected=None if settings.groups is None else frozenset(settings.groups),
        avoid=[slot_polygon(slot) for slot in slots],
    )

    ground = SurfaceHeights(scene)
    parts = stand_objects(street.placements, slots, car_types, ground, rng)
    counts: dict[str, Counter[str]] = {k: Counter() for k in ("cars", "objects", "zones", "sources")}
    for part in parts:
        if part.source == "parking":
            counts["cars"][part.zone or "none"] += 1
    parts += _group_parts(groups, ground, rng)
    for part in parts:
        counts["objects"][part.category] += 1
        counts["zones"][part.zone or "none"] += 1
        counts["sources"][(part.source or "").split(":")[0]] += 1
    populated = replace_parts(scene, objects=[*object_parts(scene), *parts])
    result: dict[str, dict[str, float]] = {
        name: dict(sorted(counter.items())) for name, counter in counts.items()
    }
    result["skipped"] = dict(street.skipped)
    result["groups"] = dict(sorted(groups.groups.items()))
    result["groups_skipped"] = dict(sorted(groups.skipped.items()))
    result["walkway_clearance_m"] = _clearance(city, zones, parts)
    return Population(scene=populated, counts=result)


def stand_objects(
    placements: Sequence[Placement],
    slots: Sequence[Slot],
    car_types: Mapping[str, float],
    ground: SurfaceHeights,
    rng: np.random.Generator,
) -> list[ObjectPart]:
    """The objects of planned street placements and of parked cars in `slots`, standing on the ground.

    Each object gets its own generator seeded from `rng` (placements first, then slots), so an object
    does not change when others are added. A car's body type is drawn from `car_types` (weights),
    redrawn up to four times until one fits its slot; placements or slots with no ground under them
    are skipped.
    """
    seeds = rng.integers(0, 2**63 - 1, size=len(placements) + len(slots))
    heights = ground(
        np.array([(p.x, p.y) for p in placements] + [(s.x, s.y) for s in slots], dtype=np.float64).reshape(
            -1, 2
        )
    )
    parts: list[ObjectPart] = []
    for index, placement in enumerate(placements):
        part = _object_part(placement, np.random.default_rng(int(seeds[index])), heights[index])
        if part is not None:
            parts.append(part)
    names, weights = list(car_types), np.array(list(car_types.values()))
    for k, slot in enumerate(slots):
        index = len(placements) + k
        car = _car_part(slot, names, weights, np.random.default_rng(int(seeds[index])), heights[index])
        if car is not None:
            parts.append(car)
    return parts


def _car_part(
    slot: Slot, names: list[str], weights: np.ndarray, rng: np.random.Generator, height: float
) -> ObjectPart | None:
    """A parked car in `slot` standing at `height`, or None when no body type fits or no ground is there."""
    size = None
    for _ in range(4):
        category = names[int(rng.choice(len(names), p=weights / weights.sum()))]
        size = _car_size(category, slot, rng)
        if size is not None:
            break
    if size is None or not np.isfinite(height):
        return None
    mesh, extent = make_object(category, rng, size=size)
    return ObjectPart(
        category=category,
        mesh=mesh,
        center=(slot.x, slot.y, float(height) + extent[2] / 2.0),
        yaw=math.remainder(slot.heading - math.pi / 2.0, math.tau),
        size=extent,
        zone=slot.zone,
        source="parking",
    )


def _clearance(city: CityMap, zones: StreetZones, parts: list[ObjectPart]) -> dict[str, float]:
    """The clear walkway widths across the sidewalks once ``parts`` stand on them."""
    shapes = [
        footprint(p.category, p.extent(), p.center[0], p.center[1], p.yaw + math.pi / 2.0) for p in parts
    ]
    free = zones.walkway.difference(shapely.union_all(shapes)) if shapes else zones.walkway
    widths = walkway_clearance(city, zones, free)
    if not len(widths):
        return {"min": 0.0, "median": 0.0, "transects": 0}
    return {
        "min": round(float(widths.min()), 3),
        "median": round(float(np.median(widths)), 3),
        "transects": len(widths),
    }


def _supports(category: str, size: tuple[float, float, float]) -> list[SupportArea]:
    return asset(category).support_areas(size)


def _group_parts(groups: GroupPlan, ground: SurfaceHeights, rng: np.random.Generator) -> list[ObjectPart]:
    """The members of the placed groups, each at its exact size, stacked ones on their supports.

    A member's bottom is the ground under its group member of the ground (itself, or the support it
    stands on, followed down) plus its own ``z``.
    """
    members = groups.members
    if not members:
        return []
    base = []
    for member in members:
        while member.support is not None:
            member = members[member.support]
        base.append((member.x, member.y))
    heights = ground(np.asarray(base, dtype=np.float64))
    seeds = rng.integers(0, 2**63 - 1, size=len(members))
    parts = []
    for member, height, seed in zip(members, heights, seeds, strict=True):
        if not np.isfinite(height):
            continue
        mesh, extent = make_object(member.category, np.random.default_rng(int(seed)), size=member.size)
        parts.append(
            ObjectPart(
                category=member.category,
                mesh=mesh,
                center=(member.x, member.y, float(height) + member.z + extent[2] / 2.0),
                yaw=math.remainder(member.heading - math.pi / 2.0, math.tau),
                size=extent,
                zone=member.zone,
                group=member.group,
                source=f"group:{member.region}",
            )
        )
    return parts


def _object_part(placement: Placement, rng: np.random.Generator, height: float) -> ObjectPart | None:
    """The object of a placement, standing at ``height`` with its front along the placement's heading."""
    if not np.isfinite(height):
        return None
    mesh, extent = make_object(placement.category, rng)
    return ObjectPart(
        category=placement.category,
        mesh=mesh,
        center=(placement.x, placement.y, float(height) + extent[2] / 2.0),
        yaw=math.remainder(placement.heading - math.pi / 2.0, math.tau),
        size=extent,
        zone=placement.zone,
        source=placement.source,
    )
