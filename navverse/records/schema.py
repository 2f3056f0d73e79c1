"""The episode schema (DESIGN.md §3): what an episode and an episode file hold, and goal distances.

Episodes follow habitat-lab's layout (``start_position``, ``start_rotation`` as ``[x, y, z, w]``,
``goals``, ``reference_path``...). An episode file ``<split>/<task>.json.gz`` is an
:class:`EpisodeFile`: ``{"episodes": [...], "goals_by_category": {...},
"category_to_task_category_id": {...}}``. :data:`FORMAT_VERSION` is the format of these files.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

from navverse.scene_types import SceneType, scene_profile

__all__ = [
    "FORMAT_VERSION",
    "INSTRUCTION_TYPES",
    "PRIVATE_FORMAT_VERSION",
    "PUBLIC_FORMAT_VERSION",
    "RECORD_CONFIG",
    "TASKS",
    "Episode",
    "EpisodeFile",
    "EpisodeInfo",
    "Goal",
    "Instruction",
    "InstructionType",
    "Landmark",
    "Task",
    "Vec3",
    "Verification",
    "goal_distance",
    "success_distance",
]

FORMAT_VERSION = "1.3"
"""Format of the dataset files (``major.minor``); a reader takes its own major, minors up to its own.
1.1 added the PlaceNav episodes' ``instructions`` by instruction type; 1.2 the manifest's
``look_version``; 1.3 private splits (the manifest's ``private``; their public episodes without
goals, reference path or ``info``). A version is written with the lowest format that holds it
(:data:`PRIVATE_FORMAT_VERSION` only when it has a private split), so a dataset without one keeps its
bytes."""
PUBLIC_FORMAT_VERSION = "1.2"
"""The format of a version without a private split."""
PRIVATE_FORMAT_VERSION = FORMAT_VERSION
"""The format of a version with a private split (1.3)."""
TASKS = ("objnav", "placenav", "vln")

Vec3 = tuple[float, float, float]
Task = Literal["objnav", "placenav", "vln"]
InstructionType = Literal["category", "route", "intention"]
INSTRUCTION_TYPES: tuple[InstructionType, ...] = ("category", "route", "intention")
"""The instruction types of a PlaceNav episode (the paper's Store Category, VLN Instruction and
Intention Driven): ``category`` names the place ("Find a bank."), ``route`` describes the way along
the reference path, naming landmarks and roads, and ``intention`` states a need the place meets ("I
need to withdraw some cash.")."""
RECORD_CONFIG = ConfigDict(extra="forbid", frozen=True)
"""Configuration of every dataset record (and the manifest): unknown fields refused, values frozen."""


class Goal(BaseModel):
    """A goal instance: an object (ObjNav, VLN) or a storefront (PlaceNav); ``object_id`` is its id."""

    model_config = RECORD_CONFIG

    object_id: int
    category: str
    position: Vec3
    radius: Annotated[float, Field(ge=0.0)]
    size: Vec3


class Landmark(BaseModel):
    """An object an instruction names, seen from the verification rollout near directive ``step``."""

    model_config = RECORD_CONFIG

    object_id: int
    category: str
    color: str | None = None
    step: int


class Instruction(BaseModel):
    """An instruction: the final text, the template it came from, and the landmarks it names.

    A VLN episode's ``instruction_type`` is ``landmark`` or ``refined``; the instructions of a
    PlaceNav episode are ``category``, ``route`` or ``intention`` (:data:`INSTRUCTION_TYPES`)."""

    model_config = RECORD_CONFIG

    instruction_text: str
    template_text: str
    instruction_type: str
    landmarks: list[Landmark] = []
    directive_times: list[float] = []
    """For each directive of the template, the rollout time (s) at which the robot carried it out."""


class Verification(BaseModel):
    """How the physics rollout of an episode went: the robot, its time, its path and when it first
    was within the success distance of a goal."""

    model_config = RECORD_CONFIG

    embodiment: str
    duration_s: float
    traveled_m: float
    oracle_success_time_s: float


class EpisodeInfo(BaseModel):
    """Derived facts of an episode."""

    model_config = RECORD_CONFIG

    geodesic_distance: float
    euclidean_distance: float
    closest_goal_object_id: int
    success_distance: float
    difficulty: Literal["easy", "medium", "hard"] | None = None
    verification: Verification | None = None


class Episode(BaseModel):
    """One navigation episode (DESIGN.md §3).

    In the public file of a private split (:mod:`navverse.dataset.private`) an episode holds only what
    an agent may know: ``goals`` and ``reference_path`` are empty, ``info`` is None and its
    instructions name no landmark and no directive time (:attr:`withheld`)."""

    model_config = RECORD_CONFIG

    episode_id: str
    scene_id: str
    scene_type: SceneType
    task: Task
    start_position: Vec3
    start_rotation: tuple[float, float, float, float]
    object_category: str | None = None
    place_category: str | None = None
    goals: list[Goal]
    instruction: Instruction | None = None
    instructions: dict[InstructionType, Instruction] = {}
    """PlaceNav: the episode's instruction of each type (:data:`INSTRUCTION_TYPES`), all three."""
    reference_path: list[Vec3]
    info: EpisodeInfo | None
    """Derived facts; None only in the public file of a private split."""

    @property
    def withheld(self) -> bool:
        """Whether this is the public record of an episode whose goals are kept private (no ``info``)."""
        return self.info is None

    @property
    def start_yaw(self) -> float:
        """Heading of the start rotation about +z (rad)."""
        x, y, z, w = self.start_rotation
        return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))

    @property
    def goal_category(self) -> str:
        """The object or place category sought."""
        return self.object_category or self.place_category or ""


class EpisodeFile(BaseModel):
    """Contents of one ``<split>/<task>.json.gz``."""

    model_config = RECORD_CONFIG

    episodes: list[Episode]
    goals_by_category: dict[str, list[Goal]] = {}
    category_to_task_category_id: dict[str, int] = {}


# ---------------------------------------------------------------------------------------------- geometry


def success_distance(robot_radius: float, *, scene_type: str) -> float:
    """Largest goal distance that counts as success in a scene of ``scene_type``: the profile's
    success margin plus ``r_robot`` (:mod:`navverse.scene_types`; 1.6 m for Spot)."""
    return scene_profile(scene_type).success_distance(robot_radius)


def goal_distance(position: Sequence[float], goal: Goal) -> float:
    """Distance to a goal (paper Appendix A.5): ``max(0, ||p - p_goal||_2 - r_goal)`` in 3-D (m).

    ``p`` is the robot's base position (x, y, z), ``p_goal`` the goal's centre and ``r_goal`` its radius,
    half its larger horizontal extent.
    """
    d = math.dist((float(position[0]), float(position[1]), float(position[2])), goal.position)
    return max(0.0, d - goal.radius)
