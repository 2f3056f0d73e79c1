"""Stable content hashes of JSON-able values, files and directories."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

KEY_LENGTH = 24
"""Hex characters kept of a sha256 digest in artifact keys (96 bits)."""

_CHUNK = 1 << 20


def canonical_json(value: Any) -> str:
    """Serialise ``value`` to JSON with sorted keys and no insignificant whitespace."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False)


def hash_value(value: Any) -> str:
    """Full sha256 hex digest of the canonical JSON of ``value``."""
    return hashlib.sha256(canonical_json(value).encode("utf-8")).hexdigest()


def short_key(value: Any) -> str:
    """Key of ``value``: the first :data:`KEY_LENGTH` hex characters of :func:`hash_value`."""
    return hash_value(value)[:KEY_LENGTH]


def hash_bytes(data: bytes) -> str:
    """sha256 hex digest of ``data``."""
    return hashlib.sha256(data).hexdigest()


def hash_file(path: Path) -> str:
    """sha256 hex digest of a file's content, read in chunks."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        while chunk := handle.read(_CHUNK):
            digest.update(chunk)
    return digest.hexdigest()


def hash_tree(root: Path, *, exclude: frozenset[str] = frozenset()) -> dict[str, dict[str, int | str]]:
    """Hash every regular file below ``root``.

    Parameters
    ----------
    root : Path
        Directory to walk.
    exclude : frozenset of str
        Relative paths (POSIX form) to leave out.

    Returns
    -------
    dict
        ``{relative_path: {"sha256": hex, "size": bytes}}`` sorted by path.
    """
    files: dict[str, dict[str, int | str]] = {}
    for path in sorted(p for p in root.rglob("*") if p.is_file()):
        rel = path.relative_to(root).as_posix()
        if rel in exclude:
            continue
        files[rel] = {"sha256": hash_file(path), "size": path.stat().st_size}
    return files
