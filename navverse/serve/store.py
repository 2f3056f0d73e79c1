"""The submission files: each upload streamed to a temporary file within the body cap, then, once
accepted, fsynced and renamed into place under a name the server makes.

Layout of the store (``--store``, by default ``<db>.submissions/`` beside the database)::

    <store>/<submission id>.jsonl      an accepted submission as sent (or .jsonl.gz: gzip by its magic)
    <store>/tmp/<random>.upload        an upload being received or checked

No name from a request reaches the file system: upload names are random, a submission's name is its
id (made by the server), and files are found from the database's ``file`` column.
"""

from __future__ import annotations

import os
import re
import secrets
import time
from pathlib import Path
from typing import IO

from navverse.serve.errors import RefusedError, ServeError

__all__ = ["GZIP_MAGIC", "Store", "Upload", "size_text", "too_large"]

GZIP_MAGIC = b"\x1f\x8b"
_FILE = re.compile(r"[A-Za-z0-9_-]{1,64}\.jsonl(\.gz)?")
_STALE_SECONDS = 3600.0
"""Uploads older than this in ``tmp/`` are left over from a server that was killed: removed at start."""


def size_text(size: int) -> str:
    """A number of bytes for people: ``64 MiB``, ``512 KiB``, ``100 bytes``."""
    for unit, scale in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if size >= scale:
            return f"{size / scale:.3g} {unit}"
    return f"{size} bytes"


class Upload:
    """A request body being written to a temporary file of the store, at most `cap` bytes.

    Parameters
    ----------
    path : Path
        The temporary file (created here, readable by its owner only).
    cap : int
        The most bytes it may hold; one more is a :class:`~navverse.serve.errors.RefusedError` 413 and the
        file is removed.
    """

    def __init__(self, path: Path, *, cap: int) -> None:
        self.path = path
        self.cap = cap
        self.size = 0
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        self._handle: IO[bytes] | None = os.fdopen(fd, "wb")

    def write(self, chunk: bytes) -> None:
        """Append a chunk of the body.

        Raises
        ------
        RefusedError
            413 once the body is over the cap (the file is removed).
        """
        self.size += len(chunk)
        if self.size > self.cap:
            self.discard()
            raise RefusedError(413, too_large(self.cap))
        assert self._handle is not None
        self._handle.write(chunk)

    def finish(self) -> None:
        """Flush the file to disk (``fsync``) and close it."""
        if self._handle is not None:
            self._handle.flush()
            os.fsync(self._handle.fileno())
            self._handle.close()
            self._handle = None

    def is_gzip(self) -> bool:
        """Whether the body starts with gzip's magic bytes (whatever the request's headers say)."""
        with self.path.open("rb") as handle:
            return handle.read(2) == GZIP_MAGIC

    def discard(self) -> None:
        """Close and remove the file (nothing if it is gone)."""
        if self._handle is not None:
            self._handle.close()
            self._handle = None
        self.path.unlink(missing_ok=True)


def too_large(cap: int) -> str:
    """The message of a body over the cap."""
    return (
        f"the submission is larger than this server takes ({size_text(cap)} as sent): gzip it "
        "(gzip -k run.jsonl) or write fewer rows (10 Hz is plenty) or fewer digits"
    )


class Store:
    """The folder of the submission files.

    Parameters
    ----------
    root : path
        The folder (made with its ``tmp/`` by :meth:`open`).
    """

    def __init__(self, root: str | os.PathLike[str]) -> None:
        self.root = Path(root)
        self.tmp = self.root / "tmp"

    def open(self) -> Store:
        """Make the folders if missing and remove stale uploads; returns the store.

        Raises
        ------
        ServeError
            If the folder cannot be made or written.
        """
        try:
            self.root.mkdir(parents=True, exist_ok=True, mode=0o700)
            self.tmp.mkdir(exist_ok=True, mode=0o700)
            probe = self.tmp / f".probe-{secrets.token_hex(6)}"
            probe.write_bytes(b"")
            probe.unlink()
        except OSError as exc:
            raise ServeError(
                f"--store {self.root}: cannot write there ({exc.strerror or exc}); give a writable folder"
            ) from None
        cutoff = time.time() - _STALE_SECONDS
        for leftover in self.tmp.glob("*.upload"):
            try:
                if leftover.stat().st_mtime < cutoff:
                    leftover.unlink()
            except OSError:
                continue
        return self

    def upload(self, *, cap: int) -> Upload:
        """A new upload in ``tmp/`` under a random name."""
        return Upload(self.tmp / f"{secrets.token_hex(12)}.upload", cap=cap)

    def place(self, upload: Upload, submission_id: str) -> str:
        """Rename a finished upload into place as ``<submission_id>.jsonl`` (``.jsonl.gz`` when gzip) and
        flush the folder's entry to disk; returns the file's name relative to the store."""
        name = f"{submission_id}.jsonl" + (".gz" if upload.is_gzip() else "")
        os.replace(upload.path, self.root / name)
        fd = os.open(self.root, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        return name

    def path(self, name: str) -> Path:
        """The file of a submission, from its ``file`` column (a name this store made).

        Raises
        ------
        ServeError
            If the name is not one the store makes.
        """
        if not _FILE.fullmatch(name):
            raise ServeError(f"the database names a submission file {name!r} this store does not make")
        return self.root / name

    def remove(self, name: str) -> None:
        """Remove a submission's file (an accepted upload whose row could not be inserted)."""
        self.path(name).unlink(missing_ok=True)
