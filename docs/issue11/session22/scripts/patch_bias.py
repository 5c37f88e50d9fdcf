"""Depth error of each arm joint's row match on rendered frames, for several patch widths.

    PYTHONPATH=. python docs/issue11/session22/scripts/patch_bias.py SCENARIO|FILE ...

For each scenario, seeds 0-5, 4 frames (t = 3, 5, 7, 9 s, the vehicle at its start pose): the truth
joints (0 px noise) are matched along the rectified rows (``joint_stereo.joint_disparities``) with
patches 0.06 / 0.09 / 0.12 m wide at the body's depth, and each matched joint's depth is compared
with the body's truth joint. Printed per scenario and patch: for shoulder, elbow and wrist
``matched frames: median error / p90 |error|`` (metres; positive = the match lies behind the joint).
"""
from __future__ import annotations

import sys

import numpy as np

from dip3d_vehicle.bench import simulated_frames
from dip3d_vehicle.perception.joint_stereo import joint_disparities
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints

PATCHES_M = (0.06, 0.09, 0.12)


def errors(scenario: str) -> list[np.ndarray]:
    """Return one (patches, 3) array of depth errors (metres, NaN = unmatched) per frame."""
    rows = []
    for seed in range(6):
        data = simulated_frames(scenario, [seed], 4, rate_hz=0.5, start_s=3.0, approach_m_s=0.0)
        rig = data.rig
        fb = rig.focal_px * rig.baseline_m
        for frame in data.frames:
            given = frame.meta.get("keypoints_truth")
            if given is None:
                continue
            left, right = rig.rectify(frame.left, frame.right)
            arm = GivenKeypoints("right", given).estimate(left, right, rig)
            truth = np.array([rig.R1 @ np.asarray(frame.meta["joints_cam_m"][j]) for j in ("shoulder", "elbow", "wrist")])
            body = float(np.median(arm.left_px[:, 0] - arm.right_px[:, 0]))
            per_patch = []
            for patch in PATCHES_M:
                found = joint_disparities(left, right, arm.left_px, body, rig.disparity_sign, rig.focal_px,
                                          rig.baseline_m, patch_m=patch)
                per_patch.append(np.where(found.matched, fb / np.abs(found.disparity_px), np.nan) - truth[:, 2])
            rows.append(np.array(per_patch))
    return rows


def summary(rows: list[np.ndarray]) -> str:
    """Return one line: per patch, per joint, 'n:median/p90|e|' (metres)."""
    a = np.array(rows)
    out = []
    for i, patch in enumerate(PATCHES_M):
        cells = []
        for j in range(3):
            v = a[:, i, j]
            v = v[np.isfinite(v)]
            cells.append(f"{len(v)}:{np.median(v):+.2f}/{np.percentile(np.abs(v), 90):.2f}" if len(v) else "0")
        out.append(f"{patch:.2f} m " + " ".join(cells))
    return " | ".join(out)


def main() -> None:
    """Print one line per scenario and one for all."""
    everything = []
    for scenario in sys.argv[1:]:
        rows = errors(scenario)
        everything += rows
        print(f"{scenario[-24:]:>24}  {summary(rows)}")
    print(f"{'all':>24}  {summary(everything)}")


if __name__ == "__main__":
    main()
