"""Finding built scene directories in the build store, without the build engine.

The store layout is a contract (DESIGN.md §3, §4): ``<built_dir>/targets/<target>/<output>`` is a
link to the current artifact of a target's output, an artifact directory is trusted only once its
``manifest.json`` is written (last), and a scene's directory is its ``scene`` artifact (with its
navmesh) or, before the navmesh is built, its ``geometry`` artifact. ``built_dir`` is ``data/built``
of the checkout (``pipeline.workspace.Workspace.built_dir``).

Example::

    scene_dirs = built_scene_dirs(dataset.episodes(split="eval"), built_dir=Path("data/built"))
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

from navverse.errors import SceneError

if TYPE_CHECKING:
    from navverse.dataset import Episode

__all__ = ["SCENE_ARTIFACTS", "built_scene_dir", "built_scene_dirs"]

SCENE_ARTIFACTS = ("scene", "geometry")
"""Artifacts that are scene directories, most complete first: a scene with its navmesh, or the
geometry a scene stage produced before the navmesh is built."""
_MANIFEST = "manifest.json"


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
    targets = Path(built_dir) / "targets" / scene_id
    found = (_committed_artifact(targets / artifact) for artifact in SCENE_ARTIFACTS)
    scene_dir = next((path for path in found if path is not None), None)
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
