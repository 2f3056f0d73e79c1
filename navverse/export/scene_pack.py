"""Scene packs: the scenes a dataset needs, copied out of the workspace that built them.

:func:`export_scene_pack` (``navverse export scenes DATASET OUT``) writes, atomically (a temporary
directory beside ``out``, renamed at the end)::

    out/scenes.json                 format, the dataset (name, version, manifest sha256), the split,
                                    and per scene: its scene hash and {relative path: sha256} of its files
    out/<scene_id>/scene.json       annotations
    out/<scene_id>/scene.usdc       geometry, labels, physics
    out/<scene_id>/navmesh.bin      the navmesh (navmesh.json, its description, when the scene has it)
    out/<scene_id>/textures/*.png   the images of textured scenes
    out/<scene_id>/look.json        the scene's look, where it was built (look stage): settings, map details,
    out/<scene_id>/look.usdc        its materials over scene.usdc,
    out/<scene_id>/textures/look/   and their images

These are the files the runner, the environment and the evaluator read from a scene directory (the
scoring fields are derived from them and cached per scene hash); the build store's own files
(``manifest.json``, ``stage.log``) and the picture ``bev.png`` are left out. Files are copied, never
linked, and each scene's copy is checked to have the scene hash the dataset's manifest lists. A pack
is a search place of :func:`navverse.scene.locate.find_scene_dirs` (``--scenes OUT``,
``$NAVVERSE_SCENES``), so a dataset version and its pack work on a machine without the workspace.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from navverse.dataset import Dataset, DatasetError
from navverse.errors import NavverseError
from navverse.files import atomic_dir
from navverse.look.files import look_files
from navverse.scene.directory import (
    NAVMESH_BIN,
    NAVMESH_JSON,
    SCENE_JSON,
    SCENE_USD,
    TEXTURES_DIR,
    scene_hash,
)
from navverse.scene.locate import find_scene_dirs

__all__ = [
    "PACK_FORMAT_VERSION",
    "PACK_INDEX",
    "ScenePack",
    "ScenePackError",
    "export_scene_pack",
    "pack_files",
]

PACK_INDEX = "scenes.json"
"""The index of a pack: what it holds and the checksum of every file."""
PACK_FORMAT_VERSION = "1.0"
REQUIRED_FILES = (SCENE_JSON, SCENE_USD, NAVMESH_BIN)
"""Files every packed scene has: a scene without its navmesh cannot be run or scored."""
OPTIONAL_FILES = (NAVMESH_JSON,)
_CHUNK = 1 << 20

Progress = Callable[[int, int], None]
"""Called with (bytes copied, bytes in all) as the copy goes on."""


class ScenePackError(NavverseError):
    """A scene pack cannot be written: the place is taken, or a scene is incomplete or not the dataset's."""


@dataclass(frozen=True)
class ScenePack:
    """What :func:`export_scene_pack` wrote.

    Attributes
    ----------
    root : Path
        The pack directory.
    scenes : dict of str to str
        The scene hash of every scene packed, by scene id.
    files : int
        Files copied.
    bytes : int
        Bytes copied.
    """

    root: Path
    scenes: dict[str, str]
    files: int
    bytes: int


def pack_files(scene_dir: str | os.PathLike[str]) -> list[str]:
    """The files of a scene directory that a pack holds, as paths relative to it, sorted.

    Raises
    ------
    ScenePackError
        If the directory lacks a required file (``scene.json``, ``scene.usdc``, ``navmesh.bin``).
    """
    root = Path(scene_dir)
    missing = [name for name in REQUIRED_FILES if not (root / name).is_file()]
    if missing:
        raise ScenePackError(
            f"scene directory {root} has no {', '.join(missing)}: build the scene's navmesh "
            "(`navverse build <scene_id>`) before exporting it"
        )
    names = [*REQUIRED_FILES, *(name for name in OPTIONAL_FILES if (root / name).is_file())]
    textures = root / TEXTURES_DIR
    if textures.is_dir():  # hidden names are temporary files of interrupted writes, not textures
        names += [
            f"{TEXTURES_DIR}/{p.name}"
            for p in textures.glob("*.png")
            if not p.name.startswith(".") and p.is_file()
        ]
    return sorted(names)


def _copy(source: Path, target: Path, advance: Callable[[int], None]) -> str:
    """Copy a file's bytes (a link is followed: the copy is a regular file) and return their sha256."""
    digest = hashlib.sha256()
    target.parent.mkdir(parents=True, exist_ok=True)
    with open(source, "rb") as reader, open(target, "wb") as writer:
        while chunk := reader.read(_CHUNK):
            digest.update(chunk)
            writer.write(chunk)
            advance(len(chunk))
    return digest.hexdigest()


def _check_out(out: Path) -> None:
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        kind = "a directory" if out.is_dir() else "a file"
        raise ScenePackError(
            f"{out} already exists ({kind}, not empty): give a new directory for the scene pack"
        )


def _scene_ids(dataset: Dataset, split: str | None) -> list[str]:
    """The scenes the episodes of a split (None: of every split) are in."""
    if split is not None and split not in dataset.manifest.splits:
        raise DatasetError(f"{dataset.root} has no split {split!r}; it has: {', '.join(dataset.splits)}")
    return sorted({e.scene_id for e in dataset.episodes(split=split)})


class _Counter:
    """Bytes copied so far, reported to a progress callback."""

    def __init__(self, total: int, progress: Progress | None) -> None:
        self.done, self.total, self._progress = 0, total, progress

    def __call__(self, count: int) -> None:
        self.done += count
        if self._progress is not None:
            self._progress(self.done, self.total)


def _pack_scene(scene_id: str, sources: Mapping[str, Path], tmp: Path, counter: _Counter) -> dict:
    """Copy one scene (its files by name in the pack) into the pack being written; its entry of the
    index."""
    target = tmp / scene_id
    files = {name: _copy(sources[name], target / name, counter) for name in sorted(sources)}
    return {"scene_hash": scene_hash(target), "files": files}


def _verify(packed: Mapping[str, dict], expected: Mapping[str, str]) -> None:
    """Each copy has the scene hash the dataset lists (when it lists one)."""
    for scene_id, entry in packed.items():
        want = expected.get(scene_id)
        if want and entry["scene_hash"] != want:
            raise ScenePackError(
                f"the copy of scene {scene_id!r} has scene hash {entry['scene_hash']}, not the dataset's "
                f"{want}: its files changed while they were copied; export again"
            )


def export_scene_pack(
    dataset_dir: str | os.PathLike[str],
    out: str | os.PathLike[str],
    *,
    split: str | None = None,
    search: Sequence[str | os.PathLike[str]] = (),
    built_dir: str | os.PathLike[str] | Callable[[], Path] | None = None,
    progress: Progress | None = None,
) -> ScenePack:
    """Copy the scenes a dataset version (or one split) needs into a scene pack at ``out``.

    Parameters
    ----------
    dataset_dir : path
        ``episodes/<name>/v<version>`` (verified before use).
    out : path
        The pack directory to create; it must not exist (or be empty). Nothing is left there on failure.
    split : str, optional
        Pack only the scenes of this split's episodes (default: every split's).
    search : sequence of path
        Where to look for the scenes before ``$NAVVERSE_SCENES`` and ``built_dir``
        (:func:`navverse.scene.locate.find_scene_dirs`).
    built_dir : path or callable, optional
        The workspace's build store (``data/built``), searched last.
    progress : callable, optional
        Called with (bytes copied, bytes in all) as the copy goes on.

    Returns
    -------
    ScenePack
        What was written.

    Raises
    ------
    ScenePackError
        If ``out`` exists and is not empty, a scene has no navmesh, or a copy does not have the scene
        hash the dataset's manifest lists.
    SceneError
        If a scene with the dataset's scene hash is found nowhere (naming each place looked in).
    DatasetError
        If the dataset does not verify or has no such split.
    """
    out = Path(out)
    _check_out(out)
    dataset = Dataset(dataset_dir)
    dataset.verify()
    hashes = dataset.manifest.scene_hashes
    scene_dirs = find_scene_dirs(
        _scene_ids(dataset, split), search=search, hashes=hashes, built_dir=built_dir
    )
    sources = {
        scene_id: {**{name: scene_dir / name for name in pack_files(scene_dir)}, **look_files(scene_dir)}
        for scene_id, scene_dir in scene_dirs.items()
    }
    total = sum(path.stat().st_size for listed in sources.values() for path in listed.values())
    counter = _Counter(total, progress)
    out.parent.mkdir(parents=True, exist_ok=True)
    with atomic_dir(out) as tmp:
        packed = {s: _pack_scene(s, sources[s], tmp, counter) for s in sorted(scene_dirs)}
        _verify(packed, hashes)
        index = {
            "format_version": PACK_FORMAT_VERSION,
            "dataset": {
                "name": dataset.manifest.name,
                "version": dataset.manifest.version,
                "manifest_sha256": dataset.manifest_sha256,
            },
            "split": split,
            "scenes": packed,
        }
        (tmp / PACK_INDEX).write_text(json.dumps(index, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    return ScenePack(
        root=out,
        scenes={s: entry["scene_hash"] for s, entry in packed.items()},
        files=sum(len(listed) for listed in sources.values()),
        bytes=counter.done,
    )
