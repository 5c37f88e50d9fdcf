"""Per family: each joint's RAW row match (before it is combined with the given disparity) against the truth joint.

    PYTHONPATH=.:tests/perception python docs/issue11/session23/scripts/raw_match.py SEED0 N_SCENES [NOISE_PX]

Truth keypoints plus Gaussian noise (the families' draws), the match as ``match_arm`` runs it (patch
``pose.match_disparity_patch_m``, the keypoints' median disparity as the body's). Depth error in metres,
positive = the match lies behind the joint; matched share per joint.
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf
from draws import draws
from dip3d_vehicle.perception.joint_stereo import joint_disparities


def main() -> None:
    seed0, n = int(sys.argv[1]), int(sys.argv[2])
    sigma = float(sys.argv[3]) if len(sys.argv) > 3 else 2.0
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        for family in sf.FAMILIES:
            for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
                truth = scene.frame.meta["keypoints_truth"]
                rig, left, right, pose, perception, _, _ = sf.prepared(scene, "default")
                joints = {j: rig.R1 @ np.asarray(v) for j, v in scene.frame.meta["joints_cam_m"].items()}
                fb = rig.focal_px * rig.baseline_m
                zt = np.array([joints[j][2] for j in ("shoulder", "elbow", "wrist")])
                for d, kp, _ in draws(scene, seed0, k, sigma):
                    pose.provide(kp)
                    arm = pose.estimate(left, right, rig)
                    body = float(np.median(arm.left_px[:, 0] - arm.right_px[:, 0]))
                    found = joint_disparities(left, right, arm.left_px, body, rig.disparity_sign, rig.focal_px,
                                              rig.baseline_m, patch_m=float(perception.params["pose.match_disparity_patch_m"]))
                    z = fb / np.abs(found.disparity_px)
                    err = np.where(found.matched, z - zt, np.nan)
                    rows.setdefault(family, []).append((err, zt))
    for family, rs in rows.items():
        err = np.array([r[0] for r in rs])
        zt = np.array([r[1] for r in rs])
        line = f"{family:13s} n {len(rs):3d} depth {np.median(zt[:, 0]):.1f} m"
        for j, name in enumerate(("shoulder", "elbow", "wrist")):
            e = err[:, j][np.isfinite(err[:, j])]
            if len(e):
                line += (f" | {name} matched {len(e) / len(rs):4.0%} median {np.median(e):+.3f} "
                         f"p10/p90 {np.percentile(e, 10):+.3f}/{np.percentile(e, 90):+.3f}")
        print(line, flush=True)


if __name__ == "__main__":
    main()
