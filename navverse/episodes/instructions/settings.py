"""The thresholds and sizes of instruction writing (:class:`InstructionSettings`)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from navverse.settings import Settings
from navverse.sim.camera import ImageSize

__all__ = ["InstructionSettings"]


class InstructionSettings(Settings):
    """Parameters of instruction writing (Appendix D.3): the landmarks an instruction must name and
    how they are searched for along the rollout, the simplification of the reference path and its
    alignment to the rollout, and the sizes of the frames rendered."""

    min_landmarks: Annotated[int, Field(ge=0, le=16)] = 2
    """Landmarks an instruction must name; episodes with fewer are dropped."""
    max_landmark_distance: Annotated[float, Field(gt=0.0, le=20.0)] = 3.5
    """Largest mean depth of a landmark's pixels, and largest distance from a turn's vertex to the
    landmark's footprint (m)."""
    resolution: ImageSize = (160, 120)
    """``(width, height)`` of the frames searched for landmarks (90 degrees horizontal field of view)."""
    simplify_tolerance: Annotated[float, Field(gt=0.0, le=10.0)] = 0.5
    """Douglas–Peucker tolerance of the path simplification (m)."""
    min_segment: Annotated[float, Field(gt=0.0, le=20.0)] = 0.75
    """Segments shorter than this are merged into their neighbours (m)."""
    window: Annotated[float, Field(gt=0.0, le=60.0)] = 3.0
    """Seconds of rollout before a turn (after the start's turn, before the arrival) searched for its
    landmark."""
    frames_per_window: Annotated[int, Field(ge=1, le=64)] = 4
    """Frames rendered per window, evenly spread over it."""
    min_pixels: Annotated[int, Field(ge=1, le=16_777_216)] = 150
    """Pixels a landmark must cover in one frame; objects covering a quarter of it count as seen when
    deciding whether a landmark is distinctive."""
    near_goal: Annotated[float, Field(gt=0.0, le=20.0)] = 2.5
    """An arrival landmark within this distance of the goal (footprint to centre, m) is described as
    next to the goal; a farther one as passed on the way."""
    max_alignment_error: Annotated[float, Field(gt=0.0, le=10.0)] = 1.5
    """Largest horizontal distance between a directive's vertex and the rollout's closest pose (m)."""
    keyframe_resolution: ImageSize = (640, 480)
    """``(width, height)`` of the keyframes handed to a refiner."""
