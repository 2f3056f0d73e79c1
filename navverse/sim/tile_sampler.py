"""Material tiles sampled at hit points: repeating, mip-mapped, bilinear.

A look's materials are square tiles that repeat over the surfaces (:mod:`navverse.look.materials`).
:class:`TileSampler` packs every tile and its mip levels (each half the size of the one before, by
2 x 2 averages) into one planar texel pool, and samples it at surface coordinates in meters: the level
is the one whose texels are about as wide as the pixel's footprint on the surface (so far asphalt
does not sparkle), then bilinear between the four nearest texels, wrapping around the tile's edges.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

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
                parts.append(np.rint(wrapped).astype(np.uint8).reshape(-1, 3).T)
                self._offset[t, level] = cursor
                self._width[t, level] = image.shape[0]
                cursor += wrapped.shape[0] * wrapped.shape[1]
        self._pool = (
            np.ascontiguousarray(np.concatenate(parts, axis=1)) if parts else np.zeros((3, 0), np.uint8)
        )
        self._texel = self._sizes / np.array([t.shape[0] for t in tiles], dtype=np.float64)

    def sample(self, tile: np.ndarray, u: np.ndarray, v: np.ndarray, footprint: np.ndarray) -> np.ndarray:
        """sRGB values ``(3, K)`` (float32, 0..255) of `tile` at ``(u, v)`` meters.

        Parameters
        ----------
        tile : ndarray of int, shape (K,)
            Tile index per hit (all valid).
        u, v : ndarray of float64, shape (K,)
            Surface coordinates in meters.
        footprint : ndarray, shape (K,)
            Width of each pixel on its surface in meters (picks the mip level).
        """
        texel = self._texel.take(tile)
        ratio = np.maximum(np.asarray(footprint, dtype=np.float64) / texel, 1.0)
        level = np.minimum(np.floor(np.log2(ratio)).astype(np.int64), self._levels.take(tile) - 1)
        width = self._width[tile, level]
        offset = self._offset[tile, level]
        scale = width / self._sizes.take(tile)
        x = u * scale - 0.5
        y = v * scale - 0.5
        col = np.floor(x)
        row = np.floor(y)
        fx = (x - col).astype(np.float32)
        fy = (y - row).astype(np.float32)
        col = np.mod(col, width).astype(np.int64)
        row = np.mod(row, width).astype(np.int64)
        index = offset + row * (width + 1) + col
        out = np.empty((3, len(tile)), dtype=np.float32)
        w00 = (1.0 - fx) * (1.0 - fy)
        w01 = fx * (1.0 - fy)
        w10 = (1.0 - fx) * fy
        w11 = fx * fy
        below = index + width + 1
        for c in range(3):
            pool = self._pool[c]
            out[c] = pool.take(index) * w00
            out[c] += pool.take(index + 1) * w01
            out[c] += pool.take(below) * w10
            out[c] += pool.take(below + 1) * w11
        return out
