"""Recipe values that name terrain classes, checked against the default table (shared by the stages)."""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator


def known_terrain_class(name: str) -> str:
    """``name`` if it is a class of :data:`navverse.scene.terrain.DEFAULT_TERRAIN_CLASSES`."""
    from navverse.scene.terrain import DEFAULT_TERRAIN_CLASSES

    if name not in DEFAULT_TERRAIN_CLASSES:
        known = ", ".join(sorted(DEFAULT_TERRAIN_CLASSES))
        raise ValueError(f"unknown terrain class {name!r} (known: {known})")
    return name


TerrainName = Annotated[str, AfterValidator(known_terrain_class)]
"""A terrain class name of the default table."""
