"""The steepest grade of each road class in a built city scene, measured by vertical ray casts.

Along every road's centre line (inside the window), points :data:`SPACING` apart are stood on the
scene's surfaces (:class:`~navverse.scene.heights.SurfaceHeights`); a point on the carriageway
counts at its height plus ``road_depression``, one on a shared surface (no curbs) at its height, one
on a crosswalk (a ramp may rise there) or off the road not at all. A road's grade is the rise over
:data:`BASELINE` between two counted points; a class's steepest is the largest over its roads.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon, box

from navverse.city.geometry.street_plan import StreetPlan
from navverse.city.map import CityMap
from navverse.scene.geometry import Scene
from navverse.scene.heights import SurfaceHeights

__all__ = ["BASELINE", "SPACING", "road_grades"]

SPACING = 1.0
"""Distance between the points measured along a centre line (m)."""
BASELINE = 5.0
"""Run over which a grade is measured (m)."""


def _lines(city: CityMap) -> list[tuple[str, LineString]]:
    """Each road's centre line inside the window (kept 0.5 m off its edge), by highway class."""
    window = box(*city.window).buffer(-0.5, join_style="mitre")
    found = []
    for road in city.roads:
        inside = LineString(road.centerline.points).intersection(window)
        for part in shapely.get_parts(inside):
            if isinstance(part, LineString) and part.length >= BASELINE:
                found.append((road.highway, part))
    return found


def road_grades(scene: Scene, city: CityMap, plan: StreetPlan, *, road_depression: float) -> dict[str, float]:
    """The steepest grade (rise per meter over :data:`BASELINE`) of each road class's centre lines.

    Parameters
    ----------
    scene : Scene
        The built city scene.
    city : CityMap
        Its map (the roads' centre lines and classes).
    plan : StreetPlan
        Its ground plan (where the carriageway, shared surfaces and crosswalks are).
    road_depression : float
        How far the carriageway lies below the terrain (m).

    Returns
    -------
    dict
        ``{highway class: grade}`` rounded to 1e-4, sorted by class; classes with no centre line
        of at least :data:`BASELINE` in the window are left out.
    """
    lines = _lines(city)
    if not lines:
        return {}
    heights = SurfaceHeights(scene)
    level = {"road": road_depression, "shared": 0.0}
    areas = {name: plan.classes.get(name, Polygon()) for name in level}
    for area in areas.values():
        shapely.prepare(area)
    step = round(BASELINE / SPACING)
    worst: dict[str, float] = {}
    for highway, line in lines:
        along = np.arange(0.0, line.length + 1e-9, SPACING)
        points = shapely.get_coordinates(line.interpolate(along))
        z = np.full(len(points), np.nan)
        measured = heights(points)
        for name, offset in level.items():
            on = shapely.contains_xy(areas[name], points[:, 0], points[:, 1])
            z[on] = measured[on] + offset
        rise = np.abs(z[step:] - z[:-step]) / (along[step:] - along[:-step])
        rise = rise[np.isfinite(rise)]
        if len(rise):
            worst[highway] = max(worst.get(highway, 0.0), float(rise.max()))
    return {highway: round(grade, 4) for highway, grade in sorted(worst.items())}
