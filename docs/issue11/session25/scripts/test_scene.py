"""One scene of a family as ``scene_families.tally_family`` draws it in the tests (2 draws at 2 px): arm and objects.

    PYTHONPATH=.:tests/perception python docs/issue11/session25/scripts/test_scene.py FAMILY SCENE SEED0

E.g. ``undetectable 3 0``: scene 3 of ``test_open_set_families_never_confidently_wrong``. Per draw: whether
the shoulder's own patch matched, the head's match (depth, stand-in sigma), the truth and estimated joints,
each placard's angle from the true and the estimated arm (deg, from the shoulder), and the objects' P.
"""
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf
from dip3d_vehicle.perception import joint_stereo as js


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """Return the angle between two vectors, degrees."""
    return math.degrees(math.acos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1)))


def main() -> None:
    """Print both draws of the scene."""
    family, want, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    with tempfile.TemporaryDirectory() as tmp:
        scene = list(sf.scenes(Path(tmp), family, want + 1, seed0))[want]
        truth_kp = scene.frame.meta["keypoints_truth"]
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", ())
        joints = {j: rig.R1 @ np.asarray(v) for j, v in scene.frame.meta["joints_cam_m"].items()}
        placards = {pid: rig.R1 @ np.asarray(p["xyz_cam_m"]) for pid, p in scene.frame.meta["placards"].items()}
        fb = rig.focal_px * rig.baseline_m
        rng = np.random.default_rng(seed0 + want)
        for d in range(2):
            pose.provide(sf.noisy(truth_kp, 2.0, rng))
            raw = pose.estimate(left, right, rig)
            body = float(np.median(raw.left_px[:, 0] - raw.right_px[:, 0]))
            head = js._head_disparity(raw, left, right, body, rig.disparity_sign, rig.focal_px, rig.baseline_m)
            own = js.joint_disparities(left, right, raw.left_px[:1], body, rig.disparity_sign, rig.focal_px,
                                       rig.baseline_m, patch_m=0.06)
            checked = perception.check_arm(perception.estimate_arm(left, right))
            arm = checked.arm3d
            print(f"draw {d}: shoulder's own patch matched {bool(own.matched[0])}; head match "
                  f"{'none' if head is None else f'{fb / abs(head[0]):.3f} m, stand-in sigma {head[1] * fb / head[0] ** 2:.3f} m'}")
            print("  truth", {j: np.round(joints[j], 3).tolist() for j in ("shoulder", "elbow", "wrist")})
            print("  est  ", {j: np.round(arm.joint(j), 3).tolist() for j in ("shoulder", "elbow", "wrist")},
                  "depth sigma", np.round(arm.depth_sigma_m, 3).tolist())
            t_axis = joints["wrist"] - joints["shoulder"]
            e_axis = arm.joint("wrist") - arm.joint("shoulder")
            for pid, c in placards.items():
                print(f"  placard {pid}{'*' if pid == scene.scenario.target_id else ' '} from the true arm "
                      f"{_angle(c - joints['shoulder'], t_axis):5.1f}, the estimated {_angle(c - arm.joint('shoulder'), e_axis):5.1f}")
            res = perception.decide(checked, perception.add_corridor(left, right, checked.arm, base), images=(left, right))
            sel = res.selection
            print(f"  {res.status}, none {sel.none_probability:.2f}")
            for o, p in zip(sel.objects, sel.scores):
                near = min(placards, key=lambda q: np.linalg.norm(placards[q] - o.xyz_m))
                print(f"    P {p:.3f} placard {near} members {len(o.members)}")


if __name__ == "__main__":
    main()
