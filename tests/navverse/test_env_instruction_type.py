"""PlaceNav instruction types in the environment and in what an agent is told (AgentTask)."""

from __future__ import annotations

from pathlib import Path

import pytest

from navverse.dataset import INSTRUCTION_TYPES, Episode
from navverse.env import EnvError, NavVerseEnv, episode_goal
from navverse.eval.agent_workers import task_for
from navverse.sim.actions import DISCRETE_ACTIONS
from tests.navverse.test_env import TABLE_CENTER, build_room, episode

TEXTS = {
    "category": "Find a bank.",
    "route": "Walk past the chair, then turn left at the table and stop by the bank.",
    "intention": "I need to withdraw some cash.",
}
GOAL = {"object_id": 1, "category": "bank", "position": list(TABLE_CENTER), "radius": 0.6,
        "size": [1.2, 0.8, 0.75]}  # fmt: skip


def _instructions() -> dict[str, dict]:
    return {
        kind: {"instruction_text": text, "template_text": text, "instruction_type": kind}
        for kind, text in TEXTS.items()
    }


def placenav(*, instructions: bool = True) -> dict:
    """A hand-made PlaceNav episode in the room, with the three instructions (or none)."""
    ep = episode(
        episode_id="room-placenav-0",
        task="placenav",
        object_category=None,
        place_category="bank",
        goals=[GOAL],
    )
    if instructions:
        ep["instructions"] = _instructions()
    return ep


def _dataset_episode(data: dict, *, task: str | None = None) -> Episode:
    """The episode as the dataset holds it (scene type, info)."""
    info = {"geodesic_distance": 4.0, "euclidean_distance": 4.0, "closest_goal_object_id": 1,
            "success_distance": 1.6}  # fmt: skip
    return Episode.model_validate(
        {**data, "scene_type": "i2o", "info": info, **({"task": task} if task else {})}
    )


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_room(tmp_path_factory.mktemp("env_room_it"))


@pytest.fixture(scope="module")
def cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("coacd_it")


@pytest.mark.parametrize("kind", INSTRUCTION_TYPES)
def test_the_goal_is_the_instruction_of_the_type(scene_dir: Path, cache: Path, kind: str):
    env = NavVerseEnv(scene_dir, collision_cache=cache, sensors=(), instruction_type=kind)
    try:
        obs, info = env.reset(seed=0, options={"episode": placenav()})
        assert obs["goal"] == TEXTS[kind]
        assert info["instruction_type"] == kind
        _, _, terminated, _, info = env.step(DISCRETE_ACTIONS.index("stop"))
        assert terminated and info["submission"]["instruction_type"] == kind
        assert info["submission"]["episode_id"] == "room-placenav-0"
        # Without instructions (a format 1.0 episode) the goal is the place category, and says so.
        obs, info = env.reset(seed=0, options={"episode": placenav(instructions=False)})
        assert obs["goal"] == "bank" and info["instruction_type"] == "category"
        # Other tasks are as before: no instruction type anywhere.
        obs, info = env.reset(seed=0, options={"episode": episode()})
        assert obs["goal"] == "table" and "instruction_type" not in info
        _, _, _, _, info = env.step(DISCRETE_ACTIONS.index("stop"))
        assert "instruction_type" not in info["submission"]
    finally:
        env.close()


def test_an_unknown_instruction_type_is_refused(scene_dir: Path, cache: Path):
    with pytest.raises(
        EnvError, match="unknown instruction type 'vln'; choose from: category, route, intention"
    ):
        NavVerseEnv(scene_dir, collision_cache=cache, sensors=(), instruction_type="vln")


def test_episode_goal():
    assert episode_goal(placenav(), "intention") == (TEXTS["intention"], "intention")
    assert episode_goal(placenav(instructions=False), "route") == ("bank", "category")
    vln = episode(task="vln", instruction={"instruction_text": "Go to the table.", "template_text": "",
                                           "instruction_type": "refined"})  # fmt: skip
    assert episode_goal(vln, "route") == ("Go to the table.", None)
    assert episode_goal(episode(), "intention") == ("table", None)
    partial = placenav()
    del partial["instructions"]["route"]
    with pytest.raises(EnvError, match=r"no 'route' instruction \(its instructions: category, intention\)"):
        episode_goal(partial, "route")
    with pytest.raises(EnvError, match="choose from: category, route, intention"):
        episode_goal(placenav(), "store")


def _task(data: dict, kind: str, *, privileged: bool, task: str | None = None):
    episode = _dataset_episode(data, task=task)
    return task_for(episode, embodiment="spot", radius=0.6, categories={1: "bank"}, seed=3,
                    scene_dir=Path("scene"), instruction_type=kind, privileged=privileged)  # fmt: skip


@pytest.mark.parametrize("kind", ["route", "intention"])
def test_an_agent_that_is_not_privileged_is_not_told_the_category(kind: str):
    task = _task(placenav(), kind, privileged=False)
    assert task.goal == TEXTS[kind] and task.goal_category == "" and task.instruction_type == kind
    oracle = _task(placenav(), kind, privileged=True)
    assert oracle.goal == TEXTS[kind] and oracle.goal_category == "bank" and oracle.instruction_type == kind


def test_under_category_and_for_other_tasks_the_category_is_told():
    task = _task(placenav(), "category", privileged=False)
    assert (task.goal, task.goal_category, task.instruction_type) == ("Find a bank.", "bank", "category")
    bare = _task(placenav(instructions=False), "route", privileged=False)
    assert (bare.goal, bare.goal_category, bare.instruction_type) == ("bank", "bank", "category")
    objnav = _task(episode(), "route", privileged=False)
    assert (objnav.goal, objnav.goal_category, objnav.instruction_type) == ("table", "table", None)
