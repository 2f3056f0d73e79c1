"""The scene directory: the files a built scene consists of, and reading/writing them.

A scene directory ``<scene_id>/`` holds :data:`SCENE_USD` (geometry, labels, physics),
:data:`SCENE_JSON` (annotations) and :data:`BEV_PNG` (a bird's-eye-view picture); the navmesh stage
adds :data:`NAVMESH_BIN` (the navmesh) and :data:`NAVMESH_JSON` (its settings, area types and
statistics). A scene with textured meshes also has :data:`TEXTURES_DIR` ``/<name>.png``, the images
the USD file refers to (written by :func:`~navverse.scene.usd.export_usd`). File names are defined
here and nowhere else.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path

from navverse.errors import SceneError
from navverse.scene.annotations import SceneAnnotations, load_annotations, save_annotations
from navverse.scene.geometry import Scene
from navverse.scene.naming import TEXTURES_DIR

__all__ = [
    "BEV_PNG",
    "NAVMESH_BIN",
    "NAVMESH_JSON",
    "SCENE_JSON",
    "SCENE_USD",
    "TEXTURES_DIR",
    "SceneFiles",
    "read_annotations",
    "read_scene",
    "scene_hash",
    "write_scene_dir",
]

SCENE_USD = "scene.usdc"
SCENE_JSON = "scene.json"
BEV_PNG = "bev.png"
NAVMESH_BIN = "navmesh.bin"
NAVMESH_JSON = "navmesh.json"


@dataclass(frozen=True)
class SceneFiles:
    """Paths of the files in one scene directory."""

    root: Path

    @property
    def usd(self) -> Path:
        """The canonical USD scene."""
        return self.root / SCENE_USD

    @property
    def annotations(self) -> Path:
        """The annotations, ``scene.json``."""
        return self.root / SCENE_JSON

    @property
    def bev(self) -> Path:
        """The bird's-eye-view picture."""
        return self.root / BEV_PNG

    @property
    def textures(self) -> Path:
        """The directory of the texture images (absent in a scene without textures)."""
        return self.root / TEXTURES_DIR

    @property
    def navmesh(self) -> Path:
        """The navigation mesh, written by the navmesh stage."""
        return self.root / NAVMESH_BIN

    @property
    def navmesh_info(self) -> Path:
        """The navmesh's settings, area types and statistics (JSON), written by the navmesh stage."""
        return self.root / NAVMESH_JSON


def write_scene_dir(scene: Scene, out_dir: Path, *, bev: bool = True) -> SceneFiles:
    """Write a scene's USD file, annotations and (optionally) its BEV picture.

    Parameters
    ----------
    scene : Scene
        The scene to write.
    out_dir : Path
        An existing directory; existing files of the same names are replaced. Making the whole
        directory appear atomically is the caller's job.
    bev : bool
        Whether to render ``bev.png``.

    Returns
    -------
    SceneFiles
        The paths of the scene directory.

    Raises
    ------
    SceneError
        If `out_dir` does not exist.
    """
    from navverse.scene.bev import render_bev  # here: reading a scene's files loads no renderer
    from navverse.scene.usd import export_usd

    files = SceneFiles(Path(out_dir))
    if not files.root.is_dir():
        raise SceneError(f"scene output directory {files.root} does not exist; create it before writing")
    export_usd(scene, files.usd)
    save_annotations(scene.annotations, files.annotations)
    if bev:
        render_bev(scene, files.bev)
    return files


def _require(path: Path, scene_dir: Path) -> None:
    if not scene_dir.is_dir():
        raise SceneError(
            f"scene directory {scene_dir} does not exist; build it with `navverse build {scene_dir.name}`"
        )
    if not path.is_file():
        raise SceneError(
            f"scene directory {scene_dir} has no {path.name} (incomplete or outdated build); "
            f"build it with `navverse build {scene_dir.name}`"
        )


def read_annotations(scene_dir: Path) -> SceneAnnotations:
    """Read a scene directory's ``scene.json``.

    Raises
    ------
    SceneError
        If the directory or the file is missing or the file is invalid.
    """
    files = SceneFiles(Path(scene_dir))
    _require(files.annotations, files.root)
    return load_annotations(files.annotations)


def read_scene(scene_dir: Path) -> Scene:
    """Load a complete scene (annotations and geometry) from its directory.

    Raises
    ------
    SceneError
        If the directory or a file is missing, invalid, or the files disagree.
    """
    from navverse.scene.usd import scene_from_usd  # here: reading annotations needs no USD

    files = SceneFiles(Path(scene_dir))
    annotations = read_annotations(files.root)
    _require(files.usd, files.root)
    return scene_from_usd(files.usd, annotations)


def scene_hash(scene_dir: str | Path) -> str:
    """SHA-256 over a built scene directory's ``scene.json``, ``navmesh.bin``, ``scene.usdc`` and
    texture images (``textures/*.png``, in name order): the ``scene_hashes`` of a dataset manifest. A
    scene without textures hashes as it did before scenes had them."""
    root = Path(scene_dir)
    texture_dir = root / TEXTURES_DIR
    # Hidden names are temporary files of interrupted writes (navverse.files), not textures.
    textures = sorted(t.name for t in texture_dir.glob("*.png") if not t.name.startswith("."))
    names = [SCENE_JSON, NAVMESH_BIN, SCENE_USD, *(f"{TEXTURES_DIR}/{t}" for t in textures)]
    digest = hashlib.sha256()
    for name in names:
        file = root / name
        if file.is_file():
            digest.update(name.encode())
            digest.update(file.read_bytes())
    return digest.hexdigest()
