"""The street plan: a city's 2-D surface classes as the geometry stage laid them, saved beside the scene.

:func:`street_plan` is the one place a map becomes its ground plan (the mapped crossings plus, when
asked, crosswalks on every junction arm; then :func:`~navverse.city.geometry.surfaces.plan_surfaces`). The
city geometry stage builds the scene from it and writes it as ``street_plan.json`` next to
``scene.json``, so that later stages (population, storefronts) place things on exactly the
sidewalks, curbs, crosswalks and roads the scene has, without redoing the plan or guessing it back
from triangles.

``street_plan.json``: ``{"format_version": "1.1", "classes": {class: WKB hex}, "crossings":
[{"position": [x, y], "road": id, "kerb": ...}], "curb_width": m}`` (1.0, without ``curb_width``, is
read as laid with the default curb width), coordinates in the scene's frame (m).
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

import shapely
from shapely.geometry.base import BaseGeometry

from navverse.city.geometry.crossings import junction_crossings
from navverse.city.geometry.surfaces import CURB_WIDTH, SURFACE_CLASSES, plan_surfaces
from navverse.city.map import CityMap, Crossing
from navverse.errors import NavverseError, rebuild_hint
from navverse.files import atomic_write

__all__ = ["STREET_PLAN_FILE", "StreetPlan", "load_street_plan", "save_street_plan", "street_plan"]

STREET_PLAN_FILE = "street_plan.json"
STREET_PLAN_FORMAT = "1.1"
_READABLE_FORMATS = (
    "1.0",
    STREET_PLAN_FORMAT,
)  # 1.0 plans have no curb_width: they were laid with the default


@dataclass(frozen=True)
class StreetPlan:
    """A city's ground plan.

    Attributes
    ----------
    classes : dict
        ``{surface class: (multi)polygon}`` for every class of
        :data:`~navverse.city.geometry.surfaces.SURFACE_CLASSES`, pairwise disjoint, tiling the window.
    crossings : tuple of Crossing
        Every crosswalk's crossing: the mapped ones and those added on junction arms.
    curb_width : float
        Width of the curb's top strip the plan was laid with (m): the sidewalk zones start beyond it.
    """

    classes: dict[str, BaseGeometry]
    crossings: tuple[Crossing, ...]
    curb_width: float


def street_plan(
    city: CityMap, *, curb_width: float, crosswalk_width: float, junction_crosswalks: bool
) -> StreetPlan:
    """Lay out the ground plan of a city map.

    Parameters
    ----------
    city : CityMap
        The map.
    curb_width, crosswalk_width : float
        Width of the curb's top strip, and of a crosswalk along its road (m).
    junction_crosswalks : bool
        Whether to add crosswalks across every arm of every junction of roads with sidewalks.
    """
    crossings = list(city.crossings)
    if junction_crosswalks:
        crossings += junction_crossings(city, crosswalk_width=crosswalk_width)
        city = city.model_copy(update={"crossings": crossings})
    classes = plan_surfaces(city, curb_width=curb_width, crosswalk_width=crosswalk_width)
    return StreetPlan(classes=classes, crossings=tuple(crossings), curb_width=curb_width)


def save_street_plan(plan: StreetPlan, path: str | os.PathLike[str]) -> None:
    """Write ``plan`` as ``street_plan.json`` at ``path`` (atomically)."""
    data = {
        "format_version": STREET_PLAN_FORMAT,
        "classes": {cls: shapely.to_wkb(plan.classes[cls], hex=True) for cls in SURFACE_CLASSES},
        "crossings": [c.model_dump(mode="json", exclude_none=True) for c in plan.crossings],
        "curb_width": plan.curb_width,
    }
    with atomic_write(Path(path), mode="w") as handle:
        json.dump(data, handle, separators=(",", ":"))


def load_street_plan(path: str | os.PathLike[str]) -> StreetPlan:
    """Read a ``street_plan.json``.

    Raises
    ------
    NavverseError
        If the file is missing or is not a street plan of this format.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if data.get("format_version") not in _READABLE_FORMATS:
            raise ValueError(f"format_version {data.get('format_version')!r}, expected {STREET_PLAN_FORMAT}")
        classes = {cls: shapely.from_wkb(data["classes"][cls]) for cls in SURFACE_CLASSES}
        crossings = tuple(Crossing.model_validate(c) for c in data["crossings"])
        curb_width = float(data.get("curb_width", CURB_WIDTH))
    except FileNotFoundError:
        raise NavverseError(f"{path} is missing: {rebuild_hint()}") from None
    except (OSError, ValueError, KeyError, TypeError, AttributeError, shapely.errors.ShapelyError) as exc:
        raise NavverseError(f"{path} is not a readable street plan ({exc}): {rebuild_hint()}") from None
    return StreetPlan(classes=classes, crossings=crossings, curb_width=curb_width)
