"""Per family, at one noise level: how each joint's row match ends (match_arm's steps, the 0.06 m patch).

    PYTHONPATH=.:tests/perception:docs/issue11/session23/scripts python docs/issue11/session24/scripts/match_census.py SEED0 [NOISE_PX] [N]

Per joint: flat/no match, matched but dropped as gross (and whether the match or the given was nearer
the truth), matched and used; for the shoulder also the head's fallback.
"""
from __future__ import annotations

import sys
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

import scene_families as sf
from draws import draws

FAMILIES = ("line_of_sight", "far", "undetectable", "elbow", "far_diver")
JOINTS = ("shoulder", "elbow", "wrist")


def main() -> None:
    """Print a census line per family and joint."""
    from dip3d_vehicle.perception import joint_stereo as js
    seed0 = int(sys.argv[1])
    sigma = float(sys.argv[2]) if len(sys.argv) > 2 else 2.0
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 20
    with tempfile.TemporaryDirectory() as tmp:
        for family in FAMILIES:
            tally = {j: Counter() for j in JOINTS}
            for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
                rig, left, right, pose, perception, _, base = sf.prepared(scene, "default")
                fb = rig.focal_px * rig.baseline_m
                for d, kp, joints in draws(scene, seed0, k, sigma):
                    pose.provide(kp)
                    arm = pose.estimate(left, right, rig)
                    given = arm.left_px[:, 0] - arm.right_px[:, 0]
                    truth = np.array([fb / joints[j][2] for j in JOINTS])
                    body = float(np.median(given))
                    found = js.joint_disparities(left, right, arm.left_px, body, rig.disparity_sign, rig.focal_px,
                                                 rig.baseline_m, patch_m=0.06)
                    ms = found.floored_sigma_px(1.0)
                    disp = found.disparity_px.copy()
                    if found.matched[0]:
                        disp[0] = fb / (fb / disp[0] + js.SHOULDER_SURFACE_M)
                    ms[0] = max(ms[0], disp[0] ** 2 / fb * js.SHOULDER_MATCH_SIGMA_M)
                    matched = found.matched.copy()
                    head = js._head_disparity(arm, left, right, body, rig.disparity_sign, rig.focal_px, rig.baseline_m)
                    used_head = head is not None and not matched[0]
                    if used_head:
                        disp[0], ms[0], matched[0] = head[0], head[1], True
                    gs = 2.0 * np.sqrt(2.0)
                    for j, name in enumerate(JOINTS):
                        tag = "head " if (j == 0 and used_head) else ""
                        if not matched[j]:
                            tally[name]["no match"] += 1
                        elif abs(disp[j] - given[j]) > js.MATCH_GROSS_SIGMAS * np.hypot(ms[j], gs):
                            better = "match nearer" if abs(disp[j] - truth[j]) < abs(given[j] - truth[j]) else "given nearer"
                            tally[name][f"{tag}gross, {better}"] += 1
                        else:
                            tally[name][f"{tag}used"] += 1
            for name in JOINTS:
                print(family, name, dict(sorted(tally[name].items())), flush=True)


if __name__ == "__main__":
    main()
