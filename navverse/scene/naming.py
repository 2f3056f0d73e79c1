"""USD prim names and paths used by scenes.

Prim names become USD identifiers (``[A-Za-z_][A-Za-z0-9_]*``); every object is a direct child of
:data:`OBJECTS_ROOT`. Keeping the rules here lets annotations, geometry and the USD writer agree.
"""

from __future__ import annotations

import re

TEXTURES_DIR = "textures"
"""The folder of a scene directory (beside its USD file) holding its texture images."""

__all__ = [
    "BUILDINGS_ROOT",
    "LOOKS_ROOT",
    "OBJECTS_ROOT",
    "PHYSICS_ROOT",
    "TERRAIN_ROOT",
    "WORLD_PATH",
    "is_identifier",
    "object_prim_path",
    "sanitize_identifier",
    "unique_name",
]

WORLD_PATH = "/World"
TERRAIN_ROOT = "/World/Terrain"
OBJECTS_ROOT = "/World/Objects"
LOOKS_ROOT = "/World/Looks"
PHYSICS_ROOT = "/World/Physics"
BUILDINGS_ROOT = "/World/Buildings"

_IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_INVALID_CHARS = re.compile(r"[^A-Za-z0-9_]")


def is_identifier(name: str) -> bool:
    """Return whether `name` is a valid USD prim name.

    Parameters
    ----------
    name : str
        Candidate prim name.

    Returns
    -------
    bool
        True for ``[A-Za-z_][A-Za-z0-9_]*``.
    """
    return bool(_IDENTIFIER.match(name))


def sanitize_identifier(name: str) -> str:
    """Turn any string into a valid USD prim name.

    Characters outside ``[A-Za-z0-9_]`` become ``_`` and a leading digit (or an empty name) gets a
    ``_`` prefix. Distinct inputs may map to the same output; callers that need unique names must
    add a suffix (e.g. an instance id).

    Parameters
    ----------
    name : str
        Any string, e.g. an object category such as ``"traffic light"``.

    Returns
    -------
    str
        A valid USD identifier.
    """
    cleaned = _INVALID_CHARS.sub("_", name)
    if not cleaned or cleaned[0].isdigit():
        cleaned = "_" + cleaned
    return cleaned


def object_prim_path(category: str, instance_id: int) -> str:
    """Return the conventional prim path of an object, e.g. ``/World/Objects/chair_0003``.

    Parameters
    ----------
    category : str
        Object category; sanitised into an identifier.
    instance_id : int
        Semantic instance id (>= 1); makes the path unique.

    Returns
    -------
    str
        Absolute prim path under :data:`OBJECTS_ROOT`.
    """
    return f"{OBJECTS_ROOT}/{sanitize_identifier(category)}_{instance_id:04d}"


def unique_name(base: str, taken: set[str]) -> str:
    """``base``, or ``base_2``, ``base_3``... if taken; the name returned is added to ``taken``."""
    name, suffix = base, 1
    while name in taken:
        suffix += 1
        name = f"{base}_{suffix}"
    taken.add(name)
    return name
