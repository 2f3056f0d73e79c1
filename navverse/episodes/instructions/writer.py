"""The instruction writer: the instruction record of each episode, and the optional refiner plug-in.

:class:`InstructionWriter` plans an episode's directives, aligns them to its rollout, finds their
landmarks and writes the texts; an optional refiner (e.g. wrapping a vision-language model) receives
keyframes (RGB at each directive's time), the template, the landmark text and the episode, and returns
the final text (``instruction_type`` "refined"); :func:`load_refiner` imports one from
``"package.module:function"``. Without one the landmark text is the instruction ("landmark").
"""

from __future__ import annotations

import importlib
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from navverse.episodes.instructions.directives import align_directives, plan_directives
from navverse.episodes.instructions.landmarks import LandmarkFinder
from navverse.episodes.instructions.roads import RoadFollowing
from navverse.episodes.instructions.settings import InstructionSettings
from navverse.episodes.instructions.wording import landmark_text, template_text
from navverse.errors import NavverseError
from navverse.records.schema import Episode, Instruction, Landmark
from navverse.scene.geometry import Scene
from navverse.sim.camera import CameraIntrinsics, check_pose
from navverse.sim.keyframes import camera_poses
from navverse.sim.render import SceneRenderer

__all__ = ["DROP_REASONS", "InstructionWriter", "Refiner", "RefinerError", "load_refiner"]

Refiner = Callable[[list[np.ndarray], str, str, Episode], str | None]
"""``refiner(keyframes, template_text, landmark_text, episode)`` -> the refined text, or None to drop."""

DROP_REASONS = ("no_path", "alignment_failed", "too_few_landmarks", "refiner_declined")
"""Codes of the reasons :meth:`InstructionWriter.write` drops an episode for."""
_DEFAULT_SETTINGS = InstructionSettings()


class RefinerError(NavverseError):
    """A refiner cannot be loaded, or returned something other than text."""


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
        settings: InstructionSettings = _DEFAULT_SETTINGS,
        refiner: Refiner | None = None,
    ) -> None:
        self._scene = scene
        self._camera_to_base = check_pose(camera_to_base)
        self._settings = settings
        self._refiner = refiner
        self._landmarks = LandmarkFinder(scene, camera_to_base=self._camera_to_base, settings=settings)
        self._keyframe_renderer: SceneRenderer | None = None

    @property
    def settings(self) -> InstructionSettings:
        """The writer's settings."""
        return self._settings

    def write(
        self,
        episode: Episode,
        rollout: ArrayLike,
        rng: np.random.Generator,
        *,
        goal: str | None = None,
        roads: RoadFollowing | None = None,
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
        goal : str, optional
            How the goal is named (default: its category's words), e.g. "fast-food restaurant".
        roads : RoadFollowing, optional
            Which segments follow a road, told as following the street (outdoor routes); a street
            followed counts as a landmark towards ``min_landmarks``.

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
        goal_words = goal if goal is not None else episode.goal_category
        template = template_text(directives, goal_words)
        rows, errors = align_directives(directives, poses)
        worst = int(np.argmax(errors))
        if errors[worst] > s.max_alignment_error:
            return None, (
                f"alignment_failed: the rollout passes {errors[worst]:.2f} m from the point of directive "
                f"{worst} (max_alignment_error {s.max_alignment_error} m)"
            )
        landmarks, goal_seen = self._landmarks.find(episode, directives, poses, rows)
        along = roads.along_road(directives) if roads is not None else [False] * len(directives)
        found = sum(lm is not None or road for lm, road in zip(landmarks, along, strict=True))
        if found < s.min_landmarks:
            return (
                None,
                f"too_few_landmarks: {found} distinctive landmark(s) seen along the rollout (streets "
                f"followed included), fewer than {s.min_landmarks}",
            )
        text = landmark_text(
            directives,
            landmarks,
            goal_words,
            goal_seen=goal_seen,
            rng=rng,
            along_road=along,
            exit_at=self._exit_directive(episode, directives),
        )
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

    def _exit_directive(self, episode: Episode, directives: list) -> int | None:
        """The directive during whose walk a route from inside the building leaves it; None if it
        starts outdoors (or the scene has no indoor region)."""
        from shapely.geometry import LineString, Point, Polygon
        from shapely.ops import unary_union

        polygons = self._scene.annotations.indoor_polygons
        if not polygons or len(episode.reference_path) < 2:
            return None
        inside = unary_union([Polygon(p) for p in polygons])
        path = LineString([p[:2] for p in episode.reference_path])
        if not inside.contains(Point(path.coords[0])):
            return None
        leaving = path.difference(inside)
        if leaving.is_empty:
            return None
        crossing = min(path.project(Point(c)) for g in getattr(leaving, "geoms", [leaving]) for c in g.coords)
        walked = [path.project(Point(d.position[:2])) for d in directives]
        return max(k for k, at in enumerate(walked) if at <= crossing + 1e-6)

    def _keyframes(self, rows: np.ndarray) -> list[np.ndarray]:
        """The refiner's keyframes: RGB images from the camera at rollout `rows` (B, 8)."""
        if self._keyframe_renderer is None:
            intrinsics = CameraIntrinsics.from_hfov(*self._settings.keyframe_resolution, 90.0)
            self._keyframe_renderer = SceneRenderer(self._scene, intrinsics=intrinsics)
        poses = camera_poses(rows, self._camera_to_base)
        return [frame.rgb for frame in self._keyframe_renderer.render_batch(poses)]


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
