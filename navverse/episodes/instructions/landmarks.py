"""Landmarks: the objects the robot's camera sees near each directive, and the names of their colours.

Frames are ray-cast from a rollout's camera poses in a window before each turn (after the initial turn
for the start, before the end for the arrival). Objects with at least ``min_pixels`` pixels at a mean
depth of at most ``max_landmark_distance`` are candidates; distinctive ones (their category unique
among the objects seen there, else made unique by their colour) are preferred, then larger and nearer
ones (:class:`LandmarkFinder`). A landmark is described by colour (:func:`object_color`, a small palette
named by :func:`color_name`) and category.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial.transform import Rotation

from navverse.episodes.instructions.directives import Directive, wrap_angle
from navverse.episodes.instructions.places import PLACE_NAMES
from navverse.episodes.instructions.settings import InstructionSettings
from navverse.episodes.instructions.wording import category_words
from navverse.records.schema import Episode
from navverse.scene.colors import default_color
from navverse.scene.geometry import Scene, SceneObject
from navverse.sim.camera import CameraIntrinsics, check_pose
from navverse.sim.keyframes import camera_poses
from navverse.sim.render import SceneRenderer, Shading

__all__ = ["PALETTE", "LandmarkFinder", "SeenLandmark", "color_name", "object_color"]

PALETTE = (
    "red",
    "orange",
    "yellow",
    "green",
    "blue",
    "purple",
    "pink",
    "brown",
    "beige",
    "white",
    "gray",
    "black",
)
"""Colour names :func:`color_name` can return."""


def _color_indices(rgb: np.ndarray) -> np.ndarray:
    """Index into PALETTE of each sRGB colour of an (N, 3) array (vectorised :func:`color_name`)."""
    c = np.asarray(rgb, dtype=float).reshape(-1, 3) / 255.0
    hi, lo = c.max(axis=1), c.min(axis=1)
    chroma, light = hi - lo, 0.5 * (hi + lo)
    saturation = np.divide(chroma, hi, out=np.zeros_like(hi), where=hi > 0)
    r, g, b = c.T
    safe = np.where(chroma > 0, chroma, 1.0)
    hue = np.where(
        hi == r, ((g - b) / safe) % 6.0, np.where(hi == g, (b - r) / safe + 2.0, (r - g) / safe + 4.0)
    )
    hue = np.where(chroma > 0, hue * 60.0, 0.0)
    bins = np.array([15.0, 42.0, 70.0, 165.0, 255.0, 290.0, 345.0])
    # red, orange, yellow, green, blue, purple, pink, red
    index = np.array([0, 1, 2, 3, 4, 5, 6, 0])[np.searchsorted(bins, hue, side="right")]
    index = np.where((index == 0) & (light >= 0.7), 6, index)  # light red: pink
    index = np.where((index == 6) & (light < 0.4), 5, index)  # dark pink: purple
    warm = (hue >= 8.0) & (hue < 50.0)
    brown = (warm & (hi < 0.7)) | ((hue >= 50.0) & (hue < 65.0) & (hi < 0.45))
    index = np.where(brown, 7, index)
    beige = (hue >= 20.0) & (hue < 65.0) & (light >= 0.6) & (saturation < 0.45) & (chroma >= 0.08)
    index = np.where(beige, 8, index)
    gray = np.where(light >= 0.8, 9, np.where(light < 0.22, 11, 10))
    index = np.where((chroma < 0.12) & ~beige, gray, index)
    return np.where(hi < 0.16, 11, index)


def color_name(rgb: Sequence[int]) -> str:
    """Name an sRGB colour (0..255) with one of :data:`PALETTE`.

    Low-chroma colours are white, gray or black by lightness (warm light ones beige); dark warm hues
    are brown; otherwise the hue decides (red, orange, yellow, green, blue, purple, pink; light red
    is pink).
    """
    return PALETTE[int(_color_indices(np.asarray(rgb).reshape(1, 3))[0])]


def object_color(obj: SceneObject) -> str:
    """The colour name covering the largest area of an object's mesh (its category colour if uncoloured)."""
    mesh = obj.mesh
    if mesh.face_colors is None or mesh.num_faces == 0:
        return color_name(default_color(obj.annotation.category))
    tri = mesh.vertices[mesh.faces]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    weights = np.bincount(_color_indices(mesh.face_colors), weights=area, minlength=len(PALETTE))
    return PALETTE[int(np.argmax(weights))]


@dataclass(frozen=True)
class SeenLandmark:
    """A landmark chosen for a directive."""

    object_id: int
    category: str
    color: str | None
    near_goal: bool

    @property
    def phrase(self) -> str:
        """Colour and category ("red cabinet"); the category alone when a word of it starts with the
        colour ("whiteboard") or it has no colour (a storefront, named by its place: "pharmacy")."""
        if self.color is None:
            return PLACE_NAMES.get(self.category, category_words(self.category))
        words = category_words(self.category)
        if any(word.lower().startswith(self.color) for word in words.split()):
            return words  # "whiteboard", not "white whiteboard"
        return f"{self.color} {words}"


def _storefront_places(scene: Scene) -> dict[int, str]:
    """The place category of each object that is a storefront's geometry (its box centre is the
    storefront's), so that landmarks name the place ("the pharmacy"), not "the storefront"."""
    by_center = {
        tuple(round(v, 3) for v in s.center): s.place_category for s in scene.annotations.storefronts
    }
    return {
        o.annotation.id: by_center[key]
        for o in scene.objects
        if (key := tuple(round(v, 3) for v in o.annotation.center)) in by_center
    }


class LandmarkFinder:
    """Finds the landmark of each directive of the episodes of one scene, in frames along their rollouts.

    Parameters
    ----------
    scene : Scene
        The scene the episodes are in; its renderer is built once, here.
    camera_to_base : array_like, shape (4, 4)
        Pose of the robot camera's optical frame in the base frame (``Embodiment.camera_to_base``).
    settings : InstructionSettings
        ``resolution``, ``window``, ``frames_per_window``, ``max_landmark_distance``, ``min_pixels``
        and ``near_goal`` are used.

    Notes
    -----
    A finder holds a renderer, so it is not thread-safe: give each thread its own.
    """

    def __init__(self, scene: Scene, *, camera_to_base: ArrayLike, settings: InstructionSettings) -> None:
        self._camera_to_base = check_pose(camera_to_base)
        self._settings = settings
        intrinsics = CameraIntrinsics.from_hfov(*settings.resolution, 90.0)
        # Only instance ids and depth are read: flat shading, the cheapest colours, and no look.
        self._renderer = SceneRenderer(scene, intrinsics=intrinsics, shading=Shading())
        self._objects = {o.annotation.id: o for o in scene.objects}
        self._colors: dict[int, str] = {}
        self._places = _storefront_places(scene)
        self._ids = max(self._objects, default=0) + 1

    def find(
        self, episode: Episode, directives: Sequence[Directive], poses: np.ndarray, rows: np.ndarray
    ) -> tuple[list[SeenLandmark | None], bool]:
        """One landmark (or None) per directive, and whether a goal instance was seen before arriving.

        Parameters
        ----------
        episode : Episode
            An episode of this scene (its goals and goal category are never landmarks).
        directives : sequence of Directive
            Its directives, in path order.
        poses : ndarray, shape (K, 8)
            Its rollout: ``[t, x, y, z, qx, qy, qz, qw]`` robot base poses.
        rows : ndarray of int, shape (N,)
            The rollout row of each directive (:func:`.directives.align_directives`).

        Returns
        -------
        tuple of (list of SeenLandmark or None, bool)
            A landmark per directive (None where none is distinctive and not named already), and
            whether a goal instance was glimpsed in the arrival's window.
        """
        s = self._settings
        goal_ids = {g.object_id for g in episode.goals}
        chosen: list[SeenLandmark | None] = []
        goal_seen = False
        for k, directive in enumerate(directives):
            near, depth, seen = self._visibility(poses[self._window(k, directives, poses, rows)])
            glimpsed = [int(i) for i in np.flatnonzero(seen >= max(1, s.min_pixels // 4))]
            if directive.kind == "arrive":
                goal_seen = not goal_ids.isdisjoint(glimpsed)
            described = Counter(self._describe(i) for i in glimpsed if i in self._objects)
            categories = Counter(category for category, _ in described.elements())
            taken = {lm.phrase for lm in chosen if lm is not None}
            best: tuple[tuple[int, float, int], SeenLandmark] | None = None
            for i in (int(i) for i in np.flatnonzero(near >= s.min_pixels)):
                if i in goal_ids or i not in self._objects:
                    continue
                category, color = self._describe(i)
                obj = self._objects[i]
                if category == episode.goal_category or (
                    directive.kind == "turn"
                    and _footprint_distance(obj, directive.position) > s.max_landmark_distance
                ):
                    continue
                if categories[category] == 1:
                    rank = 0  # the only one of its kind in sight
                elif described[(category, color)] == 1:
                    rank = 1  # the only one of its kind and colour
                else:
                    continue
                near_goal = directive.kind == "arrive" and any(
                    _footprint_distance(obj, g.position) <= s.near_goal for g in episode.goals
                )
                candidate = SeenLandmark(i, category, color, near_goal)
                key = (rank, -near[i] / max(depth[i], 0.5), i)  # distinctive, then large and near
                if candidate.phrase not in taken and (best is None or key < best[0]):
                    best = (key, candidate)
            chosen.append(None if best is None else best[1])
        return chosen, goal_seen

    # ------------------------------------------------------------------------------------------ internals

    def _describe(self, object_id: int) -> tuple[str, str | None]:
        """``(category, colour name)`` of an object; a storefront's is its place category and no colour."""
        if object_id in self._places:
            return self._places[object_id], None
        if object_id not in self._colors:
            self._colors[object_id] = object_color(self._objects[object_id])
        return self._objects[object_id].annotation.category, self._colors[object_id]

    def _window(
        self, k: int, directives: Sequence[Directive], poses: np.ndarray, rows: np.ndarray
    ) -> np.ndarray:
        """Rollout rows whose frames are searched for the landmark of directive `k`.

        The `window` seconds before the directive (not before the previous one); for the start, the
        first `window` seconds after the robot has turned to within 30° of the first segment.
        """
        t, window = poses[:, 0], self._settings.window
        if directives[k].kind == "start":
            (x0, y0, _), (x1, y1, _) = directives[0].position, directives[1].position
            yaw = Rotation.from_quat(poses[rows[0] : rows[1] + 1, 4:8]).as_euler("ZYX")[:, 0]
            aligned = np.flatnonzero(
                np.abs(wrap_angle(yaw - math.atan2(y1 - y0, x1 - x0))) < math.radians(30.0)
            )
            if not len(aligned):
                return np.zeros(0, dtype=int)
            lo = t[rows[0] + aligned[0]]
            hi = min(lo + window, t[rows[1]])
        else:
            hi = t[rows[k]]
            lo = max(t[rows[k - 1]], hi - window)
        wanted = np.linspace(lo, hi, self._settings.frames_per_window)
        return np.unique(np.clip(np.searchsorted(t, wanted), 0, len(t) - 1))

    def _visibility(self, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per object id over the frames of rollout `rows`: the most pixels it covers in a frame where its
        mean depth is within `max_landmark_distance`, that depth, and the most pixels at any
        distance."""
        near, depth, seen = np.zeros(self._ids), np.full(self._ids, np.inf), np.zeros(self._ids)
        for frame in self._renderer.render_batch(camera_poses(rows, self._camera_to_base)):
            ids = frame.semantic.ravel()
            counts = np.bincount(ids, minlength=self._ids)[: self._ids]
            total = np.bincount(ids, weights=frame.depth.ravel(), minlength=self._ids)[: self._ids]
            mean = np.divide(total, counts, out=np.full(self._ids, np.inf), where=counts > 0)
            seen = np.maximum(seen, counts)
            better = (mean <= self._settings.max_landmark_distance) & (counts > near)
            near[better], depth[better] = counts[better], mean[better]
        near[0] = seen[0] = 0.0  # no object
        return near, depth, seen


def _footprint_distance(obj: SceneObject, point: Sequence[float]) -> float:
    """Horizontal distance from a point to an object's oriented bounding box footprint (0 inside)."""
    ann = obj.annotation
    dx, dy = point[0] - ann.center[0], point[1] - ann.center[1]
    c, s = math.cos(ann.yaw), math.sin(ann.yaw)
    local_x, local_y = c * dx + s * dy, -s * dx + c * dy
    return math.hypot(max(abs(local_x) - ann.size[0] / 2, 0.0), max(abs(local_y) - ann.size[1] / 2, 0.0))
