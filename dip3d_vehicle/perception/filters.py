"""The paper's pose and candidate filters (constants from the parameter files)."""

from __future__ import annotations

import numpy as np

__all__ = ["pose_rejection", "candidate_keep"]


def pose_rejection(arm_xyz_m: np.ndarray, max_joint_dz_m: float, min_depth_m: float = 0.0) -> str | None:
    """Return why a triangulated arm (rows shoulder, elbow, wrist; metres) is rejected, or None.

    Paper: drop the pose if |z_w - z_e| > 0.5 or |z_e - z_s| > 0.5 m, or any joint has z < 0 or a
    non-finite z.
    """
    z = arm_xyz_m[:, 2]
    if not np.all(np.isfinite(arm_xyz_m)):
        return "non-finite joint depth"
    if np.any(z <= min_depth_m):
        return f"joint depth not above {min_depth_m:g} m (z = {np.round(z, 2).tolist()})"
    dz_we, dz_es = abs(z[2] - z[1]), abs(z[1] - z[0])
    if dz_we > max_joint_dz_m or dz_es > max_joint_dz_m:
        return f"|dz| wrist-elbow {dz_we:.2f} m / elbow-shoulder {dz_es:.2f} m over {max_joint_dz_m:g} m"
    return None


def candidate_keep(xyz_m: np.ndarray, min_depth_m: float = 0.0, max_depth_m: float = np.inf) -> np.ndarray:
    """Return a boolean mask of candidates with finite xyz and min_depth_m < z <= max_depth_m."""
    finite = np.all(np.isfinite(xyz_m), axis=1)
    z = np.where(finite, xyz_m[:, 2], -np.inf)
    return finite & (z > min_depth_m) & (z <= max_depth_m)
