"""The agent-facing environment: a Gymnasium ``Env`` over the PyBullet simulator and the camera.

>>> import gymnasium, navverse.env  # doctest: +SKIP
>>> env = gymnasium.make("NavVerse-Discrete-v0", scene="data/built/targets/office-s1/scene")  # doctest: +SKIP
>>> obs, info = env.reset(seed=0)  # doctest: +SKIP
>>> obs, reward, terminated, truncated, info = env.step("move_forward")  # doctest: +SKIP

Registered ids: ``NavVerse-Discrete-v0`` (actions: an index into
:data:`~navverse.sim.actions.DISCRETE_ACTIONS`, or its name), ``NavVerse-Waypoint-v0``
(``[x, y, yaw, stop]``: a world-frame waypoint appended to the path, executed for 0.1 s) and
``NavVerse-Velocity-v0`` (``[vx, vy, wz, stop]`` in the body frame for 0.1 s). ``stop > 0.5`` (or the
``stop`` action) ends the episode.

Discrete actions by name. :attr:`NavVerseEnv.action_names` are the discrete actions (an action index is
a position in it; indices never change) and :meth:`NavVerseEnv.action_index` gives the index of a name.
``step`` also takes the name itself, and habitat-lab's names as aliases (``move_forward``,
``turn_left``/``turn_right`` for the 30 degree turns, ``strafe_left``/``strafe_right``): NavVerse's
``left``/``right`` are sidesteps, not turns (table in :mod:`navverse.sim.actions`). A discrete
action that is blocked (no progress for about a second, e.g. against a wall) ends early.

Observations: ``rgb`` (480x640x3 uint8), ``depth`` (480x640x1 float32, meters, 0 where
nothing is within [0.1, 1000] m), ``semantic`` (480x640 int32 instance ids), ``pose``
(``[x, y, z, qx, qy, qz, qw]``), ``goal`` (the object or place category, or the instruction;
for a PlaceNav episode with ``instructions``, the text of the ``instruction_type`` the environment
was made with: :func:`episode_goal`) and ``goal_id`` (an int64 scalar, habitat-lab's ``objectgoal``:
:func:`episode_goal_id`). ``goal_id`` is, in this order of rules:

* -1 when the agent is not given a category: a VLN episode, a PlaceNav episode whose goal text is a
  ``route`` or ``intention`` instruction, or an episode without a category;
* with a category map (the dataset file's ``category_to_task_category_id``, given as the
  ``category_ids`` argument or as ``reset(options={"category_ids": {...}})``, which wins for that
  episode): the category's id in the map, -1 for a category the map lacks;
* without one: the category's index in :func:`navverse.assets.library.categories` (object
  categories, sorted), or for a place category ``len(categories()) +`` its index in
  :data:`navverse.assets.facade.storefronts.PLACE_CATEGORIES`; -1 for a category in neither.

``sensors`` chooses which camera images are rendered; an agent that needs none (one that follows
privileged paths) skips rendering altogether and runs at the speed of the physics.

``reset(options={"episode": {...}})`` takes an episode in the dataset's format (DESIGN.md §3:
``start_position``, ``start_rotation``, ``goals``, ``object_category`` or ``instruction``...);
without one, a start is drawn on the navmesh and an object category with instances as the goal.

Reward. By default (``reward="none"``) the reward is always 0: benchmarks are scored offline by
``navverse eval``. ``reward="habitat"`` gives habitat-lab's point-goal reward: for every action,
``d_{t-1} - d_t`` (the drop of the geodesic distance from the robot to the nearest goal position on
the navmesh, as the privileged ``distance_to_goal``; 0 for a step where either distance is unreachable)
plus ``reward_slack`` (-0.01), plus ``reward_success`` (2.5) when the episode ends by ``stop`` within
the success distance of a goal. Success is the evaluator's rule: the straight-line 3-D distance from
the robot base to the nearest goal's edge (its centre distance less its ``radius``) is at most the
scene type's ``success_margin_m + r_robot`` (:meth:`navverse.scene_types.SceneTypeProfile.success_distance`).

``info`` holds the termination label (``stop``, ``fall``, ``timeout``, ``out_of_bounds``,
``max_steps``), the number of actions (``steps``), the surface under the robot, the simulated time,
``collisions`` (collision events since the episode began: a control tick in contact with anything but
the robot's normal support, after one without; :attr:`~navverse.sim.simulator.Simulator.contact_events`),
``contact_steps`` (the collision log's length: one entry per contact point per control tick, the
figure ``collisions`` used to be; the submission's ``collisions`` times come from this log, unchanged),
``blocked`` (whether the last discrete action ended early, blocked) and ``blocked_actions`` (how many
did in this episode), ``success`` under ``reward="habitat"`` at the end of an episode, and, for a
PlaceNav episode, the ``instruction_type`` its goal text is of; with ``privileged=True`` also the
geodesic distance to the nearest goal, the goal positions and the episode's reference path.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from functools import cache
from pathlib import Path
from typing import Any, Literal

import gymnasium
import numpy as np
from gymnasium import spaces

from navverse.dynamics.runtime import EpisodeDynamics, episode_seed
from navverse.dynamics.scene_dynamics import DYNAMICS_MODES, DynamicsSettings
from navverse.env_spec import ACTION_MODES, SENSORS, EnvError, check_instruction_type, episode_goal
from navverse.look.files import load_scene_look
from navverse.look.settings import look_option
from navverse.scene_types import scene_profile
from navverse.sim.actions import DISCRETE_ACTIONS, ActionRunner, action_index, step_size
from navverse.sim.camera import CameraIntrinsics
from navverse.sim.controller import Waypoint
from navverse.sim.embodiments import make_embodiment
from navverse.sim.recorder import RolloutRecorder
from navverse.sim.render import SceneRenderer
from navverse.sim.simulator import Simulator
from navverse.sim.terminations import TIMEOUT, TerminationMonitor
from navverse.sim.world import World

__all__ = [
    "ACTION_MODES",
    "REWARDS",
    "REWARD_SLACK",
    "REWARD_SUCCESS",
    "SENSORS",
    "EnvError",
    "NavVerseEnv",
    "episode_goal",
    "episode_goal_id",
    "goal_edge_distance",
]

POSE_MARGIN = 100.0
"""The pose observation's box: the scene bounds grown by this much (m) on every side."""
REWARDS = ("none", "habitat")
"""The reward functions: none (always 0) or habitat-lab's point-goal reward."""
REWARD_SLACK = -0.01
"""Habitat-lab's reward for every action."""
REWARD_SUCCESS = 2.5
"""Habitat-lab's reward for ending an episode by ``stop`` within the success distance of a goal."""
GOAL_ID_MAX = 10**6
"""Upper bound of the ``goal_id`` observation's box."""
_TEXT = spaces.Text(max_length=2048, charset="".join(chr(c) for c in range(32, 127)))


def _check_category_ids(category_ids: Mapping[str, int] | None) -> dict[str, int] | None:
    """A category map as a dict, or an EnvError when an id is not an integer in -1..GOAL_ID_MAX."""
    if category_ids is None:
        return None
    if not isinstance(category_ids, Mapping):
        raise EnvError(f"category_ids must map category names to ids, got {type(category_ids).__name__}")
    bad = {
        k: v for k, v in category_ids.items() if isinstance(v, bool) or not isinstance(v, (int, np.integer))
    }
    bad.update({k: v for k, v in category_ids.items() if k not in bad and not -1 <= v <= GOAL_ID_MAX})
    if bad:
        raise EnvError(f"category_ids must be integers in -1..{GOAL_ID_MAX}; not: {bad}")
    return {str(k): int(v) for k, v in category_ids.items()}


@cache
def _default_category_ids() -> dict[str, int]:
    """Object categories of the library by sorted index, then place categories after them."""
    from navverse.assets.facade.storefronts import PLACE_CATEGORIES
    from navverse.assets.library import categories

    objects = categories()
    ids = {name: i for i, name in enumerate(objects)}
    for i, name in enumerate(PLACE_CATEGORIES):
        ids.setdefault(name, len(objects) + i)
    return ids


def episode_goal_id(
    episode: Mapping[str, Any],
    *,
    category_ids: Mapping[str, int] | None = None,
    instruction_type: str = "category",
) -> int:
    """The integer goal of an episode (habitat-lab's ``objectgoal``): the rule of the module docstring.

    Parameters
    ----------
    episode : mapping
        The episode, as in the dataset's files.
    category_ids : mapping of str to int, optional
        The dataset's ``category_to_task_category_id``; None: the library's object categories, then
        the place categories.
    instruction_type : str
        The PlaceNav instruction type the agent is given (a ``route`` or ``intention`` instruction
        does not tell the category).

    Returns
    -------
    int
        The category's id, or -1 when the agent is not given a category or it has no id.
    """
    _, kind = episode_goal(episode, instruction_type)
    category = episode.get("object_category") or episode.get("place_category")
    if episode.get("task") == "vln" or kind not in (None, "category") or not category:
        return -1
    ids = _default_category_ids() if category_ids is None else category_ids
    return int(ids.get(str(category), -1))


def goal_edge_distance(position: np.ndarray, goals: Sequence[Mapping[str, Any]]) -> float:
    """The evaluator's distance to goal: 3-D from ``position`` to the nearest goal's edge (its centre
    distance less its ``radius``), at least 0; inf without goals."""
    if not goals:
        return math.inf
    centers = np.array([g["position"] for g in goals], dtype=float).reshape(-1, 3)
    radii = np.array([float(g.get("radius", 0.0)) for g in goals])
    return max(float(np.min(np.linalg.norm(centers - position, axis=1) - radii)), 0.0)


def _yaw_of(quaternion) -> float:
    x, y, z, w = (float(v) for v in quaternion)
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


class NavVerseEnv(gymnasium.Env):
    """Navigate a built scene with a physically simulated robot.

    Parameters
    ----------
    scene : path
        A built scene directory (``data/built/targets/<id>/scene``).
    embodiment : str
        ``spot`` or ``turtlebot``.
    action_mode : str
        ``discrete``, ``waypoint`` or ``velocity``.
    max_time : float
        Episode time limit in simulated seconds (truncation, label ``timeout``).
    max_steps : int, optional
        Limit on the number of actions (truncation, label ``max_steps``); None: no limit.
    privileged : bool
        Whether ``info`` carries goal positions, the geodesic distance and the reference path.
    render_mode : str, optional
        ``rgb_array``: :meth:`render` returns the last camera image.
    collision_cache : path, optional
        Where convex decompositions of objects are cached (see :class:`~navverse.sim.world.World`).
    sensors : sequence of str
        Camera images rendered into the observation, among :data:`SENSORS` (``pose`` and ``goal``
        are always there).
    terrain_friction : float, optional
        Friction of every terrain class instead of the scene's own (a diagnostic); None: the scene's.
    instruction_type : str
        Which of a PlaceNav episode's ``instructions`` is its goal text, among
        :data:`~navverse.dataset.INSTRUCTION_TYPES` (``category``, ``route``, ``intention``); a
        PlaceNav episode without them is given its place category. Other tasks ignore it.
    reward : {"none", "habitat"}
        ``none``: the reward is always 0; ``habitat``: habitat-lab's point-goal reward (module
        docstring).
    reward_slack : float
        Reward of every action under ``reward="habitat"``.
    reward_success : float
        Reward of ending by ``stop`` within the success distance under ``reward="habitat"``.
    category_ids : mapping of str to int, optional
        The dataset's ``category_to_task_category_id``, for the ``goal_id`` observation; None: the
        library's categories (module docstring).
    dynamics : {"off", "pedestrians", "full"} or DynamicsSettings
        What moves besides the robot (:mod:`navverse.dynamics`): nothing (the scene as published),
        people on foot, or people and traffic; every episode's people and cars come from a seed made of
        its id (``reset(options={"dynamics_seed": ...})`` changes it), so two runs of an episode see the
        same crowd while the robot moves alike.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(
        self,
        scene: str | os.PathLike[str],
        *,
        embodiment: str = "spot",
        action_mode: str = "discrete",
        max_time: float = TIMEOUT,
        max_steps: int | None = None,
        privileged: bool = False,
        render_mode: str | None = None,
        collision_cache: str | os.PathLike[str] | None = "default",
        sensors: Sequence[str] = SENSORS,
        terrain_friction: float | None = None,
        instruction_type: str = "category",
        reward: Literal["none", "habitat"] = "none",
        reward_slack: float = REWARD_SLACK,
        reward_success: float = REWARD_SUCCESS,
        category_ids: Mapping[str, int] | None = None,
        dynamics: str | DynamicsSettings = "off",
    ) -> None:
        if isinstance(dynamics, str):
            if dynamics not in DYNAMICS_MODES:
                raise EnvError(f"unknown dynamics {dynamics!r}; choose from: {', '.join(DYNAMICS_MODES)}")
            dynamics = DynamicsSettings(mode=dynamics)
        if action_mode not in ACTION_MODES:
            raise EnvError(f"unknown action mode {action_mode!r}; choose from: {', '.join(ACTION_MODES)}")
        unknown = sorted(set(sensors) - set(SENSORS))
        if unknown:
            raise EnvError(f"unknown sensors {unknown}; choose from: {', '.join(SENSORS)}")
        if max_steps is not None and max_steps < 1:
            raise EnvError(f"max_steps must be at least 1, got {max_steps}")
        if terrain_friction is not None and not (math.isfinite(terrain_friction) and terrain_friction >= 0.0):
            raise EnvError(f"terrain_friction must be a finite number >= 0, got {terrain_friction!r}")
        check_instruction_type(instruction_type)
        if reward not in REWARDS:
            raise EnvError(f"unknown reward {reward!r}; choose from: {', '.join(REWARDS)}")
        if render_mode not in (None, "rgb_array"):
            raise EnvError(f"unsupported render mode {render_mode!r}; use 'rgb_array' or None")
        self.scene_dir = Path(scene)
        if not (self.scene_dir / "scene.json").is_file():
            raise EnvError(
                f"{self.scene_dir} is not a built scene directory (no scene.json); "
                "build it with `navverse build`"
            )
        cache = collision_cache if collision_cache in (None, "default") else Path(collision_cache)
        self.world = World(self.scene_dir, collision_cache=cache, terrain_friction=terrain_friction)
        self.scene = self.world.scene
        self.embodiment_name = embodiment
        self.sim = Simulator(self.world, make_embodiment(embodiment))
        self.runner = ActionRunner(self.sim, step=step_size(self.scene.annotations.scene_type))
        self.intrinsics = CameraIntrinsics.from_hfov()
        look = load_scene_look(self.scene, self.scene_dir)  # the scene's look directory, if built
        self.renderer = SceneRenderer(self.scene, intrinsics=self.intrinsics, look=look)
        self.dynamics_settings = dynamics
        self._dynamics: EpisodeDynamics | None = None
        self.monitor = TerminationMonitor(timeout=max_time)
        self.max_steps = max_steps
        self.sensors = tuple(s for s in SENSORS if s in sensors)
        self.action_mode = action_mode
        self.privileged = privileged
        self.instruction_type = instruction_type
        self.reward_kind = reward
        self.reward_slack = float(reward_slack)
        self.reward_success = float(reward_success)
        self.category_ids = _check_category_ids(category_ids)
        self.render_mode = render_mode
        self._navmesh = None
        self._episode: dict[str, Any] = {}
        self._goal: tuple[str, str | None] = ("", None)
        self._recorder: RolloutRecorder | None = None
        self._last_rgb: np.ndarray | None = None
        self._done = False
        self._steps = 0
        self._goal_id = -1
        self._distance = math.inf  # geodesic distance to the nearest goal after the last action
        self._blocked_actions = 0

        h, w = self.intrinsics.height, self.intrinsics.width
        lo, hi = self.world.bounds
        reach = np.array([POSE_MARGIN, POSE_MARGIN, POSE_MARGIN])
        pose_low = np.concatenate([lo - reach, -np.ones(4)])
        pose_high = np.concatenate([hi + reach, np.ones(4)])
        images = {
            "rgb": spaces.Box(0, 255, (h, w, 3), np.uint8),
            "depth": spaces.Box(0.0, 1000.0, (h, w, 1), np.float32),
            "semantic": spaces.Box(0, np.iinfo(np.int32).max, (h, w), np.int32),
        }
        self.observation_space = spaces.Dict(
            {
                **{name: images[name] for name in self.sensors},
                "pose": spaces.Box(pose_low, pose_high, (7,), np.float64),
                "goal": _TEXT,
                "goal_id": spaces.Box(-1, GOAL_ID_MAX, (), np.int64),
            }
        )
        if action_mode == "discrete":
            self.action_space = spaces.Discrete(len(DISCRETE_ACTIONS))
        elif action_mode == "waypoint":
            self.action_space = spaces.Box(
                np.array([lo[0] - 5.0, lo[1] - 5.0, -math.pi, 0.0], dtype=np.float32),
                np.array([hi[0] + 5.0, hi[1] + 5.0, math.pi, 1.0], dtype=np.float32),
            )
        else:
            vx, vy, wz = self.runner.follower.clip
            self.action_space = spaces.Box(
                np.array([-vx, -vy, -wz, 0.0], dtype=np.float32),
                np.array([vx, vy, wz, 1.0], dtype=np.float32),
            )

    # ------------------------------------------------------------------ action names

    @property
    def action_names(self) -> tuple[str, ...]:
        """The discrete actions' names; an action index is a position here
        (:data:`~navverse.sim.actions.DISCRETE_ACTIONS`)."""
        return DISCRETE_ACTIONS

    def action_index(self, name: str) -> int:
        """The index of the discrete action named ``name`` (habitat-lab's names accepted as aliases).

        Raises
        ------
        EnvError
            On an unknown name; the message lists the names and the aliases.
        """
        try:
            return action_index(name)
        except ValueError as exc:
            raise EnvError(str(exc)) from None

    # ------------------------------------------------------------------ episodes

    @property
    def navmesh(self):
        """The scene's navmesh (loaded on first use)."""
        if self._navmesh is None:
            from navverse.nav.scene_navmesh import load_scene_navmesh

            self._navmesh = load_scene_navmesh(self.scene_dir)
        return self._navmesh

    def _default_episode(self) -> dict[str, Any]:
        """A start on the navmesh's largest island and an object category with instances as the goal."""
        finder = self.navmesh
        start = finder.get_random_navigable_point(self.np_random, island=finder.largest_island)
        objects = [o for o in self.scene.annotations.objects if o.category]
        if not objects:
            raise EnvError(f"scene {self.scene.scene_id} has no objects to use as goals")
        category = sorted({o.category for o in objects})[
            int(self.np_random.integers(len({o.category for o in objects})))
        ]
        yaw = float(self.np_random.uniform(-math.pi, math.pi))
        return {
            "episode_id": f"{self.scene.scene_id}-random",
            "scene_id": self.scene.scene_id,
            "task": "objnav",
            "start_position": [float(v) for v in start],
            "start_rotation": [0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)],
            "object_category": category,
            "goals": [
                {
                    "object_id": o.id,
                    "category": o.category,
                    "position": list(o.center),
                    "radius": o.goal_radius,
                    "size": list(o.size),
                }
                for o in objects
                if o.category == category
            ],
        }

    # ------------------------------------------------------------------ gymnasium API

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        """Start an episode (``options={"episode": {...}}``, else a random ObjNav one).

        ``options={"appearance": ...}`` sets the camera's look from this episode on: ``"eval"`` (the
        fixed evaluation look, the default), ``"random"`` (time of day, sun, sky, exposure and material
        variant drawn from the environment's seeded generator: pass it at every reset to vary them) or
        a mapping of :class:`~navverse.look.settings.LookSettings` fields.
        """
        super().reset(seed=seed)
        options = options or {}
        if "appearance" in options:
            try:
                self.renderer.set_look(look_option(options["appearance"], self.np_random))
            except ValueError as exc:
                raise EnvError(str(exc)) from None
        episode = options.get("episode")
        self._episode = dict(episode) if episode is not None else self._default_episode()
        self._goal = episode_goal(self._episode, self.instruction_type)
        category_ids = _check_category_ids(options.get("category_ids", self.category_ids))
        self._goal_id = episode_goal_id(
            self._episode, category_ids=category_ids, instruction_type=self.instruction_type
        )
        try:
            start = [float(v) for v in self._episode["start_position"]]
            yaw = _yaw_of(self._episode.get("start_rotation", [0.0, 0.0, 0.0, 1.0]))
        except (KeyError, TypeError, ValueError) as exc:
            raise EnvError(
                f"episode needs start_position [x, y, z] and start_rotation [x, y, z, w] ({exc})"
            ) from None
        if self._dynamics is not None:
            self._dynamics.stop(self.sim)
        self.sim.spawn(start, yaw)
        if self.dynamics_settings.mode != "off":
            if self._dynamics is None:
                finder = self.navmesh
                if not finder.area_names:  # a navmesh saved without its navmesh.json: the scene's classes
                    from navverse.nav.scene_navmesh import scene_area_types

                    finder.name_areas(scene_area_types(self.scene.annotations))
                self._dynamics = EpisodeDynamics(
                    self.scene_dir, finder, self.dynamics_settings, self.renderer
                )
            episode_id = str(self._episode.get("episode_id", "episode"))
            self._dynamics.start(
                self.sim, seed=episode_seed(int(options.get("dynamics_seed", 0)), episode_id)
            )
        self.runner.follower.clear()
        self.monitor.start(self.sim)
        self._recorder = RolloutRecorder(
            str(self._episode.get("episode_id", "episode")), instruction_type=self._goal[1]
        )
        self._recorder.attach(self.sim)
        self._done = False
        self._steps = 0
        self._blocked_actions = 0
        self.runner.blocked = False
        if self.reward_kind == "habitat":
            self._distance = self._geodesic_to_goal()
        return self._observe(), self._info(None)

    def step(self, action):
        """Apply an action; returns ``(obs, reward, terminated, truncated, info)``."""
        if self._done:
            raise EnvError("the episode has ended: call reset() before step()")
        stop = self._act(action)
        self._steps += 1
        self._blocked_actions += int(self.runner.blocked)
        label = "stop" if stop else self.monitor.check(self.sim)
        if label is None and self.max_steps is not None and self._steps >= self.max_steps:
            label = "max_steps"
        terminated = label in ("stop", "fall", "out_of_bounds", "stuck")
        truncated = label in ("timeout", "max_steps")
        self._done = terminated or truncated
        reward, success = 0.0, False
        if self.reward_kind == "habitat":
            success = stop and self._succeeded()
            reward = self._habitat_reward(success=success)
        info = self._info(label)
        if self.reward_kind == "habitat" and self._done:
            info["success"] = success
        if self._done:
            info["submission"] = self._recorder.finish(stop=stop, termination=label)
        return self._observe(), reward, terminated, truncated, info

    def _goal_positions(self) -> np.ndarray:
        """The episode's goal positions (G, 3)."""
        return np.array([g["position"] for g in self._episode.get("goals", [])], dtype=float).reshape(-1, 3)

    def _geodesic_to_goal(self) -> float:
        """Geodesic distance (m) from the robot to the nearest goal position; inf without goals."""
        goals = self._goal_positions()
        if not len(goals):
            return math.inf
        return float(self.navmesh.geodesic_distance(self.sim.pose().position, goals))

    def _succeeded(self) -> bool:
        """Whether the robot is within the success distance of a goal (the evaluator's rule)."""
        limit = scene_profile(self.scene.annotations.scene_type).success_distance(self.sim.robot.radius)
        return goal_edge_distance(self.sim.pose().position, self._episode.get("goals", [])) <= limit

    def _habitat_reward(self, *, success: bool) -> float:
        """Habitat-lab's reward of the last action: geodesic progress (0 when a distance is unreachable),
        slack and, for a ``stop`` within the success distance, the success bonus."""
        before, self._distance = self._distance, self._geodesic_to_goal()
        progress = before - self._distance if math.isfinite(before) and math.isfinite(self._distance) else 0.0
        return float(progress + self.reward_slack + (self.reward_success if success else 0.0))

    def _act(self, action) -> bool:
        self.runner.blocked = False
        if self.action_mode == "discrete":
            index = self.action_index(action) if isinstance(action, str) else int(action)
            if not 0 <= index < len(DISCRETE_ACTIONS):
                raise EnvError(f"discrete action {action!r} out of range 0..{len(DISCRETE_ACTIONS) - 1}")
            name = DISCRETE_ACTIONS[index]
            self.runner.discrete(name)
            return name == "stop"
        if isinstance(action, str):
            raise EnvError(f"{self.action_mode} actions are 4 finite numbers, not a name ({action!r})")
        values = np.asarray(action, dtype=float).reshape(-1)
        if values.shape != (4,) or not np.isfinite(values).all():
            raise EnvError(f"{self.action_mode} actions are 4 finite numbers, got {action!r}")
        if values[3] > 0.5:
            self.sim.tick(0.0, 0.0, 0.0)
            return True
        if self.action_mode == "waypoint":
            self.runner.waypoints([Waypoint(float(values[0]), float(values[1]), float(values[2]))])
        else:
            self.runner.velocity(float(values[0]), float(values[1]), float(values[2]))
        return False

    def _observe(self) -> dict[str, Any]:
        pose = self.sim.pose()
        observation: dict[str, Any] = {}
        if self.sensors or self.render_mode is not None:
            if self._dynamics is not None:
                self._dynamics.show()
            frame = self.renderer.render(self.sim.camera_to_world())
            self._last_rgb = frame.rgb
            images = {
                "rgb": lambda: frame.rgb,
                "depth": lambda: frame.depth[..., None].astype(np.float32),
                "semantic": lambda: frame.semantic.astype(np.int32),
            }
            observation = {name: images[name]() for name in self.sensors}
        observation["pose"] = np.concatenate([pose.position, pose.quaternion]).astype(np.float64)
        observation["goal"] = self._goal[0]
        observation["goal_id"] = np.array(self._goal_id, dtype=np.int64)
        return observation

    def _info(self, label: str | None) -> dict[str, Any]:
        info: dict[str, Any] = {
            "termination": label,
            "time": self.monitor.elapsed(self.sim),
            "collisions": self.sim.contact_events,
            "contact_steps": len(self.sim.collisions),
            "blocked": self.runner.blocked,
            "blocked_actions": self._blocked_actions,
            "surface": self.sim.surface(),
            "camera_intrinsics": self.intrinsics.matrix(),
            "camera_to_base": np.array(self.sim.robot.camera_to_base, dtype=float),
            "robot_size": np.array(self.sim.robot.size, dtype=float),
            "robot_radius": self.sim.robot.radius,
            "steps": self._steps,
            "dynamics": self.dynamics_settings.mode,
        }
        if self._goal[1] is not None:
            info["instruction_type"] = self._goal[1]
        if self.privileged:
            info["goal_positions"] = self._goal_positions()
            # Under the habitat reward the distance after the last action is known already.
            info["distance_to_goal"] = (
                self._distance if self.reward_kind == "habitat" else self._geodesic_to_goal()
            )
            info["reference_path"] = np.asarray(self._episode.get("reference_path", []), dtype=float)
        return info

    def render(self):
        """The last camera image (``render_mode="rgb_array"``)."""
        return None if self.render_mode is None else self._last_rgb

    def close(self) -> None:
        """Release the physics client."""
        self.world.close()


for _mode in ACTION_MODES:
    _id = f"NavVerse-{_mode.capitalize()}-v0"
    if _id not in gymnasium.registry:
        gymnasium.register(_id, entry_point="navverse.env:NavVerseEnv", kwargs={"action_mode": _mode})
