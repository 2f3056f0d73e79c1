"""The settings of a scene's look: when it is seen (sun and sky), how it is exposed, which variant."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Annotated

import numpy as np
from pydantic import Field, ValidationError

from navverse.settings import Settings

__all__ = ["EVAL_LOOK", "LOOK_VERSION", "LookSettings", "draw_look", "look_option"]

LOOK_VERSION = "1.1"
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


def draw_look(rng: np.random.Generator) -> LookSettings:
    """A look drawn for training: time of day 7:00 to 18:00 on any day, a material variant, the sun and
    sky a little stronger or weaker, exposure within half a stop (the latitude stays the scene's).

    Parameters
    ----------
    rng : numpy.random.Generator
        The draws' source (an episode's or an environment's seeded generator).
    """
    return LookSettings(
        time_of_day=round(float(rng.uniform(7.0, 18.0)), 3),
        day_of_year=int(rng.integers(1, 366)),
        sun_intensity=round(float(rng.uniform(2.2, 3.8)), 3),
        sky_intensity=round(float(rng.uniform(0.75, 1.25)), 3),
        room_light=round(float(rng.uniform(1.2, 2.0)), 3),
        exposure_ev=round(float(rng.uniform(-0.5, 0.5)), 3),
        material_variant=int(rng.integers(1, 1_000_001)),
    )


def look_option(value: object, rng: np.random.Generator) -> LookSettings:
    """The look an ``appearance`` option asks for.

    Parameters
    ----------
    value : object
        ``"eval"`` (:data:`EVAL_LOOK`), ``"random"`` (:func:`draw_look` from `rng`), a mapping of
        :class:`LookSettings` fields (the others at their defaults) or a :class:`LookSettings`.
    rng : numpy.random.Generator
        Draws ``"random"`` looks.

    Raises
    ------
    ValueError
        Saying what is accepted, or which field is wrong.
    """
    if isinstance(value, LookSettings):
        return value
    if value == "eval":
        return EVAL_LOOK
    if value == "random":
        return draw_look(rng)
    if isinstance(value, Mapping):
        try:
            return LookSettings.model_validate(dict(value))
        except ValidationError as exc:
            problems = "; ".join(f"{'.'.join(map(str, e['loc']))}: {e['msg']}" for e in exc.errors())
            raise ValueError(
                f"appearance: {problems} (fields: {', '.join(LookSettings.model_fields)})"
            ) from None
    raise ValueError(f'appearance must be "eval", "random" or a mapping of look settings, got {value!r}')
