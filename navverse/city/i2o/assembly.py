"""Indoor-to-outdoor scenes: a building with rooms joined to a city through a door in a facade.

:func:`assemble_i2o` takes a city scene (buildings with facades, scene format 2.0, and its street
plan) and an indoor building scene (one ``indoor`` building with at least one exit) and makes one
scene of type ``i2o``:

1. **Facade selection.** Every road-facing facade of the city (its ``road`` within
   ``max_road_distance``) is a candidate; along it, the building's exit is tried every meter, the
   building turned so that the exit's outward direction is the facade's normal and its exit wall lies
   on the facade's line. A placement is kept when the facade is wide enough for the exit
   (``exit_margin`` on each side), the sidewalk (or a plaza) lies in front of the exit within
   ``sidewalk_gap``, and the building's footprint stays inside the city's window and clear of roads,
   curbs, crosswalks, sidewalks, water and every other building. Placements are ranked by how much of
   the footprint covers the city building it replaces, then by closeness to the window's centre
   (so the 50 m around the exit stay in the city); the choice and the counts of refusals by reason are
   recorded.
2. **Connection.** The city building of the facade is removed with its storefronts; the ground and
   the objects inside the building's footprint are cut away with manifold3d
   (:func:`~navverse.scene.compose.remove_inside`), and street objects in front of the exit are
   cleared. The indoor building is moved there, its floor at the height of the ground just outside
   the exit (the step between them is recorded), without its own exit aprons (the street is outside
   now). Its exit facade takes the city facade's road.
3. The result keeps the city's terrain classes and map frame, the building's rooms, doors and exits
   (``indoor: true``), and the exit's centre as the indoor anchor.

Refusals are :class:`AssemblyError` with what to change: a building without an exit, a named facade
too narrow for the exit or not facing a road, or no facade that holds the building.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Annotated

import numpy as np
import shapely
from pydantic import Field
from shapely.affinity import affine_transform
from shapely.geometry import LineString, Point, Polygon

from navverse.city.geometry.street_plan import StreetPlan
from navverse.city.places.storefronts import WALKABLE_FRONT, FacadeReach, object_box
from navverse.city.precision import union_of
from navverse.errors import NavverseError, SceneError
from navverse.scene.annotations import BuildingAnnotation, ExitAnnotation, FacadeAnnotation
from navverse.scene.compose import merge_scenes, object_parts, remove_inside, replace_parts, transform_scene
from navverse.scene.geometry import MeshData, Scene, Surface
from navverse.scene.heights import SurfaceHeights

__all__ = [
    "AssemblyError",
    "AssemblySettings",
    "I2OAssembly",
    "assemble_i2o",
    "generated_fits",
]

_BLOCKING = ("road", "curb", "lowered_curb", "crosswalk", "sidewalk", "rail", "water", "shared")
"""Street plan classes a building's footprint may not cover."""
_STEP = 1.0  # spacing of the exit positions tried along a facade (m)
_TOLERANCE = 0.05  # m² of overlap forgiven (a wall's width on a shared edge)
_CUT_BELOW = 0.05  # the ground is cut this far below the indoor floor (no coplanar floors)


class AssemblyError(NavverseError):
    """A building cannot be joined to a city as asked: the message names the constraint."""


class AssemblySettings(FacadeReach):
    """How a building is joined to a city (see the module docstring): its exit set into a
    road-facing facade whose road is within ``max_road_distance`` and whose sidewalk is within
    ``sidewalk_gap`` in front, with ``exit_margin`` of facade on each side."""

    exit_margin: Annotated[float, Field(ge=0.0, le=50.0)] = 0.5
    """Facade length kept beyond each side of the exit (m)."""
    clear_depth: Annotated[float, Field(ge=0.0, le=10.0)] = 2.0
    """Depth in front of the exit cleared of street objects (m)."""
    facade: Annotated[int, Field(ge=1, le=10_000_000)] | None = None
    """Use this city facade (its id) instead of choosing one."""
    exit: Annotated[int, Field(ge=1, le=10_000)] | None = None
    """Connect this exit of the building (its id); by default its first."""


@dataclass(frozen=True)
class I2OAssembly:
    """The assembled scene and how it was made.

    Attributes
    ----------
    scene : Scene
        Type ``i2o``: the city with the building joined to it.
    record : dict
        ``facade`` (city facade id), ``replaced`` (the city building's map id and OSM id),
        ``exit_width``, ``floor_height``, ``step`` (floor minus ground just outside the exit, m),
        ``position`` (exit centre) and ``yaw`` of the building, ``candidates`` (placements that fit),
        ``refused`` {reason: facades}, ``objects_removed``.
    """

    scene: Scene
    record: dict = field(default_factory=dict)


@dataclass(frozen=True)
class _Placement:
    facade: FacadeAnnotation
    building: BuildingAnnotation
    exit_xy: np.ndarray
    yaw: float
    translation: np.ndarray
    footprint: Polygon
    score: tuple[float, float, int]


def _indoor_building(building: Scene, exit_id: int | None) -> tuple[BuildingAnnotation, ExitAnnotation]:
    indoor = [b for b in building.annotations.buildings if b.indoor]
    if len(indoor) != 1:
        raise AssemblyError(
            f"{building.scene_id} has {len(indoor)} indoor buildings; link a scene of exactly one (an "
            "indoor_layout or import_mesh target)"
        )
    exits = indoor[0].exits
    if not exits:
        raise AssemblyError(f"{building.scene_id}'s building has no exit to join to a street")
    if exit_id is None:
        return indoor[0], exits[0]
    chosen = [e for e in exits if e.id == exit_id]
    if not chosen:
        raise AssemblyError(
            f"{building.scene_id}'s building has no exit {exit_id}; its exits: "
            + ", ".join(str(e.id) for e in exits)
        )
    return indoor[0], chosen[0]


def _rigid(yaw: float, translation: np.ndarray) -> list[float]:
    c, s = math.cos(yaw), math.sin(yaw)
    return [c, -s, s, c, float(translation[0]), float(translation[1])]


class _Site:
    """The city's street plan, buildings and window, for fit checks."""

    def __init__(self, city: Scene, plan: StreetPlan, settings: AssemblySettings) -> None:
        self.settings = settings
        self.blocking = union_of(plan.classes.get(name, Polygon()) for name in _BLOCKING)
        self.walkable = union_of(plan.classes.get(name, Polygon()) for name in WALKABLE_FRONT)
        self.roads = union_of(plan.classes.get(name, Polygon()) for name in ("road", "curb", "water"))
        for shape in (self.blocking, self.walkable, self.roads):
            shapely.prepare(shape)
        bounds = city.annotations.bounds
        self.window = Polygon.from_bounds(bounds.min[0], bounds.min[1], bounds.max[0], bounds.max[1])
        self.centre = np.array(self.window.centroid.coords[0])
        self.buildings = list(city.annotations.buildings)
        self.shapes = [Polygon(b.footprint) for b in self.buildings]
        self.tree = shapely.STRtree(self.shapes)

    def sidewalk_ahead(self, point: np.ndarray, normal: np.ndarray) -> bool:
        start = Point(point + normal * 0.05)
        ray = LineString([start, point + normal * (self.settings.sidewalk_gap + 0.6)])
        walk = ray.intersection(self.walkable)
        if walk.is_empty:
            return False
        road = ray.intersection(self.roads)
        return road.is_empty or start.distance(walk) < start.distance(road)

    def conflict(self, footprint: Polygon, own: int) -> str | None:
        """Why a placed footprint does not fit, or None."""
        inner = footprint.buffer(-0.1)
        if not self.window.contains(footprint):
            return "the building would reach out of the city's window"
        if inner.intersection(self.blocking).area > _TOLERANCE:
            return "the building would cover a road, curb, crosswalk, sidewalk or water"
        for index in self.tree.query(inner, predicate="intersects"):
            if self.buildings[index].id != own and self.shapes[index].intersection(inner).area > _TOLERANCE:
                return "the building would overlap another building"
        return None


def _placements(
    site: _Site, indoor: BuildingAnnotation, exit_: ExitAnnotation
) -> tuple[list[_Placement], Counter[str]]:
    s = site.settings
    refused: Counter[str] = Counter()
    found: list[_Placement] = []
    footprint = Polygon(indoor.footprint)
    exit_xy = np.asarray(exit_.center[:2], dtype=np.float64)
    need = exit_.width + 2 * s.exit_margin
    for building in site.buildings:
        for facade in building.facades:
            if s.facade is not None and facade.id != s.facade:
                continue
            reason = _facade_refusal(facade, need, s)
            if reason is not None:
                refused[reason] += 1
                continue
            start, end = (np.asarray(p, dtype=np.float64) for p in facade.segment)
            along = (end - start) / facade.width
            normal = np.asarray(facade.normal, dtype=np.float64)
            yaw = facade.facing - exit_.facing
            best_reason: str | None = None
            placed_here = 0
            half = exit_.width / 2 + s.exit_margin
            for t in np.arange(half, facade.width - half + 1e-9, _STEP):
                point = start + along * t
                if not site.sidewalk_ahead(point, normal):
                    best_reason = best_reason or "no sidewalk in front of the exit"
                    continue
                c, sn = math.cos(yaw), math.sin(yaw)
                translation = point - np.array(
                    [c * exit_xy[0] - sn * exit_xy[1], sn * exit_xy[0] + c * exit_xy[1]]
                )
                placed = affine_transform(footprint, _rigid(yaw, translation))
                conflict = site.conflict(placed, building.id)
                if conflict is not None:
                    best_reason = conflict
                    continue
                covered = placed.intersection(Polygon(building.footprint)).area / max(placed.area, 1e-9)
                score = (-covered, float(np.hypot(*(point - site.centre))), facade.id)
                found.append(_Placement(facade, building, point, yaw, translation, placed, score))
                placed_here += 1
            if not placed_here:
                refused[best_reason or "the facade is too short for the exit"] += 1
    return found, refused


def _facade_refusal(facade: FacadeAnnotation, need: float, settings: AssemblySettings) -> str | None:
    if (
        facade.road is None
        or facade.road_distance is None
        or facade.road_distance > settings.max_road_distance
    ):
        return "the facade faces no road"
    if facade.width < need:
        return "the facade is too narrow for the exit"
    return None


def _no_placement(building: Scene, city: Scene, indoor: BuildingAnnotation, exit_, refused, settings) -> str:
    lo = np.min(indoor.footprint, axis=0)
    hi = np.max(indoor.footprint, axis=0)
    need = exit_.width + 2 * settings.exit_margin
    if settings.facade is not None:
        facades = {f.id: f for b in city.annotations.buildings for f in b.facades}
        facade = facades.get(settings.facade)
        if facade is None:
            return f"{city.scene_id} has no facade {settings.facade}"
        if facade.width < need:
            return (
                f"facade {facade.id} of {city.scene_id} is {facade.width:.2f} m wide; the exit of "
                f"{building.scene_id} needs {need:.2f} m ({exit_.width:.2f} m and {settings.exit_margin} m "
                "on each side): name a wider facade or leave `facade` out"
            )
    reasons = ", ".join(f"{reason}: {n}" for reason, n in refused.most_common()) or "no facades"
    return (
        f"no road-facing facade of {city.scene_id} holds {building.scene_id} (footprint "
        f"{hi[0] - lo[0]:.1f} x {hi[1] - lo[1]:.1f} m, exit {exit_.width:.2f} m wide): facades refused by "
        f"reason — {reasons}. Link a smaller building or another city"
    )


def _prism(polygon: Polygon, bottom: float, top: float) -> MeshData:
    import trimesh

    solid = trimesh.creation.extrude_polygon(polygon, top - bottom)
    return MeshData(np.asarray(solid.vertices) + np.array([0.0, 0.0, bottom]), np.asarray(solid.faces))


def assemble_i2o(
    city: Scene,
    plan: StreetPlan,
    building: Scene,
    *,
    scene_id: str,
    settings: AssemblySettings | None = None,
) -> I2OAssembly:
    """Join an indoor building to a city through one of its exits (module docstring).

    Parameters
    ----------
    city : Scene
        A city scene with facades (scene format 2.0), e.g. after population and storefronts.
    plan : StreetPlan
        The city's street plan.
    building : Scene
        A scene holding one indoor building with an exit (e.g. a procedural building).
    scene_id : str
        The assembled scene's id.
    settings : AssemblySettings, optional
        How to choose the facade.

    Returns
    -------
    I2OAssembly

    Raises
    ------
    AssemblyError
        If the building has no exit, the named facade cannot hold it, or no facade can.
    """
    settings = settings or AssemblySettings()
    indoor, exit_ = _indoor_building(building, settings.exit)
    site = _Site(city, plan, settings)
    found, refused = _placements(site, indoor, exit_)
    if not found:
        raise AssemblyError(_no_placement(building, city, indoor, exit_, refused, settings))
    chosen = min(found, key=lambda p: p.score)

    # the city without the replaced building, its storefronts and what stands in the way
    gone = chosen.building.id
    kept_storefronts = [s for s in city.annotations.storefronts if s.building != gone]
    gone_fronts = {
        tuple(round(v, 3) for v in s.center) for s in city.annotations.storefronts if s.building == gone
    }
    normal = np.asarray(chosen.facade.normal, dtype=np.float64)
    along = np.array([-normal[1], normal[0]])
    half = exit_.width / 2 + 0.5
    doorway = Polygon(
        [
            chosen.exit_xy - along * half,
            chosen.exit_xy + along * half,
            chosen.exit_xy + along * half + normal * settings.clear_depth,
            chosen.exit_xy - along * half + normal * settings.clear_depth,
        ]
    )
    objects = [
        part
        for part, obj in zip(object_parts(city), city.objects, strict=True)
        if tuple(round(v, 3) for v in obj.annotation.center) not in gone_fronts
        and not object_box(obj.annotation).intersects(doorway)
    ]
    removed_objects = len(city.objects) - len(objects)
    # the merge numbers the remaining buildings 1, 2, ... in order: their solids' names follow
    renamed = {
        f"building_{b.id:04d}": f"building_{k:04d}"
        for k, b in enumerate((b for b in city.annotations.buildings if b.id != gone), start=1)
    }
    surfaces = [
        Surface(renamed.get(s.name, s.name), s.terrain_class, s.mesh)
        for s in city.surfaces
        if s.name != f"building_{gone:04d}"
    ]
    street = replace_parts(
        city,
        surfaces=surfaces,
        objects=objects,
        buildings=[b for b in city.annotations.buildings if b.id != gone],
        storefronts=kept_storefronts,
    )
    ground = SurfaceHeights(street)
    outside = ground(chosen.exit_xy + normal * 0.3)[0]
    floor = float(outside) if np.isfinite(outside) else float(ground(chosen.exit_xy)[0])
    top = floor + indoor.height + 1.0
    before = len(street.objects)
    street = remove_inside(street, _prism(chosen.footprint, floor - _CUT_BELOW, top))
    removed_objects += before - len(street.objects)

    # the building, moved there, without its exit aprons, its exit facade facing the city's road
    facades = [
        f.model_copy(update={"road": chosen.facade.road, "road_distance": chosen.facade.road_distance})
        if f.id == exit_.facade
        else f
        for f in indoor.facades
    ]
    inside = replace_parts(
        building,
        surfaces=[s for s in building.surfaces if s.name != "apron"],
        buildings=[indoor.model_copy(update={"facades": facades})],
    )
    moved = transform_scene(inside, translation=(*chosen.translation, floor), yaw=chosen.yaw)
    anchor = (float(chosen.exit_xy[0]), float(chosen.exit_xy[1]), floor)
    merged = merge_scenes([street, moved], scene_id=scene_id, scene_type="i2o")
    scene = replace_parts(merged, indoor_anchor=anchor)
    step = floor - float(ground(chosen.exit_xy + normal * 1.0)[0])
    record = {
        "facade": chosen.facade.id,
        "replaced": {"building": gone, "map_id": chosen.building.map_id, "osm": chosen.building.osm},
        "exit_width": round(exit_.width, 3),
        "floor_height": round(floor, 3),
        "step": round(step, 3),
        "position": [round(float(v), 3) for v in chosen.exit_xy],
        "yaw": round(chosen.yaw, 6),
        "candidates": len(found),
        "refused": dict(sorted(refused.items())),
        "objects_removed": removed_objects,
    }
    return I2OAssembly(scene=scene, record=record)


def _building_depth(building: BuildingAnnotation, facade: FacadeAnnotation) -> float:
    """How deep a city building reaches behind one of its facades (m)."""
    start = np.asarray(facade.segment[0], dtype=np.float64)
    normal = np.asarray(facade.normal, dtype=np.float64)
    return float(np.max((start - np.asarray(building.footprint)) @ normal))


def generated_fits(
    city: Scene,
    plan: StreetPlan,
    building_type: str,
    rng: np.random.Generator,
    *,
    scene_id: str,
    settings: AssemblySettings | None = None,
    tries: int = 16,
) -> Iterator[I2OAssembly]:
    """Procedural buildings sized to road-facing city buildings, each joined there, best facade first.

    The city's road-facing facades are ranked by how much of the building type's footprint ranges
    (length along its spine, depth across it) the city building behind them can hold: a type whose
    exit is in its long front wall (``sides: back``) turns that wall to the facade, one whose exits
    end its spine turns its depth to the facade. For the best `tries` (16: in a city with few sidewalks
    the roomiest facades often have none in front of the exit), in turn, a building of that footprint
    is generated (a seed drawn from `rng` when its turn comes) and joined with :func:`assemble_i2o` at
    that facade; each join that fits is yielded (its record names the footprint asked for), so a
    caller can pass over one whose surroundings do not suit it.

    Raises
    ------
    AssemblyError
        If no facade has room for the building type, or none of the tried ones takes it (raised by
        the first ``next``).
    """
    from navverse.indoor.building import BuildingOptions, generate_building
    from navverse.indoor.floorplan import depth_range
    from navverse.indoor.programs import PROGRAMS

    settings = settings or AssemblySettings()
    if building_type not in PROGRAMS:
        raise AssemblyError(f"unknown building type {building_type!r}; choose from: {', '.join(PROGRAMS)}")
    program = PROGRAMS[building_type]
    lengths, depths = program.length, depth_range(program)
    front = program.spine.sides == "back"  # the exit is in the long front wall
    ranked = []
    for building in city.annotations.buildings:
        for facade in building.facades:
            if _facade_refusal(facade, 2.5 + 2 * settings.exit_margin, settings) is not None:
                continue
            across, behind = facade.width, _building_depth(building, facade)
            along_range, back_range = (lengths, depths) if front else (depths, lengths)
            if across < along_range[0]:
                continue
            size_along = min(across, along_range[1])
            size_back = float(np.clip(behind, *back_range))
            overflow = max(0.0, size_back - behind)
            ranked.append((overflow, -size_along * size_back, facade.id, size_along, size_back))
    if not ranked:
        raise AssemblyError(
            f"no road-facing facade of {city.scene_id} is {lengths[0] if front else depths[0]:.1f} m wide, "
            f"as a {building_type} needs: link a building or another city"
        )
    refused = []
    fitted = False
    for _, _, facade_id, size_along, size_back in sorted(ranked)[:tries]:
        length, depth = (size_along, size_back) if front else (size_back, size_along)
        options = BuildingOptions(length=round(length, 2), depth=round(depth, 2))
        seed = int(rng.integers(0, 2**63 - 1))
        try:
            building = generate_building(
                building_type, np.random.default_rng(seed), scene_id=f"{scene_id}-building", options=options
            )
            result = assemble_i2o(
                city, plan, building, scene_id=scene_id, settings=settings.of(settings, facade=facade_id)
            )
        except (AssemblyError, SceneError) as exc:
            refused.append(f"facade {facade_id}: {exc}")
            continue
        record = dict(
            result.record,
            generated={"building_type": building_type, "length": options.length, "depth": options.depth},
        )
        yield I2OAssembly(scene=result.scene, record=record)
        fitted = True
    if fitted:
        return
    raise AssemblyError(
        f"none of the {len(refused)} facades of {city.scene_id} with the most room takes a generated "
        f"{building_type}: " + "; ".join(refused[:3])
    )
