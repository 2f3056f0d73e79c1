"""A scene's look on disk: ``look.json`` (settings and map details), found beside a built scene.

The ``look`` stage writes a look directory per scene (DESIGN.md §3): ``look.json``, ``look.usdc`` over
the scene's ``scene.usdc`` and ``textures/look/*.png``. ``look.json`` holds what the renderer needs
beyond the scene: the look's settings (the evaluation look unless the scene's recipe says otherwise)
and the city map's building types and levels, roads and crossings (for facades and markings), so a
scene pack or a store renders the same without the map. :func:`load_scene_look` compiles a scene's
look from it, or from the defaults where a scene has no look directory.
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Sequence
from pathlib import Path

from pydantic import ValidationError

from navverse.errors import SceneError
from navverse.files import atomic_write, cached_file_sha256
from navverse.look.markings import MarkedRoad
from navverse.look.scene_look import CROSSING_MARKINGS, MapDetails, SceneLook, scene_look
from navverse.look.settings import EVAL_LOOK, LOOK_VERSION, LookSettings
from navverse.scene.geometry import Scene

__all__ = [
    "LOOK_FORMAT",
    "LOOK_JSON",
    "find_look",
    "load_scene_look",
    "look_files",
    "read_look",
    "write_look",
]

LOOK_JSON = "look.json"
"""The file of a look directory that says what the look is."""
LOOK_FORMAT = "1.1"
"""Format version of ``look.json`` (1.1 added the map's ``crossings``; a 1.0 file reads without them)."""


def write_look(
    path: Path, settings: LookSettings, details: MapDetails | None, *, geometry_sha256: str
) -> None:
    """Write ``look.json`` atomically.

    Its keys: ``format_version``, ``look_version`` (:data:`~navverse.look.settings.LOOK_VERSION`),
    ``geometry_sha256`` (of the ``scene.usdc`` the look was made for), ``settings`` (every field of
    :class:`LookSettings`) and ``map`` (null for scenes not made from a map, else ``buildings`` {scene
    building id: [map type or null, levels or null]}, ``roads`` [{centerline, width, lanes, oneway,
    highway}] and ``crossings`` [[x, y, markings]]).
    """
    data = {
        "format_version": LOOK_FORMAT,
        "look_version": LOOK_VERSION,
        "geometry_sha256": geometry_sha256,
        "settings": settings.model_dump(mode="json"),
        "map": None
        if details is None
        else {
            "buildings": {str(k): list(v) for k, v in sorted(details.buildings.items())},
            "roads": [
                {
                    "centerline": [list(p) for p in road.centerline],
                    "width": road.width,
                    "lanes": road.lanes,
                    "oneway": road.oneway,
                    "highway": road.highway,
                }
                for road in details.roads
            ],
            "crossings": [[x, y, markings] for x, y, markings in details.crossings],
        },
    }
    with atomic_write(path, mode="w") as handle:
        handle.write(json.dumps(data, indent=1, sort_keys=True) + "\n")


def read_look(path: Path) -> tuple[LookSettings, MapDetails | None]:
    """The settings and map details of a ``look.json`` (:func:`look_geometry` tells its geometry).

    Raises
    ------
    SceneError
        If the file is unreadable, of another major format, or malformed (naming what to do).
    """
    rebuild = f"rebuild the scene's look with `navverse build` (or delete {path})"
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        major = str(data["format_version"]).split(".")[0]
        if major != LOOK_FORMAT.split(".")[0]:
            raise SceneError(f"{path}: look format {data['format_version']} is not {LOOK_FORMAT}; {rebuild}")
        settings = LookSettings.model_validate(data["settings"])
        mapped = data["map"]
        if mapped is None:
            return settings, None
        buildings = {int(k): (v[0], v[1]) for k, v in mapped["buildings"].items()}
        roads = [
            MarkedRoad(
                tuple((float(x), float(y)) for x, y in r["centerline"]),
                float(r["width"]),
                None if r["lanes"] is None else int(r["lanes"]),
                bool(r["oneway"]),
                str(r["highway"]),
            )
            for r in mapped["roads"]
        ]
        crossings = [(float(x), float(y), _markings(m)) for x, y, m in mapped.get("crossings", [])]
        return settings, MapDetails(buildings=buildings, roads=roads, crossings=crossings)
    except SceneError:
        raise
    except (OSError, ValueError, KeyError, TypeError, IndexError, ValidationError) as exc:
        raise SceneError(f"{path}: not a readable look ({type(exc).__name__}: {exc}); {rebuild}") from None


def _markings(value: object) -> str:
    """A crossing's markings as ``look.json`` gives them (ValueError: not one of them)."""
    if value not in CROSSING_MARKINGS:
        raise ValueError(f"unknown crossing markings {value!r}")
    return str(value)


def look_geometry(path: Path) -> str | None:
    """The sha256 of the ``scene.usdc`` a ``look.json`` was made for (None if it does not say or is
    unreadable)."""
    try:
        value = json.loads(path.read_text(encoding="utf-8")).get("geometry_sha256")
    except (OSError, ValueError, AttributeError):
        return None
    return value if isinstance(value, str) else None


def find_look(scene_dir: Path) -> Path | None:
    """The ``look.json`` of a built scene, or None if it has none.

    Looked for in the scene's own folder (a scene pack), then in its target's ``look`` output: beside
    its ``scene`` output when `scene_dir` is ``targets/<scene_id>/scene``, or, when it is a committed
    artifact (``<store>/artifacts/...``), in ``<store>/targets/<scene_id>/look``.
    """
    root = Path(scene_dir)
    candidates = [root / LOOK_JSON, root.parent / "look" / LOOK_JSON]
    resolved = root.resolve()
    for parent in resolved.parents:
        if parent.name == "artifacts" and (parent.parent / "targets").is_dir():
            try:
                scene_id = json.loads((root / "scene.json").read_text(encoding="utf-8"))["scene_id"]
            except (OSError, ValueError, KeyError, TypeError):
                break
            candidates.append(parent.parent / "targets" / str(scene_id) / "look" / LOOK_JSON)
            break
    return next((c for c in candidates if c.is_file()), None)


def look_files(scene_dir: Path) -> dict[str, Path]:
    """The files of a scene's look directory by their name in a scene folder (``look.json``,
    ``look.usdc``, ``textures/look/<name>.png``): what a scene pack copies beside the scene's files."""
    from navverse.look.usd_look import LOOK_TEXTURES, LOOK_USD

    found = find_look(scene_dir)
    if found is None:
        return {}
    root = found.parent
    names = [LOOK_JSON, LOOK_USD]
    images = root / LOOK_TEXTURES
    if images.is_dir():  # hidden names are temporary files of interrupted writes
        names += [
            f"{LOOK_TEXTURES}/{p.name}" for p in sorted(images.glob("*.png")) if not p.name.startswith(".")
        ]
    return {name: root / name for name in names if (root / name).is_file()}


def load_scene_look(
    scene: Scene,
    scene_dir: Path | None,
    *,
    settings: LookSettings | None = None,
    hidden_classes: Sequence[str] = (),
) -> SceneLook:
    """Compile the look of a built scene.

    Parameters
    ----------
    scene : Scene
        The scene, read from `scene_dir`.
    scene_dir : Path or None
        Its directory; its look directory (:func:`find_look`) gives the settings and map details.
    settings : LookSettings, optional
        Settings to use instead of the look directory's (which default to the evaluation look).
    hidden_classes : sequence of str
        Terrain classes the renderer leaves out.
    """
    found = find_look(scene_dir) if scene_dir is not None else None
    made_for = look_geometry(found) if found is not None else None
    if made_for is not None and made_for != cached_file_sha256(Path(scene_dir) / "scene.usdc"):
        warnings.warn(
            f"{found} was made for another build of scene {scene.scene_id}: using the evaluation look "
            f"without its map details; rebuild the look with `navverse build {scene.scene_id}`",
            stacklevel=2,
        )
        found = None
    stored, details = read_look(found) if found is not None else (EVAL_LOOK, None)
    return scene_look(scene, settings or stored, hidden_classes=hidden_classes, details=details)
