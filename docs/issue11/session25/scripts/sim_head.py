"""Simulator frames: the head's matched depth against the pointing shoulder's true depth (vehicle at its start pose).

    PYTHONPATH=. python docs/issue11/session25/scripts/sim_head.py SCENARIO|FILE SEED T0_S N RATE_HZ

Per frame: the head's match (``joint_stereo._head_disparity``) as depth, the truth shoulder joint's depth,
their difference (metres), whether the shoulder's own 0.06 m patch matched, and the stand-in's sigma.
"""
import sys

import numpy as np

from dip3d_vehicle.bench import make_perception, simulated_frames
from dip3d_vehicle.perception import joint_stereo as js


def main() -> None:
    """Print one line per frame."""
    scenario, seed, t0, n, hz = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
    data = simulated_frames(scenario, [seed], n, rate_hz=hz, start_s=t0, approach_m_s=0.0)
    rig = data.rig
    _, pose = make_perception("default", rig, {"pose.backend": "keypoints", "pose.match_disparity": False})
    fb, sign = rig.focal_px * rig.baseline_m, rig.disparity_sign
    for k, frame in enumerate(data.frames):
        left, right = rig.rectify(frame.left, frame.right)
        pose.provide(frame.meta.get("keypoints"))
        arm = pose.estimate(left, right, rig)
        if arm is None:
            continue
        shoulder = (rig.R1 @ np.asarray(frame.meta["joints_cam_m"]["shoulder"]))[2]
        body = float(np.median(arm.left_px[:, 0] - arm.right_px[:, 0]))
        own = js.joint_disparities(left, right, arm.left_px[:1], body, sign, rig.focal_px, rig.baseline_m, patch_m=0.06)
        head = js._head_disparity(arm, left, right, body, sign, rig.focal_px, rig.baseline_m)
        if head is None:
            print(f"t {t0 + k / hz:.1f} no head match")
            continue
        depth = fb / abs(head[0])
        print(f"t {t0 + k / hz:.1f} head match {depth:.2f} m, shoulder {shoulder:.2f} m, shoulder - head "
              f"{shoulder - depth:+.2f} m, own patch matched {bool(own.matched[0])}, stand-in sigma "
              f"{head[1] * fb / head[0] ** 2:.3f} m")


if __name__ == "__main__":
    main()
