"""The navmesh module's error type."""

from navverse.errors import NavverseError

__all__ = ["NavMeshError"]


class NavMeshError(NavverseError):
    """A navmesh cannot be built, loaded or queried as asked (bad input, nothing walkable, foreign file)."""
