"""The decimate stage: cleans and simplifies a scene's meshes, and measures what that does to its navmesh."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

from navverse.scene.simplify import DecimateSettings
from pipeline import Params, StageContext, stage

if TYPE_CHECKING:
    from navverse.nav import NavMeshSettings
    from navverse.scene.geometry import Scene


class DecimateParams(Params, DecimateSettings):
    """Parameters of :func:`decimate`: those of :class:`navverse.scene.simplify.DecimateSettings` (a
    ``ratio`` of faces kept, a ``target_faces`` budget or neither: only cleaning; ``min_faces``,
    ``merge_tolerance``, ``method``), and ``measure_navmesh``.
    """

    measure_navmesh: bool = True
    """Build the navmesh (the preset of the scene's type) of the scene before and after decimation, and
    record both build times (s), the speed-up and both navigable areas (m²) in the manifest."""


def _navmesh_figures(
    ctx: StageContext, scene: Scene, settings: NavMeshSettings
) -> tuple[float, float] | None:
    """(build seconds, navigable m^2) of the scene's navmesh, or None if it has none."""
    from navverse.nav import NavMeshError
    from navverse.nav.scene_navmesh import build_scene_navmesh

    started = time.perf_counter()
    try:
        finder = build_scene_navmesh(scene, settings)
    except NavMeshError as exc:
        ctx.log.warning("no navmesh to compare: %s", exc)
        return None
    return time.perf_counter() - started, float(finder.navigable_area)


@stage(
    name="decimate",
    inputs=["raw_geometry"],
    outputs=["geometry"],
    summary={"faces before": "faces_before", "faces after": "faces_after"},
)
def decimate(ctx: StageContext, params: DecimateParams) -> None:
    """The scene directory with every surface and object mesh cleaned and simplified, colours kept."""
    from navverse.nav import NavMeshSettings
    from navverse.scene.directory import read_scene, write_scene_dir
    from navverse.scene.simplify import decimate_scene
    from navverse.scene_types import scene_profile

    source = read_scene(ctx.input("raw_geometry"))
    scene, report = decimate_scene(source, settings=DecimateSettings.of(params), progress=ctx.progress)
    write_scene_dir(scene, ctx.output)
    removed = 1.0 - report.faces_after / report.faces_before if report.faces_before else 0.0
    ctx.record(
        faces_before=report.faces_before,
        faces_cleaned=report.faces_cleaned,
        faces_after=report.faces_after,
        removed_fraction=round(removed, 4),
        vertices_before=report.vertices_before,
        vertices_after=report.vertices_after,
        ratio=round(report.ratio, 6),
    )
    ctx.log.info(
        "decimate %s: %d -> %d faces (%.1f %% removed)",
        ctx.target, report.faces_before, report.faces_after, 100 * removed,
    )  # fmt: skip
    if not params.measure_navmesh:
        return

    preset = scene_profile(scene.annotations.scene_type).navmesh_preset
    settings = NavMeshSettings.preset(preset)
    before = _navmesh_figures(ctx, source, settings)
    after = _navmesh_figures(ctx, scene, settings)
    if before is None or after is None:
        return
    change = (after[1] - before[1]) / before[1] if before[1] > 0 else 0.0
    ctx.record(
        navmesh_preset=preset,
        navmesh_build_s_before=round(before[0], 4),
        navmesh_build_s_after=round(after[0], 4),
        navmesh_speedup=round(before[0] / after[0], 3) if after[0] > 0 else None,
        navigable_area_m2_before=round(before[1], 3),
        navigable_area_m2_after=round(after[1], 3),
        navigable_area_change=round(change, 5),
    )
    ctx.log.info(
        "navmesh (%s preset): built in %.2f s -> %.2f s, navigable %.1f m2 -> %.1f m2 (%+.2f %%)",
        preset, before[0], after[0], before[1], after[1], 100 * change,
    )  # fmt: skip
