"""What an object category is: :class:`Asset` (size range, placement, builder) and :class:`SupportArea`.

These are defined here so that category modules can declare their assets without importing the
registry; :mod:`navverse.assets.library` re-exports them. The local frame is described there.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from navverse.assets.errors import AssetSizeError
from navverse.assets.materials import PHYSICAL_MATERIALS
from navverse.assets.parts import Assembly
from navverse.scene.geometry import MeshData, snap_to_grid

__all__ = [
    "CONTEXTS",
    "INDOOR_CONTEXTS",
    "OUTDOOR_CONTEXTS",
    "PLACEMENTS",
    "Asset",
    "Builder",
    "Placement",
    "Size",
    "SupportArea",
    "check_size",
    "fit_to_size",
    "top_support",
]

Size = tuple[float, float, float]
"""``(x width, y depth, z height)`` in meters."""

Placement = Literal["floor", "wall", "surface", "wall_mounted"]
PLACEMENTS: tuple[str, ...] = ("floor", "wall", "surface", "wall_mounted")

INDOOR_CONTEXTS: frozenset[str] = frozenset({"home", "office", "school", "retail", "hospital", "cafe"})
"""Kinds of rooms and buildings an indoor asset typically appears in."""

OUTDOOR_CONTEXTS: frozenset[str] = frozenset(
    {"street", "park", "plaza", "parking", "construction", "transit", "sports", "frontage"}
)
"""Kinds of outdoor places: ``street`` (sidewalks and their furniture zone, the road), ``park``,
``plaza``, ``parking`` (lots and parking lanes), ``construction``, ``transit`` (bus stops),
``sports`` (pitches, courts, playgrounds), ``frontage`` (in front of shops and cafes, by the facades)."""

CONTEXTS: frozenset[str] = INDOOR_CONTEXTS | OUTDOOR_CONTEXTS
"""Kinds of places an asset typically appears in (a hint for furnishing and population rules); an
asset with an outdoor context is an outdoor asset."""

Builder = Callable[[np.random.Generator, Size], Assembly]
"""Builds an object of a size in the floor frame (bottom at z = 0, centred in x and y)."""

_SNAKE = re.compile(r"^[a-z][a-z0-9]*(_[a-z0-9]+)*$")


@dataclass(frozen=True)
class SupportArea:
    """A flat, free area on top of an object where other objects can stand, in the object's local frame.

    Parameters
    ----------
    height : float
        Height of the surface above the object's bottom, m.
    x_min, x_max, y_min, y_max : float
        Usable rectangle relative to the object's centre, m.
    """

    height: float
    x_min: float
    x_max: float
    y_min: float
    y_max: float

    def __post_init__(self) -> None:
        if not (self.x_min < self.x_max and self.y_min < self.y_max and self.height > 0):
            raise ValueError(f"empty support area: {self}")

    @property
    def width(self) -> float:
        """Extent along x, m."""
        return self.x_max - self.x_min

    @property
    def depth(self) -> float:
        """Extent along y, m."""
        return self.y_max - self.y_min


SupportRule = Callable[[Size], list[SupportArea]]


def top_support(
    *, inset: float = 0.03, top_drop: float = 0.0, back_margin: float = 0.0, front_margin: float = 0.0
) -> SupportRule:
    """A support rule for an object whose whole top is usable.

    Parameters
    ----------
    inset : float
        Margin kept free along every edge, m.
    top_drop : float
        How far the usable surface lies below the object's top (e.g. under a backsplash), m.
    back_margin : float
        Extra margin at the back (-y), m, e.g. for a backsplash.
    front_margin : float
        Extra margin at the front (+y), m, e.g. where drawer fronts and handles stick out under the top.
    """

    def rule(size: Size) -> list[SupportArea]:
        w, d, h = size
        return [
            SupportArea(
                height=h - top_drop,
                x_min=-0.5 * w + inset,
                x_max=0.5 * w - inset,
                y_min=-0.5 * d + inset + back_margin,
                y_max=0.5 * d - inset - front_margin,
            )
        ]

    return rule


@dataclass(frozen=True)
class Asset:
    """A parametric object category.

    Parameters
    ----------
    category : str
        lower_snake_case semantic category, e.g. ``"office_chair"``.
    size_min, size_max : tuple of float
        Range of ``(x width, y depth, z height)``, m.
    placement : {"floor", "wall", "surface", "wall_mounted"}
        ``floor``: stands freely on the floor; ``wall``: on the floor with its back (-y) against a wall;
        ``surface``: a small item on another object's :class:`SupportArea`; ``wall_mounted``: hangs on a
        wall with its bottom `mount_height` above the floor.
    mount_height : (float, float) or None
        Range of the bottom height for ``wall_mounted`` assets, else None.
    front_clearance : float
        Free floor needed in front (+y) to use the object, m.
    material : str
        Dominant physical material, one of :data:`~navverse.assets.materials.PHYSICAL_MATERIALS`.
    builder : callable
        ``builder(rng, size) -> Assembly`` in the floor frame; use :meth:`build` instead.
    supports : callable or None
        ``supports(size) -> list[SupportArea]``; None if nothing can stand on the object.
    contexts : tuple of str
        Places the object typically appears in, from :data:`CONTEXTS`.
    """

    category: str
    size_min: Size
    size_max: Size
    placement: Placement
    mount_height: tuple[float, float] | None
    front_clearance: float
    material: str
    builder: Builder = field(repr=False, compare=False)
    supports: SupportRule | None = field(default=None, repr=False, compare=False)
    contexts: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not _SNAKE.match(self.category):
            raise ValueError(f"category {self.category!r} is not lower_snake_case")
        lo, hi = np.asarray(self.size_min, float), np.asarray(self.size_max, float)
        if lo.shape != (3,) or hi.shape != (3,) or not ((lo > 0).all() and (hi >= lo).all()):
            raise ValueError(f"{self.category}: need 0 < size_min <= size_max, got {lo} and {hi}")
        if self.placement not in PLACEMENTS:
            raise ValueError(f"{self.category}: placement must be one of {PLACEMENTS}")
        if (self.placement == "wall_mounted") != (self.mount_height is not None):
            raise ValueError(f"{self.category}: mount_height is required for wall_mounted assets only")
        if self.mount_height is not None and not 0 <= self.mount_height[0] <= self.mount_height[1]:
            raise ValueError(f"{self.category}: mount_height must be an increasing range >= 0")
        if self.front_clearance < 0:
            raise ValueError(f"{self.category}: front_clearance must be >= 0")
        if self.material not in PHYSICAL_MATERIALS:
            raise ValueError(f"{self.category}: unknown material {self.material!r}")
        if not set(self.contexts) <= CONTEXTS:
            raise ValueError(f"{self.category}: unknown contexts {set(self.contexts) - CONTEXTS}")

    @property
    def outdoor(self) -> bool:
        """Whether the asset belongs outdoors (one of its contexts is in :data:`OUTDOOR_CONTEXTS`)."""
        return bool(set(self.contexts) & OUTDOOR_CONTEXTS)

    def sample_size(self, rng: np.random.Generator) -> Size:
        """Draw a size within ``[size_min, size_max]``, rounded to millimetres.

        The three axes share a common draw (plus per-axis jitter), so large objects tend to be large in
        every direction and proportions stay plausible.
        """
        lo, hi = np.asarray(self.size_min, float), np.asarray(self.size_max, float)
        common = rng.uniform()
        fraction = np.clip(common + rng.uniform(-0.3, 0.3, size=3), 0.0, 1.0)
        size = np.clip(np.round(lo + fraction * (hi - lo), 3), lo, hi)
        return (float(size[0]), float(size[1]), float(size[2]))

    def build(self, rng: np.random.Generator, size: Sequence[float]) -> MeshData:
        """Build the object's mesh in its local frame.

        Parameters
        ----------
        rng : numpy.random.Generator
            Source of colours and discrete variations (drawer counts, books, ...).
        size : sequence of 3 floats
            ``(x, y, z)`` extents, m; sizes outside the sampled range are built too.

        Returns
        -------
        MeshData
            Centred on its bounding box, whose extents equal `size`; every face coloured.

        Raises
        ------
        AssetSizeError
            If `size` is not three finite lengths > 0.
        """
        checked = check_size(size)
        built = self.builder(rng, checked).mesh()
        # Snapped before the fit (whose arithmetic is exact IEEE): the same bytes on every machine.
        snapped = MeshData(snap_to_grid(built.vertices), built.faces, built.face_colors)
        return fit_to_size(snapped, checked)

    def support_areas(self, size: Sequence[float]) -> list[SupportArea]:
        """Flat areas on the object of `size` where other objects can stand ([] if none)."""
        if self.supports is None:
            return []
        return self.supports(check_size(size))


def check_size(size: Sequence[float]) -> Size:
    """Return `size` as a tuple of three floats, or raise :class:`AssetSizeError`."""
    try:
        values = tuple(float(s) for s in size)
    except (TypeError, ValueError) as exc:
        raise AssetSizeError(
            f"an object size must be three numbers (x, y, z) in meters, got {size!r}"
        ) from exc
    if len(values) != 3 or not all(math.isfinite(v) and v > 0 for v in values):
        raise AssetSizeError(f"an object size must be three finite lengths > 0 (x, y, z), got {size!r}")
    return (values[0], values[1], values[2])


def fit_to_size(mesh: MeshData, size: Size) -> MeshData:
    """Centre a mesh on its bounding box and scale each axis so the box extents equal `size` exactly.

    Builders design their parts to fill `size`, so the scale factors are 1 up to rounding; the fit
    only makes the extents exact and absorbs the small deviations of extreme sizes.
    """
    lo, hi = mesh.bounds()
    extent = hi - lo
    scale = np.asarray(size, dtype=np.float64) / np.where(extent > 0, extent, 1.0)
    vertices = (mesh.vertices - 0.5 * (lo + hi)) * scale
    return MeshData(vertices, mesh.faces, mesh.face_colors)
