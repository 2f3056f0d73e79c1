"""What the semantic sensor calls each object: its category, and a storefront its place category.

A storefront's geometry is an object of category ``storefront``; to the semantic channel (the
runner's ``task.semantic_categories``, habitat-sim's semantic files) it is what its sign says, its
place category (``restaurant``, ``bank``...), as a bed is a ``bed``.
"""

from __future__ import annotations

import numpy as np

from navverse.scene.annotations import SceneAnnotations

__all__ = ["STOREFRONT_CATEGORY", "STOREFRONT_ID_BASE", "semantic_categories", "storefront_objects"]

STOREFRONT_CATEGORY = "storefront"
"""The object category of a storefront's geometry."""

STOREFRONT_ID_BASE = 1 << 23
"""A storefront without a geometry object of its own gets the semantic id ``STOREFRONT_ID_BASE + id``
(listed in ``.semantic.txt``, with no faces in ``.semantic.glb``)."""


def storefront_objects(annotations: SceneAnnotations) -> dict[int, int]:
    """Storefront id -> its semantic object id: the object that is its geometry (category
    ``storefront``, same centre within 1 cm), else ``STOREFRONT_ID_BASE + storefront id``."""
    objects = [o for o in annotations.objects if o.category == STOREFRONT_CATEGORY]
    centers = np.array([o.center for o in objects], dtype=np.float64).reshape(-1, 3)
    found = {}
    for store in annotations.storefronts:
        gap = np.linalg.norm(centers - np.asarray(store.center), axis=1)
        matched = len(gap) > 0 and gap.min() <= 0.01
        found[store.id] = objects[int(gap.argmin())].id if matched else STOREFRONT_ID_BASE + store.id
    return found


def semantic_categories(annotations: SceneAnnotations) -> dict[int, str]:
    """Semantic object id -> the category the semantic files give it: an object's category, a
    storefront's place category (on its object, or on its own id when it has no object)."""
    categories = {o.id: o.category for o in annotations.objects}
    places = {s.id: s.place_category for s in annotations.storefronts}
    for store, obj in storefront_objects(annotations).items():
        categories[obj] = places[store]
    return categories
