"""Walkers on a scene's navmesh: Recast's DetourCrowd behind a small z-up API.

DetourCrowd is the crowd simulation of the library our navmeshes come from: each agent keeps a path
corridor along the navmesh polygons to its target (replanned as it goes), steers round its neighbours
by sampling velocities against their velocity obstacles (ORCA-like, with an adaptive sampling
pattern), keeps apart from them by a separation force and stays on the polygons its filter allows.
Using it rather than a hand-written social-force model gives, for free, exactly the walkable surface
the robot's own paths use, with the terrain classes as area types: a kind of walker can be kept off
roads (and so cross them only where a crosswalk polygon joins two sidewalks) by excluding the ``road``
area, and prefer sidewalks by area costs.

The crowd runs on its own copy of the navmesh (its polygon flags mark which kinds may walk where), in
single-threaded float arithmetic: the same agents, targets and steps give the same trajectories.

>>> from navverse.nav.scene_navmesh import load_scene_navmesh
>>> crowd = Crowd(load_scene_navmesh(scene_dir), [PEDESTRIAN], max_agents=100)  # doctest: +SKIP
>>> agent = crowd.add(start, "pedestrian")  # doctest: +SKIP
>>> crowd.walk_to(agent, goal); crowd.step(0.1)  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from navverse.extensions import missing_extension
from navverse.nav.fileformat import read_navmesh
from navverse.nav.pathfinder import PathFinder

try:
    from navverse.dynamics import _crowd
except ImportError as exc:  # pragma: no cover - depends on the installation
    raise missing_extension(
        "navverse.dynamics._crowd", library="RecastNavigation", package="librecast-dev"
    ) from exc

__all__ = ["PEDESTRIAN", "Crowd", "CrowdState", "TargetState", "WalkerKind"]

MAX_KINDS = 15
"""Most kinds of walker one crowd holds (one DetourCrowd query filter each)."""


@dataclass(frozen=True)
class WalkerKind:
    """A kind of walker: its body, its pace and where it may walk.

    Attributes
    ----------
    name : str
        What the kind is called (``add`` takes it).
    radius, height : float
        Body cylinder (m).
    max_speed : float
        Preferred walking speed (m/s); the crowd slows it to avoid others.
    max_acceleration : float
        Largest change of velocity per second (m/s²).
    separation_weight : float
        How strongly it keeps apart from neighbours (DetourCrowd's separation).
    excluded_areas : tuple of str
        Area names (a scene's terrain classes) it never walks on.
    area_costs : mapping of str to float
        Cost per meter of an area (>= 1; others cost 1), to prefer some surfaces.
    avoidance_quality : int
        Velocity sampling of its avoidance, 0 (coarse, cheap) to 3 (fine).
    """

    name: str
    radius: float = 0.3
    height: float = 1.7
    max_speed: float = 1.3
    max_acceleration: float = 4.0
    separation_weight: float = 2.0
    excluded_areas: tuple[str, ...] = ()
    area_costs: Mapping[str, float] = field(default_factory=dict)
    avoidance_quality: int = 2


PEDESTRIAN = WalkerKind(
    name="pedestrian",
    excluded_areas=("road", "parking", "building"),
    area_costs={"curb": 2.0, "green": 1.5, "ground": 1.5},
)
"""A person on foot: 0.3 m radius, 1.3 m/s, off roads and parking (crosswalks allowed), preferring
sidewalks."""


class TargetState:
    """What an agent's move request is (DetourCrowd's ``MoveRequestState``)."""

    NONE = 0
    FAILED = 1
    VALID = 2
    PLANNING = (3, 4, 5)
    VELOCITY = 6


@dataclass(frozen=True)
class CrowdState:
    """Every agent slot of a crowd after a step (inactive slots are zeros).

    Attributes
    ----------
    positions, velocities : ndarray of float, shape (N, 3)
        World positions on the navmesh and velocities (z up).
    active : ndarray of bool, shape (N,)
        Slots holding an agent.
    areas : ndarray of int16, shape (N,)
        Area id of the polygon under each agent (-1: none).
    """

    positions: np.ndarray
    velocities: np.ndarray
    active: np.ndarray
    areas: np.ndarray


class Crowd:
    """Agents of some kinds walking a navmesh.

    Parameters
    ----------
    finder : PathFinder
        The navmesh (with its area names, as ``load_scene_navmesh`` gives it); the crowd walks a copy.
    kinds : sequence of WalkerKind
        The kinds of walker it holds (at most :data:`MAX_KINDS`, names distinct).
    max_agents : int, keyword-only
        Agent slots.
    reach : float, keyword-only
        Horizontal half size (m) of the box searched for the navmesh round a point given.

    Raises
    ------
    ValueError
        If a kind names an area the navmesh has no name for, or the kinds or slots are out of range.
    """

    def __init__(
        self, finder: PathFinder, kinds: Sequence[WalkerKind], *, max_agents: int, reach: float = 2.0
    ) -> None:
        kinds = list(kinds)
        if not 1 <= len(kinds) <= MAX_KINDS:
            raise ValueError(f"a crowd holds 1 to {MAX_KINDS} kinds of walker, got {len(kinds)}")
        names = [k.name for k in kinds]
        if len(set(names)) != len(names):
            raise ValueError(f"kinds of walker need distinct names, got {names}")
        areas = finder.area_names
        if not areas and any(k.excluded_areas or k.area_costs for k in kinds):
            raise ValueError(
                "the navmesh names no areas, so no kind can be kept off one: load a scene's navmesh with "
                "navverse.nav.scene_navmesh.load_scene_navmesh (or name them with PathFinder.name_areas)"
            )
        excluded, costs = [], []
        for kind in kinds:
            excluded.append(sorted(areas[a] for a in kind.excluded_areas if a in areas))
            table = [1.0] * 64
            for area, cost in kind.area_costs.items():
                if area not in areas:
                    continue  # a surface this scene does not have
                if not cost >= 1.0:
                    raise ValueError(f"{kind.name}: the cost of area {area!r} must be at least 1, got {cost}")
                table[areas[area]] = float(cost)
            costs.append(table)
        _, tiles = read_navmesh(finder.to_bytes(), source="the crowd's navmesh")
        largest = max(k.radius for k in kinds)
        self._kinds = {kind.name: (index, kind) for index, kind in enumerate(kinds)}
        self._reach = float(reach)
        self._crowd = _crowd.Crowd(tiles, int(max_agents), largest, excluded, costs)

    @property
    def max_agents(self) -> int:
        """Agent slots."""
        return int(self._crowd.max_agents)

    def add(self, position: ArrayLike, kind: str) -> int | None:
        """Put an agent of `kind` on the navmesh point nearest `position` (one its kind may walk).

        Returns
        -------
        int or None
            Its slot, or None if no allowed navmesh point is within reach or the crowd is full.
        """
        if kind not in self._kinds:
            raise ValueError(f"unknown kind of walker {kind!r}; this crowd has: {', '.join(self._kinds)}")
        index, spec = self._kinds[kind]
        native = _crowd.CrowdAgentSpec()
        native.radius, native.height = spec.radius, spec.height
        native.max_speed, native.max_acceleration = spec.max_speed, spec.max_acceleration
        native.separation_weight = spec.separation_weight
        native.collision_query_range = 12.0 * spec.radius
        native.path_optimization_range = 30.0 * spec.radius
        native.filter, native.avoidance_quality = index, spec.avoidance_quality
        agent = self._crowd.add_agent(_xyz(position), native, self._reach)
        return None if agent < 0 else int(agent)

    def remove(self, agent: int) -> None:
        """Free an agent's slot."""
        self._crowd.remove_agent(int(agent))

    def walk_to(self, agent: int, target: ArrayLike) -> bool:
        """Send an agent to the allowed navmesh point nearest `target`; False if there is none."""
        return bool(self._crowd.set_target(int(agent), _xyz(target), self._reach))

    def move_at(self, agent: int, velocity: ArrayLike) -> bool:
        """Move an agent at a horizontal velocity instead of to a target (a body another simulation
        drives, as the robot; the others avoid it as they avoid each other)."""
        return bool(self._crowd.set_velocity(int(agent), _xyz(velocity)))

    def place(self, agent: int, position: ArrayLike) -> bool:
        """Put an agent at the navmesh point nearest `position` (where another simulation moved it);
        False if there is none within reach."""
        return bool(self._crowd.place(int(agent), _xyz(position), self._reach))

    def target_state(self, agent: int) -> int:
        """An agent's move request (:class:`TargetState`)."""
        return int(self._crowd.target_state(int(agent)))

    def step(self, dt: float) -> None:
        """Advance every agent by `dt` seconds."""
        self._crowd.update(float(dt))

    def state(self) -> CrowdState:
        """Positions, velocities, activity and area of every slot."""
        return CrowdState(*self._crowd.state())


def _xyz(value: ArrayLike) -> np.ndarray:
    point = np.asarray(value, dtype=float).reshape(-1)
    if point.shape != (3,) or not np.isfinite(point).all():
        raise ValueError(f"expected a finite point (x, y, z), got {value!r}")
    return point
