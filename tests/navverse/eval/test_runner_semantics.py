"""What ``run-agent`` tells an agent of the semantic channel: a storefront is its place category (as in
the habitat export), only for agents that use the semantic sensor or are privileged."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from navverse import nav
from navverse.dataset import Episode
from navverse.eval.runner import run_agent
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.scene.directory import SceneFiles, write_scene_dir
from navverse.scene.semantics import STOREFRONT_ID_BASE
from tests.navverse.eval.toy_dataset import write_toy_dataset
from tests.navverse.scene.conftest import OBJECTS, build_scene

RECORDER = '''
import json


class SemanticRecorder:
    """Writes the semantic categories it is given, then stops at once."""

    action_mode = "discrete"
    privileged = {privileged}
    sensors = {sensors}

    def reset(self, task):
        with open("{out}", "w") as f:
            json.dump({{str(k): v for k, v in task.semantic_categories.items()}}, f)

    def act(self, observation, info):
        return 0
'''


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The tiny i2o scene (a room, a road and a cafe storefront with no object of its own), built."""
    root = tmp_path_factory.mktemp("tiny_room")
    scene = build_scene()
    write_scene_dir(scene, root, bev=False)
    build_scene_navmesh(scene, nav.INDOOR, jobs=1).save(SceneFiles(root).navmesh)
    return root


def _placenav() -> Episode:
    entrance = (5.0, -1.0, 0.0)
    return Episode.model_validate({
        "episode_id": "tiny_room-placenav-0000", "scene_id": "tiny_room", "scene_type": "i2o",
        "task": "placenav", "start_position": [8.0, 2.0, 0.0], "start_rotation": [0.0, 0.0, 0.0, 1.0],
        "place_category": "cafe",
        "goals": [{"object_id": 1, "category": "cafe", "position": list(entrance), "radius": 1.0,
                   "size": [3.0, 0.2, 2.5]}],
        "reference_path": [[8.0, 2.0, 0.0], [5.0, 0.5, 0.0], list(entrance)],
        "info": {"geodesic_distance": 4.0, "euclidean_distance": 4.0, "closest_goal_object_id": 1,
                 "success_distance": 1.6},
    })  # fmt: skip


@pytest.mark.parametrize(
    ("sensors", "privileged", "told"),
    [(("depth", "semantic"), False, True), (("rgb", "depth"), True, True), (("rgb", "depth"), False, False)],
    ids=["semantic-sensor", "privileged", "standard"],
)
def test_the_runner_names_a_storefront_by_its_place_category(
    scene_dir: Path, tmp_path: Path, sensors: tuple[str, ...], privileged: bool, told: bool
):
    dataset = write_toy_dataset(tmp_path / "dataset", [_placenav()])
    seen = tmp_path / "categories.json"
    agent_file = tmp_path / "recorder.py"
    agent_file.write_text(RECORDER.format(privileged=privileged, sensors=sensors, out=seen))
    summary = run_agent(dataset, agent=f"{agent_file}:SemanticRecorder", split="eval", embodiment="spot",
                        scene_dirs={"tiny_room": scene_dir}, out=tmp_path / "run.jsonl", jobs=0)  # fmt: skip
    assert summary.episodes == 1
    categories = json.loads(seen.read_text())
    if not told:
        assert categories == {}
        return
    assert categories[str(STOREFRONT_ID_BASE + 1)] == "cafe"  # not "storefront"
    assert "storefront" not in categories.values()
    assert {categories[str(obj_id)] for obj_id, *_ in OBJECTS} == {"chair", "table"}
