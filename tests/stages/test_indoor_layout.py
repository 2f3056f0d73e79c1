"""The indoor_layout stage through the engine: a complete scene, deterministic, validated recipes."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest

from navverse.nav.scene_navmesh import load_scene_navmesh, read_navmesh_info
from navverse.scene.directory import SceneFiles, read_annotations
from pipeline.errors import RecipeError
from pipeline.recipes import RecipeLoader
from pipeline.stage import discover
from tests.stages.conftest import Built, build_all, workspace_with

RECIPE = "scenes/indoor/cafe.yaml"


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Built:
    return build_all(workspace_with(tmp_path_factory.mktemp("indoor"), [RECIPE]))


def test_builds_a_complete_scene(built: Built):
    assert built.report.ok, built.report.failed
    scene_dir = built.output("cafe-s0", "scene")
    files = SceneFiles(scene_dir)
    for path in (files.usd, files.annotations, files.bev, files.navmesh, files.navmesh_info):
        assert path.is_file(), path.name
    ann = read_annotations(scene_dir)
    assert ann.scene_type == "indoor" and ann.rooms and ann.exits
    assert len(ann.objects) >= 20 and len(ann.statistics.objects_per_category) >= 10
    info = read_navmesh_info(files.navmesh_info)
    assert info.preset == "indoor" and info.island_areas_m2[0] >= 0.95 * info.navigable_area_m2
    finder = load_scene_navmesh(scene_dir)
    for ex in ann.exits:
        assert finder.island_of([ex.center[0], ex.center[1], 0.0]) == finder.largest_island
    stats = built.manifest("cafe-s0", "raw_geometry")["stats"]
    assert stats["building_type"] == "cafe" and stats["objects"] == len(ann.objects)


def test_same_recipe_and_seed_give_the_same_bytes(built: Built, tmp_path: Path):
    again = build_all(workspace_with(tmp_path, [RECIPE]), only={"cafe-s0"})  # one seed built again
    assert again.report.ok, again.report.failed
    for artifact in ("raw_geometry", "geometry", "scene"):
        first, second = (SceneFiles(b.output("cafe-s0", artifact)) for b in (built, again))
        assert _digest(first.annotations) == _digest(second.annotations), artifact
        assert _digest(first.usd) == _digest(second.usd), artifact
    a = json.loads(SceneFiles(built.output("cafe-s0", "scene")).annotations.read_text())
    b = json.loads(SceneFiles(built.output("cafe-s1", "scene")).annotations.read_text())
    assert a["buildings"] != b["buildings"] or a["objects"] != b["objects"]


@pytest.mark.parametrize(
    ("section", "message"),
    [
        ("{building_type: castle}", "'apartment', 'office', 'grocery'"),
        ("{building_type: cafe, exclude_categories: [unicorn]}", "unknown object category 'unicorn'"),
        (
            "{building_type: cafe, extra_furniture: [{room_type: cafe_kitchen, category: harp}]}",
            "unknown object category 'harp'",
        ),
        (
            "{building_type: cafe, extra_furniture: [{room_type: ballroom, category: piano}]}",
            "a cafe has no room type 'ballroom'",
        ),
        ("{building_type: cafe, density: 0}", "greater than 0"),
        (
            "{building_type: cafe, category_rules: [{pattern: '(', category: x}]}",
            "invalid regular expression",
        ),
    ],
)
def test_recipe_mistakes_fail_validation(tmp_path: Path, section: str, message: str):
    recipe = f"stages:\n  indoor_layout: {section}\n  decimate: {{}}\n  navmesh: {{}}\n"
    workspace = workspace_with(tmp_path, [], {"scenes/bad.yaml": recipe})
    with pytest.raises(RecipeError) as caught:
        RecipeLoader(workspace, stages=discover("stages")).load()
    text = str(caught.value)
    assert message in text and "scenes/bad.yaml:2: stages.indoor_layout" in text, text
