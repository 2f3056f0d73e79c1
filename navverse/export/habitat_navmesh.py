"""A scene's navmesh as habitat-sim's ``.navmesh`` file (Detour's "MSET" tile set).

habitat-sim's ``PathFinder::loadNavMesh`` (``src/esp/nav/PathFinder.cpp``) reads, little-endian::

    NavMeshSetHeader   int32 magic 'MSET', int32 version (1 or 2), int32 numTiles,
                       dtNavMeshParams {float orig[3], tileWidth, tileHeight; int32 maxTiles, maxPolys}
    [version 2 only]   sizeof(esp::nav::NavMeshSettings) raw bytes
    numTiles times     NavMeshTileHeader {dtTileRef tileRef, int32 dataSize}, then dataSize bytes of
                       Detour tile data

We write version 1, which habitat-sim reads with default ``NavMeshSettings`` (the raw struct of
version 2 changes layout between habitat-sim releases, so it is left out). habitat-sim builds Detour
without ``DT_POLYREF64``, so ``dtTileRef`` is 32 bits; navverse's Detour (the system librecast) is
built the same way, and its tile payload (``navverse.nav.fileformat``: magic ``NVDT``, the Detour tile
format version, the polygon-reference size, the ``dtNavMeshParams``, then per tile its 64-bit-stored
reference, size and raw Detour tile data) is checked to be tile format 7 with 32-bit references
before it is copied.

Frame: navverse's extension stores tiles in Recast's y-up frame as ``(x, z, -y)`` of the z-up world
(``navverse/nav/csrc/navmesh.h``: ``toRecast``), which is exactly the habitat frame of the exported
GLB, so vertices are copied unchanged. Polygon flags are rewritten: navverse marks walkable polygons
1 and adds its own bits (2 excluded area, 4 level detail mesh), while habitat-sim's filter includes
``POLYFLAGS_WALK`` (1) and uses 4 for ``POLYFLAGS_DISABLED`` and 8 for its island filter; every
walkable polygon becomes exactly 1. Polygon area ids (navverse's terrain classes) are kept; habitat-sim
gives every area the cost 1.
"""

from __future__ import annotations

import struct

import numpy as np

from navverse.errors import NavverseError

__all__ = ["MSET_MAGIC", "MSET_VERSION", "NavMeshExportError", "mset_from_tiles", "tiles_from_mset"]

MSET_MAGIC = ord("M") << 24 | ord("S") << 16 | ord("E") << 8 | ord("T")
MSET_VERSION = 1
"""The set version written: 1, the tiles without habitat-sim's ``NavMeshSettings`` struct."""
DETOUR_TILE_VERSION = 7
DETOUR_MAGIC = ord("D") << 24 | ord("N") << 16 | ord("A") << 8 | ord("V")
POLYFLAGS_WALK = 1

_NVDT = struct.Struct("<4sIii3fffii i")
"""navverse's tile payload header: magic, blob version, Detour version, ref size, params, tile count."""
_PARAMS = struct.Struct("<3fffii")
_SET_HEADER = struct.Struct("<iii")
_TILE_HEADER = struct.Struct("<Ii")
_NVDT_TILE = struct.Struct("<Qi")
_MESH_HEADER = struct.Struct("<5iI9i3f3f3ff")
"""dtMeshHeader (100 bytes): magic, version, x, y, layer, userId, polyCount, vertCount, ...."""
_POLY_SIZE = 32
"""sizeof(dtPoly) with DT_VERTS_PER_POLYGON 6; its ``flags`` (uint16) are at byte 28."""
_POLY_FLAGS = 28


class NavMeshExportError(NavverseError):
    """A navmesh cannot be written as habitat-sim's ``.navmesh`` (another Detour tile format)."""


def _align4(n: int) -> int:
    return (n + 3) & ~3


def _walk_flags(tile: bytes, *, source: str) -> bytes:
    """A Detour tile with every walkable polygon's flags set to habitat-sim's ``POLYFLAGS_WALK`` only."""
    header = _MESH_HEADER.unpack_from(tile)
    magic, version, poly_count, vert_count = header[0], header[1], header[6], header[7]
    if magic != DETOUR_MAGIC or version != DETOUR_TILE_VERSION:
        raise NavMeshExportError(f"{source}: a tile is not Detour tile format {DETOUR_TILE_VERSION}")
    start = _align4(_MESH_HEADER.size) + _align4(12 * vert_count)
    end = start + _POLY_SIZE * poly_count
    if end > len(tile):
        raise NavMeshExportError(f"{source}: a tile is shorter than its polygons")
    data = bytearray(tile)
    polys = np.frombuffer(data, dtype=np.uint8, count=end - start, offset=start).reshape(-1, _POLY_SIZE)
    flags = polys[:, _POLY_FLAGS : _POLY_FLAGS + 2].copy().view("<u2").ravel()
    walk = np.where(flags & POLYFLAGS_WALK, POLYFLAGS_WALK, 0).astype("<u2")
    polys[:, _POLY_FLAGS : _POLY_FLAGS + 2] = walk.view(np.uint8).reshape(-1, 2)
    return bytes(data)


def mset_from_tiles(payload: bytes, *, source: str = "navmesh") -> bytes:
    """habitat-sim ``.navmesh`` bytes from navverse's tile payload (``read_navmesh(...)[1]``).

    Raises
    ------
    NavMeshExportError
        If the payload is not navverse's, or its tiles are not Detour format 7 with 32-bit references.
    """
    if len(payload) < _NVDT.size or payload[:4] != b"NVDT":
        raise NavMeshExportError(f"{source}: not navverse navmesh tile data")
    _, _, dt_version, ref_size, *params, num_tiles = _NVDT.unpack_from(payload)
    if dt_version != DETOUR_TILE_VERSION or ref_size != 4:
        raise NavMeshExportError(
            f"{source}: Detour tile format {dt_version} with {8 * ref_size}-bit polygon references; "
            f"habitat-sim reads format {DETOUR_TILE_VERSION} with 32-bit references"
        )
    out = [_SET_HEADER.pack(MSET_MAGIC, MSET_VERSION, num_tiles), _PARAMS.pack(*params)]
    offset = _NVDT.size
    for _ in range(num_tiles):
        ref, size = _NVDT_TILE.unpack_from(payload, offset)
        offset += _NVDT_TILE.size
        tile = payload[offset : offset + size]
        offset += size
        if ref == 0 or ref >= 1 << 32 or len(tile) != size:
            raise NavMeshExportError(f"{source}: a tile reference or size is out of range")
        out += [_TILE_HEADER.pack(ref, size), _walk_flags(tile, source=source)]
    return b"".join(out)


def tiles_from_mset(data: bytes) -> tuple[tuple[float, ...], list[tuple[int, bytes]]]:
    """The ``dtNavMeshParams`` and ``(tileRef, tile data)`` of a version-1 ``.navmesh`` file, read as
    habitat-sim reads it (for checks)."""
    magic, version, num_tiles = _SET_HEADER.unpack_from(data)
    if magic != MSET_MAGIC or version != MSET_VERSION:
        raise NavMeshExportError("not a version-1 habitat-sim navmesh file")
    params = _PARAMS.unpack_from(data, _SET_HEADER.size)
    offset = _SET_HEADER.size + _PARAMS.size
    tiles = []
    for _ in range(num_tiles):
        ref, size = _TILE_HEADER.unpack_from(data, offset)
        offset += _TILE_HEADER.size
        tiles.append((ref, data[offset : offset + size]))
        offset += size
    return params, tiles
