"""The ``random`` agent: uniformly random discrete actions, ``stop`` among them.

The lower bound of the benchmark: every action (:data:`~navverse.sim.actions.DISCRETE_ACTIONS`,
``stop`` included) is drawn with the same probability from the episode's seed, so an episode lasts
eight actions on average. It sees no images and knows nothing of the goal.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from navverse.eval.agents.base import AgentTask
from navverse.sim.actions import DISCRETE_ACTIONS

__all__ = ["RandomAgent"]


class RandomAgent:
    """Uniformly random discrete actions, seeded per episode by :attr:`AgentTask.seed`."""

    action_mode = "discrete"
    privileged = False
    sensors: tuple[str, ...] = ()

    def __init__(self) -> None:
        self._rng = np.random.default_rng(0)

    def reset(self, task: AgentTask) -> None:
        """Seed this episode's draws."""
        self._rng = np.random.default_rng(task.seed)

    def act(self, observation: dict[str, Any], info: dict[str, Any]) -> int:
        """An action index drawn uniformly."""
        return int(self._rng.integers(len(DISCRETE_ACTIONS)))
