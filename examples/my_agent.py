"""An example agent for ``navverse run-agent``: copy this file and put your model in ``policy``.

Run it with::

    navverse run-agent --dataset episodes/navverse-mini/v2.2 --split eval \\
        --agent examples/my_agent.py:GoalSeekingAgent --out my_agent.jsonl
    navverse eval --dataset episodes/navverse-mini/v2.2 --submission my_agent.jsonl --out my_agent-eval

The agent follows the interface of :mod:`navverse.eval.agents.base`. It uses the discrete
interface, which is how the paper runs discrete-action models: each action index becomes one
single-step waypoint (``forward`` 0.25 m indoors, turns of 30° or 15°) that the robot's waypoint
follower executes until the robot has settled. Its ``policy`` is a few lines of rules on depth and
the semantic channel; a learned model takes its place with the same inputs and output.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from navverse.eval.agents.base import AgentTask
from navverse.sim.actions import DISCRETE_ACTIONS

STOP, FORWARD, ROTATE_LEFT = (DISCRETE_ACTIONS.index(a) for a in ("stop", "forward", "rotate_left"))
SMALL_LEFT, SMALL_RIGHT = (
    DISCRETE_ACTIONS.index("small_rotate_left"),
    DISCRETE_ACTIONS.index("small_rotate_right"),
)


class GoalSeekingAgent:
    """Walks towards the sought category once it is in view, wanders on free floor otherwise.

    Parameters
    ----------
    max_actions : int
        The agent stops after this many actions.
    arrive_depth : float
        It stops when the goal's pixels are this close (m), with the goal centred in view.
    """

    action_mode = "discrete"
    privileged = False
    sensors = ("depth", "semantic")

    def __init__(self, *, max_actions: int = 150, arrive_depth: float = 1.2) -> None:
        self.max_actions = max_actions
        self.arrive_depth = arrive_depth
        self._goal_ids: set[int] = set()
        self._rng = np.random.default_rng(0)
        self._actions = 0

    def reset(self, task: AgentTask) -> None:
        """Remember which semantic ids show the goal category; seed this episode's choices."""
        self._goal_ids = {i for i, c in task.semantic_categories.items() if c == task.goal_category}
        self._rng = np.random.default_rng(task.seed)
        self._actions = 0

    def act(self, observation: dict[str, Any], info: dict[str, Any]) -> int:
        """One discrete action index."""
        self._actions += 1
        if self._actions >= self.max_actions:
            return STOP
        return self.policy(observation["depth"][..., 0], observation["semantic"])

    def policy(self, depth: np.ndarray, semantic: np.ndarray) -> int:
        """Replace this with your model: images in, an index into DISCRETE_ACTIONS out."""
        height, width = depth.shape
        goal = np.isin(semantic, list(self._goal_ids)) if self._goal_ids else np.zeros_like(depth, bool)
        if goal.sum() >= 50:
            columns = np.nonzero(goal)[1]
            offset = (columns.mean() - width / 2) / (width / 2)
            if np.median(depth[goal]) < self.arrive_depth and abs(offset) < 0.3:
                return STOP
            if offset < -0.2:
                return SMALL_LEFT
            if offset > 0.2:
                return SMALL_RIGHT
        ahead = depth[height // 3 : 2 * height // 3, width // 3 : 2 * width // 3]
        free = ahead[ahead > 0]
        if free.size and np.percentile(free, 5) > 0.8:
            return FORWARD
        return ROTATE_LEFT if self._rng.random() < 0.7 else SMALL_RIGHT
