"""Errors of the object library that a user (a recipe, a furnishing rule) can cause."""

from __future__ import annotations

from navverse.errors import NavverseError

__all__ = ["AssetError", "AssetSizeError", "UnknownCategoryError"]


class AssetError(NavverseError):
    """Base class of object-library errors."""


class UnknownCategoryError(AssetError):
    """An object category that the library does not know; the message lists the known ones."""


class AssetSizeError(AssetError):
    """An object size that cannot be built (not three finite lengths > 0)."""
