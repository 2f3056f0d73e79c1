"""A scene's navmesh: terrain classes become Recast area types; build, describe, draw and load it.

Every navigable terrain class of a scene gets its own area type, numbered 1, 2, ... in the order of
``scene.json``'s ``terrain_classes``; non-navigable classes (walls, buildings, water, ceilings) and
every object get area type 0, so their tops (roofs, table tops) are never walkable but they still
block. Area costs and excluded classes are named by terrain class and turned into Detour area
costs and exclusions, so a path can prefer sidewalks and floors over roads.

The scene directory holds the navmesh as ``navmesh.bin`` (:meth:`PathFinder.save`, with the
settings and costs) and describes it in ``navmesh.json`` (:class:`NavMeshInfo`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Collection, Mapping
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from navverse.files import atomic_write
from navverse.nav.errors import NavMeshError
from navverse.nav.pathfinder import MAX_AREA_TYPE, PathFinder, build
from navverse.nav.settings import NavMeshSettings
from navverse.nav.tiles import TileStore
from navverse.scene.annotations import SceneAnnotations
from navverse.scene.bev import BevOverlay
from navverse.scene.directory import SceneFiles
from navverse.scene.geometry import Scene
from navverse.scene_types import scene_profile

__all__ = [
    "NAVMESH_INFO_VERSION",
    "NavMeshInfo",
    "build_scene_navmesh",
    "describe_navmesh",
    "load_scene_navmesh",
    "navmesh_overlay",
    "read_navmesh_info",
    "scene_area_types",
    "scene_settings",
    "write_navmesh_info",
]

NAVMESH_INFO_VERSION = "1.0"
NAVMESH_COLOR = "#1e88ff"


def scene_area_types(annotations: SceneAnnotations) -> dict[str, int]:
    """Area type of every terrain class of a scene: 1, 2, ... for navigable classes, 0 otherwise.

    Raises
    ------
    NavMeshError
        If the scene has more navigable classes than Detour has area types.
    """
    areas: dict[str, int] = {}
    next_area = 1
    for name, terrain_class in annotations.terrain_classes.items():
        if terrain_class.navigable:
            areas[name] = next_area
            next_area += 1
        else:
            areas[name] = 0
    if next_area - 1 > MAX_AREA_TYPE:
        raise NavMeshError(
            f"scene {annotations.scene_id!r} has {next_area - 1} navigable terrain classes; "
            f"a navmesh holds at most {MAX_AREA_TYPE}"
        )
    return areas


def _named_areas(
    what: str, names: Collection[str], areas: Mapping[str, int], annotations: SceneAnnotations
) -> dict[str, int]:
    """Area types of the classes in ``names`` that the scene has; non-navigable ones are refused."""
    chosen: dict[str, int] = {}
    for name in names:
        if name not in areas:
            continue  # a class the scene does not use: nothing to weigh
        if areas[name] == 0:
            raise NavMeshError(
                f"{what} names terrain class {name!r}, which is not navigable in scene "
                f"{annotations.scene_id!r}; name only navigable classes "
                f"({', '.join(n for n, a in areas.items() if a) or 'none'})"
            )
        chosen[name] = areas[name]
    return chosen


def scene_settings(settings: NavMeshSettings, annotations: SceneAnnotations) -> NavMeshSettings:
    """The build settings for one scene: ``settings`` with a fine region where the scene asks for one.

    A scene whose type's profile has a ``fine_margin_m`` (indoor-to-outdoor scenes), built with
    settings that have a ``fine_factor`` above 1 and no ``fine_region`` of their own, gets as fine
    region the bounding rectangle of its indoor buildings' footprints grown by that margin, clipped
    to the scene's bounds. Any other case returns ``settings`` unchanged.
    """
    margin = scene_profile(annotations.scene_type).fine_margin_m
    polygons = annotations.indoor_polygons
    if margin is None or settings.fine_factor <= 1 or settings.fine_region is not None or not polygons:
        return settings
    points = np.array([p for polygon in polygons for p in polygon], dtype=np.float64)
    (x0, y0, _), (x1, y1, _) = annotations.bounds.min, annotations.bounds.max
    lo = np.maximum(points.min(axis=0) - margin, (x0, y0))
    hi = np.minimum(points.max(axis=0) + margin, (x1, y1))
    if (hi <= lo).any():
        return settings
    return settings.with_overrides({"fine_region": (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))})


def build_scene_navmesh(
    scene: Scene,
    settings: NavMeshSettings,
    *,
    area_costs: Mapping[str, float] | None = None,
    excluded_classes: Collection[str] = (),
    jobs: int | None = None,
    tile_store: TileStore | None = None,
) -> PathFinder:
    """Build the navmesh of a scene, with terrain classes as area types.

    Parameters
    ----------
    scene : Scene
        The scene; all its surfaces and objects are obstacles, navigable classes are walkable.
    settings : NavMeshSettings
        Build settings (the preset of the scene's type: :mod:`navverse.scene_types`).
    area_costs : mapping of str to float, optional
        Path cost per meter by terrain class (>= 1.0; others cost 1.0). Classes the scene does not
        have are ignored, so one mapping can serve many scenes.
    excluded_classes : collection of str
        Terrain classes path queries never enter (absent ones are ignored).
    jobs : int, optional
        Tiles built at once (threads); default: the number of CPUs.
    tile_store : TileStore, optional
        Finished tiles to reuse and to add to (:mod:`navverse.nav.tiles`); the navmesh is the same.

    Returns
    -------
    PathFinder
        With the costs and exclusions set (they are saved with it).

    Raises
    ------
    NavMeshError
        When nothing is walkable, or costs/exclusions name a non-navigable class.
    """
    annotations = scene.annotations
    areas = scene_area_types(annotations)
    labeled = scene.world_mesh(include_objects=True)
    class_area = np.array([areas[name] for name in labeled.class_names] or [0], dtype=np.uint8)
    face_area = np.where(labeled.class_index >= 0, class_area[np.clip(labeled.class_index, 0, None)], 0)
    face_area = face_area.astype(np.uint8)
    if not face_area.any():
        raise NavMeshError(
            f"scene {annotations.scene_id!r} has no walkable surface: none of its terrain classes "
            f"({', '.join(annotations.terrain_classes) or 'none'}) is navigable"
        )
    try:
        finder = build(
            labeled.mesh.vertices,
            labeled.mesh.faces,
            settings,
            area_types=face_area,
            jobs=jobs,
            tile_store=tile_store,
        )
    except NavMeshError as exc:
        raise NavMeshError(f"scene {annotations.scene_id!r}: {exc}") from None
    costs = _named_areas("area_costs", list(area_costs or {}), areas, annotations)
    finder.set_area_costs({area: float((area_costs or {})[name]) for name, area in costs.items()})
    finder.set_excluded_areas(_named_areas("excluded_classes", excluded_classes, areas, annotations).values())
    finder.name_areas(areas)
    return finder


class NavMeshInfo(BaseModel):
    """Contents of ``navmesh.json``: how a scene's navmesh was built and what it holds."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    format_version: Literal["1.0"] = NAVMESH_INFO_VERSION
    preset: str
    settings: NavMeshSettings
    area_types: dict[str, Annotated[int, Field(ge=0, le=MAX_AREA_TYPE)]]
    area_costs: dict[str, float] = Field(default_factory=dict)
    excluded_classes: list[str] = Field(default_factory=list)
    tiles: Annotated[int, Field(ge=0)]
    polygons: Annotated[int, Field(ge=0)]
    navigable_area_m2: Annotated[float, Field(ge=0)]
    islands: Annotated[int, Field(ge=0)]
    island_areas_m2: list[float]
    bounds: tuple[tuple[float, float, float], tuple[float, float, float]]


def describe_navmesh(finder: PathFinder, annotations: SceneAnnotations, *, preset: str) -> NavMeshInfo:
    """The :class:`NavMeshInfo` of a scene's navmesh (area names come from the scene's classes)."""
    areas = scene_area_types(annotations)
    by_area = {area: name for name, area in areas.items() if area}
    lo, hi = np.asarray(finder.bounds, dtype=float)
    return NavMeshInfo(
        preset=preset,
        settings=finder.settings,
        area_types=areas,
        area_costs={by_area[a]: c for a, c in sorted(finder.area_costs.items()) if a in by_area},
        excluded_classes=sorted(by_area[a] for a in finder.excluded_areas if a in by_area),
        tiles=finder.num_tiles,
        polygons=finder.num_polygons,
        navigable_area_m2=finder.navigable_area,
        islands=finder.num_islands,
        island_areas_m2=[float(a) for a in finder.island_areas],
        bounds=(tuple(float(v) for v in lo), tuple(float(v) for v in hi)),
    )


def write_navmesh_info(info: NavMeshInfo, path: Path) -> None:
    """Write ``navmesh.json`` (sorted keys, so the same navmesh gives the same bytes)."""
    text = json.dumps(info.model_dump(mode="json"), indent=2, sort_keys=True) + "\n"
    with atomic_write(path) as handle:
        handle.write(text.encode("utf-8"))


def read_navmesh_info(path: Path) -> NavMeshInfo:
    """Read ``navmesh.json``.

    Raises
    ------
    NavMeshError
        If the file is missing, not JSON, or of another format.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        return NavMeshInfo.model_validate(data)
    except OSError as exc:
        raise NavMeshError(f"cannot read {path}: {exc.strerror or exc}") from None
    except (json.JSONDecodeError, ValidationError) as exc:
        raise NavMeshError(f"{path} is not a valid navmesh description ({exc}): rebuild the scene") from None


def navmesh_overlay(finder: PathFinder, *, label: str = "navmesh") -> BevOverlay:
    """A BEV overlay of a navmesh: its polygons filled, its outline drawn."""
    polygons = [p[:, :2] for p in finder.polygons()]
    outline = finder.boundary_edges()[:, :, :2]
    return BevOverlay(label, outline, color=NAVMESH_COLOR, linewidth=0.8, polygons=polygons, fill_alpha=0.4)


def load_scene_navmesh(scene_dir: str | os.PathLike[str]) -> PathFinder:
    """The navmesh of a built scene directory.

    Raises
    ------
    NavMeshError
        If the directory has no ``navmesh.bin`` (the scene was built without its navmesh stage) or
        the file cannot be read.
    """
    files = SceneFiles(Path(scene_dir))
    if not files.navmesh.is_file():
        raise NavMeshError(
            f"scene directory {files.root} has no {files.navmesh.name}: add the navmesh stage to the "
            "scene's recipe (`navmesh: {}` under `stages`) and build it"
        )
    finder = PathFinder.load(files.navmesh)
    if files.navmesh_info.is_file():  # its areas are the scene's terrain classes: costs can be set by name
        finder.name_areas(read_navmesh_info(files.navmesh_info).area_types)
    return finder
