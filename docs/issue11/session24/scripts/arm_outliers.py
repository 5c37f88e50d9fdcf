"""Per family draw: the estimated arm's direction error and limb lengths (gross row-match failures).

    PYTHONPATH=.:tests/perception:docs/issue11/session23/scripts python docs/issue11/session24/scripts/arm_outliers.py SEED0 [NOISE_PX] [N] [KEY=VALUE ...]

Prints the draws whose 3D shoulder-to-wrist direction is more than 20 deg off the truth, and a summary.
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf
from draws import draws

FAMILIES = ("line_of_sight", "far", "undetectable", "elbow", "far_diver")


def main() -> None:
    """Print the gross draws, then the count per family."""
    seed0 = int(sys.argv[1])
    sigma = float(sys.argv[2]) if len(sys.argv) > 2 else 2.0
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 20
    overrides = sys.argv[4:]
    errs = []
    with tempfile.TemporaryDirectory() as tmp:
        for family in FAMILIES:
            for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
                rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", overrides)
                for d, kp, joints in draws(scene, seed0, k, sigma):
                    pose.provide(kp)
                    checked = perception.check_arm(perception.estimate_arm(left, right))
                    if checked.arm3d is None:
                        continue
                    est = checked.arm3d.xyz_m
                    t = np.array([joints["shoulder"], joints["elbow"], joints["wrist"]])
                    u, v = est[2] - est[0], t[2] - t[0]
                    err = float(np.degrees(np.arccos(np.clip(u @ v / np.linalg.norm(u) / np.linalg.norm(v), -1, 1))))
                    errs.append((family, err))
                    if err > 20:
                        upper, fore = np.linalg.norm(est[1] - est[0]), np.linalg.norm(est[2] - est[1])
                        dz = np.round(est[:, 2] - t[:, 2], 2).tolist()
                        arm = checked.arm
                        fb = rig.focal_px * rig.baseline_m
                        derr = np.round((arm.left_px[:, 0] - arm.right_px[:, 0]) - fb / t[:, 2], 1).tolist()
                        sig = arm.disparity_sigma_px
                        sig = np.round(sig, 1).tolist() if sig is not None else None
                        matched = arm.disparity_matched.astype(int).tolist() if arm.disparity_matched is not None else None
                        print(f"{family} scene {k} draw {d} err {err:5.1f} deg upper {upper:.2f} fore {fore:.2f} m "
                              f"depth err {dz} disp err {derr} px sigma {sig} matched {matched}", flush=True)
    for family in FAMILIES:
        e = np.array([x for f, x in errs if f == family])
        print(f"{family}: {len(e)} draws, median {np.median(e):.1f} deg, p90 {np.percentile(e, 90):.1f}, >20 deg {int((e > 20).sum())}")


if __name__ == "__main__":
    main()
