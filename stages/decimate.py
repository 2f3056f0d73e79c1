"""The decimate stage: cleans and simplifies a scene's meshes, and measures what that does to its navmesh."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Annotated, Literal

from pydantic import Field, model_validator

from pipeline import Params, StageContext, stage

if TYPE_CHECKING:
    from navverse.nav import NavMeshSettings
    from navverse.scene import Scene


class DecimateParams(Params):
    """Parameters of :func:`decimate`.

    Give ``ratio`` (the fraction of faces to keep in every mesh) or ``target_faces`` (a budget for
    the whole scene, shared in proportion to the meshes' faces), or neither: then the meshes are
    only cleaned (vertices within ``merge_tolerance`` meters merged, degenerate and repeated
    triangles dropped), which is cheap for light procedural scenes. Meshes (and colour groups of a
    mesh) under ``min_faces`` faces are never simplified; each colour group is simplified alone, so
    colours stay where they were. ``method``: ``open3d`` (Open3D's quadric decimation with boundary
    quadrics: floor outlines keep their place) or ``fast`` (fast-simplification with border vertices
    pinned: about twice as fast, fewer faces removed on meshes with long open borders).
    ``measure_navmesh`` builds the navmesh (preset of the scene type) before and after and records
    build times and navigable areas in the manifest.
    """

    ratio: (
        Annotated[float, Field(gt=0.0, le=1.0, description="Fraction kept, more than 0, at most 1.")] | None
    ) = None
    target_faces: Annotated[int, Field(ge=1, le=100_000_000, description="Faces, 1 to 1e8.")] | None = None
    min_faces: Annotated[int, Field(ge=4, le=10_000_000, description="Faces, 4 to 1e7.")] = 64
    merge_tolerance: Annotated[float, Field(ge=0.0, le=0.1, description="Meters, 0 to 0.1.")] = 1e-4
    method: Literal["open3d", "fast"] = "open3d"
    measure_navmesh: bool = True

    @model_validator(mode="after")
    def _one_budget(self) -> DecimateParams:
        if self.ratio is not None and self.target_faces is not None:
            raise ValueError("give either 'ratio' or 'target_faces', not both")
        return self


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


@stage(name="decimate", inputs=["raw_geometry"], outputs=["geometry"])
def decimate(ctx: StageContext, params: DecimateParams) -> None:
    """The scene directory with every surface and object mesh cleaned and simplified, colours kept."""
    from navverse.nav import NavMeshSettings
    from navverse.scene import read_scene, write_scene_dir
    from navverse.scene.simplify import decimate_scene
    from navverse.scene_types import scene_profile

    source = read_scene(ctx.input("raw_geometry"))
    scene, report = decimate_scene(
        source,
        ratio=params.ratio,
        target_faces=params.target_faces,
        min_faces=params.min_faces,
        tolerance=params.merge_tolerance,
        method=params.method,
        progress=ctx.progress,
    )
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
