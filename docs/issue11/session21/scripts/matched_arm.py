"""The truth-pose arm with and without `pose.match_disparity` on rendered frames: per-joint depth error.

    PYTHONPATH=. python docs/issue11/session21/scripts/matched_arm.py SCENARIO SEED [T0_S N_FRAMES]

For each frame (the vehicle at its start pose, scenario time T0_S + k s): every joint's depth (rectified
camera z, metres) from the keypoints as given (truth + the scenario's noise), from the same keypoints with
their disparities matched along the rows, and the body's truth joint; and the arm's tilt toward the
camera (deg, shoulder -> wrist) for each.
"""
from __future__ import annotations

import sys

import numpy as np

from dip3d_vehicle.bench import make_perception, simulated_frames
from dip3d_vehicle.perception.triangulation import normalize_q, triangulate


def depths(arm, rig) -> np.ndarray:
    """Return the arm's three joints triangulated (rectified camera, metres)."""
    q = normalize_q(rig.Q, rig.disparity_sign)
    return triangulate(q, arm.left_px, arm.left_px[:, 0] - arm.right_px[:, 0])


def tilt_deg(xyz: np.ndarray) -> float:
    """Return the shoulder -> wrist direction's angle toward the camera (deg; positive: toward it)."""
    v = xyz[2] - xyz[0]
    return float(np.degrees(np.arcsin(-v[2] / np.linalg.norm(v))))


def main() -> None:
    """Print one block per frame."""
    scenario, seed = sys.argv[1], int(sys.argv[2])
    t0 = float(sys.argv[3]) if len(sys.argv) > 3 else 3.0
    n = int(sys.argv[4]) if len(sys.argv) > 4 else 4
    data = simulated_frames(scenario, [seed], n, rate_hz=1.0, start_s=t0, approach_m_s=0.0)
    rig = data.rig
    plain, pose_a = make_perception("default", rig, {})
    matched, pose_b = make_perception("default", rig, {"pose.match_disparity": True})
    for k, frame in enumerate(data.frames):
        truth = np.array([rig.R1 @ np.asarray(frame.meta["joints_cam_m"][j]) for j in ("shoulder", "elbow", "wrist")])
        left, right = rig.rectify(frame.left, frame.right)
        rows = []
        for perception, pose in ((plain, pose_a), (matched, pose_b)):
            pose.provide(frame.meta.get("keypoints"))
            arm = perception.estimate_arm(left, right)
            rows.append(None if arm is None else depths(arm, rig))
        print(f"t {t0 + k:.0f} s  truth z {np.round(truth[:, 2], 2).tolist()} tilt {tilt_deg(truth):6.1f}")
        for name, xyz in zip(("given  ", "matched"), rows):
            if xyz is not None:
                print(f"   {name} z {np.round(xyz[:, 2], 2).tolist()} tilt {tilt_deg(xyz):6.1f} "
                      f"(error {tilt_deg(xyz) - tilt_deg(truth):+6.1f})")


if __name__ == "__main__":
    main()
