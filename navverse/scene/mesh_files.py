"""Which files a mesh import may read: the mesh file and every file it brings in, each checked
before it is opened.

Hostile files are refused, never waited on: the file and every file it brings in (OBJ material
libraries and textures, glTF buffers and images, served by :class:`ConfinedResolver` from the
mesh's folder and below; USD sublayers, references, payloads and value clips, walked layer by layer
by :func:`usd_layer_files`) must be a regular file (``os.stat`` before any open: no named pipes,
devices or directories) of at most :data:`MAX_MESH_BYTES`, and pass the caller's :data:`FileCheck`
(e.g. the allowed folders of a recipe).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from pathlib import Path

from navverse.errors import NavverseError
from navverse.files import regular_file_problem

__all__ = [
    "MAX_MESH_BYTES",
    "ConfinedResolver",
    "FileCheck",
    "MeshImportError",
    "UsdDependencyError",
    "file_problem",
    "usd_layer_files",
]

MAX_MESH_BYTES = 2 * 1024**3
"""Largest mesh file, and largest file it brings in (2 GiB): files are parsed whole, in memory."""

FileCheck = Callable[[Path, str], str | None]
"""``check(resolved_path, written)``: why a file a mesh brings in may not be read (None: it may)."""


class MeshImportError(NavverseError):
    """A mesh file cannot be read or holds nothing to import."""


class UsdDependencyError(MeshImportError):
    """A file a USD file brings in (sublayer, reference, payload, value clip) may not be read."""


def file_problem(path: Path, *, max_bytes: int = MAX_MESH_BYTES) -> str | None:
    """Why ``path`` cannot be read as a mesh file (None: it can), found with ``os.stat``, never opening it."""
    problem = regular_file_problem(path, max_bytes=max_bytes, what="mesh file")
    if problem is not None and "limit" in problem:
        problem += "; decimate or split it first (e.g. in Blender)"
    return problem


class ConfinedResolver:
    """Serves the files a mesh names (OBJ material libraries and textures, glTF buffers and images)
    from the mesh's folder and below, each a regular file within the size cap and passing ``check``.

    trimesh swallows a resolver's errors (a material is then just missing), so the refusals are
    also kept in :attr:`refused`, for the reader to report after loading.
    """

    def __init__(self, source: Path, *, check: FileCheck | None, base: Path | None = None) -> None:
        self.root = source.parent.resolve()
        self.base = base or self.root
        self.file_name = source.name  # trimesh names an OBJ's unnamed mesh after it
        self.source = source
        self.check = check
        self.refused: list[str] = []

    def _candidates(self, name: str) -> Iterator[Path]:
        stripped = name.strip()
        for candidate in (stripped, stripped.lstrip("/"), os.path.basename(stripped)):
            path = (self.base / candidate).resolve()
            if candidate and path.is_relative_to(self.root) and os.path.lexists(path):
                yield path

    def get(self, name: str) -> bytes:
        """The bytes of the file ``name`` (relative to the mesh's folder)."""
        path = next(self._candidates(name), None)
        if path is None:
            raise FileNotFoundError(f"{name!r} is not a file in {self.root}")
        problem = file_problem(path)
        if problem is None and self.check is not None:
            problem = self.check(path, name)
        if problem is not None:
            self.refused.append(f"{name!r}: {problem}")
            raise OSError(problem)
        return path.read_bytes()

    def __getitem__(self, name: str) -> bytes:
        return self.get(name)

    def write(self, name: str, data: object) -> None:
        """Never used: reading writes nothing."""
        raise OSError(f"cannot write {name!r}: mesh import reads only")

    def namespaced(self, namespace: str) -> ConfinedResolver:
        """The same confinement, with names relative to the subfolder ``namespace``."""
        resolver = ConfinedResolver(self.source, check=self.check, base=(self.base / namespace).resolve())
        resolver.refused = self.refused
        return resolver

    def keys(self) -> Iterator[str]:
        """No listing (trimesh asks only for archives)."""
        return iter(())


def _open_layer(identifier: str) -> object:
    from pxr import Sdf, Tf

    try:
        layer = Sdf.Layer.FindOrOpen(identifier)
    except Tf.ErrorException as exc:
        message = " ".join(str(exc).split())
        raise MeshImportError(
            f"cannot read {identifier} as USD ({message}); check the file in usdview"
        ) from None
    if layer is None:
        raise MeshImportError(f"cannot read {identifier} as USD; check the file in usdview")
    return layer


def _layer_assets(layer: object) -> Iterator[tuple[str, str]]:
    """``(kind, asset path as written)`` of every file a layer names, without composing anything."""
    from pxr import UsdUtils

    sublayers, references, payloads = UsdUtils.ExtractExternalReferences(layer.identifier)  # type: ignore[attr-defined]
    for kind, assets in (("sublayer", sublayers), ("reference", references), ("payload", payloads)):
        for asset in assets:
            yield kind, str(asset)


def usd_layer_files(path: Path, *, check: FileCheck | None = None) -> list[Path]:
    """Every file a USD file brings in when opened, found layer by layer without composing a stage.

    Sublayers, references, payloads and value clips (and any asset path naming a USD layer) are
    followed recursively; each must be a regular file within :data:`MAX_MESH_BYTES` and pass
    ``check`` before it is opened. Asset paths of other files (textures) are not followed: the
    import never opens them. An asset path that resolves to nothing is skipped, as USD skips it.

    Parameters
    ----------
    path : Path
        A ``.usd``, ``.usda`` or ``.usdc`` file.
    check : callable, optional
        ``check(resolved_path, asset_path) -> str | None``: why a file may not be read (e.g.
        outside the allowed folders); None lets it be read.

    Returns
    -------
    list of Path
        The resolved files, ``path`` first, each once (the package file for a layer inside a
        ``.usdz``).

    Raises
    ------
    UsdDependencyError
        If a file brought in is not a regular file, is too big, or ``check`` refuses it; the
        message names the layer that names it and the asset path as written.
    MeshImportError
        If a layer cannot be parsed.
    """
    from pxr import Ar, Sdf

    root = Path(path).resolve()
    problem = file_problem(root)
    if problem is not None:
        raise MeshImportError(f"cannot read {path}: {problem}")
    resolver = Ar.GetResolver()
    files, queue, layers = [root], [str(root)], []
    seen = {str(root)}
    while queue:
        layer = _open_layer(queue.pop(0))
        layers.append(layer)  # keep each layer open until the walk is done (no re-reading)
        for kind, asset in _layer_assets(layer):
            identifier = resolver.CreateIdentifier(asset, layer.resolvedPath)  # type: ignore[attr-defined]
            if kind == "reference" and not Sdf.FileFormat.FindByExtension(
                Sdf.FileFormat.GetFileExtension(identifier)
            ):
                continue  # a texture or another non-layer asset: never opened
            resolved = str(resolver.Resolve(identifier))
            if not resolved or resolved in seen:
                continue
            seen.add(resolved)
            outer = (
                Ar.SplitPackageRelativePathOuter(resolved)[0]
                if Ar.IsPackageRelativePath(resolved)
                else resolved
            )
            file = Path(outer).resolve()
            problem = file_problem(file) or (check(file, asset) if check is not None else None)
            if problem is not None:
                raise UsdDependencyError(
                    f"{layer.realPath or layer.identifier}: {kind} @{asset}@ cannot be read: {problem}"  # type: ignore[attr-defined]
                )
            if file not in files:
                files.append(file)
            queue.append(resolved)
    return files
