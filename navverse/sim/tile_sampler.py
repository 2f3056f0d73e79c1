"""Material tiles sampled at hit points: repeating, mip-mapped, bilinear.

A look's materials are square tiles that repeat over the surfaces (:mod:`navverse.look.materials`).
:class:`TileSampler` packs every tile and its mip levels (each half the size of the one before, by
2 x 2 averages) into one texel pool, and samples it at surface coordinates in meters: the level
is the one whose texels are about as wide as the pixel's footprint on the surface (so far asphalt
does not sparkle), then bilinear between the four nearest texels, wrapping around the tile's edges.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from navverse.scene.colors import srgb_to_linear
from navverse.sim import shade_kernels as kernels

__all__ = ["TileSampler"]


class TileSampler:
    """Sample repeating tiles with mip-mapping.

    Parameters
    ----------
    tiles : sequence of ndarray of uint8, each (n, n, 3)
        Square sRGB tiles, sides powers of two.
    sizes : sequence of float
        Side of each tile in meters.
    """

    def __init__(self, tiles: Sequence[np.ndarray], sizes: Sequence[float]) -> None:
        self._sizes = np.asarray(sizes, dtype=np.float64)
        levels = [int(np.log2(t.shape[0])) + 1 for t in tiles]
        self._levels = np.asarray(levels, dtype=np.int64)
        top = max(levels)
        self._offset = np.zeros((len(tiles), top), dtype=np.int64)
        self._width = np.ones((len(tiles), top), dtype=np.int64)
        parts, cursor = [], 0
        for t, tile in enumerate(tiles):
            image = tile.astype(np.float32)
            for level in range(levels[t]):
                if level:
                    image = 0.25 * (
                        image[0::2, 0::2] + image[1::2, 0::2] + image[0::2, 1::2] + image[1::2, 1::2]
                    )
                wrapped = np.pad(image, ((0, 1), (0, 1), (0, 0)), mode="wrap")
                parts.append(np.rint(wrapped).astype(np.uint8).reshape(-1, 3))
                self._offset[t, level] = cursor
                self._width[t, level] = image.shape[0]
                cursor += wrapped.shape[0] * wrapped.shape[1]
        self._pool = (
            np.ascontiguousarray(np.concatenate(parts, axis=0)) if parts else np.zeros((0, 3), np.uint8)
        )
        self._texel = self._sizes / np.array([t.shape[0] for t in tiles], dtype=np.float64)
        self._to_linear = srgb_to_linear(np.arange(256)).astype(np.float32)

    def sample_into(
        self,
        albedo: np.ndarray,
        tile: np.ndarray,
        u: np.ndarray,
        v: np.ndarray,
        footprint: np.ndarray,
        *,
        shift: np.ndarray,
        tint: np.ndarray,
        modulate: np.ndarray,
        grain_base: np.ndarray,
        parts: int = 1,
    ) -> None:
        """Write the linear albedo of the tiles at `K` hits into `albedo` ``(3, K)``.

        Parameters
        ----------
        albedo : ndarray of float32, shape (3, K)
            Each hit's own colour (linear RGB); overwritten where the hit has a tile.
        tile : ndarray of int, shape (K,)
            Tile index per hit; ``-1``: none (its albedo stays).
        u, v : ndarray of float64, shape (K,)
            Surface coordinates in meters.
        footprint : ndarray, shape (K,)
            Width of each pixel on its surface in meters (picks the mip level).
        shift : ndarray of float32, shape (T, 2)
            Per tile, a shift of its pattern in meters.
        tint : ndarray of float32, shape (T, 3)
            Per tile, a factor on its linear colour.
        modulate : ndarray of bool, shape (K,)
            Hits whose own colour is kept, times the sample over `grain_base` (a fine grain on objects).
        grain_base : ndarray, shape (3,)
            The linear base colour of the modulating tile.
        parts : int
            Pieces the hits are sampled in at once, on threads (0: one per core).
        """
        kernels.split(
            kernels.tile_albedo, len(tile),
            self._pool, self._offset, self._width, self._levels, self._sizes, self._texel,
            np.ascontiguousarray(tile, dtype=np.int32), u, v, footprint, shift, tint, modulate,
            self._to_linear, np.asarray(grain_base, dtype=np.float32), albedo, parts=parts,
        )  # fmt: skip
