"""Pinhole camera model: intrinsics, poses and the per-pixel rays the renderer casts.

Frames follow OpenCV's optical convention: x right, y down, z forward. A camera pose is the 4x4
transform from that optical frame to the world (z up), ``p_world = T[:3, :3] @ p_optical + T[:3, 3]``.
Robots describe their sensors in a z-up body convention (x forward, y left, z up);
:func:`optical_from_body` is the fixed rotation between the two and :func:`optical_pose` applies it.

Pixel ``(row, col)`` covers ``[col, col + 1) x [row, row + 1)`` in image coordinates, so its centre is
``(col + 0.5, row + 0.5)``. A point ``(x, y, z)`` of the optical frame with ``z > 0`` projects to
``u = fx * x / z + cx``, ``v = fy * y / z + cy`` and lands in pixel ``(floor(v), floor(u))``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated

import numpy as np
from numpy.typing import ArrayLike
from pydantic import Field

__all__ = [
    "CameraIntrinsics",
    "ImageSize",
    "check_pose",
    "look_at",
    "optical_from_body",
    "optical_pose",
]

_OPTICAL_FROM_BODY = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]])

Pixels = Annotated[int, Field(ge=1, le=4096, description="Pixels, 1 to 4096.")]
"""An image side (pixels), 1 to 4096."""
ImageSize = tuple[Pixels, Pixels]
"""``(width, height)`` of an image (pixels, each 1 to 4096): a settings field's type."""


@dataclass(frozen=True)
class CameraIntrinsics:
    """Pinhole intrinsics of an image of ``width`` x ``height`` pixels.

    Parameters
    ----------
    width, height : int
        Image size in pixels; both > 0.
    fx, fy : float
        Focal lengths in pixels; both > 0.
    cx, cy : float
        Principal point in pixels (``width / 2, height / 2`` is the image centre).

    Raises
    ------
    ValueError
        If a size is not a positive integer or a focal length is not a positive finite number.
    """

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    def __post_init__(self) -> None:
        for name in ("width", "height"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value <= 0:
                raise ValueError(f"camera {name} must be a positive integer, got {value!r}")
            object.__setattr__(self, name, int(value))
        for name in ("fx", "fy", "cx", "cy"):
            value = float(getattr(self, name))
            if not math.isfinite(value):
                raise ValueError(f"camera {name} must be finite, got {value!r}")
            object.__setattr__(self, name, value)
        if self.fx <= 0 or self.fy <= 0:
            raise ValueError(f"focal lengths must be > 0, got fx={self.fx}, fy={self.fy}")

    @classmethod
    def from_hfov(cls, width: int = 640, height: int = 480, hfov_deg: float = 90.0) -> CameraIntrinsics:
        """Square-pixel intrinsics with the given horizontal field of view, centred principal point.

        Parameters
        ----------
        width, height : int
            Image size in pixels.
        hfov_deg : float
            Horizontal field of view in degrees, in (0, 180).

        Returns
        -------
        CameraIntrinsics
            ``fx = fy = (width / 2) / tan(hfov / 2)``, ``cx = width / 2``, ``cy = height / 2``.
        """
        if not 0.0 < hfov_deg < 180.0:
            raise ValueError(f"hfov_deg must be in (0, 180), got {hfov_deg}")
        f = 0.5 * width / math.tan(math.radians(hfov_deg) / 2.0)
        return cls(width=width, height=height, fx=f, fy=f, cx=width / 2.0, cy=height / 2.0)

    @property
    def hfov_deg(self) -> float:
        """Horizontal field of view in degrees (for a centred principal point)."""
        return math.degrees(2.0 * math.atan(0.5 * self.width / self.fx))

    @property
    def vfov_deg(self) -> float:
        """Vertical field of view in degrees (for a centred principal point)."""
        return math.degrees(2.0 * math.atan(0.5 * self.height / self.fy))

    def matrix(self) -> np.ndarray:
        """Return the 3x3 camera matrix ``K = [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    def ray_directions(self) -> np.ndarray:
        """Per-pixel ray directions through the pixel centres, in the optical frame.

        Returns
        -------
        ndarray of float64, shape (height, width, 3)
            ``((col + 0.5 - cx) / fx, (row + 0.5 - cy) / fy, 1)``: not unit length but with optical z = 1,
            so a ray parameter ``t`` along it is the z-depth of the point it reaches.
        """
        x = (np.arange(self.width, dtype=np.float64) + 0.5 - self.cx) / self.fx
        y = (np.arange(self.height, dtype=np.float64) + 0.5 - self.cy) / self.fy
        dirs = np.empty((self.height, self.width, 3), dtype=np.float64)
        dirs[..., 0] = x[None, :]
        dirs[..., 1] = y[:, None]
        dirs[..., 2] = 1.0
        return dirs

    def project(self, points: ArrayLike) -> np.ndarray:
        """Project optical-frame points to image coordinates ``(u, v)`` (continuous, in pixels).

        Parameters
        ----------
        points : array_like, shape (..., 3)
            Points in the optical frame; their z must be > 0 for a meaningful result.

        Returns
        -------
        ndarray, shape (..., 2)
            ``(u, v)``; the pixel is ``(row, col) = (floor(v), floor(u))``.
        """
        p = np.asarray(points, dtype=np.float64)
        return np.stack(
            [self.fx * p[..., 0] / p[..., 2] + self.cx, self.fy * p[..., 1] / p[..., 2] + self.cy], -1
        )


def check_pose(camera_to_world: ArrayLike) -> np.ndarray:
    """Validate a camera pose and return it as a float64 4x4 array.

    Raises
    ------
    ValueError
        If the pose is not a finite 4x4 matrix whose last row is ``[0, 0, 0, 1]`` and whose upper-left
        3x3 block is a rotation (orthonormal, determinant +1, within 1e-4).
    """
    pose = np.asarray(camera_to_world, dtype=np.float64)
    if pose.shape != (4, 4):
        raise ValueError(f"camera_to_world must be a 4x4 matrix, got shape {pose.shape}")
    if not np.isfinite(pose).all():
        raise ValueError("camera_to_world must be finite")
    if not np.allclose(pose[3], (0.0, 0.0, 0.0, 1.0), atol=1e-9):
        raise ValueError(f"camera_to_world's last row must be [0, 0, 0, 1], got {pose[3].tolist()}")
    rotation = pose[:3, :3]
    if not np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-4) or np.linalg.det(rotation) < 0:
        raise ValueError("camera_to_world's upper-left 3x3 block must be a rotation (orthonormal, det +1)")
    return pose


def look_at(eye: ArrayLike, target: ArrayLike, up: ArrayLike = (0.0, 0.0, 1.0)) -> np.ndarray:
    """Pose of a camera at `eye` looking at `target`, with image "up" towards `up`.

    Parameters
    ----------
    eye, target : array_like, shape (3,)
        Camera position and the point on its optical axis, in world coordinates.
    up : array_like, shape (3,)
        World direction that appears upwards in the image (default +z).

    Returns
    -------
    ndarray, shape (4, 4)
        The camera-to-world transform of the optical frame (x right, y down, z forward).

    Raises
    ------
    ValueError
        If `eye` equals `target` or the viewing direction is parallel to `up`.
    """
    eye = np.asarray(eye, dtype=np.float64).reshape(3)
    forward = np.asarray(target, dtype=np.float64).reshape(3) - eye
    norm = np.linalg.norm(forward)
    if norm < 1e-12:
        raise ValueError("look_at needs a target different from the eye")
    forward /= norm
    right = np.cross(forward, np.asarray(up, dtype=np.float64).reshape(3))
    norm = np.linalg.norm(right)
    if norm < 1e-9:
        raise ValueError("look_at's viewing direction is parallel to `up`; pass another `up`")
    right /= norm
    down = np.cross(forward, right)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = right, down, forward, eye
    return pose


def optical_from_body() -> np.ndarray:
    """The rotation taking z-up body-frame vectors (x forward, y left, z up) to the optical frame.

    Returns
    -------
    ndarray, shape (3, 3)
        ``R`` with ``v_optical = R @ v_body``: optical x (right) is body -y, optical y (down) is
        body -z, optical z (forward) is body x.
    """
    return _OPTICAL_FROM_BODY.copy()


def optical_pose(body_to_world: ArrayLike) -> np.ndarray:
    """Camera-to-world pose of the optical frame of a camera whose body-convention pose is given.

    Parameters
    ----------
    body_to_world : array_like, shape (4, 4)
        Pose of the camera in the z-up body convention (x forward, y left, z up), e.g. the robot's
        base pose composed with the camera mount.

    Returns
    -------
    ndarray, shape (4, 4)
        ``body_to_world @ [[R.T, 0], [0, 1]]`` with ``R = optical_from_body()``.
    """
    pose = check_pose(body_to_world)
    out = pose.copy()
    out[:3, :3] = pose[:3, :3] @ _OPTICAL_FROM_BODY.T
    return out
