"""A city map as a scene: the ground plan in 3-D (roads depressed below curbs), buildings, annotations.

:func:`city_scene` is what the city geometry stage runs:
:func:`~navverse.city.geometry.surfaces.plan_surfaces`
tiles the window with surface classes, :func:`~navverse.city.geometry.ground.ground_surfaces` gives them
heights and vertical faces, :func:`~navverse.city.geometry.buildings.building_parts` extrudes the buildings,
and :func:`~navverse.scene.compose.assemble_scene` derives bounds and statistics. The terrain every
surface follows is flat, a plane (``slope``), or a relief (:mod:`~navverse.city.geometry.terrain`:
seeded hills or a DEM, graded along the roads) over which the ground is draped. The scene records
the map's frame (``geo``: EPSG code, latitude/longitude of the origin, source and attribution).
"""

from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field
from shapely.geometry import LineString, box

from navverse.city.geometry.buildings import PLINTH_DEPTH, building_parts
from navverse.city.geometry.draped import DRAPE_STEP
from navverse.city.geometry.ground import GroundSettings, ground_surfaces
from navverse.city.geometry.prisms import HeightFn
from navverse.city.geometry.street_plan import StreetPlan, street_plan
from navverse.city.geometry.surfaces import CROSSWALK_WIDTH, CURB_WIDTH, carriageways
from navverse.city.geometry.terrain import HeightGrid, ReliefSettings, relief_terrain
from navverse.city.map import CityMap
from navverse.scene.annotations import GeoReference, SceneSource
from navverse.scene.compose import assemble_scene
from navverse.scene.geometry import Scene
from navverse.scene.terrain import TerrainName, terrain_classes

__all__ = ["CityGeometry", "city_scene", "geometry_plan", "road_length", "scene_terrain"]


Grade = Annotated[float, Field(ge=-0.3, le=0.3)]
"""Rise per meter, -0.3 to 0.3."""
Friction = Annotated[float, Field(ge=0, le=5, description="Friction coefficient, 0 to 5.")]
"""A friction coefficient, 0 to 5."""


class CityGeometry(ReliefSettings, GroundSettings):
    """How a map becomes geometry: the ground's heights
    (:class:`~navverse.city.geometry.ground.GroundSettings`),
    the widths of curbs and crosswalks, junction crosswalks, the terrain's slope, its relief
    (:class:`~navverse.city.geometry.terrain.ReliefSettings`) and friction."""

    curb_width: Annotated[float, Field(ge=0.05, le=1.0)] = CURB_WIDTH
    """Width of the curb's top strip (m)."""
    crosswalk_width: Annotated[float, Field(ge=2.0, le=10.0)] = CROSSWALK_WIDTH
    """Width of a crosswalk along its road (m)."""
    junction_crosswalks: bool = True
    """Add crosswalks across every arm of every junction of roads with sidewalks
    (:func:`~navverse.city.geometry.crossings.junction_crossings`), besides the mapped ones. On by default:
    real junctions are crossed at every arm, mapped crossings or not, and without them a map that
    does not tag its crossings leaves the blocks as islands joined only by curb climbs."""
    slope: tuple[Grade, Grade] = (0.0, 0.0)
    """An analytic terrain every surface follows, curbs included: rise per meter east and north
    (under a relief, the plane it is added to before the roads are graded)."""
    friction: dict[TerrainName, Friction] = {}
    """Friction per terrain class, replacing the default table's."""

    def terrain(self, points: np.ndarray) -> np.ndarray:
        """Height of the terrain (sidewalk level) at xy ``points`` (N, 2+): the ``slope``'s plane."""
        grade_x, grade_y = self.slope
        return points[:, 0] * grade_x + points[:, 1] * grade_y


def road_length(city: CityMap) -> float:
    """Total length of the road centre lines inside the window (m)."""
    window = box(*city.window)
    return float(sum(LineString(r.centerline.points).intersection(window).length for r in city.roads))


def geometry_plan(city: CityMap, geometry: CityGeometry) -> StreetPlan:
    """The ground plan of ``city`` with the widths and crosswalk rule of ``geometry``."""
    return street_plan(
        city,
        curb_width=geometry.curb_width,
        crosswalk_width=geometry.crosswalk_width,
        junction_crosswalks=geometry.junction_crosswalks,
    )


def scene_terrain(
    city: CityMap, geometry: CityGeometry, *, seed: int = 0, dem: HeightGrid | None = None
) -> HeightFn:
    """The terrain a city scene follows: ``geometry``'s plane, or with a relief (``relief_height`` or
    ``dem``) the relief on it, graded along the roads
    (:func:`~navverse.city.geometry.terrain.relief_terrain`).

    Returns
    -------
    callable
        :meth:`CityGeometry.terrain` without a relief, else a
        :class:`~navverse.city.geometry.terrain.HeightGrid`.
    """
    relief = relief_terrain(city, geometry, seed=seed, dem=dem, plane=geometry.slope)
    return geometry.terrain if relief is None else relief


def city_scene(
    city: CityMap,
    *,
    scene_id: str,
    geometry: CityGeometry,
    terrain: HeightFn | None = None,
    source: SceneSource | None = None,
    plan: StreetPlan | None = None,
    seed: int = 0,
    dem: HeightGrid | None = None,
) -> Scene:
    """The outdoor scene of a city map.

    Parameters
    ----------
    city : CityMap
        The map.
    scene_id : str
        The scene's id.
    geometry : CityGeometry
        Heights and widths.
    terrain : callable, optional
        Height of the terrain at xy points (sidewalk level), in place of ``geometry``'s. By default
        :func:`scene_terrain`: the slope's plane (:meth:`CityGeometry.terrain`: flat unless a slope
        is set), with the relief of ``relief_height`` or of ``dem`` graded along the roads. On any
        terrain but the default flat one, buildings reach
        :data:`~navverse.city.geometry.buildings.PLINTH_DEPTH` below the lowest ground under them
        and the land under them is closed underneath.
    source : SceneSource, optional
        Recipe and toolkit version.
    plan : StreetPlan, optional
        The plan :func:`geometry_plan` gives for ``city`` and ``geometry`` (made here if omitted).
    seed : int
        Seed of the relief's hills (the target's seed, in a build).
    dem : HeightGrid, optional
        Heights of a DEM over the window (:func:`~navverse.city.geometry.dem.read_dem`), the relief
        in place of the seeded hills.

    Returns
    -------
    Scene
        Terrain surfaces named by class, ``building_NNNN`` solids, buildings with facades in the
        annotations, the map's frame in ``geo``.
    """
    plan = geometry_plan(city, geometry) if plan is None else plan
    city = city.model_copy(update={"crossings": list(plan.crossings)})
    level = terrain is None and geometry.slope == (0.0, 0.0)
    if terrain is None:
        terrain = scene_terrain(city, geometry, seed=seed, dem=dem)
    curved = isinstance(terrain, HeightGrid)
    step = DRAPE_STEP if curved else None
    sunk = curved or not level  # buildings reach below a sloping ground: a plinth, the land under closed
    ground = ground_surfaces(
        plan.classes,
        city,
        settings=geometry,
        crosswalk_width=geometry.crosswalk_width,
        terrain=terrain,
        step=step,
        sunk_buildings=sunk,
    )
    buildings, annotations = building_parts(
        city, carriageways(city), terrain=terrain, step=step, plinth=PLINTH_DEPTH if sunk else 0.0
    )
    surfaces = [*ground, *buildings]
    names = sorted({s.terrain_class for s in surfaces})
    geo = GeoReference(
        epsg=city.frame.epsg,
        origin_lat=city.frame.origin_lat,
        origin_lon=city.frame.origin_lon,
        map=city.source.name,
        sha256=city.source.sha256,
        attribution=city.source.attribution,
    )
    return assemble_scene(
        scene_id=scene_id,
        scene_type="outdoor",
        surfaces=surfaces,
        buildings=annotations,
        terrain_classes=terrain_classes(
            names, overrides={k: v for k, v in geometry.friction.items() if k in names}
        ),
        road_length_m=round(road_length(city), 3),
        geo=geo,
        source=source,
    )
