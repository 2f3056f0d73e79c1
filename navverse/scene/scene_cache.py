"""A built scene's geometry kept as plain arrays, so that reading it again needs no USD.

:func:`cached_scene` reads a scene directory once through USD
(:func:`~navverse.scene.directory.read_scene`) and writes its meshes and textures to
``$NAVVERSE_CACHE_DIR/scenes/<hash>.npz``, keyed by the scene's files
(:func:`~navverse.scene.directory.scene_hash`); later reads load the arrays and never import the USD
library, which alone holds about 70 MB of a process's memory. Commands that only look at a scene (the
evaluator's keyframe pictures) read it this way; the scene is the same, array for array.
"""

from __future__ import annotations

import contextlib
import json
import os
import zipfile
from pathlib import Path

import numpy as np

from navverse.cache import cache_root
from navverse.files import atomic_write
from navverse.scene.annotations import SceneAnnotations
from navverse.scene.geometry import MeshData, Scene, SceneObject, Surface, Texture

__all__ = ["cached_scene", "scene_cache_path"]

_FORMAT = 1
"""Version of the cached ``.npz``; a file of another version is read from the USD file again."""

_OPTIONAL = ("face_colors", "face_uvs", "face_texture")
"""The per-face arrays a mesh may lack."""


def scene_cache_path(scene_dir: str | os.PathLike[str]) -> Path:
    """Where :func:`cached_scene` keeps a scene: ``$NAVVERSE_CACHE_DIR/scenes/<hash>.npz``, keyed by the
    scene's files (default cache ``~/.cache/navverse``)."""
    from navverse.scene.directory import scene_hash

    return cache_root() / "scenes" / f"{scene_hash(scene_dir)[:32]}.npz"


def cached_scene(scene_dir: str | os.PathLike[str]) -> Scene:
    """The complete scene of a built scene directory, read through USD once and then from the cache.

    Raises
    ------
    SceneError
        If the directory or a file is missing, invalid, or the files disagree (on the read through USD).
    """
    from navverse.scene.directory import read_annotations, read_scene

    path = scene_cache_path(scene_dir)
    annotations = read_annotations(Path(scene_dir))
    cached = _load(path, annotations) if path.is_file() else None
    if cached is not None:
        return cached
    scene = read_scene(Path(scene_dir))
    with contextlib.suppress(OSError):  # a cache that cannot be written costs the next read its time only
        _save(scene, path)
    return scene


def _meshes(scene: Scene) -> list[MeshData]:
    """The scene's meshes in the cache's order: the surfaces', then the objects'."""
    return [s.mesh for s in scene.surfaces] + [o.mesh for o in scene.objects]


def _save(scene: Scene, path: Path) -> None:
    """Write the scene's meshes and textures to ``path`` (atomically); textures shared by meshes once."""
    arrays: dict[str, np.ndarray] = {}
    textures: dict[int, int] = {}  # id of a Texture -> its index in the file
    texture_names: list[str] = []  # by that index
    meshes = []
    for index, mesh in enumerate(_meshes(scene)):
        arrays[f"m{index}_vertices"], arrays[f"m{index}_faces"] = mesh.vertices, mesh.faces
        for name in _OPTIONAL:
            if getattr(mesh, name) is not None:
                arrays[f"m{index}_{name}"] = getattr(mesh, name)
        for texture in mesh.textures:
            if id(texture) not in textures:
                arrays[f"t{len(textures)}"] = texture.image
                textures[id(texture)] = len(textures)
                texture_names.append(texture.name)
        meshes.append([textures[id(t)] for t in mesh.textures])
    index = {
        "format": _FORMAT,
        "scene_id": scene.scene_id,
        "surfaces": [[s.name, s.terrain_class] for s in scene.surfaces],
        "objects": len(scene.objects),
        "textures": texture_names,
        "mesh_textures": meshes,
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_write(path) as handle:
        np.savez_compressed(handle, index=np.asarray(json.dumps(index)), **arrays)


def _load(path: Path, annotations: SceneAnnotations) -> Scene | None:
    """The scene kept at ``path``, with ``annotations`` (its ``scene.json``); None if the file is
    damaged, of another format, or of another scene."""
    try:
        with np.load(path) as data:
            index = json.loads(str(data["index"]))
            if index.get("format") != _FORMAT or index.get("scene_id") != annotations.scene_id:
                return None
            textures = [Texture(name, data[f"t{i}"]) for i, name in enumerate(index["textures"])]

            def mesh(i: int) -> MeshData:
                given = {name: data[f"m{i}_{name}"] for name in _OPTIONAL if f"m{i}_{name}" in data}
                return MeshData(
                    data[f"m{i}_vertices"],
                    data[f"m{i}_faces"],
                    textures=tuple(textures[t] for t in index["mesh_textures"][i]),
                    **given,
                )

            if index["objects"] != len(annotations.objects):
                return None
            surfaces = [Surface(name, kind, mesh(i)) for i, (name, kind) in enumerate(index["surfaces"])]
            first = len(surfaces)
            objects = [SceneObject(a, mesh(first + i)) for i, a in enumerate(annotations.objects)]
            return Scene(annotations, tuple(surfaces), tuple(objects))
    except (OSError, zipfile.BadZipFile, KeyError, ValueError, TypeError, IndexError):
        return None
