"""The thresholds and sizes of instruction writing (:class:`InstructionSettings`)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["InstructionSettings"]


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
