"""The settings a city scene was built with, carried beside it (``city_settings.json``).

The stages that build a city write it next to the scene: the city geometry stage its
:class:`~navverse.city.geometry.scene.CityGeometry`, population its
:class:`~navverse.city.street_life.populate.PopulateSettings`, storefronts its
:class:`~navverse.city.places.storefronts.StorefrontSettings`. A stage that changes a built city later (the
indoor-to-outdoor assembly densifying the neighbourhood of an exit) reads them, so what it adds
follows the city's own rules (excluded categories, zone widths, storefront categories) rather than
defaults. A step that was skipped leaves its entry null.

``city_settings.json``: ``{"format_version": "1.0", "geometry": {...}, "populate": {...} | null,
"storefronts": {...} | null}``, sorted keys.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, ValidationError

from navverse.city.geometry.scene import CityGeometry
from navverse.city.places.storefronts import StorefrontSettings
from navverse.city.street_life.populate import PopulateSettings
from navverse.errors import NavverseError, rebuild_hint
from navverse.files import atomic_write

__all__ = ["CITY_SETTINGS_FILE", "CitySettings", "load_city_settings", "save_city_settings"]

CITY_SETTINGS_FILE = "city_settings.json"
"""The file beside a city scene that holds its :class:`CitySettings`."""


class CitySettings(BaseModel):
    """What a city scene was built with: its geometry, population and storefront settings."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    format_version: Literal["1.0"] = "1.0"
    """Version of the file's layout."""
    geometry: CityGeometry
    """The city geometry stage's settings."""
    populate: PopulateSettings | None = None
    """Population's settings; None when the street was left bare (the stage skipped)."""
    storefronts: StorefrontSettings | None = None
    """The storefront stage's settings; None when it was skipped."""

    @property
    def effective_populate(self) -> PopulateSettings:
        """The population settings, or the defaults for a city whose population was skipped."""
        return self.populate if self.populate is not None else PopulateSettings()

    @property
    def effective_storefronts(self) -> StorefrontSettings:
        """The storefront settings, or the defaults for a city whose storefronts were skipped."""
        return self.storefronts if self.storefronts is not None else StorefrontSettings()


def save_city_settings(settings: CitySettings, path: str | os.PathLike[str]) -> None:
    """Write ``settings`` as JSON at ``path`` (atomically, sorted keys: the same settings, the same bytes)."""
    with atomic_write(Path(path), mode="w") as handle:
        json.dump(settings.model_dump(mode="json"), handle, sort_keys=True, separators=(",", ":"))


def load_city_settings(path: str | os.PathLike[str]) -> CitySettings:
    """Read a ``city_settings.json``.

    Raises
    ------
    NavverseError
        If the file is missing or is not city settings of this format.
    """
    path = Path(path)
    try:
        return CitySettings.model_validate(json.loads(path.read_text(encoding="utf-8")))
    except FileNotFoundError:
        raise NavverseError(f"{path} is missing: {rebuild_hint()}") from None
    except (OSError, ValueError, ValidationError) as exc:
        raise NavverseError(f"{path} is not readable city settings ({exc}): {rebuild_hint()}") from None
