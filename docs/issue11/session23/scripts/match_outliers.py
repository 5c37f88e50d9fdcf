"""Per family draw: the given arm's direction error with and without the row match, and which joint's match hurt.

    PYTHONPATH=.:tests/perception python docs/issue11/session23/scripts/match_outliers.py SEED0 N_SCENES [NOISE_PX] [KEY=VALUE ...]

Truth keypoints plus Gaussian noise (the families' draws, 8 per scene), profile ``default`` with the match
on (as configured, ``KEY=VALUE`` overrides apply) against the same draw with ``pose.match_disparity=false``.
Disparity errors are against the truth joints' own disparity (rectified, pixels).
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf
from draws import draws


def direction_error_deg(arm3d, truth: dict) -> float:
    """Angle (deg) between the estimated and the true shoulder->wrist direction."""
    a = arm3d.joint("wrist") - arm3d.joint("shoulder")
    b = truth["wrist"] - truth["shoulder"]
    return float(np.degrees(np.arccos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1))))


def main() -> None:
    seed0, n = int(sys.argv[1]), int(sys.argv[2])
    sigma = float(sys.argv[3]) if len(sys.argv) > 3 else 2.0
    overrides = tuple(sys.argv[4:])
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for family in sf.FAMILIES:
            for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
                truth = scene.frame.meta["keypoints_truth"]
                rig, left, right, pose, on, _, _ = sf.prepared(scene, "default", overrides)
                _, _, _, pose_off, off, _, _ = sf.prepared(scene, "default", overrides + ("pose.match_disparity=false",))
                joints = {j: rig.R1 @ np.asarray(v) for j, v in scene.frame.meta["joints_cam_m"].items()}
                fb = rig.focal_px * rig.baseline_m
                true_disp = np.array([fb / joints[j][2] for j in ("shoulder", "elbow", "wrist")])
                for d, kp, _ in draws(scene, seed0, k, sigma):
                    pose.provide(kp)
                    pose_off.provide(kp)
                    a_on, a_off = on.estimate_arm(left, right), off.estimate_arm(left, right)
                    c_on, c_off = on.check_arm(a_on), off.check_arm(a_off)
                    if c_on.arm3d is None or c_off.arm3d is None:
                        continue
                    e_on, e_off = direction_error_deg(c_on.arm3d, joints), direction_error_deg(c_off.arm3d, joints)
                    d_on = rig.disparity_sign * (a_on.left_px[:, 0] - a_on.right_px[:, 0]) - true_disp
                    d_off = rig.disparity_sign * (a_off.left_px[:, 0] - a_off.right_px[:, 0]) - true_disp
                    used = a_on.disparity_matched if a_on.disparity_matched is not None else np.zeros(3, bool)
                    rows.append((family, k, d, e_on, e_off, d_on, d_off, used, scene.band))
                    if e_on > e_off + 8.0:
                        print(f"{family:13s} scene {k:2d} draw {d} dir err on {e_on:5.1f} off {e_off:5.1f} "
                              f"disp err on {np.round(d_on, 1).tolist()} off {np.round(d_off, 1).tolist()} "
                              f"used {used.tolist()} true disp {np.round(true_disp, 1).tolist()}", flush=True)
    for family in (*sf.FAMILIES, "all"):
        sub = [r for r in rows if family in ("all", r[0])]
        if not sub:
            continue
        on = np.array([r[3] for r in sub])
        off = np.array([r[4] for r in sub])
        print(f"{family:13s} n {len(sub):3d} dir err on median {np.median(on):5.1f} p90 {np.percentile(on, 90):5.1f} "
              f">15deg {np.mean(on > 15):5.1%} | off median {np.median(off):5.1f} p90 {np.percentile(off, 90):5.1f} "
              f">15deg {np.mean(off > 15):5.1%} | on worse by >8deg {np.mean(on > off + 8):5.1%}")
        used = np.array([r[7] for r in sub])
        err = np.abs(np.array([r[5] for r in sub]))
        print(f"{'':13s} matched share S/E/W {np.round(used.mean(axis=0), 2).tolist()}  |disp err| px median S/E/W "
              f"{np.round(np.median(err, axis=0), 2).tolist()} p90 {np.round(np.percentile(err, 90, axis=0), 2).tolist()}"
              f"  as given {np.round(np.median(np.abs(np.array([r[6] for r in sub])), axis=0), 2).tolist()}")


if __name__ == "__main__":
    main()
