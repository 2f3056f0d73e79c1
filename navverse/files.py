"""Atomic writes: a reader finds the old file (or none) or the whole new one, never a part of it.

Each helper is a context manager that has the block write under a temporary name beside the target
(in the same directory, so the final rename is atomic) and renames it over the target when the block
ends normally. On any exception, ``KeyboardInterrupt`` included, the temporary file or directory is
removed, the target is left as it was and the exception goes on.

- :func:`atomic_write` yields an open file, for writers that take one::

      with atomic_write(path, mode="w") as handle:
          handle.write(text)

- :func:`atomic_path` yields the temporary path, for writers that open the file themselves by name
  (USD stages, ``numpy.savez`` of a file name)::

      with atomic_path(directory / "scene.usdc") as tmp:
          stage = Usd.Stage.CreateNew(str(tmp))
          ...
          stage.Save()

- :func:`atomic_dir` yields a temporary directory that becomes the target directory as a whole.

Temporary names are ``.<name>.<pid>.<random>.tmp``: hidden, unique per process and call, and, ending
in ``.tmp``, not matched by the patterns readers look for (``*.json``, ``v*``, ``<digest>.npz``).
Only :func:`atomic_path` adds the target's suffix after ``.tmp``, for the writers that choose a format
by it. A file's content is flushed to disk (``fsync``) before the rename, so a crash right after it
cannot leave an empty file under the target's name; a directory's files are not.

Beside them, helpers for reading files: what a file is in words (:func:`file_kind`), why a file
cannot be read as a regular file within a size cap (:func:`regular_file_problem`), and a file's
SHA-256 read in chunks (:func:`file_sha256`).
"""

from __future__ import annotations

import hashlib
import os
import secrets
import shutil
import stat
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from functools import lru_cache
from pathlib import Path
from typing import IO, Any, Literal

__all__ = ["atomic_dir", "atomic_path", "atomic_write", "file_sha256"]


def _temporary(target: Path, *, suffix: str = "") -> Path:
    return target.with_name(f".{target.name}.{os.getpid()}.{secrets.token_hex(6)}.tmp{suffix}")


@contextmanager
def _replacing(tmp: Path, target: Path) -> Iterator[None]:
    """Rename `tmp` over `target` after the block; remove `tmp` if anything raises."""
    try:
        yield
        os.replace(tmp, target)
    except BaseException:
        if tmp.is_dir():
            shutil.rmtree(tmp, ignore_errors=True)
        else:
            tmp.unlink(missing_ok=True)
        raise


@contextmanager
def atomic_write(
    path: str | os.PathLike[str], *, mode: Literal["wb", "w"] = "wb", encoding: str = "utf-8"
) -> Iterator[IO[Any]]:
    """Write a file through an open temporary file that replaces `path` when the block ends.

    Parameters
    ----------
    path : path
        The file to write; its directory must exist.
    mode : {"wb", "w"}
        Binary or text.
    encoding : str
        Encoding of text mode (unused in binary mode).

    Yields
    ------
    file object
        The temporary file, open for writing; it is closed before the rename.
    """
    target = Path(path)
    tmp = _temporary(target)
    with _replacing(tmp, target), open(tmp, mode, encoding=None if "b" in mode else encoding) as handle:
        yield handle
        handle.flush()
        os.fsync(handle.fileno())


@contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A temporary file name beside `path`, with its suffix; the file written there replaces `path`.

    Parameters
    ----------
    path : path
        The file to write; its directory must exist.

    Yields
    ------
    Path
        Where the block writes the file (not created yet). Not writing it is an error
        (``FileNotFoundError``), and `path` is left as it was.
    """
    target = Path(path)
    tmp = _temporary(target, suffix=target.suffix)
    with _replacing(tmp, target):
        yield tmp
        fd = os.open(tmp, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


@contextmanager
def atomic_dir(path: str | os.PathLike[str]) -> Iterator[Path]:
    """An empty temporary directory beside `path` that becomes `path` when the block ends.

    Parameters
    ----------
    path : path
        The directory to create; its parent must exist, and `path` must not exist (or be empty).

    Yields
    ------
    Path
        The temporary directory the block fills.
    """
    target = Path(path)
    tmp = _temporary(target)
    with _replacing(tmp, target):
        tmp.mkdir()
        yield tmp


def link_or_copy(source: str | os.PathLike[str], target: str | os.PathLike[str]) -> None:
    """Hard-link `source` to `target` (for files that never change, such as artifacts' files), copying
    where a link cannot be made (another filesystem, no link support)."""
    try:
        os.link(source, target)
    except OSError:
        shutil.copy2(source, target)


def file_kind(mode: int) -> str:
    """What a file of ``st_mode`` ``mode`` is, in words, for messages ("a named pipe (FIFO)"...)."""
    kinds = (
        (stat.S_ISREG, "a regular file"),
        (stat.S_ISDIR, "a directory"),
        (stat.S_ISFIFO, "a named pipe (FIFO)"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    )
    return next((name for test, name in kinds if test(mode)), "a special file")


def regular_file_problem(path: str | os.PathLike[str], *, max_bytes: int, what: str = "file") -> str | None:
    """Why ``path`` cannot be read as a ``what`` (None: it can), found with ``os.stat``, never opening it.

    A FIFO, device or directory would block or mislead a reader, and a file over ``max_bytes`` would
    exhaust memory, so readers of untrusted files ask this first (symbolic links are followed).

    Returns
    -------
    str or None
        E.g. ``"/x/a.obj is a named pipe (FIFO), not a regular file"``, or None for a regular file
        within the cap.
    """
    try:
        info = os.stat(path)
    except FileNotFoundError:
        return f"{path} does not exist"
    except OSError as exc:
        return f"cannot read {path}: {exc.strerror or exc}"
    if not stat.S_ISREG(info.st_mode):
        return f"{path} is {file_kind(info.st_mode)}, not a regular file"
    if info.st_size > max_bytes:
        size, limit = info.st_size / 1024**3, max_bytes / 1024**3
        return f"{path} is {size:.2f} GiB, over the {limit:.2f} GiB limit of a {what}"
    return None


def file_sha256(path: str | os.PathLike[str], *, progress: Callable[[str, int], None] | None = None) -> str:
    """The SHA-256 of a file's bytes, hex, read in 1 MiB chunks.

    Parameters
    ----------
    path : path
        The file.
    progress : callable, optional
        Called as ``progress("checksum", bytes_hashed)`` after every 64 MiB.

    Returns
    -------
    str
        64 lowercase hex digits.
    """
    digest, done = hashlib.sha256(), 0
    with open(path, "rb") as handle:
        while chunk := handle.read(1024 * 1024):
            digest.update(chunk)
            done += len(chunk)
            if progress is not None and done % (64 * 1024 * 1024) < len(chunk):
                progress("checksum", done)
    return digest.hexdigest()


def cached_file_sha256(path: str | os.PathLike[str]) -> str:
    """:func:`file_sha256`, computed once per process for each version of a file.

    The result is kept keyed by the resolved path and the file's identity (device, inode, size and
    modification time), so a file replaced or rewritten since is hashed again.

    Parameters
    ----------
    path : path
        The file.

    Returns
    -------
    str
        64 lowercase hex digits.
    """
    resolved = Path(path).resolve()
    info = resolved.stat()
    return _sha256_of(str(resolved), (info.st_dev, info.st_ino, info.st_size, info.st_mtime_ns))


@lru_cache(maxsize=1024)
def _sha256_of(path: str, identity: tuple[int, int, int, int]) -> str:
    del identity  # part of the cache key only
    return file_sha256(path)
