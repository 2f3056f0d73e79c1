"""The agent interface of ``navverse run-agent``: what an agent is told, what it returns.

An agent is any object with an ``action_mode`` (``"discrete"``, ``"waypoint"`` or ``"velocity"``:
the Gymnasium environment it is run in, :mod:`navverse.env`), a ``privileged`` flag, optionally the
``sensors`` it looks at (a subset of :data:`navverse.env.SENSORS`; ``rgb`` and ``depth`` when absent:
the ground-truth ``semantic`` sensor is opt-in), and two methods::

    class MyAgent:
        action_mode = "discrete"
        privileged = False          # True: info carries goal positions and the reference path
        sensors = ("rgb", "depth")  # camera images rendered for it

        def reset(self, task: AgentTask) -> None: ...
        def act(self, observation: dict, info: dict) -> int | np.ndarray: ...

``reset`` is called at the start of every episode with an :class:`AgentTask`; ``act`` with the
environment's observation (the chosen images among ``rgb``, ``depth``, ``semantic``; always
``pose`` and ``goal``) and ``info`` (``time``, ``steps``, ``collisions``, ``surface``,
``camera_intrinsics``, ``camera_to_base``, ``robot_radius``; privileged agents also get
``goal_positions``, ``distance_to_goal`` and ``reference_path``), and returns one action of its
mode: an index into :data:`~navverse.sim.actions.DISCRETE_ACTIONS`, or ``[x, y, yaw, stop]``
(waypoint, world frame), or ``[vx, vy, wz, stop]`` (velocity, body frame).

Discrete actions are executed the way the paper runs discrete-action models: each becomes a
single-step waypoint (:func:`~navverse.sim.actions.discrete_waypoint`: 0.25 m indoors, 1 m outdoors,
turns of 30° or 15°) that the shared waypoint follower tracks until the robot has settled on it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import numpy as np

__all__ = ["Agent", "AgentTask"]


@dataclass(frozen=True)
class AgentTask:
    """What an agent is told at the start of an episode.

    Attributes
    ----------
    episode_id : str
        The dataset episode.
    task : str
        ``objnav``, ``placenav`` or ``vln``.
    goal : str
        The object or place category sought, or the VLN instruction; for PlaceNav, the episode's
        instruction of the run's ``instruction_type`` (the observation's ``goal``).
    goal_category : str
        The category sought, where the observation protocol tells it (:mod:`navverse.eval.protocol`):
        ObjNav, and PlaceNav under the ``category`` instruction type. It is "" for VLN and for PlaceNav
        under ``route`` and ``intention`` for an agent that is not privileged: the instruction is what
        it is told. Privileged agents (``oracle``, ``gt_goal``) always get it.
    scene_type : str
        ``indoor``, ``outdoor`` or ``i2o``.
    embodiment : str
        ``spot`` or ``turtlebot``.
    robot_radius : float
        ``r_robot``: the success distance is ``1.0 + r_robot`` from the goal's edge.
    semantic_categories : dict
        Category of each instance id of the semantic channel (the scene's semantic annotation, as
        a simulator's semantic sensor provides it); not the goals' positions. Empty unless the agent
        uses the ``semantic`` sensor (or is privileged).
    seed : int
        Seed for the agent's own randomness in this episode.
    scene_dir : str
        The built scene directory. Only privileged agents may use it (to load the navmesh, as the
        ground-truth planners do); an agent that reads scene files is not a benchmark entry.
    instruction_type : str or None
        PlaceNav: the type of instruction ``goal`` is, among
        :data:`~navverse.dataset.INSTRUCTION_TYPES` (``category``, ``route``, ``intention``;
        ``category`` for an episode without instructions). None for ObjNav and VLN.
    """

    episode_id: str
    task: str
    goal: str
    goal_category: str
    scene_type: str
    embodiment: str
    robot_radius: float
    semantic_categories: dict[int, str] = field(default_factory=dict)
    seed: int = 0
    scene_dir: str = ""
    instruction_type: str | None = None


@runtime_checkable
class Agent(Protocol):
    """A navigation agent (see the module docstring)."""

    action_mode: str
    privileged: bool

    def reset(self, task: AgentTask) -> None:
        """Start an episode."""

    def act(self, observation: dict[str, Any], info: dict[str, Any]) -> int | np.ndarray:
        """The next action."""
