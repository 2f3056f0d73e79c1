"""What each scene type means to every part of the toolkit: one profile per type, in one table.

A scene is ``indoor`` (a building), ``outdoor`` (a city) or ``i2o`` (a building joined to a city
through a door in a facade). The navmesh stage, the scoring fields, the discrete actions, episode
sampling and the metrics read the profile of a scene's type here, and nowhere else decide by type.

=====================  ==========  ==========  ================================================
                       indoor      outdoor     i2o
=====================  ==========  ==========  ================================================
navmesh preset         indoor      outdoor     i2o: outdoor climb, 5 cm cells within
                                               ``fine_margin_m`` of the indoor buildings
field cell (m)         0.05        0.1         0.1
discrete step (m)      0.25        1.0         1.0
episode starts         anywhere    anywhere    inside an indoor building
success margin (m)     1.0         1.0         1.0 (success distance = margin + r_robot)
transition metrics     no          no          yes
goals outside          no          yes         yes: indoor starts lead out of the building
sky                    no          yes         yes (the renderer's default shading)
=====================  ==========  ==========  ================================================

The table's order (:data:`SCENE_TYPES`) is the natural order of scene types wherever they are
listed (tables, reports, group keys).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Literal

from navverse.errors import NavverseError
from navverse.settings import Settings

__all__ = [
    "PROFILES",
    "SCENE_TYPES",
    "SceneType",
    "SceneTypeProfile",
    "SceneTypeSettings",
    "UnknownSceneTypeError",
    "scene_profile",
]

SceneType = Literal["indoor", "outdoor", "i2o"]
"""The scene types (the values of ``scene.json``'s ``scene_type``)."""


class UnknownSceneTypeError(NavverseError):
    """A scene type that has no profile."""


@dataclass(frozen=True)
class SceneTypeProfile:
    """How scenes of one type are built, sampled, acted in and scored.

    Attributes
    ----------
    name : str
        The scene type.
    navmesh_preset : str
        Name of the navmesh settings preset (:data:`navverse.nav.PRESETS`) the navmesh stage uses
        unless the recipe names another.
    fine_margin_m : float or None
        For scenes that join buildings to a city: the navmesh is built at the indoor preset's cell
        size over the indoor buildings' footprints grown by this margin (m), and at the preset's
        own cell size elsewhere. ``None``: one cell size everywhere.
    field_cell_m : float
        Cell size of the scene's top-down scoring fields (:mod:`navverse.scene.fields`), m.
    discrete_step_m : float
        Translation of the discrete ``forward``/``left``/``right`` actions (m).
    start_region : {"anywhere", "indoor"}
        Where episode starts are drawn (``sample_episodes: start_region: auto``).
    success_margin_m : float
        A goal is reached within ``success_margin_m + r_robot`` of its region (paper, A.5).
    transition_metrics : bool
        Whether the indoor-to-outdoor transition measures apply to its episodes.
    goals_outside : bool
        Whether the scene has ground outside its buildings: an episode that starts inside a building
        (``start_region: indoor``) then has its goals outside, so that it leaves the building.
    sky : bool
        Whether the renderer's default shading shows a sky above the scene.
    """

    name: SceneType
    navmesh_preset: str
    fine_margin_m: float | None
    field_cell_m: float
    discrete_step_m: float
    start_region: Literal["anywhere", "indoor"]
    success_margin_m: float
    transition_metrics: bool
    goals_outside: bool
    sky: bool

    def success_distance(self, robot_radius: float) -> float:
        """Largest goal distance that counts as success: ``success_margin_m + r_robot`` (m)."""
        return self.success_margin_m + float(robot_radius)


PROFILES: Mapping[str, SceneTypeProfile] = MappingProxyType(
    {
        "indoor": SceneTypeProfile(
            name="indoor",
            navmesh_preset="indoor",
            fine_margin_m=None,
            field_cell_m=0.05,
            discrete_step_m=0.25,
            start_region="anywhere",
            success_margin_m=1.0,
            transition_metrics=False,
            goals_outside=False,
            sky=False,
        ),
        "outdoor": SceneTypeProfile(
            name="outdoor",
            navmesh_preset="outdoor",
            fine_margin_m=None,
            field_cell_m=0.1,
            discrete_step_m=1.0,
            start_region="anywhere",
            success_margin_m=1.0,
            transition_metrics=False,
            goals_outside=True,
            sky=True,
        ),
        "i2o": SceneTypeProfile(
            name="i2o",
            navmesh_preset="i2o",
            fine_margin_m=10.0,
            field_cell_m=0.1,
            discrete_step_m=1.0,
            start_region="indoor",
            success_margin_m=1.0,
            transition_metrics=True,
            goals_outside=True,
            sky=True,
        ),
    }
)
"""The profile of every scene type (read-only)."""

SCENE_TYPES: tuple[str, ...] = tuple(PROFILES)
"""The scene types, in their natural order."""


def scene_profile(scene_type: str) -> SceneTypeProfile:
    """The profile of ``scene_type``.

    Raises
    ------
    UnknownSceneTypeError
        If the type has no profile; the message lists the known ones.
    """
    try:
        return PROFILES[scene_type]
    except KeyError:
        raise UnknownSceneTypeError(
            f"unknown scene type {scene_type!r}; expected one of {', '.join(SCENE_TYPES)}"
        ) from None


class SceneTypeSettings(Settings):
    """The type a scene is given when it is made from declared parts (primitive solids, an imported
    mesh) rather than generated as a building or a city."""

    scene_type: SceneType = "indoor"
    """The scene's type, and so its profile (navmesh preset, episode starts, metrics...)."""
