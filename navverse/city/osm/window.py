"""The window a city map covers: a rectangle in a local UTM frame centred on the window.

The frame is the WGS 84 UTM zone of the window's centre (EPSG 326xx north, 327xx south; the standard
6° zones, without the Norway and Svalbard exceptions), shifted so the centre is the origin: x east,
y north, in meters. :class:`Window` also carries the latitude/longitude box covering the rectangle,
which the reader uses to skip what lies elsewhere before projecting anything.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any

import numpy as np
from pydantic import Field
from pyproj import Transformer

from navverse.city.map import CityMapError
from navverse.settings import Settings

__all__ = [
    "MAX_WINDOW_SIDE",
    "LocalFrame",
    "LonLatBox",
    "OsmWindow",
    "Window",
    "box_text",
    "make_window",
    "utm_epsg",
]

MAX_WINDOW_SIDE = 50_000.0
"""Longest side of a window (m)."""

LonLatBox = tuple[float, float, float, float]
"""``(min_lon, min_lat, max_lon, max_lat)`` in degrees."""


Latitude = Annotated[float, Field(ge=-90.0, le=90.0, description="Degrees north, -90 to 90.")]
Longitude = Annotated[float, Field(ge=-180.0, le=180.0, description="Degrees east, -180 to 180.")]
Side = Annotated[float, Field(gt=0.0, le=MAX_WINDOW_SIDE, description="Meters, more than 0, at most 50 km.")]


class OsmWindow(Settings):
    """The window of an OSM file a city map covers: ``center`` ``[lat, lon]`` with ``size_m``
    ``[east-west, north-south]``, or ``bbox`` ``[min_lat, min_lon, max_lat, max_lon]``; with
    neither, the centre of the file's declared bounds (for a file that declares none, the node
    nearest the median of its nodes)."""

    center: tuple[Latitude, Longitude] | None = None
    """Centre of a ``size_m`` window (degrees)."""
    size_m: tuple[Side, Side] = (1000.0, 1000.0)
    """East-west and north-south sides of a centred window (m)."""
    bbox: tuple[Latitude, Longitude, Latitude, Longitude] | None = None
    """The window as a lat/lon box instead of ``center``."""


def utm_epsg(lat: float, lon: float) -> int:
    """EPSG code of the WGS 84 UTM zone holding (lat, lon): 326xx north of the equator, 327xx south."""
    zone = min(60, max(1, math.floor((lon + 180.0) / 6.0) + 1))
    return (32600 if lat >= 0.0 else 32700) + zone


def box_text(box: LonLatBox) -> str:
    """A lat/lon box in words, for messages: ``lat a..b, lon c..d``."""
    return f"lat {box[1]:.6f}..{box[3]:.6f}, lon {box[0]:.6f}..{box[2]:.6f}"


def _boxes_meet(a: LonLatBox, b: LonLatBox) -> bool:
    return a[0] <= b[2] and b[0] <= a[2] and a[1] <= b[3] and b[1] <= a[3]


@dataclass(frozen=True)
class LocalFrame:
    """A local metric frame: the UTM zone of a position, with the origin there (x east, y north, m)."""

    epsg: int
    origin: tuple[float, float]
    """The origin's easting and northing in the zone (m)."""
    _forward: Any = field(repr=False, compare=False)
    _inverse: Any = field(repr=False, compare=False)

    @classmethod
    def around(cls, lat: float, lon: float) -> LocalFrame:
        """The frame of the UTM zone holding (lat, lon), its origin there."""
        epsg = utm_epsg(lat, lon)
        forward = Transformer.from_crs("EPSG:4326", f"EPSG:{epsg}", always_xy=True)
        inverse = Transformer.from_crs(f"EPSG:{epsg}", "EPSG:4326", always_xy=True)
        x, y = forward.transform(lon, lat)
        return cls(epsg, (float(x), float(y)), forward, inverse)

    def project(self, lon: Any, lat: Any) -> np.ndarray:
        """Local (x, y) of WGS 84 positions: an ``(n, 2)`` array of meters."""
        x, y = self._forward.transform(np.asarray(lon, dtype=float), np.asarray(lat, dtype=float))
        return np.column_stack([np.asarray(x) - self.origin[0], np.asarray(y) - self.origin[1]])

    def lonlat(self, x: Any, y: Any) -> tuple[np.ndarray, np.ndarray]:
        """WGS 84 longitudes and latitudes of local positions."""
        lons, lats = self._inverse.transform(
            np.asarray(x, dtype=float) + self.origin[0], np.asarray(y, dtype=float) + self.origin[1]
        )
        return np.asarray(lons), np.asarray(lats)


@dataclass(frozen=True)
class Window:
    """The window a map covers: a rectangle in a local UTM frame and the lat/lon box around it.

    Attributes
    ----------
    epsg : int
        UTM zone of the window's centre.
    origin_lat, origin_lon : float
        The centre, the frame's origin.
    rect : tuple of float
        ``(min_x, min_y, max_x, max_y)`` in the local frame (m).
    lonlat : tuple of float
        ``(min_lon, min_lat, max_lon, max_lat)`` covering ``rect``, a little padded.

    Positions are projected with :meth:`project` (the window's :class:`LocalFrame`).
    """

    epsg: int
    origin_lat: float
    origin_lon: float
    rect: tuple[float, float, float, float]
    lonlat: LonLatBox
    frame: LocalFrame = field(repr=False, compare=False)

    def project(self, lon: Any, lat: Any) -> np.ndarray:
        """Local (x, y) of WGS 84 positions: an ``(n, 2)`` array of meters."""
        return self.frame.project(lon, lat)

    def contains_lonlat(self, lon: float, lat: float) -> bool:
        """Whether a position is in the window's lat/lon box (the rectangle is tested after projection)."""
        box = self.lonlat
        return box[0] <= lon <= box[2] and box[1] <= lat <= box[3]

    def contains(self, x: float, y: float) -> bool:
        """Whether a local position is in the window's rectangle."""
        rect = self.rect
        return rect[0] <= x <= rect[2] and rect[1] <= y <= rect[3]

    def meets(self, box: LonLatBox) -> bool:
        """Whether a lat/lon box meets the window's lat/lon box."""
        return _boxes_meet(self.lonlat, box)


def _pair(value: object, what: str) -> tuple[float, float]:
    if isinstance(value, (str, bytes)):
        raise CityMapError(f"{what} must be two numbers, not the text {value!r}")
    try:
        first, second = (float(v) for v in value)  # type: ignore[attr-defined]
    except (TypeError, ValueError):
        raise CityMapError(f"{what} must be two numbers, not {value!r}") from None
    if not (math.isfinite(first) and math.isfinite(second)):
        raise CityMapError(f"{what} must be finite, not {value!r}")
    return first, second


def _check_lat_lon(lat: float, lon: float, what: str) -> None:
    if not (-84.0 <= lat <= 84.0 and -180.0 <= lon <= 180.0):
        raise CityMapError(
            f"{what} ({lat:g}, {lon:g}) is outside the UTM range (latitude -84..84, longitude -180..180)"
        )


def _ring_points(rect: tuple[float, float, float, float], steps: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """Points along a rectangle's boundary (the ends of each side included)."""
    t = np.linspace(0.0, 1.0, steps + 1)
    x0, y0, x1, y1 = rect
    xs = np.concatenate([x0 + (x1 - x0) * t, np.full_like(t, x1), x1 - (x1 - x0) * t, np.full_like(t, x0)])
    ys = np.concatenate([np.full_like(t, y0), y0 + (y1 - y0) * t, np.full_like(t, y1), y1 - (y1 - y0) * t])
    return xs, ys


def _bbox(bbox: object) -> tuple[float, float, float, float]:
    if isinstance(bbox, (str, bytes)):
        raise CityMapError(f"bbox must be four numbers (min_lat, min_lon, max_lat, max_lon), not {bbox!r}")
    try:
        min_lat, min_lon, max_lat, max_lon = (float(v) for v in bbox)  # type: ignore[attr-defined]
    except (TypeError, ValueError):
        raise CityMapError(f"bbox must be (min_lat, min_lon, max_lat, max_lon), not {bbox!r}") from None
    finite = all(map(math.isfinite, (min_lat, min_lon, max_lat, max_lon)))
    if not (finite and min_lat < max_lat and min_lon < max_lon):
        raise CityMapError(f"bbox {bbox!r} must be finite (min_lat, min_lon, max_lat, max_lon), min < max")
    _check_lat_lon(min_lat, min_lon, "bbox corner")
    _check_lat_lon(max_lat, max_lon, "bbox corner")
    return min_lat, min_lon, max_lat, max_lon


def _centre(
    center: object, bbox: tuple[float, float, float, float] | None, data_bounds: LonLatBox | None, path: Path
) -> tuple[float, float]:
    """The window's centre (lat, lon): ``center``, else the centre of ``bbox`` or ``data_bounds``
    (rounded to 1e-7°, OSM's precision)."""
    if bbox is not None:
        return round((bbox[0] + bbox[2]) / 2.0, 7), round((bbox[1] + bbox[3]) / 2.0, 7)
    if center is not None:
        lat, lon = _pair(center, "center (lat, lon)")
        _check_lat_lon(lat, lon, "center")
        return lat, lon
    if data_bounds is None:
        raise CityMapError(
            f"{path} declares no data bounds in its header: give the window as center=(lat, lon) or bbox"
        )
    lat = round((data_bounds[1] + data_bounds[3]) / 2.0, 7)
    lon = round((data_bounds[0] + data_bounds[2]) / 2.0, 7)
    _check_lat_lon(lat, lon, f"the centre of the bounds of {path.name}")
    return lat, lon


def _rect_around(
    bbox: tuple[float, float, float, float], frame: LocalFrame
) -> tuple[float, float, float, float]:
    """The local rectangle around a lat/lon box, rounded outwards to the millimetre."""
    min_lat, min_lon, max_lat, max_lon = bbox
    xy = frame.project(*_ring_points((min_lon, min_lat, max_lon, max_lat)))
    xs, ys = xy[:, 0], xy[:, 1]
    rect = (
        math.floor(float(np.min(xs)) * 1000.0) / 1000.0,
        math.floor(float(np.min(ys)) * 1000.0) / 1000.0,
        math.ceil(float(np.max(xs)) * 1000.0) / 1000.0,
        math.ceil(float(np.max(ys)) * 1000.0) / 1000.0,
    )
    if max(rect[2] - rect[0], rect[3] - rect[1]) > MAX_WINDOW_SIDE:
        raise CityMapError(f"bbox {bbox!r} is wider than {MAX_WINDOW_SIDE:g} m: choose a smaller one")
    return rect


def make_window(
    *,
    center: tuple[float, float] | None,
    size_m: tuple[float, float],
    bbox: tuple[float, float, float, float] | None,
    data_bounds: LonLatBox | None,
    path: Path,
) -> Window:
    """The window from ``center`` + ``size_m``, or ``bbox``, or the centre of ``data_bounds``.

    Parameters
    ----------
    center : (lat, lon) or None
        Centre of a ``size_m`` window.
    size_m : (width, height)
        East-west and north-south sides of a centred window (m), at most :data:`MAX_WINDOW_SIDE`;
        unused with ``bbox``.
    bbox : (min_lat, min_lon, max_lat, max_lon) or None
        A lat/lon box instead: the window is the local rectangle around it, centred on its centre.
    data_bounds : lon/lat box or None
        The file's declared bounds: the default centre, and checked to meet the window.
    path : Path
        The file, for messages.

    Raises
    ------
    CityMapError
        If both or (without data bounds) neither of ``center`` and ``bbox`` are given, values are out
        of range, the window crosses the antimeridian, or it does not meet ``data_bounds``.
    """
    if center is not None and bbox is not None:
        raise CityMapError("give the window as center (with size_m) or as bbox, not both")
    box = _bbox(bbox) if bbox is not None else None
    lat, lon = _centre(center, box, data_bounds, path)
    frame = LocalFrame.around(lat, lon)
    if box is not None:
        rect = _rect_around(box, frame)
    else:
        width, height = _pair(size_m, "size_m (width, height)")
        if not (0.0 < width <= MAX_WINDOW_SIDE and 0.0 < height <= MAX_WINDOW_SIDE):
            raise CityMapError(f"size_m {size_m!r} must be two sides in (0, {MAX_WINDOW_SIDE:g}] m")
        rect = (-width / 2.0, -height / 2.0, width / 2.0, height / 2.0)
    lons, lats = frame.lonlat(*_ring_points(rect))
    pad = 1e-6  # about 0.1 m
    lonlat = (
        float(np.min(lons)) - pad,
        float(np.min(lats)) - pad,
        float(np.max(lons)) + pad,
        float(np.max(lats)) + pad,
    )
    if lonlat[0] < -180.0 or lonlat[2] > 180.0 or not all(map(math.isfinite, lonlat)):
        raise CityMapError("the window crosses the antimeridian (longitude ±180°), which is not supported")
    window = Window(frame.epsg, lat, lon, rect, lonlat, frame)
    if data_bounds is not None and not window.meets(data_bounds):
        raise CityMapError(
            f"the window ({box_text(lonlat)}) does not meet the data of {path.name} "
            f"({box_text(data_bounds)}): move it onto the data"
        )
    return window
