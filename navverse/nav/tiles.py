"""A store of finished navmesh tiles, keyed by what each tile's build reads.

Recast builds every tile of a tiled navmesh from the triangles that reach it (its core plus a
border), the settings and the tile's place in the grid, and nothing else. :class:`TileStore` keeps
each finished tile under the hash of exactly that input (the bytes
:meth:`navverse.nav._recast.TiledBuild.tile_key` gives), salted with the fingerprint of the code
that builds tiles (the extension module and the Recast and Detour libraries it runs on). A build
given a store reuses every tile whose key it holds and builds only the others, so an
indoor-to-outdoor scene rebuilds just the tiles its building reaches, and the navmesh has the same
bytes as a build without the store.

A store is a folder (by default ``navmesh-tiles`` under :func:`navverse.cache.cache_root`) of files
``<key[:2]>/<key>.tile``, each the tile's data after its own BLAKE2b digest; a file that is cut
short or damaged fails its digest and is built again. Files are written atomically, so builds in
several processes can share a store. Deleting the folder loses nothing but time.
"""

from __future__ import annotations

import functools
import hashlib
import os
from dataclasses import dataclass
from pathlib import Path

from navverse.cache import cache_root
from navverse.files import atomic_write

__all__ = ["TileStore", "TileStoreUse", "default_tile_store", "tile_code_fingerprint"]

_DIGEST_BYTES = 32
_SUFFIX = ".tile"


@functools.cache
def tile_code_fingerprint() -> bytes:
    """A digest of the code that builds tiles: the extension module and the Recast/Detour libraries.

    The libraries are those mapped into this process (read from ``/proc/self/maps`` where the
    system has it); a rebuilt extension or an upgraded library gives other keys, so no tile built
    by other code is ever reused.
    """
    from navverse.nav import _recast

    digest = hashlib.blake2b(digest_size=_DIGEST_BYTES)
    paths = [Path(_recast.__file__)]
    try:
        with open("/proc/self/maps", encoding="utf-8") as maps:
            libraries = {line.split()[-1] for line in maps if "/" in line}
    except OSError:
        libraries = set()
    paths += sorted(Path(p) for p in libraries if any(n in Path(p).name for n in ("Recast", "Detour")))
    for path in paths:
        digest.update(path.name.encode("utf-8"))
        digest.update(path.read_bytes())
    return digest.digest()


@dataclass
class TileStoreUse:
    """What one build did with a store.

    Attributes
    ----------
    tiles : int
        Tiles of the navmesh (with or without triangles).
    reused : int
        Tiles taken from the store.
    built : int
        Tiles built (and stored); the rest reached no triangle and needed neither.
    """

    tiles: int = 0
    reused: int = 0
    built: int = 0


class TileStore:
    """Finished navmesh tiles in a folder, keyed by their build input.

    Parameters
    ----------
    root : path
        The folder; made when the first tile is stored.

    Attributes
    ----------
    last_use : TileStoreUse
        What the latest build given this store did with it.
    """

    def __init__(self, root: str | os.PathLike[str]) -> None:
        self.root = Path(root)
        self.last_use = TileStoreUse()

    def key(self, tile_input: bytes) -> str:
        """The store key of a tile's build input (hex)."""
        digest = hashlib.blake2b(tile_code_fingerprint(), digest_size=_DIGEST_BYTES)
        digest.update(tile_input)
        return digest.hexdigest()

    def _path(self, key: str) -> Path:
        return self.root / key[:2] / f"{key}{_SUFFIX}"

    def get(self, key: str) -> bytes | None:
        """The tile data stored under ``key`` (``b""`` for a tile that built empty), or None."""
        try:
            blob = self._path(key).read_bytes()
        except OSError:
            return None
        data = blob[_DIGEST_BYTES:]
        if (
            len(blob) < _DIGEST_BYTES
            or hashlib.blake2b(data, digest_size=_DIGEST_BYTES).digest() != blob[:_DIGEST_BYTES]
        ):
            return None
        return data

    def put(self, key: str, data: bytes) -> None:
        """Store ``data`` under ``key`` (atomically; a store that cannot be written is skipped)."""
        path = self._path(key)
        blob = hashlib.blake2b(data, digest_size=_DIGEST_BYTES).digest() + data
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            with atomic_write(path) as handle:
                handle.write(blob)
        except OSError:
            pass  # a read-only or full cache only costs the next build its time


def default_tile_store() -> TileStore:
    """The store under the toolkit's cache folder (``$NAVVERSE_CACHE_DIR/navmesh-tiles``)."""
    return TileStore(cache_root() / "navmesh-tiles")
