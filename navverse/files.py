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
"""

from __future__ import annotations

import os
import secrets
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any, Literal

__all__ = ["atomic_dir", "atomic_path", "atomic_write"]


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
