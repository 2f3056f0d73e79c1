"""The sun and the sky of a look: where the sun stands, its colour, the sky's colours and its light.

The sun's direction follows the standard solar-position formulas (declination from the day of the
year, hour angle from the solar time) in the scene frame (x east, y north, z up). Its colour is white
light dimmed through the air mass of its elevation (Kasten and Young's formula), more in blue than in
red, so a low sun is warm and weak. The sky is a gradient from a pale horizon to a blue zenith, greyer
and dimmer as the sun sinks. Colours are linear RGB; radiance 1.0 is "white paper in full sky light".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from navverse.look.settings import LookSettings

__all__ = ["DEFAULT_LATITUDE_DEG", "SunSky", "sun_direction", "sun_sky"]

DEFAULT_LATITUDE_DEG = 45.0
"""Latitude of the sun's path for a scene without a map origin."""
_EXTINCTION = np.array([0.11, 0.2, 0.42])  # optical depth per air mass, red green blue
_SKY_ZENITH = np.array([0.16, 0.3, 0.66])  # linear RGB of a clear zenith under a high sun
_SKY_HORIZON = np.array([0.62, 0.72, 0.86])
_GROUND_BOUNCE = np.array([0.22, 0.21, 0.19])  # the sky's light seen back from the ground, per unit


@dataclass(frozen=True)
class SunSky:
    """The sun and sky of one look, in linear RGB.

    Attributes
    ----------
    sun_direction : ndarray, shape (3,)
        Unit vector from the scene towards the sun (z up); its z is the sine of the elevation and may
        be negative (the sun below the horizon gives no direct light).
    sun_color : ndarray, shape (3,)
        Irradiance of the sun on a surface facing it.
    sky_zenith, sky_horizon : ndarray, shape (3,)
        Radiance of the sky straight up and at the horizon.
    sky_light, ground_light : ndarray, shape (3,)
        Irradiance from the sky on a surface facing up, and from the ground (bounced light) on one
        facing down, in the open; a surface in between gets the blend by its normal's z.
    """

    sun_direction: np.ndarray
    sun_color: np.ndarray
    sky_zenith: np.ndarray
    sky_horizon: np.ndarray
    sky_light: np.ndarray
    ground_light: np.ndarray


def sun_direction(*, time_of_day: float, day_of_year: int, latitude_deg: float) -> np.ndarray:
    """Unit vector towards the sun in the local east-north-up frame.

    Parameters
    ----------
    time_of_day : float
        Local solar time in hours (12 is solar noon).
    day_of_year : int
        1 to 366.
    latitude_deg : float
        Latitude in degrees, north positive.

    Returns
    -------
    ndarray, shape (3,)
        ``(east, north, up)``.
    """
    declination = math.radians(-23.44) * math.cos(2.0 * math.pi * (day_of_year + 10) / 365.0)
    hour_angle = math.radians(15.0 * (time_of_day - 12.0))
    latitude = math.radians(latitude_deg)
    east = -math.cos(declination) * math.sin(hour_angle)
    north = math.sin(declination) * math.cos(latitude) - math.cos(declination) * math.cos(
        hour_angle
    ) * math.sin(latitude)
    up = math.sin(declination) * math.sin(latitude) + math.cos(declination) * math.cos(hour_angle) * math.cos(
        latitude
    )
    vector = np.array([east, north, up])
    return vector / np.linalg.norm(vector)


def sun_sky(settings: LookSettings, *, latitude_deg: float | None = None) -> SunSky:
    """The sun and sky of `settings`.

    Parameters
    ----------
    settings : LookSettings
        Time of day, day of the year, intensities; its ``latitude_deg`` wins over the argument.
    latitude_deg : float, optional
        The scene's latitude (its map origin); :data:`DEFAULT_LATITUDE_DEG` when neither gives one.

    Returns
    -------
    SunSky
    """
    latitude = settings.latitude_deg
    if latitude is None:
        latitude = DEFAULT_LATITUDE_DEG if latitude_deg is None else latitude_deg
    direction = sun_direction(
        time_of_day=settings.time_of_day, day_of_year=settings.day_of_year, latitude_deg=latitude
    )
    elevation = math.degrees(math.asin(max(-1.0, min(1.0, float(direction[2])))))
    if elevation > 0.0:
        air_mass = 1.0 / (math.sin(math.radians(elevation)) + 0.50572 * (elevation + 6.07995) ** -1.6364)
        sun = settings.sun_intensity * np.exp(-_EXTINCTION * air_mass) / np.exp(-_EXTINCTION)
        sun = sun * min(1.0, elevation / 2.0)  # the disc sinking below the horizon
    else:
        sun = np.zeros(3)
    # The sky dims and greys with a low sun; a little light remains at dawn and dusk.
    height = max(0.0, math.sin(math.radians(elevation)))
    daylight = 0.25 + 0.75 * min(1.0, height / 0.5)
    warm = np.array([1.0, 0.88, 0.74])
    horizon = _SKY_HORIZON * (warm + (1.0 - warm) * min(1.0, height / 0.3))
    zenith = _SKY_ZENITH * daylight
    sky_light = settings.sky_intensity * daylight * (0.5 * (horizon + zenith) / _SKY_HORIZON.mean())
    ground = _GROUND_BOUNCE * (settings.sky_intensity * daylight + float(sun.mean()) * height)
    return SunSky(
        sun_direction=direction,
        sun_color=sun,
        sky_zenith=settings.sky_intensity * zenith,
        sky_horizon=settings.sky_intensity * daylight * horizon,
        sky_light=sky_light,
        ground_light=ground,
    )
