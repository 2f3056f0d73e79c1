"""A modular ObjNav agent that explores frontiers of its own occupancy map (no privileged information).

Each :meth:`FrontierAgent.act`:

1. **Maps** the depth image: pixels (every ``stride``-th row and column) are back-projected with the
   camera intrinsics and the camera pose (``pose`` of the base composed with ``camera_to_base``).
   Heights are taken above the floor, whose depth below the base is estimated once from the first
   views (the lowest well-populated height band under the base). Points in the obstacle band mark
   their cells occupied, floor points mark theirs free, and along every image column the cells
   between the camera and the nearest obstacle (or the farthest floor point) are carved free; a ray
   that should meet the floor within range but does not (an edge, a drop) marks an obstacle where it
   would have. The robot's own footprint is free. Cells hold log-odds, so a few contradicting views
   overturn a wrong one; the map grows as the robot goes.
2. **Detects the goal** in the semantic channel: pixels of instances whose category
   (:attr:`AgentTask.semantic_categories`) is the goal category, when there are enough of them, are
   back-projected and kept (one point per cell-sized voxel).
3. **Plans** on the map with Dijkstra (:func:`scipy.sparse.csgraph.dijkstra`): occupied cells are
   inflated by the robot's half width (impassable) plus a margin (costly), unknown cells cost more
   than free ones. The target is a free cell near the goal points once the goal has been seen,
   otherwise the best reachable frontier cell (free, next to unknown; near and in a large cluster).
   A forward step that does not move the robot marks the cells in front of it occupied; a turn the
   body could not make (it hit something) is followed by a sideways step away from obstacles.
4. **Acts**: turns (30 or 15 degrees) towards a point a little way along the path, then steps forward.
   At the start it turns on the spot to look around (cut short once the goal is in view); with no
   target left it turns to look, and stops after two full turns with none.
   Told an instruction instead of a category (VLN; PlaceNav under ``route`` or ``intention``), it
   looks for the category the instruction names last (:func:`~navverse.eval.agents.goal_text.
   named_goal_category`); it does not follow the route's directions, and an intention names none.
5. **Stops** when the base is within ``stop_distance`` (horizontally) of a goal point, or after
   ``max_steps`` actions.

The agent never reads goal positions, the reference path or the navmesh. Its map is
:mod:`navverse.eval.agents.mapping`, its planner :mod:`navverse.eval.agents.grid_planning`.

>>> agent = FrontierAgent()  # doctest: +SKIP
>>> agent.reset(task)  # doctest: +SKIP
>>> action = agent.act(observation, info)  # doctest: +SKIP
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy import ndimage

from navverse.eval.agents.base import AgentTask
from navverse.eval.agents.goal_text import named_goal_category
from navverse.eval.agents.grid_planning import grid_dijkstra, trace_path, traversal_costs
from navverse.eval.agents.mapping import (
    LOGODDS_CLAMP,
    LogOddsGrid,
    OccupancyMap,
    back_project,
    column_free_ranges,
    disk,
    estimate_floor,
    pixel_rays,
    pose_matrix,
    pose_yaw,
)
from navverse.sim.actions import DISCRETE_ACTIONS
from navverse.sim.controller import wrap_angle

__all__ = ["FrontierAgent", "heading_action"]

STOP = DISCRETE_ACTIONS.index("stop")
FORWARD = DISCRETE_ACTIONS.index("forward")
LEFT = DISCRETE_ACTIONS.index("left")
RIGHT = DISCRETE_ACTIONS.index("right")
ROTATE_LEFT = DISCRETE_ACTIONS.index("rotate_left")
ROTATE_RIGHT = DISCRETE_ACTIONS.index("rotate_right")
SMALL_LEFT = DISCRETE_ACTIONS.index("small_rotate_left")
SMALL_RIGHT = DISCRETE_ACTIONS.index("small_rotate_right")

_PLAN_MARGIN = 1.0  # m of unknown around the known area the planner may cross
_TURNS = {ROTATE_LEFT: 30.0, ROTATE_RIGHT: -30.0, SMALL_LEFT: 15.0, SMALL_RIGHT: -15.0}  # degrees
_FLOOR_VIEWS = 5  # views whose floor estimates are pooled (median) before the floor offset is fixed


def heading_action(yaw: float, bearing: float, *, tolerance: float = math.radians(12.0)) -> int:
    """The discrete action towards a bearing: a 30- or 15-degree turn, or forward when within tolerance."""
    error = wrap_angle(bearing - yaw)
    if abs(error) > math.radians(22.5):
        return ROTATE_LEFT if error > 0 else ROTATE_RIGHT
    if abs(error) > tolerance:
        return SMALL_LEFT if error > 0 else SMALL_RIGHT
    return FORWARD


# ---------------------------------------------------------------------------------------------- the agent


class FrontierAgent:
    """Frontier exploration with an occupancy map from depth and goal detection from semantics.

    Parameters
    ----------
    cell_size : float
        Map cell edge (m).
    map_size : float
        Initial map edge (m), centred at the start; the map grows as needed.
    obstacle_band : tuple of float
        Heights above the floor (m) whose points are obstacles; lower points are floor.
    drop_height : float
        Points this far below the floor (a drop) are obstacles too (m).
    max_depth : float
        Farthest depth (m) used for mapping.
    goal_depth : float
        Farthest depth (m) at which goal pixels are kept.
    stride : int
        Pixel subsampling step of the mapping.
    min_goal_pixels : int
        Fewest goal pixels (full resolution) in a view for a detection.
    body_radius : float, optional
        Clearance (m) from obstacle cells the robot's centre keeps; default half the robot's width
        (``info["robot_size"]``) plus a cell, or 0.3 m.
    clearance_margin : float
        Width (m) of the costly band beyond ``body_radius``.
    stop_distance : float
        Horizontal distance (m) from the base to the nearest goal point at which the agent stops.
    lookahead : float
        Distance (m) along the path of the point the robot turns towards.
    max_steps : int
        The agent stops at its ``max_steps``-th action.
    initial_turns : int
        30-degree turns made at the start to look around (the goal in view cuts them short).
    min_frontier_cells : int
        Smallest frontier cluster that is a target.
    frontier_size_cap : float
        A frontier cell's score is its path cost (m) less its cluster's length (m, at most this) ...
    turn_weight : float
        ... plus this many meters per radian the robot would turn to face it.
    """

    action_mode = "discrete"
    privileged = False
    sensors = ("depth", "semantic")

    def __init__(
        self,
        *,
        cell_size: float = 0.1,
        map_size: float = 20.0,
        obstacle_band: tuple[float, float] = (0.1, 1.5),
        drop_height: float = 0.3,
        max_depth: float = 5.0,
        goal_depth: float = 10.0,
        stride: int = 4,
        min_goal_pixels: int = 80,
        body_radius: float | None = None,
        clearance_margin: float = 0.4,
        stop_distance: float = 1.0,
        lookahead: float = 0.5,
        max_steps: int = 500,
        initial_turns: int = 9,
        min_frontier_cells: int = 3,
        frontier_size_cap: float = 3.0,
        turn_weight: float = 0.5,
    ) -> None:
        if cell_size <= 0 or map_size <= 0 or stride < 1 or max_steps < 1:
            raise ValueError("cell_size and map_size must be > 0, stride and max_steps >= 1")
        self.cell_size = cell_size
        self.map_size = map_size
        self.obstacle_band = obstacle_band
        self.drop_height = drop_height
        self.max_depth = max_depth
        self.goal_depth = goal_depth
        self.stride = stride
        self.min_goal_pixels = min_goal_pixels
        self.body_radius = body_radius
        self.clearance_margin = clearance_margin
        self.stop_distance = stop_distance
        self.lookahead = lookahead
        self.max_steps = max_steps
        self.initial_turns = initial_turns
        self.min_frontier_cells = min_frontier_cells
        self.frontier_size_cap = frontier_size_cap
        self.turn_weight = turn_weight
        self.reset(AgentTask("", "objnav", "", "", "indoor", "", 0.0))

    # ------------------------------------------------------------------ read-only state

    @property
    def map(self) -> OccupancyMap | None:
        """The current occupancy map (None before the first observation)."""
        return None if self._grid is None else self._grid.snapshot()

    @property
    def goal_points(self) -> np.ndarray:
        """World points ``(N, 3)`` seen on goal instances so far (one per cell-sized voxel)."""
        out = self._goal_points.copy()
        out.setflags(write=False)
        return out

    @property
    def floor_height(self) -> float | None:
        """The floor's height under the robot at the last observation (None until estimated)."""
        if self._floor_offset is None or self._pose is None:
            return None
        return float(self._pose[2] - self._floor_offset)

    @property
    def path(self) -> np.ndarray:
        """World ``(x, y)`` of the cells of the last planned path (empty if none)."""
        return self._path.copy()

    @property
    def steps(self) -> int:
        """Actions taken in this episode."""
        return self._steps

    # ------------------------------------------------------------------ the Agent protocol

    def reset(self, task: AgentTask) -> None:
        """Start an episode: forget the map, the goal points and the plan."""
        self.task = task
        sought = task.goal_category or named_goal_category(task.goal, task.semantic_categories.values())
        self._goal_ids = np.array(
            sorted(i for i, c in task.semantic_categories.items() if c == sought), dtype=np.int64
        )
        self._grid: LogOddsGrid | None = None
        self._goal_points = np.zeros((0, 3))
        self._floor_estimates: list[float] = []
        self._floor_offset: float | None = None
        self._pose: np.ndarray | None = None
        self._last: tuple[int, np.ndarray] | None = None
        self._target: tuple[float, float] | None = None
        self._visited: list[tuple[float, float]] = []
        self._path = np.zeros((0, 2))
        self._robot_size: np.ndarray | None = None
        self._turns_left = self.initial_turns
        self._idle = 0
        self._steps = 0
        self._escape: int | None = None

    def act(self, observation: dict[str, Any], info: dict[str, Any]) -> int:
        """The next discrete action (an index into :data:`~navverse.sim.actions.DISCRETE_ACTIONS`)."""
        pose = np.asarray(observation["pose"], dtype=float)
        self._steps += 1
        if self._grid is None:
            self._grid = LogOddsGrid(pose, size=self.map_size, cell=self.cell_size)
        self._pose = pose
        if "robot_size" in info:
            self._robot_size = np.asarray(info["robot_size"], dtype=float)
        self._note_blocked(pose)
        self._note_blocked_turn(pose)
        self._observe(observation, info, pose)
        action = self._decide(pose)
        self._last = (action, pose)
        return action

    # ------------------------------------------------------------------ perception

    def _observe(self, observation: dict[str, Any], info: dict[str, Any], pose: np.ndarray) -> None:
        """Update the goal points, the floor estimate and the map from one observation."""
        depth = np.asarray(observation["depth"])
        depth = depth.reshape(depth.shape[0], depth.shape[1])
        camera = pose_matrix(pose) @ np.asarray(info["camera_to_base"], dtype=float)
        k = np.asarray(info["camera_intrinsics"], dtype=float)
        if len(self._goal_ids):
            self._detect_goal(depth, np.asarray(observation["semantic"]), k, camera)
        points, hit = back_project(depth, k, camera, stride=self.stride)
        near = hit & (depth[:: self.stride, :: self.stride] <= self.max_depth)
        self._update_floor(points[near], pose, camera)
        if self._floor_offset is not None:
            rays = pixel_rays(k, depth.shape, camera[:3, :3], stride=self.stride)
            self._map_points(points, hit, near, rays, pose, camera)

    def _update_floor(self, points: np.ndarray, pose: np.ndarray, camera: np.ndarray) -> None:
        """Estimate the base's height above the floor from the first views (median of their estimates)."""
        if len(self._floor_estimates) >= _FLOOR_VIEWS:
            return
        near = np.hypot(points[:, 0] - camera[0, 3], points[:, 1] - camera[1, 3]) < 4.0
        floor = estimate_floor(points[near, 2], below=float(min(pose[2], camera[2, 3])) - 0.05)
        if floor is not None:
            self._floor_estimates.append(float(pose[2]) - floor)
            self._floor_offset = float(np.median(self._floor_estimates))

    def _map_points(
        self,
        points: np.ndarray,
        hit: np.ndarray,
        near: np.ndarray,
        rays: np.ndarray,
        pose: np.ndarray,
        camera: np.ndarray,
    ) -> None:
        """Add one view to the map (``hit``: pixels with a return; ``near``: those within range)."""
        grid = self._grid
        floor_z = pose[2] - self._floor_offset
        height = points[..., 2] - floor_z
        lo, hi = self.obstacle_band
        obstacle = near & (((height >= lo) & (height <= hi)) | (height < -self.drop_height))
        floor = near & (height < lo) & (height >= -self.drop_height)
        # A ray that should meet the floor within range but finds nothing there looks over an edge.
        with np.errstate(divide="ignore", invalid="ignore"):
            t_floor = np.where(rays[..., 2] < -1e-6, (floor_z - camera[2, 3]) / rays[..., 2], np.inf)
        void = (t_floor <= self.max_depth) & (~hit | (height < -self.drop_height))
        points = np.where(
            void[..., None], camera[:3, 3] + np.where(void, t_floor, 0.0)[..., None] * rays, points
        )
        obstacle |= void
        camera_xy = camera[:2, 3]
        ranges = column_free_ranges(points, near | void, obstacle, floor, camera_xy) - 0.5 * self.cell_size
        bearings = rays[rays.shape[0] // 2, :, :2]  # the columns' horizontal directions
        bearings = bearings / np.maximum(np.linalg.norm(bearings, axis=1, keepdims=True), 1e-9)
        t = np.arange(0.0, self.max_depth, 0.5 * self.cell_size)
        carved = (camera_xy + t[None, :, None] * bearings[:, None, :])[t[None, :] < ranges[:, None]]
        body = self._body_cells(pose)
        hits = points[obstacle][:, :2]
        seen_free = np.concatenate([points[floor][:, :2], carved, body])
        everything = np.concatenate([hits, seen_free, pose[None, :2]])
        grid.fit(everything.min(axis=0), everything.max(axis=0))
        grid.update(grid.mask(seen_free), grid.mask(hits))

    def _body_cells(self, pose: np.ndarray) -> np.ndarray:
        """World points covering the robot's footprint (it stands there, so that floor is free).

        The footprint is the ``robot_size`` rectangle (length along the heading) when ``info`` gave one,
        else a disk of the body radius. Turning on the spot sweeps it round, which frees the floor
        around the robot that the camera, mounted at its front, never sees.
        """
        half = 0.5 * self.cell_size
        if self._robot_size is None:
            length = width = 2.0 * self._body_radius()
        else:
            length, width = float(self._robot_size[0]), float(self._robot_size[1])
        u = np.arange(-0.5 * length, 0.5 * length + half, half)
        v = np.arange(-0.5 * width, 0.5 * width + half, half)
        u, v = (a.ravel() for a in np.meshgrid(u, v))
        yaw = pose_yaw(pose)
        c, s = math.cos(yaw), math.sin(yaw)
        return pose[:2] + np.stack([c * u - s * v, s * u + c * v], -1)

    def _detect_goal(
        self, depth: np.ndarray, semantic: np.ndarray, k: np.ndarray, camera: np.ndarray
    ) -> None:
        """Keep the world points of goal pixels (every other row and column) when there are enough."""
        step = 2
        goal = np.isin(semantic[::step, ::step], self._goal_ids)
        goal &= (depth[::step, ::step] > 0) & (depth[::step, ::step] <= self.goal_depth)
        if goal.sum() * step * step < self.min_goal_pixels:
            return
        points, _ = back_project(depth, k, camera, stride=step)
        new = np.concatenate([self._goal_points, points[goal]])
        keys = np.floor(new / self.cell_size).astype(np.int64)
        _, first = np.unique(keys, axis=0, return_index=True)
        self._goal_points = new[np.sort(first)]

    # ------------------------------------------------------------------ decisions

    def _decide(self, pose: np.ndarray) -> int:
        """Stop, escape a blocked turn, look around at the start, or follow the plan."""
        if self._steps >= self.max_steps:
            return STOP
        if self._goal_distance(pose) <= self.stop_distance:
            return STOP
        if self._escape is not None:
            action, self._escape = self._escape, None
            return action
        if self._turns_left > 0 and not len(self._goal_points):
            self._turns_left -= 1
            return ROTATE_LEFT
        self._turns_left = 0
        if self._floor_offset is None:
            return ROTATE_LEFT
        return self._navigate(pose)

    def _goal_distance(self, pose: np.ndarray) -> float:
        """Horizontal distance (m) from the base to the nearest goal point (inf before any is seen)."""
        if not len(self._goal_points):
            return math.inf
        return float(np.hypot(*(self._goal_points[:, :2] - pose[:2]).T).min())

    def _body_radius(self) -> float:
        """Clearance (m) the robot's centre keeps from obstacle cells."""
        if self.body_radius is not None:
            return self.body_radius
        if self._robot_size is None:
            return 0.3
        return 0.5 * float(self._robot_size[1]) + self.cell_size

    def _navigate(self, pose: np.ndarray) -> int:
        """Turn towards the plan or step along it; with no target, turn to look (and stop eventually)."""
        plan = self._plan(pose)
        if plan is None:
            self._idle += 1
            if self._idle == 12:  # looked all round without a target: try the skipped frontiers again
                self._visited.clear()
            return STOP if self._idle > 24 else ROTATE_LEFT
        self._idle = 0
        return heading_action(pose_yaw(pose), self._bearing_along(pose, plan))

    def _bearing_along(self, pose: np.ndarray, path: np.ndarray) -> float:
        """Bearing from the robot to the first path point at least ``lookahead`` away (else the last)."""
        distance = np.hypot(*(path - pose[:2]).T)
        far = np.nonzero(distance >= self.lookahead)[0]
        point = path[far[0]] if len(far) else path[-1]
        return math.atan2(point[1] - pose[1], point[0] - pose[0])

    def _plan(self, pose: np.ndarray) -> np.ndarray | None:
        """A path (world xy, from the robot) to the current target, choosing a new target if needed."""
        grid = self._grid
        window = self._window(pose)
        occupied = grid.occupied()[window]
        unknown = ~grid.observed[window]
        radius = self._body_radius()
        costs = traversal_costs(
            occupied, unknown, cell_size=grid.cell, body_radius=radius, margin=self.clearance_margin
        )
        row, col = grid.cells(pose[None, :2])
        start = (int(row[0]) - window[0].start, int(col[0]) - window[1].start)
        # The robot stands where it is: let it leave a spot the inflation closed (not an obstacle).
        near = np.zeros_like(occupied)
        near[start] = True
        near = ndimage.binary_dilation(near, disk(radius / grid.cell)) & ~occupied & ~np.isfinite(costs)
        costs[near] = 10.0
        costs[start] = 1.0
        distance, predecessors = grid_dijkstra(costs, start)
        target = self._choose_target(pose, window, distance, unknown)
        if target is None:
            self._path = np.zeros((0, 2))
            return None
        cells = trace_path(predecessors, target, costs.shape[1])
        self._path = grid.centers(cells[:, 0] + window[0].start, cells[:, 1] + window[1].start)
        return self._path

    def _window(self, pose: np.ndarray) -> tuple[slice, slice]:
        """The part of the map worth planning on: what was observed, the robot and the goal points."""
        grid = self._grid
        rows, cols = np.nonzero(grid.observed)
        r, c = grid.cells(np.concatenate([pose[None, :2], self._goal_points[:, :2]]))
        rows, cols = np.concatenate([rows, r]), np.concatenate([cols, c])
        pad = math.ceil(_PLAN_MARGIN / grid.cell)
        return (
            slice(max(0, int(rows.min()) - pad), min(grid.shape[0], int(rows.max()) + pad + 1)),
            slice(max(0, int(cols.min()) - pad), min(grid.shape[1], int(cols.max()) + pad + 1)),
        )

    def _choose_target(
        self,
        pose: np.ndarray,
        window: tuple[slice, slice],
        distance: np.ndarray,
        unknown: np.ndarray,
    ) -> tuple[int, int] | None:
        """A cell near the goal once it has been seen and one is reachable, else a frontier cell."""
        reachable = np.isfinite(distance)
        if len(self._goal_points):
            target = self._goal_target(window, distance, reachable)
            if target is not None:
                return target
        return self._frontier_target(pose, window, distance, reachable, unknown)

    def _goal_target(
        self, window: tuple[slice, slice], distance: np.ndarray, reachable: np.ndarray
    ) -> tuple[int, int] | None:
        """The cheapest reachable cell within ``stop_distance`` (less a cell) of a goal point."""
        grid = self._grid
        goal = grid.mask(self._goal_points[:, :2])[window]
        near = ndimage.distance_transform_edt(~goal) * grid.cell <= self.stop_distance - grid.cell
        candidates = np.where(near & reachable, distance, np.inf)
        if not np.isfinite(candidates).any():
            return None
        self._target = None
        return tuple(int(v) for v in np.unravel_index(np.argmin(candidates), candidates.shape))

    def _frontier_target(
        self,
        pose: np.ndarray,
        window: tuple[slice, slice],
        distance: np.ndarray,
        reachable: np.ndarray,
        unknown: np.ndarray,
    ) -> tuple[int, int] | None:
        """The frontier cell that is cheapest to reach, discounted for large frontier clusters."""
        grid = self._grid
        free = grid.free()[window]
        frontier = free & ndimage.binary_dilation(unknown, ndimage.generate_binary_structure(2, 1))
        labels, n = ndimage.label(frontier, ndimage.generate_binary_structure(2, 2))
        if n == 0:
            return None
        sizes = np.bincount(labels.ravel())
        candidates = frontier & reachable & (sizes[labels] >= self.min_frontier_cells)
        offset = np.array([window[0].start, window[1].start])
        for x, y in self._visited:
            cell = grid.cells(np.array([[x, y]]))
            r = np.array([cell[0][0], cell[1][0]]) - offset
            self._clear_disk(candidates, r, 1.0 / grid.cell)
        robot = np.array(grid.cells(pose[None, :2]))[:, 0] - offset
        self._clear_disk(candidates, robot, self.lookahead / grid.cell)
        if self._target is not None:
            kept = self._keep_target(pose, candidates, offset)
            if kept is not None:
                return kept
        if not candidates.any():
            return None
        rows, cols = np.nonzero(candidates)
        centers = grid.centers(rows + offset[0], cols + offset[1])
        bearing = np.arctan2(centers[:, 1] - pose[1], centers[:, 0] - pose[0])
        turn = np.abs((bearing - pose_yaw(pose) + math.pi) % (2.0 * math.pi) - math.pi)
        size_m = np.minimum(sizes[labels[rows, cols]] * grid.cell, self.frontier_size_cap)
        score = distance[rows, cols] * grid.cell - size_m + self.turn_weight * turn
        best = int(np.argmin(score))
        self._target = (float(centers[best, 0]), float(centers[best, 1]))
        return int(rows[best]), int(cols[best])

    def _keep_target(
        self, pose: np.ndarray, candidates: np.ndarray, offset: np.ndarray
    ) -> tuple[int, int] | None:
        """The current frontier target, while it is still a candidate and not reached yet."""
        grid = self._grid
        tx, ty = self._target
        if math.hypot(tx - pose[0], ty - pose[1]) < self.lookahead:
            self._visited.append(self._target)
            self._target = None
            return None
        row, col = (int(v[0]) for v in grid.cells(np.array([[tx, ty]])))
        r, c = row - offset[0], col - offset[1]
        if 0 <= r < candidates.shape[0] and 0 <= c < candidates.shape[1] and candidates[r, c]:
            return int(r), int(c)
        self._target = None
        return None

    @staticmethod
    def _clear_disk(mask: np.ndarray, center: np.ndarray, radius: float) -> None:
        """Set ``mask`` False within ``radius`` cells of the cell ``center`` (row, col)."""
        r0, c0 = int(center[0]), int(center[1])
        k = math.ceil(radius)
        rows = slice(max(0, r0 - k), max(0, min(mask.shape[0], r0 + k + 1)))
        cols = slice(max(0, c0 - k), max(0, min(mask.shape[1], c0 + k + 1)))
        rr, cc = np.mgrid[rows, cols]
        mask[rows, cols] &= (rr - r0) ** 2 + (cc - c0) ** 2 > radius * radius

    # ------------------------------------------------------------------ getting unstuck

    def _note_blocked(self, pose: np.ndarray) -> None:
        """After a forward step that did not move the robot, mark the cells just ahead of it occupied."""
        if self._last is None or self._last[0] != FORWARD:
            return
        before = self._last[1]
        if math.hypot(pose[0] - before[0], pose[1] - before[1]) >= 0.05:
            return
        yaw = pose_yaw(pose)
        forward = np.array([math.cos(yaw), math.sin(yaw)])
        left = np.array([-forward[1], forward[0]])
        length = 0.6 if self._robot_size is None else float(self._robot_size[0])
        ahead = pose[:2] + forward * (0.5 * length + self.cell_size)
        across = np.linspace(-self._body_radius(), self._body_radius(), 7)
        blocked = ahead + across[:, None] * left
        self._grid.fit(blocked.min(axis=0), blocked.max(axis=0))
        mask = self._grid.mask(blocked)
        self._grid.logodds[mask] = LOGODDS_CLAMP[1]
        self._grid.observed |= mask
        self._target = None

    def _note_blocked_turn(self, pose: np.ndarray) -> None:
        """After a turn the body could not make (it hit something), step sideways, away from obstacles."""
        if self._last is None or self._last[0] not in _TURNS:
            return
        turned = math.degrees(wrap_angle(pose_yaw(pose) - pose_yaw(self._last[1])))
        if abs(turned) >= abs(_TURNS[self._last[0]]) / 3.0:
            return
        yaw = pose_yaw(pose)
        forward = np.array([math.cos(yaw), math.sin(yaw)])
        left = np.array([-forward[1], forward[0]])
        along = np.linspace(-0.6, 0.6, 7)
        away = np.linspace(0.3, 0.8, 6)
        occupied = self._grid.occupied()
        counts = []
        for side in (left, -left):
            points = pose[:2] + along[:, None, None] * forward + away[None, :, None] * side
            row, col = self._grid.cells(points.reshape(-1, 2))
            inside = (row >= 0) & (row < occupied.shape[0]) & (col >= 0) & (col < occupied.shape[1])
            counts.append(int(occupied[row[inside], col[inside]].sum()))
        self._escape = LEFT if counts[0] <= counts[1] else RIGHT
