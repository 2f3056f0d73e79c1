"""Deterministic ``.json.gz`` files: written with sorted keys and a zero gzip time stamp (the same
content gives the same bytes), read decompressed in chunks up to a cap."""

from __future__ import annotations

import gzip
import json
import os
import zlib
from pathlib import Path
from typing import Any

from navverse.files import atomic_write
from navverse.records.errors import DatasetError
from navverse.records.files import MAX_FILE_BYTES, TooLargeError, gunzip, mib

__all__ = ["parse_json", "read_json_gz", "write_json_gz"]


def write_json_gz(data: Any, path: str | os.PathLike[str]) -> Path:
    """Write JSON (sorted keys, compact) gzipped with a zero time stamp: same data, same bytes."""
    path = Path(path)
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_write(path) as handle:
        handle.write(gzip.compress(text.encode(), compresslevel=9, mtime=0))
    return path


def read_json_gz(path: str | os.PathLike[str], *, max_bytes: int = MAX_FILE_BYTES) -> Any:
    """Read a gzipped JSON file, decompressing it in chunks up to ``max_bytes``.

    Raises
    ------
    DatasetError
        If the file is missing, not gzip, not JSON, or decompresses to more than ``max_bytes``.
    """
    path = Path(path)
    try:
        with open(path, "rb") as handle:
            _, data = gunzip(handle, limit=max_bytes, keep=True)
    except FileNotFoundError:
        raise DatasetError(f"{path} does not exist") from None
    except TooLargeError:
        raise DatasetError(f"{path} decompresses to more than {mib(max_bytes)}: refused") from None
    except (OSError, EOFError, zlib.error) as exc:
        raise DatasetError(f"{path} is not a gzipped JSON file ({exc})") from None
    return parse_json(data, path)


def parse_json(data: bytes, source: Path) -> Any:
    """The JSON value of a ``.json.gz`` file's decompressed bytes.

    Raises
    ------
    DatasetError
        If the bytes are not JSON (naming ``source``).
    """
    try:
        return json.loads(data)
    except (ValueError, RecursionError) as exc:
        raise DatasetError(f"{source} is not a gzipped JSON file ({type(exc).__name__}: {exc})") from None
