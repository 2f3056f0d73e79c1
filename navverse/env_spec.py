"""What the agent-facing environment accepts, importable without the simulator: its action modes,
sensors and error, and the goal text an episode gives the agent.

:mod:`navverse.env` (which loads the simulator and the camera) builds on these; code that only checks
an agent's action mode or reads an episode's goal (``run-agent``'s parent process, the agent workers
before they make an environment) imports this module instead.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from navverse.dataset import INSTRUCTION_TYPES
from navverse.errors import NavverseError

__all__ = ["ACTION_MODES", "SENSORS", "EnvError", "check_instruction_type", "episode_goal"]

ACTION_MODES = ("discrete", "waypoint", "velocity")
"""How an agent acts: discrete actions, world-frame waypoints or body-frame velocities."""
SENSORS = ("rgb", "depth", "semantic")
"""The camera images an environment can render."""


class EnvError(NavverseError):
    """The environment was given something it cannot use (a scene, an episode, an action mode)."""


def check_instruction_type(instruction_type: str) -> None:
    """Check a PlaceNav instruction type.

    Parameters
    ----------
    instruction_type : str
        One of :data:`~navverse.dataset.INSTRUCTION_TYPES`, or not.

    Raises
    ------
    EnvError
        Naming the instruction types, when ``instruction_type`` is not one of them.
    """
    if instruction_type not in INSTRUCTION_TYPES:
        raise EnvError(
            f"unknown instruction type {instruction_type!r}; choose from: {', '.join(INSTRUCTION_TYPES)}"
        )


def _instruction_text(instruction: Any) -> str:
    """The text of an instruction given as a dict (``instruction_text``), "" if it has none."""
    return str(instruction.get("instruction_text", "")) if isinstance(instruction, Mapping) else ""


def episode_goal(episode: Mapping[str, Any], instruction_type: str = "category") -> tuple[str, str | None]:
    """The goal text of an episode (given as in the dataset's files) and its instruction type.

    Parameters
    ----------
    episode : mapping
        The episode: ``task``, ``object_category`` or ``place_category``, ``instruction``, and for
        PlaceNav ``instructions`` (by instruction type, dataset format 1.1).
    instruction_type : str
        The PlaceNav instruction type to give (:data:`~navverse.dataset.INSTRUCTION_TYPES`).

    Returns
    -------
    goal : str
        The instruction of that type for a PlaceNav episode with ``instructions``; else the VLN
        instruction when there is one, or the object or place category (at most 2048 characters).
    instruction_type : str or None
        For a PlaceNav episode, the type the goal text is of: ``instruction_type``, or ``category``
        for an episode without ``instructions`` (older datasets, ad-hoc episodes), whose goal is its
        place category. None for the other tasks.

    Raises
    ------
    EnvError
        If ``instruction_type`` is unknown, or a PlaceNav episode's ``instructions`` lack it.
    """
    check_instruction_type(instruction_type)
    placenav = episode.get("task") == "placenav"
    instructions = episode.get("instructions")
    if placenav and instructions:
        if not isinstance(instructions, Mapping) or instruction_type not in instructions:
            have = ", ".join(sorted(instructions)) if isinstance(instructions, Mapping) else "none"
            raise EnvError(
                f"PlaceNav episode {episode.get('episode_id')} has no {instruction_type!r} instruction "
                f"(its instructions: {have})"
            )
        return _instruction_text(instructions[instruction_type])[:2048], instruction_type
    kind = "category" if placenav else None
    if episode.get("instruction"):
        return _instruction_text(episode["instruction"])[:2048], kind
    return str(episode.get("object_category") or episode.get("place_category") or ""), kind
