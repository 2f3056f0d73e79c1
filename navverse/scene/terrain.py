"""Default terrain classes and a helper to pick them for a scene."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from types import MappingProxyType
from typing import Annotated

from pydantic import AfterValidator, ValidationError

from navverse.errors import SceneError
from navverse.scene.annotations import TerrainClass

__all__ = ["DEFAULT_TERRAIN_CLASSES", "TerrainName", "known_terrain_class", "terrain_classes"]


def _tc(
    name: str,
    friction: float,
    color: tuple[int, int, int],
    *,
    navigable: bool,
    preferred: bool = False,
    show_in_bev: bool = True,
) -> TerrainClass:
    return TerrainClass(
        name=name,
        friction=friction,
        color=color,
        navigable=navigable,
        preferred=preferred,
        show_in_bev=show_in_bev,
    )


DEFAULT_TERRAIN_CLASSES: Mapping[str, TerrainClass] = MappingProxyType(
    {
        tc.name: tc
        for tc in (
            _tc("floor", 0.9, (226, 208, 172), navigable=True, preferred=True),  # light beige
            _tc("wall", 0.6, (96, 92, 90), navigable=False),  # dark grey
            _tc("ceiling", 0.6, (222, 224, 244), navigable=False, show_in_bev=False),
            _tc("sidewalk", 0.9, (196, 196, 192), navigable=True, preferred=True),  # light grey
            _tc("road", 0.85, (54, 58, 68), navigable=True),  # dark asphalt
            _tc("curb", 0.9, (130, 140, 162), navigable=True),  # blue-grey
            _tc("crosswalk", 0.85, (240, 228, 140), navigable=True, preferred=True),  # pale yellow
            _tc("green", 0.55, (108, 168, 82), navigable=True),  # grass
            _tc("water", 0.05, (72, 132, 204), navigable=False),  # blue
            _tc("rail", 0.6, (84, 70, 60), navigable=False),  # ballast and sleepers
            _tc("building", 0.8, (150, 128, 116), navigable=False),  # brownish grey
            _tc("ground", 0.8, (176, 154, 112), navigable=True),  # bare earth
            _tc("parking", 0.85, (104, 108, 118), navigable=True),  # lighter asphalt
            _tc("plaza", 0.9, (200, 168, 150), navigable=True, preferred=True),  # warm paving
            _tc("obstacle", 0.6, (128, 62, 62), navigable=False),  # dark red-brown
        )
    }
)
"""Terrain classes every scene stage can use, by name (read-only)."""


def known_terrain_class(name: str) -> str:
    """``name`` if it is a class of :data:`DEFAULT_TERRAIN_CLASSES` (a settings validator).

    Raises
    ------
    ValueError
        Naming the known classes.
    """
    if name not in DEFAULT_TERRAIN_CLASSES:
        known = ", ".join(sorted(DEFAULT_TERRAIN_CLASSES))
        raise ValueError(f"unknown terrain class {name!r} (known: {known})")
    return name


TerrainName = Annotated[str, AfterValidator(known_terrain_class)]
"""A terrain class name of the default table (settings and recipes that name classes)."""


def terrain_classes(
    names: Iterable[str], *, overrides: Mapping[str, float] | None = None
) -> dict[str, TerrainClass]:
    """Pick default terrain classes by name, optionally overriding their friction.

    Parameters
    ----------
    names : iterable of str
        Class names from :data:`DEFAULT_TERRAIN_CLASSES`, in the order the result should have.
        Repeated names are kept once.
    overrides : mapping of str to float, optional
        New friction per class name; every key must also be in `names`.

    Returns
    -------
    dict of str to TerrainClass
        The selected classes, keyed by name, ready for ``SceneAnnotations.terrain_classes``.

    Raises
    ------
    SceneError
        On an unknown class name, an override of a class not selected, or a negative friction.
    """
    known = ", ".join(DEFAULT_TERRAIN_CLASSES)
    selected: dict[str, TerrainClass] = {}
    for name in names:
        if name not in DEFAULT_TERRAIN_CLASSES:
            raise SceneError(f"unknown terrain class {name!r}; choose from: {known}")
        selected[name] = DEFAULT_TERRAIN_CLASSES[name]
    for name, friction in (overrides or {}).items():
        if name not in selected:
            raise SceneError(
                f"friction override for {name!r}, which is not among the selected terrain classes "
                f"({', '.join(selected) or 'none'}); add it to the class list or remove the override"
            )
        try:
            selected[name] = TerrainClass.model_validate(
                {**selected[name].model_dump(), "friction": friction}
            )
        except ValidationError:
            raise SceneError(
                f"friction override for terrain class {name!r} must be a number >= 0, got {friction!r}"
            ) from None
    return selected
