"""The navmesh file (``navmesh.bin``): a versioned header, JSON metadata and Detour tiles.

Layout (little-endian)::

    offset  size  field
    0       8     magic b"NVNAVMSH"
    8       4     uint32 format version (FORMAT_VERSION)
    12      4     uint32 metadata length in bytes (M)
    16      8     uint64 tile payload length in bytes (T)
    24      4     uint32 CRC-32 of metadata + payload
    28      M     metadata, UTF-8 JSON: settings, area_costs, excluded_areas, area_types, ...
    28 + M  T     tile payload, written by the extension: its own magic "NVDT" and version, the
                  Detour tile format version and polygon-reference size, the dtNavMeshParams,
                  then per tile its dtTileRef and dtNavMesh tile data (so polygon references, and
                  with them random sampling, survive a save/load).

A file of another format version is refused with a message to rebuild it; the CRC catches
truncated or damaged files before Detour sees their tiles.
"""

from __future__ import annotations

import json
import struct
import zlib
from typing import Any

from navverse.errors import rebuild_hint
from navverse.nav.errors import NavMeshError

__all__ = ["FORMAT_VERSION", "MAGIC", "read_navmesh", "write_navmesh"]

MAGIC = b"NVNAVMSH"
FORMAT_VERSION = 1
_HEADER = struct.Struct("<8sIIQI")


def write_navmesh(tiles: bytes, **meta: Any) -> bytes:
    """The file bytes for a tile payload and its metadata (JSON-serializable keyword values)."""
    meta_bytes = json.dumps(
        {"format_version": FORMAT_VERSION, **meta}, sort_keys=True, separators=(",", ":")
    ).encode()
    body = meta_bytes + tiles
    return _HEADER.pack(MAGIC, FORMAT_VERSION, len(meta_bytes), len(tiles), zlib.crc32(body)) + body


def read_navmesh(data: bytes, *, source: str = "navmesh data") -> tuple[dict[str, Any], bytes]:
    """Split file bytes into (metadata, tile payload), checking magic, version, sizes and CRC.

    Raises
    ------
    NavMeshError
        For a foreign file, another format version, or a truncated/damaged file.
    """
    if len(data) < len(MAGIC) or data[: len(MAGIC)] != MAGIC:
        raise NavMeshError(f"{source} is not a navverse navmesh file (no {MAGIC.decode()} header)")
    if len(data) < _HEADER.size:
        raise NavMeshError(f"{source} is truncated: {rebuild_hint()}")
    _, version, meta_len, tiles_len, crc = _HEADER.unpack_from(data)
    if version != FORMAT_VERSION:
        raise NavMeshError(
            f"{source}: navmesh file format v{version}, this toolkit reads v{FORMAT_VERSION}: "
            f"{rebuild_hint()}"
        )
    body = data[_HEADER.size :]
    if len(body) != meta_len + tiles_len or zlib.crc32(body) != crc:
        raise NavMeshError(f"{source} is truncated or damaged (size or checksum mismatch): {rebuild_hint()}")
    try:
        meta = json.loads(body[:meta_len].decode())
    except (UnicodeDecodeError, json.JSONDecodeError):
        raise NavMeshError(f"{source} has unreadable metadata: {rebuild_hint()}") from None
    if not isinstance(meta, dict) or "settings" not in meta:
        raise NavMeshError(f"{source} has no navmesh settings: {rebuild_hint()}")
    return meta, body[meta_len:]
