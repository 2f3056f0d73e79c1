"""The navmesh stage: completes a scene directory with its navigation mesh."""

from __future__ import annotations

import time
from typing import Annotated

from pydantic import AfterValidator, Field

from navverse.files import link_or_copy
from navverse.nav.settings import NavMeshOverrides
from navverse.scene.terrain import known_terrain_class
from pipeline import Params, StageContext, stage


def _navigable_class(name: str) -> str:
    from navverse.scene.terrain import DEFAULT_TERRAIN_CLASSES

    known_terrain_class(name)
    if not DEFAULT_TERRAIN_CLASSES[name].navigable:
        raise ValueError(f"terrain class {name!r} is never walkable; name a navigable class")
    return name


TerrainName = Annotated[str, AfterValidator(_navigable_class)]


def _known_preset(name: str) -> str:
    from navverse.nav.settings import PRESETS

    if name != "auto" and name not in PRESETS:
        raise ValueError(f"unknown navmesh preset {name!r} (known: auto, {', '.join(PRESETS)})")
    return name


class NavmeshParams(Params):
    """Parameters of :func:`navmesh`: the settings (a preset, single fields replaced) and how path
    queries treat terrain classes. Classes a scene does not have are ignored, so one recipe section can
    serve many scenes.
    """

    preset: Annotated[str, AfterValidator(_known_preset)] = "auto"
    """The navmesh settings to start from: ``auto`` (the preset of the scene type's profile,
    :mod:`navverse.scene_types`) or a preset of :data:`navverse.nav.PRESETS` (``indoor``, ``outdoor``,
    ``i2o``)."""
    settings: NavMeshOverrides = Field(default_factory=NavMeshOverrides)
    """Single fields of the navmesh settings replacing the preset's (cell size, agent radius...);
    fields left out keep the preset's value."""
    area_costs: dict[TerrainName, Annotated[float, Field(ge=1.0, le=1000.0)]] = {}
    """Path cost per meter by navigable terrain class (other classes cost 1 per meter): path queries
    go round a costly class where the detour costs less than crossing it."""
    excluded_classes: list[TerrainName] = []
    """Navigable terrain classes that path queries never enter."""


@stage(
    name="navmesh",
    inputs=["geometry"],
    outputs=["scene"],
    summary={
        "navigable m2": "navigable_area_m2",
        "islands": "islands",
        "largest island m2": "largest_island_m2",
        "polygons": "polygons",
        "preset": "preset",
    },
)
def navmesh(ctx: StageContext, params: NavmeshParams) -> None:
    """The complete scene directory: geometry files, navmesh.bin, navmesh.json, bev.png with the navmesh.

    Tiles whose input an earlier build already had (same triangles, settings and place) are taken
    from the tile store under the cache folder (:mod:`navverse.nav.tiles`), with the same bytes.
    """
    from navverse.nav import NavMeshSettings
    from navverse.nav.scene_navmesh import (
        build_scene_navmesh,
        describe_navmesh,
        navmesh_overlay,
        scene_settings,
        write_navmesh_info,
    )
    from navverse.nav.tiles import default_tile_store
    from navverse.scene.annotations import save_annotations
    from navverse.scene.bev import render_bev
    from navverse.scene.directory import SceneFiles, read_scene
    from navverse.scene.geometry import Scene
    from navverse.scene_types import scene_profile

    source = SceneFiles(ctx.inputs["geometry"])
    files = SceneFiles(ctx.outputs["scene"])
    scene = read_scene(source.root)
    annotations = scene.annotations
    preset = (
        scene_profile(annotations.scene_type).navmesh_preset if params.preset == "auto" else params.preset
    )
    settings = scene_settings(NavMeshSettings.preset(preset).with_overrides(params.settings), annotations)

    ctx.progress(0, 3, "navmesh")
    started = time.perf_counter()
    tiles = default_tile_store()
    finder = build_scene_navmesh(
        scene,
        settings,
        area_costs=params.area_costs,
        excluded_classes=params.excluded_classes,
        tile_store=tiles,
    )
    build_seconds = time.perf_counter() - started
    ctx.progress(1, 3, "navmesh")

    info = describe_navmesh(finder, annotations, preset=preset)
    statistics = annotations.statistics.model_copy(update={"navigable_area_m2": info.navigable_area_m2})
    annotations = annotations.model_copy(update={"statistics": statistics})
    link_or_copy(source.usd, files.usd)
    if source.textures.is_dir():  # the images a textured scene.usdc names beside it
        files.textures.mkdir(exist_ok=True)
        for image in sorted(source.textures.glob("*.png")):
            link_or_copy(image, files.textures / image.name)
    save_annotations(annotations, files.annotations)
    finder.save(files.navmesh)
    write_navmesh_info(info, files.navmesh_info)
    ctx.progress(2, 3, "navmesh")
    scene = Scene(annotations=annotations, surfaces=scene.surfaces, objects=scene.objects)
    render_bev(scene, files.bev, overlays=[navmesh_overlay(finder)])
    ctx.progress(3, 3, "navmesh")

    ctx.record(
        preset=preset,
        build_time_s=round(build_seconds, 4),
        tiles=info.tiles,
        polygons=info.polygons,
        navigable_area_m2=round(info.navigable_area_m2, 3),
        islands=info.islands,
        largest_island_m2=round(info.island_areas_m2[0], 3) if info.island_areas_m2 else 0.0,
    )
    ctx.log.info(
        "navmesh %s (%s preset): %d polygons in %d tiles, %.1f m2 navigable, %d islands, built in %.2f s "
        "(of the grid's %d tiles, %d taken from the tile store %s, %d built)",
        ctx.target, preset, info.polygons, info.tiles, info.navigable_area_m2, info.islands, build_seconds,
        tiles.last_use.tiles, tiles.last_use.reused, tiles.root, tiles.last_use.built,
    )  # fmt: skip
