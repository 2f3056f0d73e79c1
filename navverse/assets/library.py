"""The object library: every category's :class:`Asset`, looked up by name.

The categories are declared by the family modules of :mod:`navverse.assets.indoor` and
:mod:`navverse.assets.outdoor`; this registry is the one module that imports them.

Local frame of every object
---------------------------
- x = width, y = depth, z = height (up), meters.
- The object's **front** -- where a person uses it: the seat of a chair, the doors of a wardrobe, the
  screen of a tv, the keyboard of a piano -- faces **+y**; its back is at -y. An object placed with yaw
  0 against a wall on the room's south side (the wall at smaller y) therefore has its back on the wall.
- Meshes from :meth:`Asset.build` and :func:`make_object` are centred on their axis-aligned bounding
  box: the bounding-box centre is the origin, the bottom is at ``z = -height / 2``, and the box
  extents equal the object's size.
- :class:`SupportArea` heights are measured from the object's bottom, their rectangles from its centre.
- Triangles are wound counter-clockwise seen from outside (outward normals); every part is a closed
  solid of one colour (parts may touch or overlap), so the joined mesh is closed too.

Building is deterministic: the same generator state and size give byte-identical vertices, faces and
colours.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence

import numpy as np

from navverse.assets.errors import UnknownCategoryError
from navverse.assets.indoor import (
    decor,
    electronics,
    fixtures,
    home,
    kitchen_bath,
    medical,
    retail,
    seating,
    storage,
    tables,
)
from navverse.assets.outdoor import (
    carried_items,
    nature,
    street_amenities,
    street_furniture,
    vehicles,
    work_play,
)
from navverse.assets.spec import Asset, Size, SupportArea
from navverse.scene.geometry import MeshData

__all__ = ["Asset", "SupportArea", "asset", "categories", "make_object"]

_INDOOR = (seating, tables, storage, home, kitchen_bath, electronics, fixtures, decor, retail, medical)
_OUTDOOR = (vehicles, street_furniture, street_amenities, nature, work_play, carried_items)
_MODULES = _INDOOR + _OUTDOOR


@functools.cache
def _registry() -> dict[str, Asset]:
    registry: dict[str, Asset] = {}
    for module in _MODULES:
        for item in module.ASSETS:
            if item.category in registry:
                raise RuntimeError(f"object category {item.category!r} is defined twice")
            registry[item.category] = item
    return dict(sorted(registry.items()))


def categories() -> tuple[str, ...]:
    """All object categories of the library, sorted."""
    return tuple(_registry())


def asset(category: str) -> Asset:
    """Return the :class:`Asset` of a category.

    Raises
    ------
    UnknownCategoryError
        If the library has no such category; the message lists the known ones.
    """
    try:
        return _registry()[category]
    except KeyError:
        known = ", ".join(categories())
        raise UnknownCategoryError(
            f"unknown object category {category!r}; the object library knows: {known}"
        ) from None


def make_object(
    category: str, rng: np.random.Generator, *, size: Sequence[float] | None = None
) -> tuple[MeshData, Size]:
    """Build one object of a category.

    Parameters
    ----------
    category : str
        One of :func:`categories`.
    rng : numpy.random.Generator
        Draws the size (unless given), colours and variations.
    size : sequence of 3 floats, optional
        ``(x, y, z)`` extents in meters; sampled from the category's range if omitted.

    Returns
    -------
    tuple
        ``(mesh, size)``: the mesh in the local frame (centred on its bounding box) and the measured
        extents of that bounding box.

    Raises
    ------
    UnknownCategoryError
        If the category is unknown.
    AssetSizeError
        If `size` is not three finite lengths > 0.
    """
    spec = asset(category)
    chosen = spec.sample_size(rng) if size is None else size
    mesh = spec.build(rng, chosen)
    lo, hi = mesh.bounds()
    extent = hi - lo
    return mesh, (float(extent[0]), float(extent[1]), float(extent[2]))
