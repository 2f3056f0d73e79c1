"""Bounded, checked reading of dataset files (:mod:`navverse.dataset.reader` uses it to verify a version).

Every read here is streamed in chunks of :data:`CHUNK` bytes: a file's SHA-256, what a gzip file
decompresses to (stopped past a limit, so a gzip bomb costs one chunk of memory), the entries of a
version directory (never following a symbolic link, at most :data:`MAX_ENTRIES`). Files are opened
as regular files only: a symbolic link, a FIFO or a device is a problem, never followed or waited on.

Problems are reported as kinds (:data:`PROBLEMS`), which :func:`describe` turns into the sentence a
:class:`~navverse.records.errors.DatasetError` carries.
"""

from __future__ import annotations

import errno
import gzip
import hashlib
import os
import stat
import zlib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import IO, Any

__all__ = [
    "CHUNK",
    "MAX_ENTRIES",
    "MAX_FILE_BYTES",
    "PROBLEMS",
    "TooLargeError",
    "describe",
    "gunzip",
    "listing",
    "member_state",
    "mib",
    "open_regular",
    "read_checked",
    "sha256_of",
]

MAX_FILE_BYTES = 512 << 20
"""Largest dataset file read, compressed or decompressed (bytes): a bigger one is refused unread."""
MAX_ENTRIES = 10_000
"""Most entries in a version directory (files and folders) before it is refused unlisted."""
CHUNK = 1 << 20
"""Bytes read (and decompressed) at a time."""


def sha256_of(handle: IO[bytes]) -> str:
    """Hex SHA-256 of what is left to read in a binary file, read in chunks."""
    digest = hashlib.sha256()
    for block in iter(lambda: handle.read(CHUNK), b""):
        digest.update(block)
    return digest.hexdigest()


class TooLargeError(Exception):
    """A file, or what it decompresses to, is over the size limit."""


class _HashingReader:
    """A binary reader that feeds every byte it hands out to a digest."""

    def __init__(self, handle: IO[bytes], digest: Any) -> None:
        self._handle = handle
        self._digest = digest

    def read(self, size: int = -1) -> bytes:
        data = self._handle.read(size)
        self._digest.update(data)
        return data


def gunzip(handle: IO[bytes], *, limit: int, keep: bool) -> tuple[str, bytes]:
    """SHA-256 of a gzip file's bytes and (``keep``) what it decompresses to, read in chunks.

    Raises :class:`TooLargeError` as soon as more than ``limit`` bytes came out, so a gzip bomb costs at
    most one chunk of memory when ``keep`` is False; gzip errors as ``OSError``, ``EOFError`` or
    ``zlib.error``.
    """
    digest = hashlib.sha256()
    reader = _HashingReader(handle, digest)
    parts: list[bytes] = []
    total = 0
    with gzip.GzipFile(fileobj=reader, mode="rb") as unzipped:  # type: ignore[arg-type]
        for block in iter(lambda: unzipped.read(CHUNK), b""):
            total += len(block)
            if total > limit:
                raise TooLargeError
            if keep:
                parts.append(block)
    while reader.read(CHUNK):  # whatever gzip did not need still counts in the checksum
        pass
    return digest.hexdigest(), b"".join(parts)


def mib(size: int) -> str:
    """A size in bytes as ``512 MiB``."""
    return f"{size / (1 << 20):g} MiB"


def open_regular(path: Path) -> IO[bytes]:
    """Open a regular file for reading, never through a symbolic link at its last component, and
    without blocking on a FIFO.

    Raises
    ------
    OSError
        ``ELOOP`` for a symbolic link, ``EINVAL`` for anything but a regular file.
    """
    flags = os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
    fd = os.open(path, flags)
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise OSError(errno.EINVAL, "not a regular file", str(path))
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_checked(path: Path, expected: str, *, keep: bool = False) -> tuple[str | None, bytes]:
    """Check a listed file: its SHA-256 first (streamed), then, only if it matched, what it
    decompresses to against :data:`MAX_FILE_BYTES` (streamed, nothing kept), then with ``keep`` its
    content, hashing the bytes decompressed again.

    Returns
    -------
    tuple of (str or None, bytes)
        The problem kind (None: sound) and, with ``keep``, the decompressed content.
    """
    try:
        with open_regular(path) as handle:
            if sha256_of(handle) != expected:
                return "checksum", b""
        with open_regular(path) as handle:
            gunzip(handle, limit=MAX_FILE_BYTES, keep=False)
        if not keep:
            return None, b""
        with open_regular(path) as handle:
            digest, data = gunzip(handle, limit=MAX_FILE_BYTES, keep=True)
    except TooLargeError:
        return "large", b""
    except (EOFError, zlib.error, gzip.BadGzipFile):
        return "gzip", b""
    except OSError as exc:
        return {errno.ELOOP: "link", errno.EINVAL: "special", errno.ENOENT: "missing"}.get(
            exc.errno, "unreadable"
        ), b""
    return (None, data) if digest == expected else ("checksum", b"")  # or it changed while read


PROBLEMS = {
    "checksum": "files differ from the manifest's checksums",
    "missing": "files listed in manifest.json are missing",
    "unlisted": "files are not listed in manifest.json (added or renamed)",
    "link": "files are symbolic links, not regular files",
    "special": "files are not regular files",
    "large": f"files are larger than {mib(MAX_FILE_BYTES)} (compressed or decompressed)",
    "gzip": "files are not valid gzip",
    "unreadable": "files cannot be read",
    "crowded": "the version directory has too many entries",
}


def describe(problems: Mapping[str, Sequence[str]]) -> str:
    """``files differ from the manifest's checksums: a, b; files ... : c`` (at most 5 names each)."""
    parts = []
    for kind, names in problems.items():
        shown = ", ".join(names[:5]) + (f" and {len(names) - 5} more" if len(names) > 5 else "")
        parts.append(f"{PROBLEMS[kind]}: {shown}")
    return "; ".join(parts)


def member_state(root: Path, name: str) -> str | None:
    """The problem kind of a listed file's place (``missing``, ``link``, ``special``, ``large``), or
    None when it is a regular file in a real folder of the version directory, not over the size cap."""
    path = root
    for part in name.split("/"):
        path = path / part
        try:
            info = os.lstat(path)
        except FileNotFoundError:
            return "missing"
        except OSError:
            return "special"
        if stat.S_ISLNK(info.st_mode):
            return "link"
    if not stat.S_ISREG(info.st_mode):
        return "special"
    return "large" if info.st_size > MAX_FILE_BYTES else None


def listing(root: Path) -> tuple[set[str], bool]:
    """Relative paths of every entry of a version directory but its folders and ``manifest.json``
    (symbolic links are entries, never followed), and whether there were more than the cap."""
    found: set[str] = set()
    count = 0
    stack = [(root, "")]
    while stack:
        folder, prefix = stack.pop()
        with os.scandir(folder) as entries:
            for entry in entries:
                count += 1
                if count > MAX_ENTRIES:
                    return found, True
                relative = prefix + entry.name
                if entry.is_dir(follow_symlinks=False):
                    stack.append((Path(entry.path), relative + "/"))
                elif relative != "manifest.json":
                    found.add(relative)
    return found, False
