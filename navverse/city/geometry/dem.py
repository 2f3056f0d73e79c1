"""A city window's heights from a GeoTIFF digital elevation model (DEM), with rasterio (``navverse[dem]``).

:func:`read_dem` samples the DEM's first band at the nodes of the window's relief raster
(:func:`~navverse.city.geometry.terrain.raster_nodes`): each node, in the map's frame (its EPSG code
and origin), is projected into the DEM's coordinate reference system with pyproj, and the DEM is
interpolated there bilinearly between pixel centres. Heights are taken as meters and made relative to
the window's centre. Only the part of the DEM under the window is read (averaged down when it would
exceed :data:`MAX_PIXELS`). A DEM that does not cover the window, or has no data in it, is refused;
so is a map without a geographic frame (a synthetic one).
"""

from __future__ import annotations

import math
import os

import numpy as np
from pyproj import Transformer
from scipy.ndimage import map_coordinates

from navverse.city.geometry.terrain import HeightGrid, raster_nodes
from navverse.city.map import Frame
from navverse.errors import NavverseError

__all__ = ["DEM_INSTALL", "MAX_PIXELS", "DemError", "rasterio_missing", "read_dem"]

DEM_INSTALL = "pip install 'navverse[dem]'"
"""How to install the optional reader of DEMs (rasterio)."""
MAX_PIXELS = 16_000_000
"""Most DEM pixels read for one window; a finer DEM is averaged down to this many."""


class DemError(NavverseError):
    """A DEM that cannot be read for a city's window."""


def rasterio_missing() -> str | None:
    """Why DEMs cannot be read here (rasterio is not installed, with how to install it), or None."""
    try:
        import rasterio  # noqa: F401
    except ImportError:
        return f"reading a DEM needs rasterio, which is not installed: {DEM_INSTALL}"
    return None


def _in_window(points: np.ndarray, window: tuple[float, float, float, float]) -> np.ndarray:
    """Whether each xy point lies in ``window`` (a millimetre of slack)."""
    min_x, min_y, max_x, max_y = window
    x, y = points[:, 0], points[:, 1]
    return (x >= min_x - 1e-3) & (x <= max_x + 1e-3) & (y >= min_y - 1e-3) & (y <= max_y + 1e-3)


def read_dem(
    path: str | os.PathLike[str], *, frame: Frame, window: tuple[float, float, float, float]
) -> HeightGrid:
    """Heights of the DEM at ``path`` over ``window`` of a map in ``frame``, relative to its centre.

    Parameters
    ----------
    path : path-like
        A GeoTIFF (or any raster GDAL reads) with a coordinate reference system; heights in meters.
    frame : Frame
        The map's frame: EPSG code of its projection and the latitude/longitude of its origin.
    window : tuple of float
        min_x, min_y, max_x, max_y in that frame (m).

    Returns
    -------
    HeightGrid
        On :func:`~navverse.city.geometry.terrain.raster_nodes` of the window, 0 at its centre.

    Raises
    ------
    DemError
        If rasterio is missing, the map has no geographic frame, the file is not a readable raster
        with a coordinate reference system, or the DEM does not cover the window with data.
    """
    missing = rasterio_missing()
    if missing is not None:
        raise DemError(missing)
    import rasterio
    from rasterio.enums import Resampling
    from rasterio.errors import RasterioError
    from rasterio.windows import Window

    name = os.path.basename(os.fspath(path))
    if frame.epsg == 0:
        raise DemError(
            f"DEM {name}: the city map has no geographic frame (a synthetic map); a DEM needs a map read "
            "from OSM (osm_city), synthetic cities take relief_height instead"
        )
    grid = raster_nodes(window)
    centre = ((window[0] + window[2]) / 2.0, (window[1] + window[3]) / 2.0)
    local = np.vstack([grid.nodes, centre])
    project = Transformer.from_crs("EPSG:4326", f"EPSG:{frame.epsg}", always_xy=True)
    east, north = project.transform(frame.origin_lon, frame.origin_lat)
    try:
        source = rasterio.open(path)
    except RasterioError as exc:
        raise DemError(f"DEM {name} is not a raster that can be read ({exc})") from None
    with source:
        if source.crs is None:
            raise DemError(f"DEM {name} has no coordinate reference system")
        to_dem = Transformer.from_crs(f"EPSG:{frame.epsg}", source.crs.to_wkt(), always_xy=True)
        x, y = to_dem.transform(local[:, 0] + east, local[:, 1] + north)
        inverse = ~source.transform
        col = inverse.a * np.asarray(x) + inverse.b * np.asarray(y) + inverse.c
        row = inverse.d * np.asarray(x) + inverse.e * np.asarray(y) + inverse.f
        covered = (col >= 0) & (col <= source.width) & (row >= 0) & (row <= source.height)
        needed = _in_window(local, window)  # the raster's outer nodes, a cell beyond, may fall short
        if not np.all((covered & np.isfinite(col) & np.isfinite(row))[needed]):
            left, bottom, right, top = source.bounds
            wx, wy = np.asarray(x)[needed], np.asarray(y)[needed]
            raise DemError(
                f"DEM {name} does not cover the city's window: the window spans x {np.nanmin(wx):.1f} to "
                f"{np.nanmax(wx):.1f}, y {np.nanmin(wy):.1f} to {np.nanmax(wy):.1f} in the DEM's "
                f"coordinates ({source.crs}), the DEM x {left:.1f} to {right:.1f}, "
                f"y {bottom:.1f} to {top:.1f}"
            )
        col = np.clip(np.nan_to_num(col), 0.0, source.width)
        row = np.clip(np.nan_to_num(row), 0.0, source.height)
        c0, r0 = max(0, math.floor(col.min()) - 1), max(0, math.floor(row.min()) - 1)
        c1 = min(source.width, math.ceil(col.max()) + 1)
        r1 = min(source.height, math.ceil(row.max()) + 1)
        factor = max(1, math.ceil(math.sqrt((c1 - c0) * (r1 - r0) / MAX_PIXELS)))
        shape = (max(1, math.ceil((r1 - r0) / factor)), max(1, math.ceil((c1 - c0) / factor)))
        data = source.read(
            1,
            window=Window(c0, r0, c1 - c0, r1 - r0),
            out_shape=shape,
            masked=True,
            resampling=Resampling.average,
        )
    values = np.ma.filled(data.astype(np.float64), np.nan)
    # pixel-centre coordinates of the read block: pixel k's centre is at k + 0.5
    u = (col - c0) * shape[1] / (c1 - c0) - 0.5
    v = (row - r0) * shape[0] / (r1 - r0) - 0.5
    sampled = map_coordinates(values, [v, u], order=1, mode="nearest")
    if not np.all(np.isfinite(sampled)):
        raise DemError(f"DEM {name} has no data (nodata) under part of the city's window")
    heights = sampled[:-1] - sampled[-1]
    return grid.with_heights(heights.reshape(grid.heights.shape))
