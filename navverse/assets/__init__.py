"""Parametric object library: category -> coloured, closed triangle mesh of a sampled size.

See :mod:`navverse.assets.library` for the local frame every object is built in. The names below are
re-exported from :mod:`navverse.assets.library` and :mod:`navverse.assets.errors` on first use, so that
importing a light submodule (e.g. :mod:`navverse.assets.primitives`) does not load the whole library.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from navverse.assets.errors import AssetError, AssetSizeError, UnknownCategoryError
    from navverse.assets.library import Asset, SupportArea, asset, categories, make_object

__all__ = [
    "Asset",
    "AssetError",
    "AssetSizeError",
    "SupportArea",
    "UnknownCategoryError",
    "asset",
    "categories",
    "make_object",
]

_SOURCES = {
    "Asset": "navverse.assets.library",
    "SupportArea": "navverse.assets.library",
    "asset": "navverse.assets.library",
    "categories": "navverse.assets.library",
    "make_object": "navverse.assets.library",
    "AssetError": "navverse.assets.errors",
    "AssetSizeError": "navverse.assets.errors",
    "UnknownCategoryError": "navverse.assets.errors",
}


def __getattr__(name: str) -> Any:
    source = _SOURCES.get(name)
    if source is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(source), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
