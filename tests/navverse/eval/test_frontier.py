"""The frontier agent in the real environment: its map, goal detection, stopping, whole episodes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from navverse import nav
from navverse.dataset import Goal, goal_distance
from navverse.env import NavVerseEnv
from navverse.eval.agents.base import Agent, AgentTask
from navverse.eval.agents.frontier import (
    FORWARD,
    ROTATE_LEFT,
    ROTATE_RIGHT,
    SMALL_LEFT,
    STOP,
    FrontierAgent,
    heading_action,
)
from navverse.eval.agents.grid_planning import grid_dijkstra, trace_path
from navverse.eval.agents.mapping import FREE, OCCUPIED, UNKNOWN, back_project, estimate_floor
from navverse.indoor import generate_building
from navverse.nav.scene_navmesh import build_scene_navmesh
from navverse.scene.directory import SceneFiles, write_scene_dir
from navverse.scene.geometry import Scene
from navverse.sim.camera import CameraIntrinsics, look_at
from tests.scenes import box_part, box_room, scene_of

# A closed room x in [-2, 4], y in [-3, 3] (wall faces), 2.6 m high, with a chair and a table.
ROOM_X, ROOM_Y, ROOM_H, WALL = (-2.0, 4.0), (-3.0, 3.0), 2.6, 0.2
CHAIR = ("chair", (2.0, 0.6, 0.5), (0.4, 0.4, 1.0))
TABLE = ("table", (2.5, -1.8, 0.375), (1.0, 0.6, 0.75))
SPOT_RADIUS = 0.6


def room_scene() -> Scene:
    """The room, its walls as boxes outside the faces, and two box-shaped objects."""
    objects = [box_part(c, p, s) for c, p, s in (CHAIR, TABLE)]
    return scene_of(box_room(ROOM_X, ROOM_Y, ROOM_H, WALL), objects, scene_id="frontier_room")


def footprints() -> list[tuple[float, float, float, float]]:
    """Every solid of the room seen from above, as ``(xmin, xmax, ymin, ymax)``."""
    (x0, x1), (y0, y1), t = ROOM_X, ROOM_Y, WALL
    walls = [
        (x1, x1 + t, y0 - t, y1 + t),
        (x0 - t, x0, y0 - t, y1 + t),
        (x0, x1, y1, y1 + t),
        (x0, x1, y0 - t, y0),
    ]
    objects = [
        (p[0] - s[0] / 2, p[0] + s[0] / 2, p[1] - s[1] / 2, p[1] + s[1] / 2) for _, p, s in (CHAIR, TABLE)
    ]
    return walls + objects


def distance_to_rect(xy: np.ndarray, rect: tuple[float, float, float, float]) -> np.ndarray:
    """Horizontal distance of points ``(N, 2)`` to a rectangle (0 inside)."""
    dx = np.maximum(np.maximum(rect[0] - xy[:, 0], xy[:, 0] - rect[1]), 0.0)
    dy = np.maximum(np.maximum(rect[2] - xy[:, 1], xy[:, 1] - rect[3]), 0.0)
    return np.hypot(dx, dy)


def write_scene(scene: Scene, root: Path) -> Path:
    write_scene_dir(scene, root, bev=False)
    build_scene_navmesh(scene, nav.INDOOR, jobs=1).save(SceneFiles(root).navmesh)
    return root


def episode(scene_id: str, start: tuple[float, float], yaw: float, category: str) -> dict:
    return {
        "episode_id": f"{scene_id}-objnav-0000",
        "scene_id": scene_id,
        "task": "objnav",
        "start_position": [start[0], start[1], 0.0],
        "start_rotation": [0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)],
        "object_category": category,
    }


def task_for(scene: Scene, category: str, *, seed: int = 0) -> AgentTask:
    return AgentTask(
        episode_id="test",
        task="objnav",
        goal=category,
        goal_category=category,
        scene_type="indoor",
        embodiment="spot",
        robot_radius=SPOT_RADIUS,
        semantic_categories={o.id: o.category for o in scene.annotations.objects},
        seed=seed,
    )


def run_episode(env: NavVerseEnv, agent: FrontierAgent, ep: dict, *, max_steps: int = 400):
    """Run the agent until the episode ends; returns the actions, the last observation and info."""
    obs, info = env.reset(options={"episode": ep})
    actions = []
    for _ in range(max_steps):
        action = agent.act(obs, info)
        actions.append(action)
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    return actions, obs, info


def record(env: NavVerseEnv, agent: FrontierAgent, ep: dict, steps: int):
    """The first ``steps`` (observation, info, action) triples of an episode."""
    obs, info = env.reset(options={"episode": ep})
    rows = []
    for _ in range(steps):
        action = agent.act(obs, info)
        rows.append((obs, info, action))
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    return rows


def nearest_goal_distance(scene: Scene, category: str, position: np.ndarray) -> float:
    goals = [
        Goal(object_id=o.id, category=o.category, position=o.center, radius=o.goal_radius, size=o.size)
        for o in scene.annotations.objects
        if o.category == category
    ]
    return min(goal_distance(position, g) for g in goals)


# ---------------------------------------------------------------------------------------------- fixtures


@pytest.fixture(scope="module")
def room() -> Scene:
    return room_scene()


@pytest.fixture(scope="module")
def room_env(room: Scene, tmp_path_factory: pytest.TempPathFactory):
    scene_dir = write_scene(room, tmp_path_factory.mktemp("frontier_room"))
    env = NavVerseEnv(scene_dir, embodiment="spot", action_mode="discrete", privileged=False,
                      collision_cache=tmp_path_factory.mktemp("coacd_room"))  # fmt: skip
    yield env
    env.close()


@pytest.fixture(scope="module")
def apartment(tmp_path_factory: pytest.TempPathFactory) -> tuple[Scene, Path]:
    scene = generate_building("apartment", np.random.default_rng(0), scene_id="apartment-s0")
    return scene, write_scene(scene, tmp_path_factory.mktemp("apartment-s0"))


@pytest.fixture(scope="module")
def apartment_env(apartment: tuple[Scene, Path], tmp_path_factory: pytest.TempPathFactory):
    env = NavVerseEnv(apartment[1], embodiment="spot", action_mode="discrete", privileged=False,
                      collision_cache=tmp_path_factory.mktemp("coacd_apartment"))  # fmt: skip
    yield env
    env.close()


@pytest.fixture(scope="module")
def first_view(room: Scene, room_env: NavVerseEnv) -> FrontierAgent:
    """An agent after one observation from (0, 0), facing the chair (ahead, left) and the east wall."""
    agent = FrontierAgent()
    agent.reset(task_for(room, "chair"))
    obs, info = room_env.reset(options={"episode": episode("frontier_room", (0.0, 0.0), 0.0, "chair")})
    agent.act(obs, info)
    return agent


# ---------------------------------------------------------------------------------------------- helpers


def test_back_project_inverts_the_projection():
    k = CameraIntrinsics.from_hfov(64, 48, 90.0)
    pose = look_at((1.0, 2.0, 0.6), (4.0, 3.0, 0.2))
    depth = np.full((48, 64), 2.5)
    depth[0, :] = 0.0  # no hit
    points, valid = back_project(depth[..., None], k.matrix(), pose, stride=2)
    assert points.shape == (24, 32, 3) and not valid[0].any() and valid[1:].all()
    local = (points[valid] - pose[:3, 3]) @ pose[:3, :3]  # back into the optical frame
    np.testing.assert_allclose(local[:, 2], 2.5, atol=1e-9)
    uv = k.project(local)
    rows, cols = np.nonzero(valid)
    np.testing.assert_allclose(uv, np.stack([cols * 2 + 0.5, rows * 2 + 0.5], -1), atol=1e-9)


def test_floor_is_the_lowest_well_populated_band():
    rng = np.random.default_rng(3)
    heights = np.concatenate(
        [
            rng.normal(0.20, 0.002, 400),  # the floor
            rng.normal(0.65, 0.002, 900),  # a bigger table top
            rng.uniform(0.0, 0.8, 300),  # walls
            [0.05, 0.07],  # a little noise below the floor
        ]
    )
    assert estimate_floor(heights, below=0.7) == pytest.approx(0.20, abs=0.01)
    assert estimate_floor(heights[:10], below=0.7) is None


def test_grid_dijkstra_finds_the_way_through_a_gap():
    costs = np.ones((20, 20))
    costs[:, 10] = np.inf
    costs[15, 10] = 1.0  # the only gap
    distance, predecessors = grid_dijkstra(costs, (10, 2))
    # Octile moves: (10, 2) -> (15, 10) -> (10, 18) is 2 x (3 + 5 sqrt 2) cells.
    assert distance[10, 18] == pytest.approx(2 * (3 + 5 * math.sqrt(2)))
    path = trace_path(predecessors, (10, 18), 20)
    assert tuple(path[0]) == (10, 2) and tuple(path[-1]) == (10, 18) and [15, 10] in path.tolist()
    assert np.isfinite(costs[path[:, 0], path[:, 1]]).all()
    costs[15, 10] = np.inf
    assert np.isinf(grid_dijkstra(costs, (10, 2))[0][10, 18])


def test_heading_action_turns_towards_the_bearing():
    assert heading_action(0.0, 0.05) == FORWARD
    assert heading_action(0.0, math.radians(18)) == SMALL_LEFT
    assert heading_action(0.0, math.radians(60)) == ROTATE_LEFT
    assert heading_action(math.radians(170), math.radians(-170)) == SMALL_LEFT  # across +-pi
    assert heading_action(0.0, math.radians(-100)) == ROTATE_RIGHT


# ---------------------------------------------------------------------------------------------- mapping


def test_agent_satisfies_the_protocol_without_privileges():
    agent = FrontierAgent()
    assert isinstance(agent, Agent)
    assert agent.action_mode == "discrete" and agent.privileged is False


def test_first_view_maps_the_wall_and_objects_where_they_are(first_view: FrontierAgent):
    assert first_view.floor_height == pytest.approx(0.0, abs=0.03)
    m = first_view.map
    assert m is not None and m.grid.dtype == np.int8 and not m.grid.flags.writeable
    rows, cols = np.nonzero(m.grid == OCCUPIED)
    centers = m.center_of(np.stack([rows, cols], -1))
    assert len(centers) > 50
    # Every occupied cell is within a cell or so of a solid (walls, chair, table).
    nearest = np.min([distance_to_rect(centers, r) for r in footprints()], axis=0)
    assert nearest.max() <= 0.15
    # The east wall's face (x = 4) is occupied wherever the camera sees it (not behind the objects).
    camera = np.array([0.5, 0.0])  # Spot's camera is 0.5 m ahead of the base
    objects = footprints()[4:]
    seen = 0
    for y in np.arange(-2.75, 2.8, 0.1):
        ray = camera + np.linspace(0.0, 1.0, 200)[:, None] * (np.array([4.0, y]) - camera)
        if min(distance_to_rect(ray, r).min() for r in objects) < 0.05:
            continue  # in an object's shadow
        cells = m.cell_of(np.array([[3.95, y], [4.05, y]]))
        seen += 1
        assert (m.grid[cells[:, 0], cells[:, 1]] == OCCUPIED).any(), f"wall at y={y:.2f} not mapped"
    assert seen > 30
    # The chair's near face is mapped.
    chair = distance_to_rect(centers, footprints()[4]) <= 0.1
    assert chair.sum() >= 3

    def state(x: float, y: float) -> int:
        r, c = m.cell_of(np.array([x, y]))
        return int(m.grid[r, c])

    # Free floor up to the wall, unknown behind the robot, behind the wall and in the chair's shadow.
    assert [state(3.0, -0.5), state(1.2, 0.0), state(3.5, 0.1), state(2.0, -1.0)] == [FREE] * 4
    assert [state(-1.5, 0.0), state(5.0, 0.0), state(2.7, 0.75)] == [UNKNOWN] * 3


def test_goal_points_lie_on_the_goal_instance(first_view: FrontierAgent):
    points = first_view.goal_points
    assert len(points) >= 10
    (cx, cy, cz), (sx, sy, sz) = CHAIR[1], CHAIR[2]
    lo = np.array([cx - sx / 2, cy - sy / 2, cz - sz / 2]) - 0.05
    hi = np.array([cx + sx / 2, cy + sy / 2, cz + sz / 2]) + 0.05
    assert ((points >= lo) & (points <= hi)).all()  # on the chair, none on the table
    assert points[:, 0].min() == pytest.approx(cx - sx / 2, abs=0.05)  # its near face was seen


def test_no_goal_points_for_a_category_that_is_not_in_view(room: Scene, room_env: NavVerseEnv):
    agent = FrontierAgent()
    agent.reset(task_for(room, "sofa"))
    obs, info = room_env.reset(options={"episode": episode("frontier_room", (0.0, 0.0), 0.0, "sofa")})
    assert agent.act(obs, info) == ROTATE_LEFT  # looks around first
    assert len(agent.goal_points) == 0 and agent.map is not None


def test_stops_next_to_the_goal_but_not_far_from_it(room: Scene, room_env: NavVerseEnv):
    agent = FrontierAgent()
    agent.reset(task_for(room, "chair"))
    # 0.8 m from the chair's face: stop at once.
    obs, info = room_env.reset(options={"episode": episode("frontier_room", (1.0, 0.6), 0.0, "chair")})
    assert agent.act(obs, info) == STOP
    # 1.8 m away with the chair in view: no stop, and no looking around either.
    agent.reset(task_for(room, "chair"))
    obs, info = room_env.reset(options={"episode": episode("frontier_room", (0.0, 0.0), 0.0, "chair")})
    assert agent.act(obs, info) in (FORWARD, SMALL_LEFT, ROTATE_LEFT)
    assert agent.steps == 1 and len(agent.path) > 0


def test_step_budget_ends_the_episode(room: Scene, room_env: NavVerseEnv):
    agent = FrontierAgent(max_steps=3)
    agent.reset(task_for(room, "sofa"))
    actions, _, info = run_episode(room_env, agent, episode("frontier_room", (0.0, 0.0), 0.0, "sofa"))
    assert actions == [ROTATE_LEFT, ROTATE_LEFT, STOP] and info["termination"] == "stop"


def test_finds_a_goal_behind_it_in_the_room(room: Scene, room_env: NavVerseEnv):
    agent = FrontierAgent()
    agent.reset(task_for(room, "chair"))
    ep = episode("frontier_room", (-0.5, 0.0), math.pi, "chair")  # facing the west wall
    actions, obs, info = run_episode(room_env, agent, ep, max_steps=80)
    assert info["termination"] == "stop" and info["submission"]["stop"] is True
    assert actions[0] == ROTATE_LEFT and actions[-1] == STOP
    assert nearest_goal_distance(room, "chair", obs["pose"][:3]) <= 1.0 + SPOT_RADIUS


# ---------------------------------------------------------------------------------------------- episodes


@pytest.mark.parametrize(
    ("category", "start", "yaw"),
    [
        ("bed", (7.5, 7.8), 0.0),  # living room -> bedroom, through a door, facing away
        ("tv", (14.0, 11.0), 0.0),  # kitchen -> living room
    ],
)
def test_finds_the_goal_in_a_furnished_apartment(
    apartment: tuple[Scene, Path], apartment_env: NavVerseEnv, category: str, start: tuple, yaw: float
):
    scene, _ = apartment
    agent = FrontierAgent()
    agent.reset(task_for(scene, category))
    start_distance = nearest_goal_distance(scene, category, np.array([*start, 0.55]))
    actions, obs, info = run_episode(apartment_env, agent, episode("apartment-s0", start, yaw, category))
    final = nearest_goal_distance(scene, category, obs["pose"][:3])
    assert start_distance > 3.0  # the goal was not next to the start
    assert info["termination"] == "stop" and info["submission"]["stop"] is True, (len(actions), final)
    assert final <= 1.0 + SPOT_RADIUS, (len(actions), final)
    # The map explains the success: goal points were seen, and the robot never left the free space.
    assert len(agent.goal_points) > 0
    rows = np.array(info["submission"]["trajectory"])[:, 1:3]
    m = agent.map
    cells = m.cell_of(rows[:: max(1, len(rows) // 200)])
    assert (m.grid[cells[:, 0], cells[:, 1]] == FREE).mean() > 0.95


def test_same_observations_and_seed_give_the_same_actions(
    apartment: tuple[Scene, Path], apartment_env: NavVerseEnv
):
    scene, _ = apartment
    ep = episode("apartment-s0", (7.5, 7.8), 0.0, "bed")
    first = FrontierAgent()
    first.reset(task_for(scene, "bed", seed=5))
    rows = record(apartment_env, first, ep, 40)
    actions = [a for _, _, a in rows]
    assert set(actions) - {ROTATE_LEFT}  # it got going, not only looked around
    second = FrontierAgent()
    second.reset(task_for(scene, "bed", seed=5))
    assert [second.act(obs, info) for obs, info, _ in rows] == actions
    np.testing.assert_array_equal(second.map.grid, first.map.grid)


def test_privileged_information_is_neither_given_nor_used(
    apartment: tuple[Scene, Path], apartment_env: NavVerseEnv
):
    scene, _ = apartment
    ep = episode("apartment-s0", (7.5, 7.8), 0.0, "bed")
    agent = FrontierAgent()
    agent.reset(task_for(scene, "bed"))
    rows = record(apartment_env, agent, ep, 30)
    assert not apartment_env.privileged
    assert not {"goal_positions", "distance_to_goal", "reference_path"} & set(rows[0][1])
    # Misleading privileged signals (a goal far behind the robot) change nothing.
    liar = FrontierAgent()
    liar.reset(task_for(scene, "bed"))
    fake = {"goal_positions": np.array([[15.0, 12.0, 0.5]]), "distance_to_goal": 0.5,
            "reference_path": np.array([[7.5, 7.8, 0.0], [15.0, 12.0, 0.0]])}  # fmt: skip
    assert [liar.act(obs, {**info, **fake}) for obs, info, _ in rows] == [a for _, _, a in rows]
