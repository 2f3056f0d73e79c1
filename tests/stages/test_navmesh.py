"""The navmesh stage on shipped blockout scenes: files, presets, known answers, costs, errors."""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from navverse.nav import NavMeshError, PathFinder
from navverse.nav.scene_navmesh import load_scene_navmesh, read_navmesh_info
from navverse.scene.directory import SceneFiles, read_annotations
from pipeline.errors import RecipeError
from pipeline.recipes import RecipeLoader
from pipeline.stage import discover
from tests.stages.conftest import Built, build_all, workspace_with

RECIPES = [
    "scenes/blockout/step-ramp-course.yaml",
    "scenes/blockout/curb-street.yaml",
    "scenes/blockout/two-rooms.yaml",
]
WALLS_ONLY = """
    description: walls standing in the void, nothing to walk on
    stages:
      blockout:
        surfaces:
          - {name: wall_a, terrain: wall, center: [0.0, 0.0, 1.25], box: [6.0, 0.2, 2.5]}
          - {name: wall_b, terrain: wall, center: [0.0, 3.0, 1.25], box: [6.0, 0.2, 2.5]}
      navmesh: {}
"""


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Built:
    root = tmp_path_factory.mktemp("navmesh-stage")
    extra = {"scenes/walls-only.yaml": textwrap.dedent(WALLS_ONLY)}
    return build_all(workspace_with(root, RECIPES, extra))


def test_scene_directory_is_complete(built: Built):
    scene_dir = built.output("curb-street", "scene")
    files = SceneFiles(scene_dir)
    for path in (files.usd, files.annotations, files.bev, files.navmesh, files.navmesh_info):
        assert path.is_file(), path.name
    geometry = SceneFiles(built.output("curb-street", "geometry"))
    assert files.usd.read_bytes() == geometry.usd.read_bytes()
    info = read_navmesh_info(files.navmesh_info)
    annotations = read_annotations(scene_dir)
    assert annotations.statistics.navigable_area_m2 == pytest.approx(info.navigable_area_m2)
    assert read_annotations(geometry.root).statistics.navigable_area_m2 is None
    finder = load_scene_navmesh(scene_dir)
    assert finder.navigable_area == pytest.approx(info.navigable_area_m2)
    assert finder.settings == info.settings


def test_manifest_records_the_build(built: Built):
    stats = built.manifest("step-ramp-course", "scene")["stats"]
    for key in ("build_time_s", "polygons", "navigable_area_m2", "islands", "tiles", "preset"):
        assert key in stats, key
    assert stats["build_time_s"] > 0 and stats["polygons"] > 0
    info = read_navmesh_info(SceneFiles(built.output("step-ramp-course", "scene")).navmesh_info)
    assert stats["islands"] == info.islands and stats["polygons"] == info.polygons
    # navmesh.json holds no timing, so rebuilding gives the same bytes.
    assert "time" not in json.loads(info.model_dump_json())


@pytest.mark.parametrize(
    ("target", "preset", "cell"), [("step-ramp-course", "outdoor", 0.1), ("two-rooms", "indoor", 0.05)]
)
def test_preset_follows_the_scene_type(built: Built, target: str, preset: str, cell: float):
    info = read_navmesh_info(SceneFiles(built.output(target, "scene")).navmesh_info)
    assert info.preset == preset
    assert info.settings.cell_size == cell


def test_step_and_ramps_on_the_course(built: Built):
    finder = load_scene_navmesh(built.output("step-ramp-course", "scene"))
    start = [10.0, 6.0, 0.0]
    # The 0.25 m step (outdoor climb 0.30) and the 20 degree ramp are walkable...
    assert math.isfinite(finder.geodesic_distance(start, [4.0, 2.0, 0.25]))
    platform = [26.0, 7.4, 1.0]  # on the gentle ramp's platform, clear of its cone
    gentle = finder.geodesic_distance(start, platform)
    assert math.isfinite(gentle)
    assert gentle > math.hypot(math.dist(start[:2], platform[:2]), 1.0)  # around and up 1 m
    # ...the platform behind the 50 degree ramp is not (steeper than 45 degrees, higher than the climb).
    assert finder.geodesic_distance(start, [18.0, 2.5, 1.0]) == math.inf
    assert finder.is_navigable([18.0, 2.5 - 1.2, 1.0])  # its top is navmesh, just unreachable


def test_two_rooms_are_two_islands(built: Built):
    finder = load_scene_navmesh(built.output("two-rooms", "scene"))
    assert finder.num_islands == 2
    assert finder.geodesic_distance([2.5, 3.5, 0.0], [9.5, 3.5, 0.0]) == math.inf
    # Furniture is never walkable: the bed's top is not navmesh, the floor beside it is.
    assert not finder.is_navigable([1.2, 2.5, 0.5])


def _road_length(finder: PathFinder, start, end) -> tuple[float, float]:
    """(path length, horizontal length of it over the road strip |y| < 3.4) from start to end."""
    path = finder.find_path(start, end)
    on_road = 0.0
    for a, b in zip(path.points[:-1, :2], path.points[1:, :2], strict=True):
        t = np.linspace(0.0, 1.0, 1001)
        mid = a + np.outer((t[:-1] + t[1:]) / 2, b - a)  # midpoints of 1000 equal pieces
        on_road += float(np.mean(np.abs(mid[:, 1]) < 3.4)) * float(np.linalg.norm(b - a))
    return path.geodesic_distance, on_road


def test_area_costs_keep_paths_on_the_sidewalk(built: Built):
    scene_dir = built.output("curb-street", "scene")
    info = read_navmesh_info(SceneFiles(scene_dir).navmesh_info)
    assert info.area_costs == {"curb": 3.0, "road": 3.0}  # from the navmesh-outdoor preset
    finder = load_scene_navmesh(scene_dir)
    start, end = [2.0, -5.0, 0.0], [38.0, 2.0, -0.2]  # south sidewalk to the far end of the road
    costed_length, costed_road = _road_length(finder, start, end)
    finder.set_area_costs({})
    plain_length, plain_road = _road_length(finder, start, end)
    assert plain_length == pytest.approx(math.dist(start[:2], end[:2]), rel=0.02)  # nearly straight
    assert costed_length > plain_length + 0.5  # the detour along the sidewalk is longer...
    assert costed_road < 0.75 * plain_road  # ...and keeps off the road longer
    assert costed_road > 5.4  # the road is still crossed: the goal is on it


def test_bev_shows_the_navmesh(built: Built):
    def bluish(path: Path) -> int:
        rgb = np.asarray(Image.open(path).convert("RGB")).astype(int)
        return int(((rgb[..., 2] - rgb[..., 0]) > 30).sum())

    before = bluish(SceneFiles(built.output("curb-street", "geometry")).bev)
    after = bluish(SceneFiles(built.output("curb-street", "scene")).bev)
    assert after > before + 100_000  # ~680 m2 of navmesh at ~40 px per m2


def test_no_walkable_surface_fails_the_stage_with_a_clear_message(built: Built):
    failed = {node: result.error for node, result in built.report.failed.items()}
    assert list(failed) == ["walls-only:navmesh"]
    assert "no walkable surface" in failed["walls-only:navmesh"]
    assert "Traceback" not in failed["walls-only:navmesh"]
    assert built.store.target_output("walls-only", "scene") is None


def test_geometry_without_navmesh_is_a_clear_error(built: Built):
    with pytest.raises(NavMeshError, match="add the navmesh stage"):
        load_scene_navmesh(built.output("two-rooms", "geometry"))


@pytest.mark.parametrize(
    ("section", "message"),
    [
        ("{area_costs: {sidwalk: 2.0}}", "unknown terrain class 'sidwalk'"),
        ("{area_costs: {wall: 2.0}}", "never walkable"),
        ("{area_costs: {road: 0.5}}", "greater than or equal to 1"),
        ("{excluded_classes: [ceiling]}", "never walkable"),
        ("{settings: {cell_size: -0.1}}", "greater than or equal to 0.01"),
        ("{settings: {cell_size: 1e308}}", "less than or equal to 2"),
        ("{settings: {voxel_size: 0.1}}", "unknown key 'voxel_size'"),
        ("{preset: attic}", "unknown navmesh preset 'attic' (known: auto, indoor, outdoor, i2o)"),
    ],
)
def test_recipe_mistakes_are_reported_with_their_line(tmp_path: Path, section: str, message: str):
    recipe = (
        "stages:\n"
        "  blockout:\n"
        "    surfaces: [{name: floor, terrain: floor, center: [0, 0, 0], box: [4, 4, 0.1]}]\n"
        f"  navmesh: {section}\n"
    )
    workspace = workspace_with(tmp_path, [], {"scenes/bad.yaml": recipe})
    with pytest.raises(RecipeError) as caught:
        RecipeLoader(workspace, stages=discover("stages")).load()
    text = str(caught.value)
    assert message in text, text
    assert "scenes/bad.yaml:4: stages.navmesh." in text, text
