"""VLN instructions from an episode's reference path and its verification rollout (paper Appendix D.3).

One mechanism, in four steps, behind :class:`InstructionWriter`:

1. **Template.** The reference path is simplified (Douglas–Peucker, then segments shorter than
   ``min_segment`` are merged and vertices without a real turn dropped) into :class:`Directive` s:
   a start (turn from the start heading, walk the first segment), one turn per remaining vertex
   (signed angle classified by :func:`turn_class`), and an arrival naming the goal category.
   :func:`template_text` writes them with distances: "Turn left and walk forward about 4 meters,
   turn right and walk about 3 meters, then stop at the bed."
2. **Alignment.** Each directive is matched to the rollout time at which the robot carried it out,
   its closest approach to the directive's vertex, with times kept in path order
   (:func:`align_directives`): ``Instruction.directive_times``. An episode whose rollout stays
   farther than ``max_alignment_error`` from a directive's vertex is dropped.
3. **Landmarks.** Frames are ray-cast from the rollout's camera poses in a window before each turn
   (after the initial turn for the start, before the end for the arrival). Objects with at least
   ``min_pixels`` pixels at a mean depth of at most ``max_distance`` are candidates; distinctive ones
   (their category unique among the objects seen there, else made unique by their colour) are
   preferred, then larger and nearer ones. Each directive names at most one landmark, described by
   colour (:func:`object_color`, a small palette named by :func:`color_name`) and category. The text is
   rewritten from sentence patterns drawn with the episode's random generator, with no distances.
   Episodes with fewer than ``min_landmarks`` landmarks are dropped.
4. **Refiner (optional).** A callable (e.g. wrapping a vision-language model) receives keyframes
   (RGB at each directive's time), the template, the landmark text and the episode, and returns the
   final text (``instruction_type`` "refined"); :func:`load_refiner` imports one from
   ``"package.module:function"``. Without one the landmark text is the instruction ("landmark").

Example::

    writer = InstructionWriter(scene, camera_to_base=make_embodiment("spot").camera_to_base)
    instruction, reason = writer.write(episode, rollout, np.random.default_rng(seed))

``write`` returns ``(Instruction, None)``, or ``(None, reason)`` for a dropped episode. Rendering is
deterministic and the generator only chooses wording, so the same inputs and seed give the same
instruction.
"""

from __future__ import annotations

import importlib
import itertools
import math
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial.transform import Rotation

from navverse.dataset import Episode, Instruction, Landmark
from navverse.errors import NavverseError
from navverse.scene.colors import default_color
from navverse.scene.geometry import Scene, SceneObject
from navverse.sim.camera import CameraIntrinsics, check_pose
from navverse.sim.render import SceneRenderer

__all__ = [
    "DROP_REASONS",
    "PALETTE",
    "Directive",
    "InstructionSettings",
    "InstructionWriter",
    "Refiner",
    "RefinerError",
    "align_directives",
    "color_name",
    "load_refiner",
    "object_color",
    "plan_directives",
    "template_text",
    "turn_class",
]

Refiner = Callable[[list[np.ndarray], str, str, Episode], str | None]
"""``refiner(keyframes, template_text, landmark_text, episode)`` -> the refined text, or None to drop."""

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

DROP_REASONS = ("no_path", "alignment_failed", "too_few_landmarks", "refiner_declined")
"""Codes of the reasons :meth:`InstructionWriter.write` drops an episode for."""

_TURNS = ((20.0, "straight"), (60.0, "slight"), (120.0, "turn"), (160.0, "sharp"))  # |angle| below, in deg


class RefinerError(NavverseError):
    """A refiner cannot be loaded, or returned something other than text."""


@dataclass(frozen=True)
class InstructionSettings:
    """Parameters of instruction writing.

    Parameters
    ----------
    min_landmarks : int
        Landmarks an instruction must name; episodes with fewer are dropped.
    resolution : tuple of int
        ``(width, height)`` of the frames searched for landmarks (90 degrees horizontal field of view).
    simplify_tolerance : float
        Douglas–Peucker tolerance of the path simplification (m).
    min_segment : float
        Segments shorter than this are merged into their neighbours (m).
    window : float
        Seconds of rollout before a turn (after the start's turn, before the arrival) searched for
        its landmark.
    frames_per_window : int
        Frames rendered per window, evenly spread over it.
    max_distance : float
        Largest mean depth of a landmark's pixels, and largest distance from a turn's vertex to the
        landmark's footprint (m).
    min_pixels : int
        Pixels a landmark must cover in one frame; objects covering a quarter of it count as seen
        when deciding whether a landmark is distinctive.
    near_goal : float
        An arrival landmark within this distance of the goal (footprint to centre, m) is described as
        next to the goal; a farther one as passed on the way.
    max_alignment_error : float
        Largest horizontal distance between a directive's vertex and the rollout's closest pose (m).
    keyframe_resolution : tuple of int
        ``(width, height)`` of the keyframes handed to a refiner.
    """

    min_landmarks: int = 2
    resolution: tuple[int, int] = (160, 120)
    simplify_tolerance: float = 0.5
    min_segment: float = 0.75
    window: float = 3.0
    frames_per_window: int = 4
    max_distance: float = 3.5
    min_pixels: int = 150
    near_goal: float = 2.5
    max_alignment_error: float = 1.5
    keyframe_resolution: tuple[int, int] = (640, 480)

    def __post_init__(self) -> None:
        if self.min_landmarks < 0 or self.frames_per_window < 1 or self.min_pixels < 1:
            raise ValueError("min_landmarks must be >= 0, frames_per_window and min_pixels >= 1")
        for name in ("simplify_tolerance", "min_segment", "window", "max_distance", "near_goal"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)!r}")
        if not self.max_alignment_error > 0.0:
            raise ValueError(f"max_alignment_error must be > 0, got {self.max_alignment_error!r}")


@dataclass(frozen=True)
class Directive:
    """One step of a template: turn by ``angle`` at ``position``, then walk ``length``.

    Attributes
    ----------
    kind : {"start", "turn", "arrive"}
        The first directive turns from the start heading; the last one is the arrival (no turn).
    turn : str
        :func:`turn_class` of `angle`: ``straight``, ``slight_left``, ``left``, ``sharp_left``,
        ``around`` (and the ``right`` ones).
    angle : float
        Signed turn (rad), positive to the left (counter-clockwise seen from above).
    length : float
        Horizontal length of the segment walked after the turn (m); 0 for the arrival.
    position : tuple of float
        The path vertex where the directive is carried out.
    """

    kind: Literal["start", "turn", "arrive"]
    turn: str
    angle: float
    length: float
    position: tuple[float, float, float]


# ---------------------------------------------------------------------------------------------- template


def turn_class(angle: float) -> str:
    """Name a signed turn angle (rad, positive left): ``straight`` below 20°, ``slight_*`` below 60°,
    ``left``/``right`` below 120°, ``sharp_*`` below 160°, else ``around``."""
    degrees = abs(math.degrees(angle))
    side = "left" if angle > 0.0 else "right"
    for limit, name in _TURNS:
        if degrees < limit:
            return name if name == "straight" else side if name == "turn" else f"{name}_{side}"
    return "around"


def _wrap(angle: ArrayLike) -> np.ndarray:
    return (np.asarray(angle) + np.pi) % (2.0 * np.pi) - np.pi


def _douglas_peucker(points: np.ndarray, tolerance: float) -> np.ndarray:
    """Indices of the vertices kept by Douglas–Peucker on a 2-D polyline (iterative)."""
    keep = np.zeros(len(points), dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, len(points) - 1)]
    while stack:
        first, last = stack.pop()
        if last - first < 2:
            continue
        a, b = points[first], points[last]
        ab = b - a
        rel = points[first + 1 : last] - a
        length = float(np.hypot(*ab))
        if length < 1e-9:
            dist = np.hypot(rel[:, 0], rel[:, 1])
        else:
            dist = np.abs(ab[0] * rel[:, 1] - ab[1] * rel[:, 0]) / length
        worst = int(np.argmax(dist))
        if dist[worst] > tolerance:
            mid = first + 1 + worst
            keep[mid] = True
            stack.extend([(first, mid), (mid, last)])
    return np.flatnonzero(keep)


def _merge_short(points: list[np.ndarray], min_segment: float) -> list[np.ndarray]:
    """Merge segments shorter than `min_segment`: the start and the end vertex never move."""
    while len(points) > 2:
        lengths = [float(np.hypot(*(b[:2] - a[:2]))) for a, b in itertools.pairwise(points)]
        i = int(np.argmin(lengths))
        if lengths[i] >= min_segment:
            break
        if i == 0:
            del points[1]
        elif i == len(points) - 2:
            del points[i]
        else:
            points[i : i + 2] = [0.5 * (points[i] + points[i + 1])]
    return points


def plan_directives(
    reference_path: ArrayLike, start_yaw: float, *, tolerance: float = 0.5, min_segment: float = 0.75
) -> list[Directive]:
    """Turn-and-move directives of a reference path.

    Parameters
    ----------
    reference_path : array_like, shape (K, 3)
        Path corners from the start to the goal region (z up).
    start_yaw : float
        The robot's heading at the start (rad).
    tolerance : float
        Douglas–Peucker tolerance (m).
    min_segment : float
        Shorter segments are merged into their neighbours (m).

    Returns
    -------
    list of Directive
        A start, one turn per kept interior vertex, and an arrival; empty if the path has no length.
    """
    path = np.asarray(reference_path, dtype=float).reshape(-1, 3)
    if len(path):
        step = np.hypot(*np.diff(path[:, :2], axis=0).T)
        path = path[np.concatenate([[True], step > 1e-6])]
    if len(path) < 2:
        return []
    points = [path[i] for i in _douglas_peucker(path[:, :2], tolerance)]
    points = _merge_short(points, min_segment)
    while True:  # drop vertices whose turn is too small to mention
        headings = [math.atan2(*(b[1::-1] - a[1::-1])) for a, b in itertools.pairwise(points)]
        turns = [float(_wrap(h1 - h0)) for h0, h1 in itertools.pairwise(headings)]
        straight = [i + 1 for i, a in enumerate(turns) if turn_class(a) == "straight"]
        if not straight:
            break
        del points[min(straight, key=lambda i: abs(turns[i - 1]))]
    angles = [float(_wrap(headings[0] - start_yaw)), *turns]
    directives = [
        Directive(
            kind="start" if i == 0 else "turn",
            turn=turn_class(angle),
            angle=angle,
            length=float(np.hypot(*(points[i + 1][:2] - points[i][:2]))),
            position=tuple(float(v) for v in points[i]),
        )
        for i, angle in enumerate(angles)
    ]
    end = tuple(float(v) for v in points[-1])
    return [*directives, Directive(kind="arrive", turn="straight", angle=0.0, length=0.0, position=end)]


_TEMPLATE_TURN = {
    "straight": "continue straight",
    "slight_left": "turn slightly left",
    "slight_right": "turn slightly right",
    "left": "turn left",
    "right": "turn right",
    "sharp_left": "turn sharply left",
    "sharp_right": "turn sharply right",
    "around": "turn around",
}


def _meters(length: float) -> str:
    n = max(1, round(length))
    return f"about {n} meter" + ("" if n == 1 else "s")


def template_text(directives: Sequence[Directive], goal: str) -> str:
    """The template instruction: turns and distances, then the arrival at `goal` (a category).

    Parameters
    ----------
    directives : sequence of Directive
        From :func:`plan_directives`.
    goal : str
        Goal category (underscores read as spaces).

    Returns
    -------
    str
        E.g. "Turn left and walk forward about 4 meters, turn right and walk about 3 meters, then stop
        at the bed."
    """
    clauses = []
    for d in directives:
        if d.kind == "start":
            walk = f"walk forward {_meters(d.length)}"
            clauses.append(walk if d.turn == "straight" else f"{_TEMPLATE_TURN[d.turn]} and {walk}")
        elif d.kind == "turn":
            clauses.append(f"{_TEMPLATE_TURN[d.turn]} and walk {_meters(d.length)}")
    clauses.append(f"then stop at the {_words(goal)}.")
    text = ", ".join(clauses)
    return text[0].upper() + text[1:]


# ---------------------------------------------------------------------------------------------- alignment


def align_directives(directives: Sequence[Directive], rollout: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Rollout rows at which the directives were carried out, in order, and how far off they were.

    Each directive is matched to a rollout pose near its vertex; the rows strictly increase (when the
    rollout has at least as many rows as directives) and minimise the sum of horizontal distances,
    found by dynamic programming, so a path that comes back near an earlier vertex is not misread.

    Parameters
    ----------
    directives : sequence of Directive
        The directives, in path order.
    rollout : array_like, shape (K, 8)
        ``[t, x, y, z, qx, qy, qz, qw]`` rows.

    Returns
    -------
    rows : ndarray of int, shape (N,)
        Row of each directive (non-decreasing; increasing when ``K >= N``).
    errors : ndarray of float, shape (N,)
        Horizontal distance from each vertex to its row's position (m).
    """
    poses = np.asarray(rollout, dtype=float)[:, 1:3]
    vertices = np.array([d.position[:2] for d in directives], dtype=float).reshape(-1, 2)
    dist = np.linalg.norm(vertices[:, None, :] - poses[None, :, :], axis=2)  # (N, K)
    n, k = dist.shape
    if n == 0:
        return np.zeros(0, dtype=int), np.zeros(0)
    strict = k >= n
    cost = dist.copy()
    back = np.zeros((n, k), dtype=int)
    for i in range(1, n):
        prev = cost[i - 1]
        best = np.minimum.accumulate(prev)
        arg = np.zeros(k, dtype=int)
        for j in range(1, k):  # index of the running minimum (first one on ties)
            arg[j] = arg[j - 1] if prev[arg[j - 1]] <= prev[j] else j
        if strict:
            cost[i, 0] = np.inf
            cost[i, 1:] += best[:-1]
            back[i, 1:] = arg[:-1]
        else:
            cost[i] += best
            back[i] = arg
    rows = np.zeros(n, dtype=int)
    rows[-1] = int(np.argmin(cost[-1]))
    for i in range(n - 1, 0, -1):
        rows[i - 1] = back[i, rows[i]]
    return rows, dist[np.arange(n), rows]


# ---------------------------------------------------------------------------------------------- colours


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


def _words(category: str) -> str:
    """A category as read in a sentence: underscores as spaces, "tv" as "TV"."""
    return " ".join("TV" if w == "tv" else w for w in category.replace("_", " ").split())


# ---------------------------------------------------------------------------------------------- phrasing

# Sentence patterns of the landmark text, by situation; {verb} is a turn (_VERBS), {lm} a landmark
# ("the" is in the pattern), {dist} a length in words, {goal} the goal category.
# fmt: off
_VERBS = {
    "slight": ("bear slightly {side}", "veer slightly {side}", "turn slightly {side}"),
    "turn": ("turn {side}", "go {side}", "take a {side}"),
    "sharp": ("make a sharp {side}", "turn sharply {side}", "take a hard {side}"),
    "around": ("turn around", "turn back", "make a U-turn"),
}
_PATTERNS = {
    "start": ("walk forward {dist}", "go straight ahead {dist}", "move ahead {dist}"),
    "start+lm": ("head towards the {lm}", "walk forward past the {lm}", "go ahead, passing the {lm}",
                 "start by walking towards the {lm}"),
    "start_turn": ("{verb} and walk forward {dist}", "{verb} and go ahead {dist}",
                   "first {verb}, then walk {dist}"),
    "start_turn+lm": ("{verb} and head towards the {lm}", "{verb}, then walk past the {lm}",
                      "first {verb} and walk towards the {lm}", "{verb} and go ahead, passing the {lm}"),
    "turn": ("{verb}", "{verb} and keep walking {dist}", "{verb} and walk {dist}"),
    "turn+lm": ("{verb} at the {lm}", "when you reach the {lm}, {verb}", "at the {lm}, {verb}",
                "{verb} once you get to the {lm}", "{verb} by the {lm} and walk {dist}",
                "{verb} when you see the {lm}"),
    "arrive": ("stop by the {goal}", "stop when you reach the {goal}", "your goal is the {goal}"),
    "arrive+near": ("stop by the {goal} next to the {lm}", "your goal is the {goal} near the {lm}",
                    "stop at the {goal}, close to the {lm}", "the {goal} beside the {lm} is your goal"),
    "arrive+pass": ("walk past the {lm} and stop by the {goal}", "pass the {lm} and stop at the {goal}",
                    "continue past the {lm} to the {goal}"),
    # the goal was not seen on the way: the paper's "you will arrive at [target]"
    "arrive_unseen": ("you will arrive at the {goal}",),
    "arrive_unseen+near": ("you will arrive at the {goal} near the {lm}",),
    "arrive_unseen+pass": ("pass the {lm} and you will arrive at the {goal}",),
}
_JOINERS = (". ", ". Then ", ", then ", ". After that, ", ". Next, ")
_FINAL_JOINERS = (". ", ". Finally, ")
# fmt: on


def _distance_words(length: float) -> str:
    if length < 2.0:
        return "a few steps"
    if length < 4.0:
        return "a short distance"
    return "a while" if length < 7.0 else "a long way"


def _verb(turn: str, rng: np.random.Generator) -> str:
    kind, _, side = turn.partition("_")
    if kind in ("left", "right"):
        kind, side = "turn", kind
    return str(rng.choice(_VERBS[kind])).format(side=side)


# ---------------------------------------------------------------------------------------------- writer


@dataclass(frozen=True)
class _Seen:
    """A landmark chosen for a directive."""

    object_id: int
    category: str
    color: str
    near_goal: bool

    @property
    def phrase(self) -> str:
        words = _words(self.category)
        if any(word.lower().startswith(self.color) for word in words.split()):
            return words  # "whiteboard", not "white whiteboard"
        return f"{self.color} {words}"


class InstructionWriter:
    """Writes the VLN instructions of the episodes of one scene.

    Parameters
    ----------
    scene : Scene
        The scene the episodes are in; its renderer is built once, here.
    camera_to_base : array_like, shape (4, 4)
        Pose of the robot camera's optical frame in the base frame (``Embodiment.camera_to_base``).
    settings : InstructionSettings
        Thresholds and sizes.
    refiner : callable, optional
        ``refiner(keyframes, template_text, landmark_text, episode)`` returning the final text, or
        None to drop the episode; keyframes are ``uint8 (H, W, 3)`` RGB images rendered at each
        directive's time. See :func:`load_refiner`.

    Notes
    -----
    A writer holds a renderer, so it is not thread-safe: give each thread its own.
    """

    def __init__(
        self,
        scene: Scene,
        *,
        camera_to_base: ArrayLike,
        settings: InstructionSettings = InstructionSettings(),
        refiner: Refiner | None = None,
    ) -> None:
        self._scene = scene
        self._camera_to_base = check_pose(camera_to_base)
        self._settings = settings
        self._refiner = refiner
        intrinsics = CameraIntrinsics.from_hfov(*settings.resolution, 90.0)
        self._renderer = SceneRenderer(scene, intrinsics=intrinsics)
        self._keyframe_renderer: SceneRenderer | None = None
        self._objects = {o.annotation.id: o for o in scene.objects}
        self._colors: dict[int, str] = {}
        self._ids = max(self._objects, default=0) + 1

    @property
    def settings(self) -> InstructionSettings:
        """The writer's settings."""
        return self._settings

    def write(
        self, episode: Episode, rollout: ArrayLike, rng: np.random.Generator
    ) -> tuple[Instruction | None, str | None]:
        """Write the instruction of one episode.

        Parameters
        ----------
        episode : Episode
            An episode of this scene (its reference path, start rotation, goals and category).
        rollout : array_like, shape (K, 8)
            Its verification rollout: ``[t, x, y, z, qx, qy, qz, qw]`` robot base poses.
        rng : numpy.random.Generator
            Chooses the wording (only).

        Returns
        -------
        tuple of (Instruction or None, str or None)
            The instruction and None, or None and why the episode is dropped: ``"<code>: <details>"``
            with a code of :data:`DROP_REASONS`.

        Raises
        ------
        ValueError
            If the episode is of another scene or the rollout is not finite ``(K, 8)`` rows, K >= 1.
        RefinerError
            If the refiner returns something other than text or None.
        """
        if episode.scene_id != self._scene.scene_id:
            raise ValueError(
                f"episode {episode.episode_id} is of scene {episode.scene_id}, not {self._scene.scene_id}"
            )
        poses = np.asarray(rollout, dtype=float)
        if poses.ndim != 2 or poses.shape[1] != 8 or len(poses) == 0 or not np.isfinite(poses).all():
            raise ValueError(f"rollout must be finite (K, 8) rows with K >= 1, got shape {poses.shape}")
        s = self._settings
        directives = plan_directives(
            episode.reference_path,
            episode.start_yaw,
            tolerance=s.simplify_tolerance,
            min_segment=s.min_segment,
        )
        if not directives:
            return None, "no_path: the reference path has no length"
        template = template_text(directives, episode.goal_category)
        rows, errors = align_directives(directives, poses)
        worst = int(np.argmax(errors))
        if errors[worst] > s.max_alignment_error:
            return None, (
                f"alignment_failed: the rollout passes {errors[worst]:.2f} m from the point of directive "
                f"{worst} (max_alignment_error {s.max_alignment_error} m)"
            )
        landmarks, goal_seen = self._landmarks(episode, directives, poses, rows)
        found = sum(lm is not None for lm in landmarks)
        if found < s.min_landmarks:
            return (
                None,
                f"too_few_landmarks: {found} distinctive landmark(s) seen along the rollout, fewer than "
                f"{s.min_landmarks}",
            )
        text = _landmark_text(directives, landmarks, episode.goal_category, goal_seen=goal_seen, rng=rng)
        kind = "landmark"
        if self._refiner is not None:
            refined = self._refiner(self._keyframes(poses[rows]), template, text, episode)
            if refined is not None and not isinstance(refined, str):
                raise RefinerError(
                    f"the refiner returned a {type(refined).__name__}; it must return the instruction text "
                    "(str), or None to drop the episode"
                )
            if refined is None or not refined.strip():
                return None, "refiner_declined: the refiner returned no instruction"
            text, kind = refined.strip(), "refined"
        return Instruction(
            instruction_text=text,
            template_text=template,
            instruction_type=kind,
            landmarks=[
                Landmark(object_id=lm.object_id, category=lm.category, color=lm.color, step=step)
                for step, lm in enumerate(landmarks)
                if lm is not None
            ],
            directive_times=[float(t) for t in poses[rows, 0]],
        ), None

    # ------------------------------------------------------------------------------------------ internals

    def _camera_poses(self, rows: np.ndarray) -> np.ndarray:
        """Camera-to-world poses (B, 4, 4) of rollout rows."""
        if not len(rows):
            return np.zeros((0, 4, 4))
        base = np.tile(np.eye(4), (len(rows), 1, 1))
        base[:, :3, :3] = Rotation.from_quat(rows[:, 4:8]).as_matrix()
        base[:, :3, 3] = rows[:, 1:4]
        return base @ self._camera_to_base

    def _keyframes(self, rows: np.ndarray) -> list[np.ndarray]:
        if self._keyframe_renderer is None:
            intrinsics = CameraIntrinsics.from_hfov(*self._settings.keyframe_resolution, 90.0)
            self._keyframe_renderer = SceneRenderer(self._scene, intrinsics=intrinsics)
        return [frame.rgb for frame in self._keyframe_renderer.render_batch(self._camera_poses(rows))]

    def _describe(self, object_id: int) -> tuple[str, str]:
        """``(category, colour name)`` of an object."""
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
            aligned = np.flatnonzero(np.abs(_wrap(yaw - math.atan2(y1 - y0, x1 - x0))) < math.radians(30.0))
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
        mean depth is within `max_distance`, that depth, and the most pixels at any distance."""
        near, depth, seen = np.zeros(self._ids), np.full(self._ids, np.inf), np.zeros(self._ids)
        for frame in self._renderer.render_batch(self._camera_poses(rows)):
            ids = frame.semantic.ravel()
            counts = np.bincount(ids, minlength=self._ids)[: self._ids]
            total = np.bincount(ids, weights=frame.depth.ravel(), minlength=self._ids)[: self._ids]
            mean = np.divide(total, counts, out=np.full(self._ids, np.inf), where=counts > 0)
            seen = np.maximum(seen, counts)
            better = (mean <= self._settings.max_distance) & (counts > near)
            near[better], depth[better] = counts[better], mean[better]
        near[0] = seen[0] = 0.0  # no object
        return near, depth, seen

    def _landmarks(
        self, episode: Episode, directives: Sequence[Directive], poses: np.ndarray, rows: np.ndarray
    ) -> tuple[list[_Seen | None], bool]:
        """One landmark (or None) per directive, and whether a goal instance was seen before arriving."""
        s = self._settings
        goal_ids = {g.object_id for g in episode.goals}
        chosen: list[_Seen | None] = []
        goal_seen = False
        for k, directive in enumerate(directives):
            near, depth, seen = self._visibility(poses[self._window(k, directives, poses, rows)])
            glimpsed = [int(i) for i in np.flatnonzero(seen >= max(1, s.min_pixels // 4))]
            if directive.kind == "arrive":
                goal_seen = not goal_ids.isdisjoint(glimpsed)
            described = Counter(self._describe(i) for i in glimpsed if i in self._objects)
            categories = Counter(category for category, _ in described.elements())
            taken = {lm.phrase for lm in chosen if lm is not None}
            best: tuple[tuple[int, float, int], _Seen] | None = None
            for i in (int(i) for i in np.flatnonzero(near >= s.min_pixels)):
                if i in goal_ids or i not in self._objects:
                    continue
                category, color = self._describe(i)
                obj = self._objects[i]
                if category == episode.goal_category or (
                    directive.kind == "turn" and _footprint_distance(obj, directive.position) > s.max_distance
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
                candidate = _Seen(i, category, color, near_goal)
                key = (rank, -near[i] / max(depth[i], 0.5), i)  # distinctive, then large and near
                if candidate.phrase not in taken and (best is None or key < best[0]):
                    best = (key, candidate)
            chosen.append(None if best is None else best[1])
        return chosen, goal_seen


def _footprint_distance(obj: SceneObject, point: Sequence[float]) -> float:
    """Horizontal distance from a point to an object's oriented bounding box footprint (0 inside)."""
    ann = obj.annotation
    dx, dy = point[0] - ann.center[0], point[1] - ann.center[1]
    c, s = math.cos(ann.yaw), math.sin(ann.yaw)
    local_x, local_y = c * dx + s * dy, -s * dx + c * dy
    return math.hypot(max(abs(local_x) - ann.size[0] / 2, 0.0), max(abs(local_y) - ann.size[1] / 2, 0.0))


def _landmark_text(
    directives: Sequence[Directive],
    landmarks: Sequence[_Seen | None],
    goal: str,
    *,
    goal_seen: bool,
    rng: np.random.Generator,
) -> str:
    """The landmark-grounded instruction: one pattern per directive, drawn with `rng`; no distances."""
    clauses = []
    for d, lm in zip(directives, landmarks, strict=True):
        if d.kind == "start":
            situation = "start" if d.turn == "straight" else "start_turn"
        else:
            situation = d.kind if d.kind == "turn" or goal_seen else "arrive_unseen"
        if lm is not None:
            situation += "+lm" if d.kind != "arrive" else "+near" if lm.near_goal else "+pass"
        fields = {
            "verb": "" if d.turn == "straight" else _verb(d.turn, rng),
            "lm": "" if lm is None else lm.phrase,
            "dist": _distance_words(d.length),
            "goal": _words(goal),
        }
        patterns = _PATTERNS[situation]
        clauses.append(patterns[int(rng.integers(len(patterns)))].format(**fields))
    text = clauses[0]
    for i, clause in enumerate(clauses[1:], start=1):
        joiner = str(rng.choice(_FINAL_JOINERS if i == len(clauses) - 1 else _JOINERS))
        text += joiner + (clause[0].upper() + clause[1:] if joiner == ". " else clause)
    return text[0].upper() + text[1:] + "."


# ---------------------------------------------------------------------------------------------- plug-in


def load_refiner(spec: str) -> Refiner:
    """Import a refiner named ``"package.module:function"`` (the attribute may be dotted).

    Raises
    ------
    RefinerError
        If the spec is malformed, the module cannot be imported, it has no such attribute, or the
        attribute is not callable.
    """
    module_name, sep, attribute = spec.partition(":")
    if not sep or not module_name or not attribute:
        raise RefinerError(f"refiner {spec!r} must be written 'package.module:function'")
    try:
        target = importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        missing = exc.name or ""
        if module_name == missing or module_name.startswith(missing + "."):
            raise RefinerError(
                f"refiner {spec!r}: no module named {missing!r}; install it or put it on PYTHONPATH"
            ) from None
        raise RefinerError(f"refiner {spec!r}: importing {module_name!r} failed: {exc}") from None
    except Exception as exc:
        raise RefinerError(
            f"refiner {spec!r}: importing {module_name!r} failed: {type(exc).__name__}: {exc}"
        ) from None
    for part in attribute.split("."):
        if not hasattr(target, part):
            raise RefinerError(f"refiner {spec!r}: {module_name!r} has no attribute {attribute!r}")
        target = getattr(target, part)
    if not callable(target):
        raise RefinerError(
            f"refiner {spec!r} is a {type(target).__name__}, not a callable taking "
            "(keyframes, template_text, landmark_text, episode)"
        )
    return target
