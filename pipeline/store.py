"""The content-addressed artifact store under ``data/built/``.

Layout::

    artifacts/<stage>/<output>-<key>/      one committed artifact: files + stage.log + manifest.json
    targets/<target>/<output>  -> symlink  the current artifact of each target output
    tmp/                                   work in progress; never read, cleaned on the next run
    checkpoints/<key>/map-<n>/<item>.pkl   results of ``ctx.map`` items of a stage run not committed yet
    logs/<target>/<stage>.log              the log of the latest run of each stage
    build.lock                             held (flock) by the build or clean working here

An artifact is written into ``tmp/``, its manifest is written last, then the directory is renamed
into ``artifacts/`` in one step. A directory in ``artifacts/`` without a valid manifest (readable,
of :data:`MANIFEST_FORMAT`, listing every file with its size and sha256) is never trusted: it is
removed and rebuilt.

The manifest's ``files`` let a committed artifact be checked (:meth:`ArtifactStore.verify`): by
size (a ``stat`` per file, cheap: every build does it for the artifacts it reuses) or by content
(sha256, ``--verify``). A file missing, of another size or content, or a file the manifest does
not list (``manifest.json`` and ``stage.log`` aside) makes the artifact corrupt; the build then
rebuilds it and :meth:`ArtifactStore.commit` swaps the new directory in for the old one atomically.
"""

from __future__ import annotations

import ctypes
import errno
import functools
import json
import os
import shutil
import uuid
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from pipeline.errors import StoreError
from pipeline.hashing import hash_file

MANIFEST_NAME = "manifest.json"
MANIFEST_FORMAT = 1
"""Format of ``manifest.json``. Format 1: ``files`` is ``{relative path: {"size": bytes, "sha256":
hex}}`` (every file of the artifact but the manifest and ``stage.log``). A manifest of another
format, or without well-formed ``files``, is not trusted: its artifact is rebuilt."""
LOG_NAME = "stage.log"
"""The copy of the stage's log kept in each artifact (not listed in the manifest: it holds timings)."""
LOCK_NAME = "build.lock"
"""The lock file a build (or clean) holds in the build directory (:mod:`pipeline.lock`)."""

VerifyLevel = Literal["size", "hash"]
"""How a committed artifact is checked: ``size`` stats each file, ``hash`` also compares sha256."""

_UNLISTED = frozenset({MANIFEST_NAME, LOG_NAME})


@dataclass(frozen=True)
class Corruption:
    """One way a committed artifact differs from its manifest.

    Attributes
    ----------
    artifact : Path
        The artifact directory.
    file : str
        The file (relative to the artifact, POSIX form) that differs.
    problem : str
        What differs, e.g. ``size differs (6747 bytes recorded, 100 on disk)``.
    """

    artifact: Path
    file: str
    problem: str

    def describe(self, root: Path) -> str:
        """``<artifact>/<file> <problem>``, the artifact relative to the build directory ``root``."""
        try:
            where = self.artifact.relative_to(root)
        except ValueError:
            where = self.artifact
        return f"{where.as_posix()}/{self.file} {self.problem}"


class ArtifactStore:
    """Reads, checks and commits artifacts in a build directory.

    Parameters
    ----------
    root : Path
        The build directory (``data/built``).
    """

    def __init__(self, root: Path) -> None:
        self.root = Path(root)

    @property
    def artifacts_dir(self) -> Path:
        """Committed artifacts."""
        return self.root / "artifacts"

    @property
    def targets_dir(self) -> Path:
        """Named links to each target's current artifacts."""
        return self.root / "targets"

    @property
    def tmp_dir(self) -> Path:
        """Artifacts being written."""
        return self.root / "tmp"

    @property
    def checkpoints_dir(self) -> Path:
        """The checkpoints of stage runs not committed yet (:meth:`checkpoint_dir`)."""
        return self.root / "checkpoints"

    def checkpoint_dir(self, key: str) -> Path:
        """Where the stage run of cache key ``key`` keeps the results of its ``ctx.map`` items until it
        commits: a run killed part way resumes from them (:mod:`pipeline.context`)."""
        return self.checkpoints_dir / key

    @property
    def logs_dir(self) -> Path:
        """Per-stage logs."""
        return self.root / "logs"

    @property
    def lock_path(self) -> Path:
        """The file a build or clean locks while it works here."""
        return self.root / LOCK_NAME

    def artifact_path(self, stage: str, output: str, key: str) -> Path:
        """Where the artifact ``output`` of ``stage`` with ``key`` lives once committed."""
        return self.artifacts_dir / stage / f"{output}-{key}"

    def log_path(self, target: str, stage: str) -> Path:
        """The log file of ``stage`` for ``target``."""
        return self.logs_dir / target / f"{stage}.log"

    # -- reading ----------------------------------------------------------------------------
    @staticmethod
    def read_manifest(path: Path) -> dict[str, Any] | None:
        """The manifest of the artifact directory ``path``, or None if absent or unreadable."""
        try:
            manifest = json.loads((path / MANIFEST_NAME).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        return manifest if isinstance(manifest, dict) else None

    def has(self, stage: str, output: str, key: str) -> bool:
        """True if an artifact with ``key`` is committed with a trusted manifest (files not checked)."""
        manifest = self.read_manifest(self.artifact_path(stage, output, key))
        return manifest is not None and manifest.get("key") == key and manifest_files(manifest) is not None

    def discard_untrusted(self, stage: str, output: str, key: str) -> bool:
        """Remove the directory of ``key`` if it exists without a trusted manifest; True if removed."""
        path = self.artifact_path(stage, output, key)
        if path.exists() and not self.has(stage, output, key):
            shutil.rmtree(path, ignore_errors=True)
            return True
        return False

    def verify(self, path: Path, *, level: VerifyLevel = "size") -> list[Corruption]:
        """Compare the committed artifact ``path`` with its manifest; ``[]`` if it is intact.

        Parameters
        ----------
        path : Path
            An artifact directory.
        level : {"size", "hash"}
            ``size`` lists the directory and stats each file; ``hash`` also compares each file's
            sha256 (read in full), when every size is right.

        Returns
        -------
        list of Corruption
            Missing files, files of another size or content, and files the manifest does not list,
            in path order; a single entry for ``manifest.json`` if the manifest is not trusted.
        """
        files = manifest_files(self.read_manifest(path))
        if files is None:
            return [Corruption(path, MANIFEST_NAME, "is missing, unreadable or of another format")]
        on_disk = set(_files_below(path))
        problems = [
            Corruption(path, rel, "is not in the manifest") for rel in on_disk - files.keys() - _UNLISTED
        ]
        for rel, entry in files.items():
            problem = _size_problem(path / rel, entry["size"]) if rel in on_disk else "is missing"
            if problem:
                problems.append(Corruption(path, rel, problem))
        if level == "hash" and not problems:
            problems = [
                Corruption(path, rel, "content differs (sha256 does not match the manifest)")
                for rel, entry in files.items()
                if hash_file(path / rel) != entry["sha256"]
            ]
        return sorted(problems, key=lambda c: c.file)

    # -- writing ----------------------------------------------------------------------------
    def new_tmp(self, stage: str, output: str, key: str) -> Path:
        """A fresh, empty work directory for an artifact (tagged with this process id)."""
        path = self.tmp_dir / f"{stage}.{output}-{key}.{os.getpid()}.{uuid.uuid4().hex[:8]}"
        try:
            path.mkdir(parents=True)
        except OSError as exc:
            raise StoreError(
                f"cannot create {path}: {exc.strerror}; check that {self.root} is writable"
            ) from exc
        return path

    def commit(self, tmp: Path, final: Path, manifest: dict[str, Any], *, replace: bool = False) -> Path:
        """Write ``manifest`` last into ``tmp`` and move ``tmp`` to ``final`` in one step.

        Parameters
        ----------
        tmp : Path
            The finished work directory.
        final : Path
            Where the artifact lives once committed.
        manifest : dict
            Written as ``manifest.json`` (with ``manifest_format``).
        replace : bool
            Replace a committed ``final`` (a forced rebuild, or a corrupt artifact): the new
            directory is swapped in atomically, so a reader sees the old or the new one, never a
            half. Without it, a ``final`` another process committed first is kept and ``tmp``
            discarded. A ``final`` without a trusted manifest is always replaced.

        Returns
        -------
        Path
            ``final``.
        """
        manifest = {"manifest_format": MANIFEST_FORMAT, **manifest}
        partial = tmp / f".{MANIFEST_NAME}.partial"
        with open(partial, "w", encoding="utf-8") as handle:
            json.dump(manifest, handle, indent=2, sort_keys=True)
            handle.write("\n")
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(partial, tmp / MANIFEST_NAME)
        final.parent.mkdir(parents=True, exist_ok=True)
        trusted = manifest_files(self.read_manifest(final)) is not None
        if os.path.lexists(final) and (replace or not trusted):
            self._swap_in(tmp, final)
        elif os.path.lexists(final):
            shutil.rmtree(tmp, ignore_errors=True)
            return final
        else:
            try:
                os.rename(tmp, final)
            except OSError:  # another process committed it in between
                if self.read_manifest(final) is None:
                    raise
                shutil.rmtree(tmp, ignore_errors=True)
        _fsync_dir(final.parent)
        return final

    def _swap_in(self, tmp: Path, final: Path) -> None:
        """Put ``tmp`` at ``final`` in place of the directory there, and remove the old one.

        On Linux the two are exchanged in one step (``renameat2(RENAME_EXCHANGE)``); elsewhere
        the old directory is first renamed aside, so for an instant ``final`` is absent (never
        half written).
        """
        if _exchange(tmp, final):
            shutil.rmtree(tmp, ignore_errors=True)
            return
        aside = self.tmp_dir / f"{final.name}.replaced.{os.getpid()}.{uuid.uuid4().hex[:8]}"
        aside.parent.mkdir(parents=True, exist_ok=True)
        os.rename(final, aside)
        os.rename(tmp, final)
        shutil.rmtree(aside, ignore_errors=True)

    def link_target(self, target: str, output: str, artifact: Path) -> None:
        """Point ``targets/<target>/<output>`` at ``artifact`` (atomically replacing the old link)."""
        link = self.targets_dir / target / output
        link.parent.mkdir(parents=True, exist_ok=True)
        relative = os.path.relpath(artifact, link.parent)
        if link.is_symlink() and os.readlink(link) == relative:
            return
        temporary = link.parent / f".{output}.{os.getpid()}.{uuid.uuid4().hex[:8]}"
        os.symlink(relative, temporary)
        os.replace(temporary, link)

    def target_output(self, target: str, output: str) -> Path | None:
        """The committed artifact a target output currently points at, or None."""
        link = self.targets_dir / target / output
        if not link.is_symlink():
            return None
        resolved = link.resolve()
        return resolved if self.read_manifest(resolved) is not None else None

    def clean_stale_tmp(self) -> int:
        """Remove work directories and files left by processes that no longer run; returns how many."""
        if not self.tmp_dir.is_dir():
            return 0
        removed = 0
        for path in self.tmp_dir.iterdir():
            pid_text = path.name.rsplit(".", 2)[-2] if path.name.count(".") >= 2 else ""
            if pid_text.isdigit() and _alive(int(pid_text)):
                continue
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path, ignore_errors=True)
            else:
                path.unlink(missing_ok=True)
            removed += 1
        return removed


def manifest_files(manifest: Mapping[str, Any] | None) -> dict[str, dict[str, Any]] | None:
    """The ``files`` of a manifest of the current format, or None if it cannot be trusted."""
    if manifest is None or manifest.get("manifest_format") != MANIFEST_FORMAT:
        return None
    files = manifest.get("files")
    if not isinstance(files, dict):
        return None
    for rel, entry in files.items():
        if not (
            isinstance(rel, str)
            and isinstance(entry, dict)
            and isinstance(entry.get("size"), int)
            and isinstance(entry.get("sha256"), str)
        ):
            return None
    return files


def _files_below(root: Path) -> Iterator[str]:
    """Relative POSIX paths of everything below ``root`` that is not a directory."""
    for folder, dirs, names in os.walk(root):
        base = Path(folder)
        for name in names + [d for d in dirs if (base / d).is_symlink()]:
            yield (base / name).relative_to(root).as_posix()


def _size_problem(path: Path, size: int) -> str:
    try:
        found = path.stat().st_size
    except OSError:
        return "is missing"
    if found != size:
        return f"size differs ({size} bytes recorded, {found} on disk)"
    return ""


_AT_FDCWD = -100
_RENAME_EXCHANGE = 2


@functools.cache
def _renameat2() -> Callable[..., int] | None:
    """glibc's ``renameat2`` (Linux), or None where the C library has none."""
    try:
        function = ctypes.CDLL(None, use_errno=True).renameat2
    except (OSError, AttributeError):
        return None
    function.argtypes = (ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint)
    function.restype = ctypes.c_int
    return function


def _exchange(first: Path, second: Path) -> bool:
    """Swap two existing paths in one step; False if the system or file system cannot."""
    function = _renameat2()
    if function is None:
        return False
    if function(_AT_FDCWD, os.fsencode(first), _AT_FDCWD, os.fsencode(second), _RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP, errno.EPERM):
        return False
    raise OSError(code, os.strerror(code), str(second))


def _alive(pid: int) -> bool:
    """True if process ``pid`` exists and is not a zombie (a killed worker not yet reaped)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return True
    return stat.rpartition(")")[2].split()[0] not in ("Z", "X")


def _fsync_dir(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
