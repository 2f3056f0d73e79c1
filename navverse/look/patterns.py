"""Procedural patterns on surface coordinates: lattice hashes, value noise, joints of laid units.

Every function is a pure, vectorised function of coordinates in meters and an integer seed, so a
pattern is the same wherever and whenever it is evaluated (no image is stored, nothing is random).
Cell values come from a table of 256 x 256 integer hashes (a 32-bit avalanche of the lattice
coordinates, no random generator), looked up with the seed as an offset.
"""

from __future__ import annotations

import numpy as np

__all__ = ["cell_value", "hash_cells", "laid_units", "value_noise"]

_M1 = np.uint64(0x9E3779B1)
_M2 = np.uint64(0x85EBCA77)
_M3 = np.uint64(0xC2B2AE3D)
_MASK = np.uint64(0xFFFFFFFF)


def hash_cells(ix: np.ndarray, iy: np.ndarray, seed: int) -> np.ndarray:
    """A value in [0, 1) per integer lattice cell ``(ix, iy)`` and `seed` (float32)."""
    h = (ix.astype(np.int64).astype(np.uint64) * _M1) & _MASK
    h ^= (iy.astype(np.int64).astype(np.uint64) * _M2) & _MASK
    h ^= (np.uint64(seed & 0xFFFFFFFF) * _M3) & _MASK
    h ^= h >> np.uint64(15)
    h = (h * _M2) & _MASK
    h ^= h >> np.uint64(13)
    h = (h * _M3) & _MASK
    h ^= h >> np.uint64(16)
    return (h.astype(np.float64) / 4294967296.0).astype(np.float32)


_PERIOD = 256
_CELLS = hash_cells(*np.meshgrid(np.arange(_PERIOD + 1), np.arange(_PERIOD + 1), indexing="ij"), seed=0x5EED)
"""Cell values for the patterns: a hash per lattice cell, periodic over 256 cells (with its first row and
column repeated after the last, for bilinear neighbours), so a pattern looks them up, not hashes."""


def _lattice(ix: np.ndarray, iy: np.ndarray, seed: int) -> np.ndarray:
    """Flat index into :data:`_CELLS` of cell ``(ix, iy)`` (whole-number floats) for `seed`."""
    x = (ix.astype(np.int64) + 97 * seed) & (_PERIOD - 1)
    y = (iy.astype(np.int64) + 61 * seed + (seed >> 8)) & (_PERIOD - 1)
    return x * (_PERIOD + 1) + y


def cell_value(ix: np.ndarray, iy: np.ndarray, seed: int) -> np.ndarray:
    """A value in [0, 1) per lattice cell ``(ix, iy)`` and `seed` (a lookup; repeats every 256 cells)."""
    return _CELLS.reshape(-1).take(_lattice(np.asarray(ix), np.asarray(iy), seed))


def value_noise(
    u: np.ndarray, v: np.ndarray, *, scale: float, seed: int, octaves: int = 2, period: int | None = None
) -> np.ndarray:
    """Smooth noise in [0, 1) at coordinates ``(u, v)`` (meters), features about `scale` meters wide.

    Octaves halve the scale and the amplitude each (fractal sum, renormalised). With `period` (in
    cells of the first octave) the noise repeats every ``period * scale`` meters along both axes.
    """
    flat = _CELLS.reshape(-1)
    total = np.zeros(np.shape(u), dtype=np.float32)
    weight, amplitude, size = 0.0, 1.0, float(scale)
    for octave in range(octaves):
        x = np.asarray(u, dtype=np.float64) / size
        y = np.asarray(v, dtype=np.float64) / size
        x0, y0 = np.floor(x), np.floor(y)
        fx, fy = (x - x0).astype(np.float32), (y - y0).astype(np.float32)
        fx = fx * fx * (3.0 - 2.0 * fx)
        fy = fy * fy * (3.0 - 2.0 * fy)
        s = seed + 7919 * octave
        if period is None:
            index = _lattice(x0, y0, s)
            a, c = flat.take(index), flat.take(index + 1)  # (x0, y0), (x0, y0 + 1)
            b, d = flat.take(index + _PERIOD + 1), flat.take(index + _PERIOD + 2)  # x0 + 1
        else:
            cells = period << octave
            x1, y1 = np.mod(x0 + 1, cells), np.mod(y0 + 1, cells)
            x0, y0 = np.mod(x0, cells), np.mod(y0, cells)
            a, b = cell_value(x0, y0, s), cell_value(x1, y0, s)
            c, d = cell_value(x0, y1, s), cell_value(x1, y1, s)
        top = a + fx * (b - a)
        total += np.float32(amplitude) * (top + fy * (c + fx * (d - c) - top))
        weight += amplitude
        amplitude *= 0.5
        size *= 0.5
    return total / np.float32(weight)


def laid_units(
    u: np.ndarray,
    v: np.ndarray,
    *,
    length: float,
    width: float,
    joint: float,
    stagger: float,
    seed: int,
    period: tuple[int, int] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Units laid in rows (slabs, tiles, bricks, boards): which unit each point is on, and the joints.

    Rows run along `u`, `width` apart in `v`; each row's units are `length` long, the row shifted by
    `stagger` of a unit against the one below (0.5: a running bond; 0: a grid; -1: a shift drawn per
    row, as boards are laid).

    Returns
    -------
    unit : ndarray of float32
        A value in [0, 1) per unit (its tint).
    in_joint : ndarray of bool
        Whether the point is on a joint (within ``joint / 2`` of a unit's edge).
    """
    rows = np.asarray(v, dtype=np.float64) / width
    row = np.floor(rows)
    key_row = row if period is None else np.mod(row, period[1])
    shift = cell_value(key_row, np.zeros_like(row), seed + 1) if stagger < 0 else np.mod(row * stagger, 1.0)
    along = np.asarray(u, dtype=np.float64) / length + shift
    column = np.floor(along)
    half_u, half_v = 0.5 * joint / length, 0.5 * joint / width
    frac_u, frac_v = along - column, rows - row
    in_joint = (frac_u < half_u) | (frac_u > 1.0 - half_u) | (frac_v < half_v) | (frac_v > 1.0 - half_v)
    key_column = column if period is None else np.mod(column, period[0])
    return cell_value(key_column, key_row, seed), in_joint
