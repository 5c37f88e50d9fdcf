"""Is the arm's stated depth uncertainty honest? Per family draw: (dz_est - dz_true) / hypot(sigma_shoulder, sigma_wrist).

    PYTHONPATH=.:tests/perception python docs/issue11/session23/scripts/tilt_calibration.py SEED0 N_SCENES [NOISE_PX] [KEY=VALUE ...]

dz = wrist depth - shoulder depth (metres), the arm's tilt toward the camera, which the selector's
Occam factor widens by the same hypot. A calibrated arm gives a normalised error of std ~1.
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf
from draws import draws


def main() -> None:
    seed0, n = int(sys.argv[1]), int(sys.argv[2])
    sigma = float(sys.argv[3]) if len(sys.argv) > 3 else 2.0
    overrides = tuple(sys.argv[4:])
    with tempfile.TemporaryDirectory() as tmp:
        for family in sf.FAMILIES:
            z = []
            for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
                truth = scene.frame.meta["keypoints_truth"]
                rig, left, right, pose, perception, _, _ = sf.prepared(scene, "default", overrides)
                joints = {j: rig.R1 @ np.asarray(v) for j, v in scene.frame.meta["joints_cam_m"].items()}
                dz_true = joints["wrist"][2] - joints["shoulder"][2]
                for d, kp, _ in draws(scene, seed0, k, sigma):
                    pose.provide(kp)
                    checked = perception.check_arm(perception.estimate_arm(left, right))
                    if checked.arm3d is None:
                        continue
                    a = checked.arm3d
                    dz = a.joint("wrist")[2] - a.joint("shoulder")[2]
                    z.append((dz - dz_true) / np.hypot(a.depth_sigma_m[0], a.depth_sigma_m[2]))
            z = np.array(z)
            print(f"{family:13s} n {len(z):3d} normalised tilt error: median {np.median(z):+.2f} "
                  f"robust std {1.4826 * np.median(np.abs(z - np.median(z))):.2f} |z|>2 {np.mean(np.abs(z) > 2):.0%} "
                  f"|z|>3 {np.mean(np.abs(z) > 3):.0%}", flush=True)


if __name__ == "__main__":
    main()
