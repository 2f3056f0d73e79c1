"""Publishing: a built dataset version copied into ``episodes/<name>/v<version>``.

A published version is immutable: :func:`publish` verifies the built version, does nothing when the
same content is already there, and refuses other content under the same version.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from pydantic import ValidationError

from navverse.dataset.errors import DatasetError
from navverse.dataset.manifest import DatasetManifest
from navverse.dataset.reader import Dataset
from navverse.files import atomic_dir

__all__ = ["built_version", "publish"]


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
    dataset = Dataset(built)
    dataset.verify()
    manifest = dataset.manifest
    target = Path(episodes_dir) / manifest.name / f"v{manifest.version}"
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
