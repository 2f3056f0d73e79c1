"""The decimate stage: dense meshes lose most faces but keep shape, colours and navmesh; cleanup only."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from navverse.scene.directory import SceneFiles, read_annotations, read_scene
from navverse.scene.geometry import MeshData, Scene
from navverse.scene.simplify import (
    SimplifyError,
    budget_ratio,
    clean_mesh,
    decimate_mesh,
    merge_vertices,
    triangle_areas,
)
from pipeline.errors import RecipeError
from pipeline.recipes import RecipeLoader
from pipeline.stage import discover
from tests.stages.conftest import Built, build_all, workspace_with

RED, BLUE = (255, 0, 0), (0, 0, 255)
SIZE, CELLS = 12.0, 60  # the terrain: 12 m x 12 m, 60 x 60 quads


def _usd_mesh(name: str, vertices: np.ndarray, polygons, colors: np.ndarray | None) -> str:
    points = ", ".join(f"({x:.9g}, {y:.9g}, {z:.9g})" for x, y, z in vertices)
    counts = ", ".join(str(len(p)) for p in polygons)
    indices = ", ".join(str(int(i)) for p in polygons for i in p)
    text = (
        f'    def Mesh "{name}"\n    {{\n'
        f"        int[] faceVertexCounts = [{counts}]\n"
        f"        int[] faceVertexIndices = [{indices}]\n"
        f"        point3f[] points = [{points}]\n"
    )
    if colors is not None:
        values = ", ".join(f"({r / 255:g}, {g / 255:g}, {b / 255:g})" for r, g, b in colors)
        text += f'        color3f[] primvars:displayColor = [{values}] (interpolation = "uniform")\n'
    return text + "    }\n"


def terrain_usda() -> str:
    """A z-up, metric USD stage: a bumpy 12 m terrain (red west half, blue east half, one mesh) and a
    ball (a dense sphere, 0.5 m radius) on it."""
    steps = np.linspace(0.0, SIZE, CELLS + 1)
    x, y = np.meshgrid(steps, steps, indexing="xy")
    z = 0.3 * np.sin(x / 2.0) * np.cos(y / 3.0)
    vertices = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    row = CELLS + 1
    quads = np.array(
        [
            [j * row + i, j * row + i + 1, (j + 1) * row + i + 1, (j + 1) * row + i]
            for j in range(CELLS)
            for i in range(CELLS)
        ]
    )
    colors = np.array(
        [RED if (i + 0.5) * SIZE / CELLS < SIZE / 2 else BLUE for _ in range(CELLS) for i in range(CELLS)]
    )
    ball = trimesh.creation.icosphere(subdivisions=3, radius=0.5)
    return (
        '#usda 1.0\n(\n    upAxis = "Z"\n    metersPerUnit = 1\n)\n\ndef Xform "Site"\n{\n'
        + _usd_mesh("terrain", vertices, quads, colors)
        + _usd_mesh("ball", ball.vertices + np.array([3.0, 3.0, 1.0]), ball.faces, None)
        + "}\n"
    )


def seams_usda() -> str:
    """Two 5 m floor quads whose shared edge is doubled 50 um apart, and a 30 um triangle."""
    e = 5e-5
    vertices = np.array(
        [[0, 0, 0], [5, 0, 0], [5, 5, 0], [0, 5, 0], [5 + e, 0, 0], [10, 0, 0], [10, 5, 0], [5 + e, 5, 0],
         [2, 2, 0], [2 + 3 * e / 5, 2, 0], [2, 2 + 3 * e / 5, 0]]
    )  # fmt: skip
    polygons = [[0, 1, 2, 3], [4, 5, 6, 7], [8, 9, 10]]
    return '#usda 1.0\n(\n    upAxis = "Z"\n    metersPerUnit = 1\n)\n\n' + _usd_mesh(
        "floor", vertices, polygons, None
    )


IMPORT = """\
stages:
  import_mesh:
    source: {source}
    rules:
      - {{pattern: ball, object: ball}}
    default: floor
    subdivide: {subdivide}
  decimate: {decimate}
"""


def _recipe(decimate: str, *, source: str = "site.usda", subdivide: int = 1, navmesh: bool = False) -> str:
    text = IMPORT.format(source=source, subdivide=subdivide, decimate=decimate)
    return text + ("  navmesh: {}\n" if navmesh else "")


RECIPES = {
    "dense": _recipe("{ratio: 0.1}", navmesh=True),
    "dense-fast": _recipe("{ratio: 0.1, method: fast, measure_navmesh: false}"),
    "dense-budget": _recipe("{target_faces: 5000, measure_navmesh: false}"),
    "dense-keep": _recipe("{ratio: 1.0, measure_navmesh: false}"),
    "seams": _recipe("{}", source="seams.usda", subdivide=0),
    "over-budget": _recipe("{target_faces: 10, min_faces: 100000, measure_navmesh: false}"),
}


def _workspace(root: Path, names: list[str]):
    extra = {f"scenes/{name}.yaml": RECIPES[name] for name in names}
    workspace = workspace_with(root, [], extra)
    (workspace.recipes_dir / "scenes").mkdir(exist_ok=True)
    (workspace.recipes_dir / "scenes" / "site.usda").write_text(terrain_usda())
    (workspace.recipes_dir / "scenes" / "seams.usda").write_text(seams_usda())
    return workspace


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Built:
    return build_all(_workspace(tmp_path_factory.mktemp("decimate"), list(RECIPES)))


def raw_and_decimated(built: Built, target: str) -> tuple[Scene, Scene]:
    return read_scene(built.output(target, "raw_geometry")), read_scene(built.output(target, "geometry"))


def area(mesh: MeshData) -> float:
    return float(triangle_areas(mesh.vertices, mesh.faces).sum())


def faces(scene: Scene) -> int:
    return sum(s.mesh.num_faces for s in scene.surfaces) + sum(o.mesh.num_faces for o in scene.objects)


# ---------------------------------------------------------------------------------------- dense


def test_dense_meshes_lose_most_faces_and_keep_their_shape(built: Built):
    raw, out = raw_and_decimated(built, "dense")
    assert faces(raw) == 4 * (2 * CELLS * CELLS + 1280)
    assert faces(out) <= 0.2 * faces(raw)
    (terrain_before,), (terrain_after,) = raw.surfaces, out.surfaces
    assert area(terrain_after.mesh) == pytest.approx(area(terrain_before.mesh), rel=0.01)
    np.testing.assert_allclose(terrain_after.mesh.bounds(), terrain_before.mesh.bounds(), atol=0.01)
    (ball_before,), (ball_after,) = raw.objects, out.objects
    assert ball_after.annotation == ball_before.annotation  # simplified in its own frame
    assert area(ball_after.mesh) == pytest.approx(area(ball_before.mesh), rel=0.03)
    np.testing.assert_allclose(ball_after.mesh.bounds(), ball_before.mesh.bounds(), atol=0.02)
    sphere = trimesh.Trimesh(ball_after.mesh.vertices, ball_after.mesh.faces, process=False)
    assert sphere.is_watertight and sphere.volume > 0  # still closed, still outward


def test_colours_stay_on_their_side(built: Built):
    mesh = read_scene(built.output("dense", "geometry")).surfaces[0].mesh
    assert mesh.face_colors is not None
    colors = {tuple(int(c) for c in row) for row in np.unique(mesh.face_colors, axis=0)}
    assert colors == {RED, BLUE}
    centroid_x = mesh.vertices[mesh.faces].mean(axis=1)[:, 0]
    red = (mesh.face_colors == RED).all(axis=1)
    assert centroid_x[red].max() <= SIZE / 2 + 1e-6 and centroid_x[~red].min() >= SIZE / 2 - 1e-6
    areas = triangle_areas(mesh.vertices, mesh.faces)
    assert areas[red].sum() == pytest.approx(areas[~red].sum(), rel=0.02)


def test_manifest_records_faces_and_the_navmesh_before_and_after(built: Built):
    stats = built.manifest("dense", "geometry")["stats"]
    for key in (
        "faces_before", "faces_after", "removed_fraction", "navmesh_build_s_before", "navmesh_build_s_after",
        "navigable_area_m2_before", "navigable_area_m2_after", "navigable_area_change",
    ):  # fmt: skip
        assert key in stats, key
    assert stats["removed_fraction"] >= 0.8
    assert stats["removed_fraction"] == pytest.approx(
        1 - stats["faces_after"] / stats["faces_before"], abs=1e-4
    )
    assert stats["navmesh_build_s_before"] > 0 and stats["navmesh_build_s_after"] > 0
    assert stats["navigable_area_m2_before"] > 50
    assert abs(stats["navigable_area_change"]) <= 0.03
    annotations = read_annotations(built.output("dense", "geometry"))
    assert annotations.statistics.faces == stats["faces_after"]
    # The navmesh stage reads the decimated geometry and gets the same area as measured.
    scene_stats = built.manifest("dense", "scene")["stats"]
    assert scene_stats["navigable_area_m2"] == pytest.approx(stats["navigable_area_m2_after"], abs=1e-2)
    # Timings go in the manifest only.
    assert "time" not in SceneFiles(built.output("dense", "geometry")).annotations.read_text()


def test_fast_method_and_face_budget(built: Built):
    raw, fast = raw_and_decimated(built, "dense-fast")
    assert faces(fast) <= 0.3 * faces(raw)  # fewer collapses: its borders are pinned
    outline_fast, outline_raw = (
        np.array(fast.surfaces[0].mesh.bounds()),
        np.array(raw.surfaces[0].mesh.bounds()),
    )
    np.testing.assert_allclose(outline_fast[:, :2], outline_raw[:, :2], atol=1e-6)  # borders pinned
    np.testing.assert_allclose(outline_fast, outline_raw, atol=0.01)
    assert area(fast.surfaces[0].mesh) == pytest.approx(area(raw.surfaces[0].mesh), rel=0.01)
    stats = built.manifest("dense-budget", "geometry")["stats"]
    assert stats["faces_after"] == pytest.approx(5000, rel=0.05)
    assert "navmesh_build_s_before" not in stats  # measure_navmesh: false


def test_ratio_one_only_cleans(built: Built):
    raw, kept = raw_and_decimated(built, "dense-keep")
    for before, after in zip(raw.surfaces + raw.objects, kept.surfaces + kept.objects, strict=True):
        np.testing.assert_array_equal(after.mesh.vertices, before.mesh.vertices)
        np.testing.assert_array_equal(after.mesh.faces, before.mesh.faces)
    stats = built.manifest("dense-keep", "geometry")["stats"]
    assert stats["faces_after"] == stats["faces_before"] and stats["removed_fraction"] == 0.0


def test_cleanup_merges_near_vertices_and_drops_degenerate_faces(built: Built):
    raw, out = raw_and_decimated(built, "seams")
    (before,), (after,) = raw.surfaces, out.surfaces
    assert (before.mesh.num_vertices, before.mesh.num_faces) == (11, 5)
    assert (after.mesh.num_vertices, after.mesh.num_faces) == (6, 4)  # seam closed, speck gone
    assert area(after.mesh) == pytest.approx(50.0, rel=1e-4)
    stats = built.manifest("seams", "geometry")["stats"]
    assert (stats["faces_before"], stats["faces_after"]) == (5, 4)


def test_same_inputs_give_the_same_bytes(built: Built, tmp_path: Path):
    again = build_all(_workspace(tmp_path, ["dense"]))
    first, second = (
        SceneFiles(built.output("dense", "geometry")),
        SceneFiles(again.output("dense", "geometry")),
    )
    for name in ("usd", "annotations", "bev"):
        assert getattr(first, name).read_bytes() == getattr(second, name).read_bytes(), name


# --------------------------------------------------------------------------------------- errors


def test_an_impossible_budget_fails_the_stage_with_a_clear_message(built: Built):
    failed = {node: result.error for node, result in built.report.failed.items()}
    assert list(failed) == ["over-budget:decimate"]
    assert failed["over-budget:decimate"].startswith("SimplifyError: target_faces 10 cannot be met")
    assert "raise target_faces or lower min_faces" in failed["over-budget:decimate"]


@pytest.mark.parametrize(
    ("section", "message"),
    [
        ("{ratio: 0.5, target_faces: 100}", "either 'ratio' or 'target_faces'"),
        ("{ratio: 0}", "greater than 0"),
        ("{ratio: 1.5}", "less than or equal to 1"),
        ("{target_faces: 0}", "greater than or equal to 1"),
        ("{method: magic}", "'open3d' or 'fast'"),
        ("{merge_tolerance: -1}", "greater than or equal to 0"),
        ("{ratio: 0.5, keep_uvs: true}", "unknown key 'keep_uvs'"),
    ],
)
def test_recipe_mistakes_are_reported_with_their_line(tmp_path: Path, section: str, message: str):
    workspace = _workspace(tmp_path, [])
    (workspace.recipes_dir / "scenes" / "bad.yaml").write_text(_recipe(section))
    with pytest.raises(RecipeError) as caught:
        RecipeLoader(workspace, stages=discover("stages")).load()
    text = str(caught.value)
    assert message in text, text
    assert "scenes/bad.yaml:8: stages.decimate" in text, text


# ------------------------------------------------------------------------------------- helpers


def test_merge_vertices_joins_chains_and_keeps_first_positions():
    points = np.array(
        [[0, 0, 0], [1, 0, 0], [0, 0, 0], [1.00004, 0, 0], [1.00008, 0, 0], [3, 0, 0]], dtype=float
    )
    merged, index = merge_vertices(points, tolerance=5e-5)
    np.testing.assert_array_equal(merged, [[0, 0, 0], [1, 0, 0], [3, 0, 0]])
    np.testing.assert_array_equal(index, [0, 1, 0, 1, 1, 2])
    exact, exact_index = merge_vertices(points)
    assert len(exact) == 5 and exact_index[2] == 0


def test_clean_mesh_drops_repeats_but_keeps_two_sided_sheets():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)
    faces = np.array(
        [[0, 1, 2], [1, 2, 0], [0, 2, 1], [0, 0, 1]]
    )  # a rotated repeat, the reverse, a degenerate
    colors = np.array([[1, 1, 1], [2, 2, 2], [3, 3, 3], [4, 4, 4]], dtype=np.uint8)
    cleaned = clean_mesh(MeshData(vertices, faces, colors))
    np.testing.assert_array_equal(cleaned.faces, [[0, 1, 2], [0, 2, 1]])
    np.testing.assert_array_equal(cleaned.face_colors[:, 0], [1, 3])


def test_budget_ratio_keeps_small_groups_whole():
    sphere = trimesh.creation.icosphere(subdivisions=3)  # 1280 faces
    large = MeshData(sphere.vertices, sphere.faces)
    small = MeshData.box((1, 1, 1))  # 12 faces, under min_faces
    assert budget_ratio([large, small], 652, min_faces=64) == pytest.approx(0.5)
    assert budget_ratio([large, small], 5000, min_faces=64) == 1.0
    with pytest.raises(SimplifyError, match="raise target_faces or lower min_faces"):
        budget_ratio([large, small], 12, min_faces=64)


def test_decimate_mesh_without_colours():
    sphere = trimesh.creation.icosphere(subdivisions=4)  # 5120 faces
    out = decimate_mesh(MeshData(sphere.vertices, sphere.faces), 0.1, min_faces=64, method="open3d")
    assert out.face_colors is None
    assert out.num_faces == pytest.approx(512, rel=0.05)
    assert area(out) == pytest.approx(sphere.area, rel=0.03)
    with pytest.raises(ValueError, match="ratio"):
        decimate_mesh(MeshData(sphere.vertices, sphere.faces), 0.0, min_faces=64, method="open3d")
