"""The settings of a scene's look: when it is seen (sun and sky), how it is exposed, which variant."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from navverse.settings import Settings

__all__ = ["EVAL_LOOK", "LOOK_VERSION", "LookSettings"]

LOOK_VERSION = "1.0"
"""Version of how looks are computed from a scene and its settings; a dataset's manifest records it."""


class LookSettings(Settings):
    """When and how a scene is seen: the sun's place from the time of day, exposure, material variant.

    The evaluation look (:data:`EVAL_LOOK`) is these defaults; training may draw other values from an
    episode or environment seed.
    """

    time_of_day: Annotated[float, Field(ge=5.0, le=19.0)] = 10.5
    """Local solar time in hours; with the day of the year and the latitude it places the sun."""
    day_of_year: Annotated[int, Field(ge=1, le=366)] = 80
    """Day of the year (80: the March equinox)."""
    latitude_deg: Annotated[float, Field(ge=-66.0, le=66.0)] | None = None
    """Latitude for the sun's path; None takes the scene's map origin, or 45 degrees without one."""
    sun_intensity: Annotated[float, Field(ge=0.0, le=10.0)] = 3.0
    """Irradiance of the sun at the zenith on a surface facing it, relative to the sky's."""
    sky_intensity: Annotated[float, Field(ge=0.0, le=10.0)] = 1.0
    """Irradiance of the sky on an upward-facing surface in the open."""
    room_light: Annotated[float, Field(ge=0.0, le=10.0)] = 1.6
    """Strength of the light of each room (a lamp under its ceiling at its centre)."""
    exposure_ev: Annotated[float, Field(ge=-4.0, le=4.0)] = 0.0
    """Exposure compensation in stops over the camera's automatic exposure."""
    shadows: bool = True
    """Cast shadows from the sun and the room lights (one more ray per lit pixel and light)."""
    material_variant: Annotated[int, Field(ge=0, le=1_000_000)] = 0
    """Which variant of every material (colours and pattern phases); 0 is the evaluation look."""


EVAL_LOOK = LookSettings()
"""The look every evaluation renders with: the defaults, fixed and documented."""
