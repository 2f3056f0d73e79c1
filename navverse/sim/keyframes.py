"""Camera poses along a robot trajectory, and the keyframes a camera sees there.

A trajectory is rows ``[t, x, y, z, qx, qy, qz, qw]`` of robot base poses (a submission's, a
verification rollout's); the camera's optical frame sits at ``camera_to_base`` in the base frame (an
embodiment's ``camera_to_base``). Verification keeps keyframes of every rollout, the instruction writer
looks at rollouts through them, and the evaluation report shows a strip of them per episode.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from navverse.sim.render import SceneRenderer

__all__ = ["camera_poses", "keyframe_rows", "render_keyframes"]


def camera_poses(rows: np.ndarray, camera_to_base: np.ndarray) -> np.ndarray:
    """Camera-to-world poses of trajectory rows.

    Parameters
    ----------
    rows : ndarray, shape (B, 8)
        ``[t, x, y, z, qx, qy, qz, qw]`` robot base poses.
    camera_to_base : ndarray, shape (4, 4)
        Pose of the camera's optical frame in the base frame.

    Returns
    -------
    ndarray, shape (B, 4, 4)
    """
    rows = np.asarray(rows, dtype=float).reshape(-1, 8)
    if not len(rows):
        return np.zeros((0, 4, 4))
    base = np.tile(np.eye(4), (len(rows), 1, 1))
    base[:, :3, :3] = Rotation.from_quat(rows[:, 4:8]).as_matrix()
    base[:, :3, 3] = rows[:, 1:4]
    return base @ np.asarray(camera_to_base, dtype=float)


def keyframe_rows(count_rows: int, count: int) -> np.ndarray:
    """Indices of ``count`` rows evenly spaced over ``count_rows`` (first and last included)."""
    if count_rows <= 0 or count <= 0:
        return np.zeros(0, dtype=int)
    return np.linspace(0, count_rows - 1, count).round().astype(int)


def render_keyframes(
    renderer: SceneRenderer, trajectory: np.ndarray, camera_to_base: np.ndarray, count: int
) -> list[np.ndarray]:
    """RGB frames the camera sees at ``count`` evenly spaced rows of a trajectory."""
    trajectory = np.asarray(trajectory, dtype=float).reshape(-1, 8)
    rows = trajectory[keyframe_rows(len(trajectory), count)]
    return [frame.rgb for frame in renderer.render_batch(camera_poses(rows, camera_to_base))]
