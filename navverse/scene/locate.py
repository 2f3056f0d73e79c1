"""Finding scene directories: in scene packs, in build stores, along a search path.

The store layout is a contract (DESIGN.md §3, §4): ``<built_dir>/targets/<target>/<output>`` is a
link to the current artifact of a target's output, an artifact directory is trusted only once its
``manifest.json`` is written (last), and a scene's directory is its ``scene`` artifact (with its
navmesh) or, before the navmesh is built, its ``geometry`` artifact. ``built_dir`` is ``data/built``
of the checkout (``pipeline.workspace.Workspace.built_dir``).

A dataset can be used away from the workspace that built it: :func:`find_scene_dirs` looks for each
scene, in order, in the directories given (``--scenes DIR``), then in those of ``$NAVVERSE_SCENES``
(:data:`SCENES_ENV`, ``os.pathsep``-separated), then in the workspace's build store. Each directory is
a scene pack (``DIR/<scene_id>/``, written by ``navverse export scenes``) or a build store
(``DIR/targets/<scene_id>/scene``). When the dataset's manifest gives a scene's hash, a directory
whose :func:`~navverse.scene.directory.scene_hash` differs is passed over; the first that matches is
the scene's.

Example::

    scene_dirs = find_scene_dirs(
        dataset.episodes(split="eval"), search=[Path("scene-pack")], hashes=dataset.manifest.scene_hashes
    )
"""

from __future__ import annotations

import json
import os
import warnings
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from navverse.errors import NavverseError, SceneError
from navverse.scene.directory import NAVMESH_BIN, SCENE_JSON, SCENE_USD, TEXTURES_DIR, scene_hash

if TYPE_CHECKING:
    from navverse.dataset import Episode

__all__ = [
    "SCENES_ENV",
    "SCENE_ARTIFACTS",
    "ScenePlace",
    "built_scene_dir",
    "built_scene_dirs",
    "cached_scene_hash",
    "find_scene_dirs",
    "scene_search_path",
]

SCENE_ARTIFACTS = ("scene", "geometry")
"""Artifacts that are scene directories, most complete first: a scene with its navmesh, or the
geometry a scene stage produced before the navmesh is built."""
SCENES_ENV = "NAVVERSE_SCENES"
"""The environment variable of scene directories searched after ``--scenes`` (``os.pathsep``-separated)."""
_MANIFEST = "manifest.json"
_STORE = "the workspace's build store"
_SHOWN_HASH = 12  # hex digits of a hash in messages


@dataclass(frozen=True)
class ScenePlace:
    """One place scenes are looked for.

    Attributes
    ----------
    path : Path or None
        A scene pack root or a build store; None when there is no such place (see ``absent``).
    source : str
        Where it comes from, for messages: ``--scenes``, ``$NAVVERSE_SCENES`` or the workspace's
        build store.
    absent : str
        Why there is no place (``path`` None), e.g. no workspace here.
    """

    path: Path | None
    source: str
    absent: str = ""

    def __str__(self) -> str:
        if self.source == _STORE:
            return f"{self.source} ({self.path})" if self.path is not None else self.source
        return f"{self.source} {self.path}"


def _committed_artifact(link: Path) -> Path | None:
    """The artifact directory a target link points at, or None if there is no link or the artifact has
    no readable manifest (a JSON object)."""
    if not link.is_symlink():
        return None
    artifact = link.resolve()
    try:
        manifest = json.loads((artifact / _MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return artifact if isinstance(manifest, dict) else None


def _store_scene(built_dir: Path, scene_id: str) -> Path | None:
    """A scene's committed ``scene`` artifact in a build store, else its ``geometry`` one, else None."""
    targets = Path(built_dir) / "targets" / scene_id
    found = (_committed_artifact(targets / artifact) for artifact in SCENE_ARTIFACTS)
    return next((path for path in found if path is not None), None)


def built_scene_dir(built_dir: Path, scene_id: str) -> Path:
    """The directory of a built scene: its ``scene`` artifact, else its ``geometry`` artifact.

    Parameters
    ----------
    built_dir : Path
        The build store (``data/built``).
    scene_id : str
        The scene's target id.

    Returns
    -------
    Path
        The committed artifact directory (links resolved).

    Raises
    ------
    SceneError
        If neither artifact of the scene is built, naming the command that builds it.
    """
    scene_dir = _store_scene(built_dir, scene_id)
    if scene_dir is None:
        raise SceneError(
            f"scene {scene_id!r} is not built: run 'navverse build {scene_id}' "
            "('navverse status' lists the scenes)"
        )
    return scene_dir


def built_scene_dirs(episodes: Iterable[Episode], *, built_dir: Path) -> dict[str, Path]:
    """The built scene directory of every scene the episodes are in.

    Parameters
    ----------
    episodes : iterable of Episode
        Dataset episodes (only their ``scene_id`` is read).
    built_dir : Path
        The build store (``data/built``).

    Returns
    -------
    dict of str to Path
        :func:`built_scene_dir` by scene id, in sorted order.

    Raises
    ------
    SceneError
        If a scene is not built (the first missing one in sorted order).
    """
    return {scene: built_scene_dir(built_dir, scene) for scene in sorted({e.scene_id for e in episodes})}


# ------------------------------------------------------------------------------------------- scene hash


def _hashed_files(root: Path) -> tuple[tuple[str, int, int, int, int], ...]:
    """The identity (name, device, inode, size, mtime) of every file :func:`scene_hash` reads."""
    textures = root / TEXTURES_DIR
    names = [SCENE_JSON, NAVMESH_BIN, SCENE_USD]
    if textures.is_dir():
        names += sorted(f"{TEXTURES_DIR}/{p.name}" for p in textures.iterdir() if not p.name.startswith("."))
    found = []
    for name in names:
        try:
            stat = (root / name).stat()
        except OSError:
            continue
        found.append((name, stat.st_dev, stat.st_ino, stat.st_size, stat.st_mtime_ns))
    return tuple(found)


@lru_cache(maxsize=512)
def _hash_of(root: str, identity: tuple[tuple[str, int, int, int, int], ...]) -> str:
    del identity  # part of the cache key only
    return scene_hash(root)


def cached_scene_hash(scene_dir: str | os.PathLike[str]) -> str:
    """:func:`~navverse.scene.directory.scene_hash` of a scene directory, computed once per process.

    Hashing reads every byte of the scene (tens of MB for a city), so the result is kept for this
    process, keyed by the directory and by the identity of the files hashed (device, inode, size and
    modification time): a file replaced or rewritten since is hashed again.

    Parameters
    ----------
    scene_dir : path
        A scene directory.

    Returns
    -------
    str
        The SHA-256, hex.
    """
    root = Path(scene_dir).resolve()
    return _hash_of(str(root), _hashed_files(root))


# ------------------------------------------------------------------------------------------ search path


def _env_dirs(environ: Mapping[str, str]) -> list[Path]:
    value = environ.get(SCENES_ENV, "")
    return [Path(part).expanduser() for part in value.split(os.pathsep) if part.strip()]


def scene_search_path(
    search: Sequence[str | os.PathLike[str]] = (), *, environ: Mapping[str, str] | None = None
) -> list[ScenePlace]:
    """The places searched before the workspace's build store: ``search``, then ``$NAVVERSE_SCENES``.

    Parameters
    ----------
    search : sequence of path
        Directories given on the command line (``--scenes DIR``), in order.
    environ : mapping, optional
        The environment (default ``os.environ``).

    Returns
    -------
    list of ScenePlace
        In search order.
    """
    env = os.environ if environ is None else environ
    given = [ScenePlace(Path(p).expanduser(), "--scenes") for p in search]
    return given + [ScenePlace(p, f"${SCENES_ENV}") for p in _env_dirs(env)]


class _Store:
    """The workspace's build store as a search place, found only when first needed."""

    def __init__(self, built_dir: str | os.PathLike[str] | Callable[[], Path] | None) -> None:
        self._given = built_dir
        self._place: ScenePlace | None = None

    def place(self) -> ScenePlace:
        if self._place is None:
            self._place = self._find()
        return self._place

    def _find(self) -> ScenePlace:
        if self._given is None:
            return ScenePlace(None, _STORE, absent="none given")
        if not callable(self._given):
            return ScenePlace(Path(self._given), _STORE)
        try:
            return ScenePlace(Path(self._given()), _STORE)
        except NavverseError as exc:
            return ScenePlace(None, _STORE, absent=str(exc))


def _candidate(place: ScenePlace, scene_id: str) -> tuple[Path | None, str]:
    """The scene's directory at one place (pack first, then store layout), or None and why not."""
    if place.path is None:
        return None, place.absent
    if not place.path.is_dir():
        return None, "no such directory" if not place.path.exists() else "not a directory"
    packed = place.path / scene_id
    if (packed / SCENE_JSON).is_file():
        return packed.resolve(), ""
    stored = _store_scene(place.path, scene_id)
    if stored is not None:
        return stored, ""
    return None, "not there"


def _short(digest: str) -> str:
    return f"{digest[:_SHOWN_HASH]}…" if len(digest) > _SHOWN_HASH else digest


def _places(places: Sequence[ScenePlace], store: _Store) -> Iterator[ScenePlace]:
    yield from places
    yield store.place()


def _missing(scene_id: str, tried: Sequence[tuple[ScenePlace, str]]) -> SceneError:
    """The error of a scene found nowhere: each place looked in, why it was not used, what to do."""
    lines = [f"scene {scene_id!r} not found; looked in, in order:"]
    lines += [f"  {i}. {place}: {why}" for i, (place, why) in enumerate(tried, start=1)]
    lines.append(
        "give the dataset's scenes with --scenes DIR (repeatable) or $NAVVERSE_SCENES: a scene pack "
        "written by `navverse export scenes DATASET OUT` on the machine that built the dataset, or a "
        f"build store (DIR/targets/<scene_id>/scene); or build the scene here: navverse build {scene_id}"
    )
    return SceneError("\n".join(lines))


def _find_one(
    scene_id: str,
    places: Sequence[ScenePlace],
    store: _Store,
    *,
    expected: str | None,
    rebuilt: Literal["skip", "warn"],
    warn: Callable[[str], None],
) -> Path:
    tried: list[tuple[ScenePlace, str]] = []
    differing: tuple[Path, str] | None = None
    for place in _places(places, store):
        found, why = _candidate(place, scene_id)
        if found is not None and expected:
            got = cached_scene_hash(found)
            if got != expected:
                why = f"scene hash {_short(got)} differs from the dataset's {_short(expected)} ({found})"
                if place.source == _STORE and differing is None:
                    differing = (found, got)
                found = None
        if found is not None:
            return found
        tried.append((place, why))
    if differing is not None and rebuilt == "warn":
        found, got = differing
        warn(
            f"scene {scene_id!r} in {_STORE} ({found}) has scene hash {_short(got)}, not the dataset's "
            f"{_short(expected or '')} (rebuilt since the dataset was packaged?); using it as built now"
        )
        return found
    raise _missing(scene_id, tried)


def _scene_ids(scenes: Iterable[Episode | str]) -> list[str]:
    return sorted({s if isinstance(s, str) else s.scene_id for s in scenes})


def find_scene_dirs(
    scenes: Iterable[Episode | str],
    *,
    search: Sequence[str | os.PathLike[str]] = (),
    hashes: Mapping[str, str] | None = None,
    built_dir: str | os.PathLike[str] | Callable[[], Path] | None = None,
    environ: Mapping[str, str] | None = None,
    rebuilt: Literal["skip", "warn"] = "skip",
    warn: Callable[[str], None] | None = None,
) -> dict[str, Path]:
    """The directory of every scene, found along the search path.

    Each scene is looked for, in order, in the directories of ``search``, then in those of
    ``$NAVVERSE_SCENES`` (:data:`SCENES_ENV`), then in the workspace's build store ``built_dir``. A
    directory may be a scene pack (``DIR/<scene_id>/`` holding ``scene.json``) or a build store
    (``DIR/targets/<scene_id>/scene``, else ``geometry``: a committed artifact). When ``hashes`` has the
    scene, a directory whose scene hash differs is passed over; the first that matches is taken.

    Parameters
    ----------
    scenes : iterable of Episode or str
        Dataset episodes (their ``scene_id`` is read) or scene ids.
    search : sequence of path
        Directories searched first (``--scenes DIR``), in order.
    hashes : mapping of str to str, optional
        The dataset manifest's ``scene_hashes``; without a scene's hash, any directory of it is taken.
    built_dir : path or callable, optional
        The workspace's build store (``data/built``), searched last; a callable is called only when a
        scene is not found before it, and a :class:`~navverse.errors.NavverseError` it raises (no
        workspace here) is the reason given for that place. None: no build store is searched.
    environ : mapping, optional
        The environment holding ``$NAVVERSE_SCENES`` (default ``os.environ``).
    rebuilt : {"skip", "warn"}
        ``"warn"``: when no place has a scene with the dataset's hash but the workspace's build store
        has the scene with another hash (rebuilt since the dataset was packaged), use that one and call
        ``warn`` (the commands' behaviour in the workspace that built a dataset). ``"skip"``: refuse it.
    warn : callable, optional
        Called with the warning's text (default :func:`warnings.warn`).

    Returns
    -------
    dict of str to Path
        The scene directory (absolute) by scene id, in sorted order.

    Raises
    ------
    SceneError
        If a scene is found nowhere (the first in sorted order): naming it, every place looked in, in
        order, why each was not used ("not there", "scene hash … differs from the dataset's …"), and what
        to do (``--scenes DIR``, ``$NAVVERSE_SCENES``, ``navverse export scenes``, building its recipe).
    """
    places = scene_search_path(search, environ=environ)
    store = _Store(built_dir)
    say = warn if warn is not None else (lambda text: warnings.warn(text, stacklevel=3))
    known = hashes or {}
    return {
        scene_id: _find_one(scene_id, places, store, expected=known.get(scene_id), rebuilt=rebuilt, warn=say)
        for scene_id in _scene_ids(scenes)
    }
