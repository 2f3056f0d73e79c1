"""The ground of a city in 3-D: every surface class of the ground plan at its height, as terrain surfaces.

Heights, relative to the terrain (flat, or the elevation function given):

==============  ===========================================================================================
surface         top
==============  ===========================================================================================
road            ``-road_depression`` (default 0.2 m below the sidewalks)
shared          0: living streets, service roads and tracks have no curbs (terrain class ``road``)
crosswalk       road level; within ``ramp_length`` of the road's edge a crosswalk whose kerb is not
                ``raised`` rises to ``-lip`` at the edge (``lowered``/``rolled``: ``lowered_curb_height``,
                ``flush``: 0), so the step onto the curb is the lip and the slope stays gentle
lowered curb    0 (the curb strip where a crosswalk meets it: terrain class ``crosswalk``; at a ``raised``
                crossing it stays ``curb``)
curb            0: the curb's top strip; its vertical face down to the road is the curb face
sidewalk, plaza 0
green, ground,  0 (land under buildings is ``ground``)
parking, rail
water           ``-water_depth`` (not navigable)
==============  ===========================================================================================

Each region is a prism (:func:`~navverse.city.geometry.prisms.polygon_prism`, open at the bottom) whose walls
reach below every neighbour, so wherever two regions of different heights meet there is a vertical
face and no gap: the curb face between road and curb, the ramp's sides, the bank of a pond. On a
curved terrain (a relief, :mod:`navverse.city.geometry.terrain`) the prisms are draped over it
(:func:`~navverse.city.geometry.draped.draped_prism`: cut into grid cells, edges a ``step`` long), so
the curb face keeps its height all along.
"""

from __future__ import annotations

from typing import Annotated

import numpy as np
import shapely
from pydantic import Field, model_validator
from shapely.geometry import Polygon, box
from shapely.geometry.base import BaseGeometry
from shapely.strtree import STRtree

from navverse.city.geometry.draped import draped_prism
from navverse.city.geometry.prisms import HeightFn, polygon_prism, polygons_of
from navverse.city.geometry.surfaces import crosswalk_polygons
from navverse.city.map import CityMap
from navverse.city.precision import difference, intersection, union, union_of
from navverse.city.shape_grid import ShapeGrid
from navverse.scene.geometry import MeshData, Surface
from navverse.settings import Settings

__all__ = ["TERRAIN_OF_SURFACE", "GroundSettings", "flat", "ground_surfaces"]

TERRAIN_OF_SURFACE = {
    "road": "road",
    "shared": "road",
    "crosswalk": "crosswalk",
    "lowered_curb": "crosswalk",
    "curb": "curb",
    "sidewalk": "sidewalk",
    "rail": "rail",
    "water": "water",
    "parking": "parking",
    "plaza": "plaza",
    "pedestrian": "plaza",
    "green": "green",
    "ground": "ground",
    "building": "ground",
}
"""Terrain class (:data:`navverse.scene.terrain.DEFAULT_TERRAIN_CLASSES`) of each ground-plan class."""
LIPS = {"lowered": None, "rolled": None, "flush": 0.0}
"""Lip of a crosswalk ramp by kerb (``None``: ``lowered_curb_height``); ``raised`` has no ramp."""


class GroundSettings(Settings):
    """Heights of the ground (m): how far roads, crosswalk ramps and water lie below the sidewalks."""

    road_depression: Annotated[float, Field(ge=0.0, le=0.5)] = 0.2
    """How far roads lie below the sidewalks: the curb height."""
    lowered_curb_height: Annotated[float, Field(ge=0.0, le=0.05)] = 0.005
    """The step left at a lowered curb (a crosswalk's edge, ``kerb=lowered``). 5 mm by default:
    accessibility rules allow at most 6 mm of vertical change at a curb ramp, and a wheel of 3.5 cm
    radius needs a friction above tan(acos((r - h) / r)) to climb a step h on traction alone (0.97
    for 1 cm, 0.59 for 5 mm), so a TurtleBot crosses at 5 mm and not at 1 cm on asphalt (0.85)."""
    ramp_length: Annotated[float, Field(ge=0.3, le=5.0)] = 1.5
    """How far into the road a crosswalk ramps down from the curb."""
    water_depth: Annotated[float, Field(ge=0.1, le=5.0)] = 0.5
    """How far water lies below the ground."""

    @model_validator(mode="after")
    def _lip_below_curb(self) -> GroundSettings:
        if self.lowered_curb_height > self.road_depression:
            raise ValueError(
                f"lowered_curb_height ({self.lowered_curb_height}) must not exceed road_depression "
                f"({self.road_depression})"
            )
        return self


def flat(points: np.ndarray) -> np.ndarray:
    """The flat terrain: height 0 everywhere."""
    return np.zeros(len(points))


def _offset(terrain: HeightFn, level: float) -> HeightFn:
    return lambda points: terrain(points) + level


def _ramp(terrain: HeightFn, edge: BaseGeometry, settings: GroundSettings, lip: float) -> HeightFn:
    """Heights of a crosswalk ramp: ``-lip`` at the road's ``edge``, road level ``ramp_length`` away."""
    depth = settings.road_depression

    def heights(points: np.ndarray) -> np.ndarray:
        distance = shapely.distance(shapely.points(points), edge)
        rise = np.clip(1.0 - distance / settings.ramp_length, 0.0, 1.0) * (depth - lip)
        return terrain(points) - depth + rise

    return heights


def _prisms(
    geometry: BaseGeometry,
    top: HeightFn,
    *,
    margin: float,
    terrain: HeightFn,
    step: float | None,
    closed: bool = False,
) -> list[MeshData]:
    meshes = []
    for polygon in polygons_of(geometry):
        if step is None:
            lowest = float(terrain(np.asarray(polygon.exterior.coords)).min())
            mesh = polygon_prism(polygon, top=top, bottom=lowest - margin, closed=closed)
        else:
            mesh = draped_prism(polygon, top=top, depth=margin, step=step, closed=closed)
        if mesh.num_faces:
            meshes.append(mesh)
    return meshes


class _Nearby:
    """The parts of a large geometry near a shape, through an STR tree of its parts."""

    def __init__(self, geometry: BaseGeometry) -> None:
        self.parts = [g for g in getattr(geometry, "geoms", [geometry]) if not g.is_empty]
        self.tree = STRtree(self.parts)

    def near(self, shape: BaseGeometry, distance: float = 0.0) -> BaseGeometry:
        """The union of the parts within ``distance`` of ``shape``'s envelope (empty if none)."""
        hits = self.tree.query(shape.envelope.buffer(distance, join_style="mitre") if distance else shape)
        items = [self.parts[i] for i in sorted(hits.tolist())]
        return shapely.union_all(items) if items else Polygon()


def _crosswalk_parts(
    plan: dict[str, BaseGeometry], city: CityMap, *, crosswalk_width: float, settings: GroundSettings
) -> tuple[list[tuple[BaseGeometry, float, BaseGeometry]], BaseGeometry, BaseGeometry]:
    """Crosswalk ramps with their lips and the road edge they rise to, the flat rest of the
    crosswalks, and the curb strip of raised crossings.

    Each crosswalk reads only the parts of the plan and of the road's edge near it (STR trees), and
    each ramp gives way only to the earlier ramps it meets, so the work grows with the number of
    crosswalks, not with its square.
    """
    carriageway = union(plan["road"], plan["crosswalk"])
    window = box(*city.window)
    edges = _Nearby(shapely.difference(carriageway.boundary, window.exterior.buffer(1e-6)))
    crosswalk_plan = _Nearby(plan["crosswalk"])
    ramps: list[tuple[BaseGeometry, float, BaseGeometry]] = []
    taken = ShapeGrid(25.0)
    raised: list[BaseGeometry] = []
    for kerb, polygon in crosswalk_polygons(city, crosswalk_width=crosswalk_width):
        if kerb == "raised":
            raised.append(polygon)
            continue
        lip = LIPS[kerb]
        reach = settings.ramp_length + 1.0
        x0, y0, x1, y1 = polygon.bounds
        edge = shapely.clip_by_rect(
            edges.near(polygon, reach), x0 - reach, y0 - reach, x1 + reach, y1 + reach
        )
        if edge.is_empty:
            continue
        band = edge.buffer(settings.ramp_length, quad_segs=2)
        piece = intersection(intersection(polygon, crosswalk_plan.near(polygon)), band)
        for earlier in taken.meeting(piece):
            piece = difference(piece, earlier)
        if not piece.is_empty:
            ramps.append((piece, settings.lowered_curb_height if lip is None else lip, edge))
            taken.add(piece)
    flat_rest = plan["crosswalk"]
    if ramps:
        flat_rest = difference(flat_rest, union_of(p for p, _, _ in ramps))
    raised_curb = intersection(plan["lowered_curb"], union_of(raised))
    return ramps, flat_rest, raised_curb


def ground_surfaces(
    plan: dict[str, BaseGeometry],
    city: CityMap,
    *,
    settings: GroundSettings,
    crosswalk_width: float,
    terrain: HeightFn = flat,
    step: float | None = None,
    sunk_buildings: bool = False,
) -> list[Surface]:
    """Terrain surfaces of the ground plan, one per terrain class, at their heights.

    Parameters
    ----------
    plan : dict
        :func:`~navverse.city.geometry.surfaces.plan_surfaces` of ``city``.
    city : CityMap
        The map (its crossings' kerbs shape the ramps).
    settings : GroundSettings
        Heights.
    crosswalk_width : float
        The width the plan was made with.
    terrain : callable
        Height of the terrain (sidewalk level) at xy points; flat by default.
    step : float, optional
        For a curved terrain (a relief): every region is draped over it
        (:func:`~navverse.city.geometry.draped.draped_prism`), cut into grid cells with edges at most
        ``step`` long. None (a flat or planar terrain): tops on the regions' own vertices.
    sunk_buildings : bool
        Whether buildings reach below the ground they stand on (on a sloping terrain): the land
        under them is then closed underneath, a solid the navmesh fills with the building sunk
        into it (an open ground's top would be a walkable floor inside it), and what is left when
        a building is removed is still a solid's top.

    Returns
    -------
    list of Surface
        Named by terrain class, in the order of :data:`TERRAIN_OF_SURFACE`'s classes.
    """
    depth = settings.road_depression
    margin = depth + settings.water_depth + 0.3
    ramps, flat_crosswalk, raised_curb = _crosswalk_parts(
        plan, city, crosswalk_width=crosswalk_width, settings=settings
    )
    pieces: dict[str, list[MeshData]] = {}

    def add(terrain_class: str, geometry: BaseGeometry, top: HeightFn, *, closed: bool = False) -> None:
        pieces.setdefault(terrain_class, []).extend(
            _prisms(geometry, top, margin=margin, terrain=terrain, step=step, closed=closed)
        )

    for surface_class, terrain_class in TERRAIN_OF_SURFACE.items():
        geometry = plan[surface_class]
        if surface_class == "crosswalk":
            add(terrain_class, flat_crosswalk, _offset(terrain, -depth))
            for piece, lip, edge in ramps:
                add(terrain_class, piece, _ramp(terrain, edge, settings, lip))
            continue
        if surface_class == "lowered_curb" and not raised_curb.is_empty:
            add("curb", raised_curb, terrain)
            geometry = difference(geometry, raised_curb)
        level = {"road": -depth, "water": -settings.water_depth}.get(surface_class, 0.0)
        closed = sunk_buildings and surface_class == "building"
        add(terrain_class, geometry, _offset(terrain, level) if level else terrain, closed=closed)
    return [
        Surface(name=name, terrain_class=name, mesh=MeshData.concatenate(meshes))
        for name, meshes in pieces.items()
        if meshes
    ]
