"""Publishing: a built dataset version copied into ``episodes/<name>/v<version>``.

A published version is immutable: :func:`publish` verifies the built version, does nothing when the
same content is already there, and refuses other content under the same version. The private files
of its private splits go to ``episodes/<name>/private/v<version>/``, outside the version directory
(:mod:`navverse.dataset.private`).
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from pydantic import ValidationError

from navverse.dataset.manifest import DatasetManifest
from navverse.dataset.private import private_dir, private_file_name
from navverse.dataset.reader import Dataset
from navverse.files import atomic_dir, file_sha256
from navverse.records.errors import DatasetError

__all__ = ["built_version", "local_dataset", "publish"]


def built_version(artifact: str | os.PathLike[str]) -> Path:
    """The ``<name>/v<version>`` directory inside a built ``dataset`` artifact (laid out as published).

    Raises
    ------
    DatasetError
        If the artifact holds no dataset version, or more than one.
    """
    found = sorted(p.parent for p in Path(artifact).glob("*/v*/manifest.json"))
    if len(found) != 1:
        raise DatasetError(f"{artifact} holds {len(found)} dataset versions, not one: rebuild it")
    return found[0]


def local_dataset(root: str | os.PathLike[str], *, private: str | os.PathLike[str] | None = None) -> Dataset:
    """A dataset version with its private files: `private` when given, else those beside it, where a
    build and :func:`publish` put them (``<name>/private/v<version>``), when they are there.

    Parameters
    ----------
    root : path
        As :class:`~navverse.dataset.reader.Dataset` takes it (a version, or a dataset's newest).
    private : path, optional
        The directory of the version's private files.
    """
    dataset = Dataset(root)
    if private is None and dataset.manifest.private and private_dir(dataset.root).is_dir():
        private = private_dir(dataset.root)
    return dataset if private is None else Dataset(dataset.root, private=private)


def publish(built: str | os.PathLike[str], episodes_dir: str | os.PathLike[str]) -> tuple[Path, bool]:
    """Copy a built dataset version into ``<episodes_dir>/<name>/v<version>``.

    A published version is immutable: publishing the same content again does nothing; different
    content under the same version is refused.

    Parameters
    ----------
    built : path
        A dataset version directory with ``manifest.json`` (:func:`built_version` of the artifact).
    episodes_dir : path
        The ``episodes/`` folder.

    Returns
    -------
    tuple of (Path, bool)
        The published directory, and whether it was written now (False: it was already there).

    Raises
    ------
    DatasetError
        If the built version does not match its manifest, or that version exists with other content.
    """
    dataset = local_dataset(built)
    dataset.verify()
    manifest = dataset.manifest
    target = Path(episodes_dir) / manifest.name / f"v{manifest.version}"
    _publish_private(dataset, private_dir(target))
    if (target / "manifest.json").is_file():
        try:
            existing = DatasetManifest.model_validate_json((target / "manifest.json").read_text())
        except ValidationError:
            existing = None
        if existing is not None and existing.files == manifest.files:
            return target, False
        raise DatasetError(
            f"{target} is already published with different content, and a published version is "
            f"immutable: bump the dataset version in {manifest.recipe} (package_dataset: version) or "
            f"delete {target} if it was never shared"
        )
    target.parent.mkdir(parents=True, exist_ok=True)
    with atomic_dir(target) as staging:
        shutil.copytree(dataset.root, staging, dirs_exist_ok=True)
    return target, True


def _publish_private(dataset: Dataset, target: Path) -> None:
    """Copy a version's private files into `target` (``<name>/private/v<version>``), unless the same
    files are there; other files there are refused, as a published version's are."""
    wanted = {private_file_name(split): sha for split, sha in dataset.manifest.private.items()}
    if not wanted:
        return
    assert dataset.private_dir is not None
    if target.is_dir():
        present = {p.name: file_sha256(p) for p in target.iterdir() if p.is_file()}
        if present == wanted:
            return
        raise DatasetError(
            f"{target} holds other private files than {dataset.manifest.name} v{dataset.manifest.version} "
            "was built with, and a published version is immutable: bump the dataset version or delete "
            f"{target} if it was never used"
        )
    target.parent.mkdir(parents=True, exist_ok=True)
    with atomic_dir(target) as staging:
        for name in sorted(wanted):
            shutil.copy2(dataset.private_dir / name, Path(staging) / name)
