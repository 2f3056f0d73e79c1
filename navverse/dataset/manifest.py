"""The manifest of a dataset version (``manifest.json``, DESIGN.md §3): its model, validated strictly,
and how it is read.

``files`` lists every file of the version but the manifest, by its path relative to the version
directory, with its SHA-256; a ``files`` entry is a plain ``<split>/<task>[.rollouts].json.gz``
inside the version directory, checksums are SHA-256 hex, names are single path components, splits
are scene-disjoint. :func:`read_manifest` reads the file with a size cap
(:data:`MAX_MANIFEST_BYTES`) as strict JSON (no duplicate keys, no NaN), checks its format version
against :data:`~navverse.records.schema.FORMAT_VERSION` and validates it.
"""

from __future__ import annotations

import errno
import hashlib
import json
import re
from pathlib import Path
from typing import Annotated, Any

from pydantic import (
    BaseModel,
    Field,
    NonNegativeInt,
    ValidationError,
    field_validator,
    model_validator,
)

from navverse.records.errors import REMEDY, DatasetError, first_error
from navverse.records.files import mib, open_regular
from navverse.records.schema import FORMAT_VERSION, RECORD_CONFIG, Task
from navverse.scene_types import SceneType

__all__ = ["MAX_MANIFEST_BYTES", "DatasetManifest", "Name", "Sha256", "SplitName", "read_manifest"]

MAX_MANIFEST_BYTES = 4 << 20
"""Largest ``manifest.json`` read (bytes)."""
_MEMBER = re.compile(
    r"(?P<split>[a-z][a-z0-9_]*)/(?P<task>objnav|placenav|vln)(?P<rollouts>\.rollouts)?\.json\.gz"
)
"""A ``files`` entry: ``<split>/<task>.json.gz`` or ``<split>/<task>.rollouts.json.gz``."""


Sha256 = Annotated[str, Field(pattern=r"^[0-9a-f]{64}$")]
SplitName = Annotated[str, Field(pattern=r"^[a-z][a-z0-9_]*$")]
Name = Annotated[str, Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9._-]*$", max_length=200)]
"""A dataset or scene name: one path component, never ``.`` or ``..``."""


class DatasetManifest(BaseModel):
    """``manifest.json`` of a dataset version.

    ``files`` lists every file of the version but the manifest, by its path relative to the version
    directory (``<split>/<task>.json.gz`` or ``<split>/<task>.rollouts.json.gz``), with its SHA-256;
    ``counts`` holds the episodes per split, task and scene type; ``look_version`` how the scenes' RGB
    images are made.
    """

    model_config = RECORD_CONFIG

    format_version: str
    name: Name
    version: Annotated[str, Field(pattern=r"^\d+\.\d+$")]
    toolkit_version: str
    recipe: str
    recipe_hash: str
    embodiment: str
    scene_hashes: dict[Name, str]
    splits: dict[SplitName, list[Name]]
    counts: dict[SplitName, dict[Task, dict[SceneType, NonNegativeInt]]]
    difficulty_thresholds: dict[Task, tuple[float, float]]
    files: dict[str, Sha256]
    look_version: str | None = None
    """Version of how the scenes' looks are made (:data:`navverse.look.settings.LOOK_VERSION`) when the
    version was packaged: the RGB an agent sees; None in versions made before looks (format < 1.2)."""
    private: dict[SplitName, Sha256] = {}
    """The private splits (format 1.3; :mod:`navverse.dataset.private`): the SHA-256 of each one's
    private file, which holds its goals and is not part of the version."""

    def to_json(self) -> bytes:
        """The manifest's bytes as written: indented JSON, ``private`` only when there is one."""
        exclude = None if self.private else {"private"}
        return (self.model_dump_json(indent=2, exclude=exclude) + "\n").encode("utf-8")

    @field_validator("files")
    @classmethod
    def _plain_paths(cls, files: dict[str, str]) -> dict[str, str]:
        for name in files:
            problem = _member_problem(name)
            if problem is not None:
                raise ValueError(
                    f"files entry {name!r} {problem}: every entry is <split>/<task>.json.gz or "
                    "<split>/<task>.rollouts.json.gz inside the version directory"
                )
        return files

    @model_validator(mode="after")
    def _known_splits(self) -> DatasetManifest:
        named = [n.split("/")[0] for n in self.files] + list(self.counts)
        unknown = sorted(set(named) - set(self.splits))
        if unknown:
            raise ValueError(f"files or counts name splits that splits does not list: {', '.join(unknown)}")
        scenes = [scene for members in self.splits.values() for scene in members]
        shared = sorted({scene for scene in scenes if scenes.count(scene) > 1})
        if shared:
            raise ValueError(f"splits must be scene-disjoint; in several splits: {', '.join(shared)}")
        unknown = sorted(set(self.private) - set(self.splits))
        if unknown:
            raise ValueError(f"private names splits that splits does not list: {', '.join(unknown)}")
        revealed = sorted(
            n for n in self.files if n.endswith(".rollouts.json.gz") and n.split("/")[0] in self.private
        )
        if revealed:
            raise ValueError(
                f"a private split's rollouts are in its private file, not the version: {', '.join(revealed)}"
            )
        return self


def _member_problem(name: str) -> str | None:
    """What is wrong with a ``files`` entry, or None for a plain ``<split>/<task>...json.gz``."""
    if name.startswith("/") or re.match(r"^[A-Za-z]:", name):
        return "is an absolute path"
    if any(part in ("..", ".") for part in re.split(r"[/\\]", name)):
        return "leaves the version directory"
    if _MEMBER.fullmatch(name) is None:
        return "is not a dataset file name"
    return None


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON object's dict, refusing a key given twice (JSON would keep the last one silently)."""
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"the key {key!r} appears twice in one object")
        out[key] = value
    return out


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a JSON number")


def read_manifest(path: Path) -> tuple[DatasetManifest, str]:
    """Read and strictly validate ``manifest.json`` (at most :data:`MAX_MANIFEST_BYTES`); with its SHA-256."""
    try:
        with open_regular(path) as handle:
            text = handle.read(MAX_MANIFEST_BYTES + 1)
    except OSError as exc:
        what = "is a symbolic link" if exc.errno == errno.ELOOP else f"cannot be read ({exc.strerror})"
        raise DatasetError(f"{path} {what}: a dataset manifest is a regular file. {REMEDY}") from None
    if len(text) > MAX_MANIFEST_BYTES:
        raise DatasetError(
            f"{path} is larger than {mib(MAX_MANIFEST_BYTES)}: not a dataset manifest. {REMEDY}"
        )
    try:
        raw = json.loads(text, object_pairs_hook=_unique_keys, parse_constant=_no_constant)
    except (ValueError, RecursionError) as exc:
        raise DatasetError(f"{path} is not JSON ({exc}). {REMEDY}") from None
    _check_format(str(raw.get("format_version", "?")) if isinstance(raw, dict) else "?", path)
    try:
        manifest = DatasetManifest.model_validate_json(text, strict=True)
    except ValidationError as exc:
        raise DatasetError(f"{path} is malformed: {first_error(exc)}. {REMEDY}") from None
    return manifest, hashlib.sha256(text).hexdigest()


def _check_format(version: str, source: Path) -> None:
    try:
        major, minor = (int(part) for part in version.split("."))
        own_major, own_minor = (int(part) for part in FORMAT_VERSION.split("."))
    except ValueError:
        raise DatasetError(f"{source}: format_version {version!r} is not 'major.minor'") from None
    if major != own_major or minor > own_minor:
        raise DatasetError(
            f"{source} has dataset format {version}; this toolkit ({_toolkit_version()}) reads format "
            f"{own_major}.x up to {FORMAT_VERSION}. "
            + ("Update the toolkit." if (major, minor) > (own_major, own_minor) else "Rebuild the dataset.")
        )


def _toolkit_version() -> str:
    from navverse import __version__

    return __version__
