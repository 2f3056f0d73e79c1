"""The content-addressed artifact store under ``data/built/``.

Layout::

    artifacts/<stage>/<output>-<key>/      one committed artifact: files + manifest.json (written last)
    targets/<target>/<output>  -> symlink  the current artifact of each target output
    tmp/                                   work in progress; never read, cleaned on the next run
    logs/<target>/<stage>.log              the log of the latest run of each stage

An artifact is written into ``tmp/``, its manifest is written last, then the directory is renamed
into ``artifacts/`` in one step. A directory in ``artifacts/`` without a valid manifest is never
trusted: it is removed and rebuilt.
"""

from __future__ import annotations

import json
import os
import shutil
import uuid
from pathlib import Path
from typing import Any

from pipeline.errors import StoreError

MANIFEST_NAME = "manifest.json"
MANIFEST_FORMAT = 1


class ArtifactStore:
    """Reads and commits artifacts in a build directory.

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
    def logs_dir(self) -> Path:
        """Per-stage logs."""
        return self.root / "logs"

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
        """True if a trusted artifact with ``key`` is committed."""
        path = self.artifact_path(stage, output, key)
        manifest = self.read_manifest(path)
        return manifest is not None and manifest.get("key") == key

    def discard_untrusted(self, stage: str, output: str, key: str) -> bool:
        """Remove the directory of ``key`` if it exists without a valid manifest; True if removed."""
        path = self.artifact_path(stage, output, key)
        if path.exists() and not self.has(stage, output, key):
            shutil.rmtree(path, ignore_errors=True)
            return True
        return False

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

    def commit(self, tmp: Path, final: Path, manifest: dict[str, Any]) -> Path:
        """Write ``manifest`` last into ``tmp`` and rename it to ``final`` in one step.

        If another process committed ``final`` first, ``tmp`` is discarded and ``final`` kept.
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
        if final.exists():
            if self.read_manifest(final) is not None:
                shutil.rmtree(tmp, ignore_errors=True)
                return final
            shutil.rmtree(final, ignore_errors=True)
        try:
            os.rename(tmp, final)
        except OSError:
            if self.read_manifest(final) is None:
                raise
            shutil.rmtree(tmp, ignore_errors=True)
        _fsync_dir(final.parent)
        return final

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
        """Remove work directories left by processes that no longer run; returns how many."""
        if not self.tmp_dir.is_dir():
            return 0
        removed = 0
        for path in self.tmp_dir.iterdir():
            pid_text = path.name.rsplit(".", 2)[-2] if path.name.count(".") >= 2 else ""
            if pid_text.isdigit() and _alive(int(pid_text)):
                continue
            shutil.rmtree(path, ignore_errors=True)
            removed += 1
        return removed


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
