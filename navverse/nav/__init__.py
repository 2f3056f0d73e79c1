"""Navigation meshes: RecastNavigation (Recast + Detour) behind a habitat-sim-like ``PathFinder``.

>>> from navverse import nav
>>> finder = nav.build(vertices, faces, nav.INDOOR, area_types=areas)  # doctest: +SKIP
>>> finder.find_path([1, 0, 0], [9, 0, 0]).geodesic_distance  # doctest: +SKIP

The API is z-up (world frame); the C++ extension converts to and from Recast's y-up frame.
"""

from navverse.nav.errors import NavMeshError
from navverse.nav.fileformat import FORMAT_VERSION
from navverse.nav.pathfinder import (
    DEFAULT_AREA,
    MAX_AREA_TYPE,
    SNAP_MAX_HORIZONTAL,
    SNAP_MAX_VERTICAL,
    MultiGoalShortestPath,
    PathFinder,
    ShortestPath,
    TopDownView,
    build,
    load,
)
from navverse.nav.settings import I2O, INDOOR, OUTDOOR, PRESETS, NavMeshSettings

__all__ = [
    "DEFAULT_AREA",
    "FORMAT_VERSION",
    "I2O",
    "INDOOR",
    "MAX_AREA_TYPE",
    "OUTDOOR",
    "PRESETS",
    "SNAP_MAX_HORIZONTAL",
    "SNAP_MAX_VERTICAL",
    "MultiGoalShortestPath",
    "NavMeshError",
    "NavMeshSettings",
    "PathFinder",
    "ShortestPath",
    "TopDownView",
    "build",
    "load",
]
