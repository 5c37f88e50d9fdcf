"""The paper's pose and candidate filters (constants from the parameter files)."""

from __future__ import annotations

import numpy as np

__all__ = ["pose_rejection", "candidate_keep"]


def pose_rejection(arm_xyz_m: np.ndarray, max_joint_dz_m: float, min_depth_m: float = 0.0,
                   depth_sigma_m: np.ndarray | None = None, dz_sigmas: float = 0.0) -> str | None:
    """Return why a triangulated arm (rows shoulder, elbow, wrist; metres) is rejected, or None.

    Paper: drop the pose if |z_w - z_e| > 0.5 or |z_e - z_s| > 0.5 m, or any joint has z < 0 or a
    non-finite z. With ``dz_sigmas`` > 0 the |dz| limit grows by that many sigmas of the two
    joints' stereo depth (``depth_sigma_m``): a far diver's joint depths are uncertain by tens of
    centimetres, which says nothing against the pose (the selector's limb priors judge it).
    """
    z = arm_xyz_m[:, 2]
    if not np.all(np.isfinite(arm_xyz_m)):
        return "non-finite joint depth"
    if np.any(z <= min_depth_m):
        return f"joint depth not above {min_depth_m:g} m (z = {np.round(z, 2).tolist()})"
    dz_we, dz_es = abs(z[2] - z[1]), abs(z[1] - z[0])
    limit_we = limit_es = max_joint_dz_m
    if dz_sigmas > 0 and depth_sigma_m is not None:
        limit_we += dz_sigmas * float(np.hypot(depth_sigma_m[2], depth_sigma_m[1]))
        limit_es += dz_sigmas * float(np.hypot(depth_sigma_m[1], depth_sigma_m[0]))
    if dz_we > limit_we or dz_es > limit_es:
        return (f"|dz| wrist-elbow {dz_we:.2f} m / elbow-shoulder {dz_es:.2f} m over "
                f"{limit_we:.2f} / {limit_es:.2f} m")
    return None


def candidate_keep(xyz_m: np.ndarray, min_depth_m: float = 0.0, max_depth_m: float = np.inf) -> np.ndarray:
    """Return a boolean mask of candidates with finite xyz and min_depth_m < z <= max_depth_m."""
    finite = np.all(np.isfinite(xyz_m), axis=1)
    z = np.where(finite, xyz_m[:, 2], -np.inf)
    return finite & (z > min_depth_m) & (z <= max_depth_m)
