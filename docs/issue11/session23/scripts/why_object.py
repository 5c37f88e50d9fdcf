"""One family scene: the arm as given vs estimated (3D, rectified left frame), each object's gate and log odds.

    PYTHONPATH=.:tests/perception python docs/issue11/session23/scripts/why_object.py FAMILY SEED0 SCENE [NOISE_PX DRAW] [KEY=VALUE ...]
"""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf
from draws import draws, nth_scene, scene_args


def main() -> None:
    """Print the arm, then per object: placard, gate, cost, log odds."""
    family, seed0, want, sigma, want_draw, overrides = scene_args()
    with tempfile.TemporaryDirectory() as tmp:
        scene = nth_scene(Path(tmp), family, seed0, want)
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", overrides)
        pl = {pid: rig.R1 @ np.asarray(p["xyz_cam_m"]) for pid, p in scene.frame.meta["placards"].items()}
        for d, kp, joints in draws(scene, seed0, want, sigma):
            if d != want_draw:
                continue
            print("truth joints", {j: np.round(v, 3).tolist() for j, v in joints.items()})
            pose.provide(kp)
            checked = perception.check_arm(perception.estimate_arm(left, right))
            arm3d = checked.arm3d
            print("est joints  ", {j: np.round(arm3d.joint(j), 3).tolist() for j in ("shoulder", "elbow", "wrist")},
                  "depth sigma", np.round(arm3d.depth_sigma_m, 3).tolist())
            ax_t = joints["wrist"] - joints["shoulder"]
            ax_e = arm3d.joint("wrist") - arm3d.joint("shoulder")
            ang = np.degrees(np.arccos(ax_t @ ax_e / np.linalg.norm(ax_t) / np.linalg.norm(ax_e)))
            print(f"arm direction error {ang:.1f} deg")
            for pid, c in pl.items():
                d_ = c - joints["shoulder"]
                a_t = np.degrees(np.arccos(d_ @ ax_t / np.linalg.norm(d_) / np.linalg.norm(ax_t)))
                d2 = c - arm3d.joint("shoulder")
                a_e = np.degrees(np.arccos(d2 @ ax_e / np.linalg.norm(d2) / np.linalg.norm(ax_e)))
                print(f"  placard {pid}{'*' if pid == scene.scenario.target_id else ' '} angle from truth arm {a_t:5.1f}, from est arm {a_e:5.1f}")
            res = perception.decide(checked, perception.add_corridor(left, right, checked.arm, base), images=(left, right))
            sel = res.selection
            print(res.status, res.reason, "none %.3f" % sel.none_probability if sel else "")
            if sel is None:
                return
            for o, p in zip(sel.objects, sel.scores):
                near = min(pl, key=lambda q: np.linalg.norm(pl[q] - o.xyz_m))
                print(f"  object P {p:.3f} placard {near} ({np.linalg.norm(pl[near] - o.xyz_m):.2f} m) "
                      f"px {np.round(o.left_px).tolist()} xyz {np.round(o.xyz_m, 2).tolist()} from wrist {np.linalg.norm(o.xyz_m - arm3d.joint('wrist')):.2f} m members {len(o.members)}")
            return


if __name__ == "__main__":
    main()
