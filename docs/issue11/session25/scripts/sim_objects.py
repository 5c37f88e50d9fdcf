"""One simulator frame in detail (vehicle at its start pose, truth + the scenario's noise, ``default``).

    PYTHONPATH=. python docs/issue11/session25/scripts/sim_objects.py SCENARIO|FILE SEED T_S

The truth and estimated joints, and per object: the nearest placard, its probability, its angle from the
true arm and from the estimated (triangulated) arm, seen from the shoulder.
"""
import math
import sys

import numpy as np

from dip3d_vehicle.bench import make_perception, simulated_frames


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """Return the angle between two vectors, degrees."""
    return math.degrees(math.acos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1)))


def main() -> None:
    """Print the frame's arm and objects."""
    scenario, seed, t = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
    data = simulated_frames(scenario, [seed], 1, rate_hz=10, start_s=t, approach_m_s=0.0)
    rig = data.rig
    perception, pose = make_perception("default", rig, {"pose.backend": "keypoints"})
    frame = data.frames[0]
    pose.provide(frame.meta.get("keypoints"))
    res = perception.process(frame.left, frame.right)
    truth = np.array([rig.R1 @ np.asarray(frame.meta["joints_cam_m"][j]) for j in ("shoulder", "elbow", "wrist")])
    placards = {int(i): rig.R1 @ np.asarray(p["xyz_cam_m"]) for i, p in frame.meta["placards"].items()}
    print("target", frame.meta["target_id"], "placards", {i: np.round(c, 2).tolist() for i, c in placards.items()})
    print("truth joints", np.round(truth, 2).tolist())
    if res.arm3d is None or res.selection is None:
        print(res.status, res.reason)
        return
    est = res.arm3d.xyz_m
    print("est joints  ", np.round(est, 2).tolist(), "depth sigma", np.round(res.arm3d.depth_sigma_m, 2).tolist())
    sel = res.selection
    print(res.status, "confidence", round(sel.confidence, 2), "none", round(sel.none_probability, 3), sel.reason)
    for j in np.argsort(-np.asarray(sel.scores)):
        c = np.asarray(sel.objects[j].xyz_m)
        near = min(placards, key=lambda i: np.linalg.norm(placards[i] - c))
        print(f"  placard {near} ({np.linalg.norm(placards[near] - c):.2f} m) P {sel.scores[j]:.3f} "
              f"members {len(sel.objects[j].members)} angle from the true arm {_angle(c - truth[0], truth[2] - truth[0]):.1f}"
              f", from the estimated {_angle(c - est[0], est[2] - est[0]):.1f} deg")


if __name__ == "__main__":
    main()
