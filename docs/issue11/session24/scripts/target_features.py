"""One family scene: the matched features on the pointed placard (main pass, corridor), their 3D points and groups.

    PYTHONPATH=.:tests/perception:docs/issue11/session23/scripts python docs/issue11/session24/scripts/target_features.py FAMILY SEED0 SCENE [NOISE_PX DRAW] [KEY=VALUE ...]
"""
from __future__ import annotations

import tempfile
from pathlib import Path

import cv2
import numpy as np

import scene_families as sf
from draws import draws, nth_scene, scene_args


def main() -> None:
    """Print every candidate on the target placard with its 3D point and its group (min 1 feature: the fragments, none joined)."""
    family, seed0, want, sigma, want_draw, overrides = scene_args()
    from dip3d_vehicle.perception.selection import group_objects
    from dip3d_vehicle.perception.triangulation import triangulate
    with tempfile.TemporaryDirectory() as tmp:
        scene = nth_scene(Path(tmp), family, seed0, want)
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", overrides)
        tgt = rig.R1 @ np.asarray(scene.frame.meta["placards"][scene.scenario.target_id]["xyz_cam_m"])
        print("target", np.round(tgt, 2).tolist(), "width px", round(scene.target_width_px, 1))
        for d, kp, _ in draws(scene, seed0, want, sigma):
            if d != want_draw:
                continue
            pose.provide(kp)
            checked = perception.check_arm(perception.estimate_arm(left, right))
            cands = perception.add_corridor(left, right, checked.arm, base)
            xyz = triangulate(perception.Q, cands.left_px, cands.disparity_px)
            orig = rig.to_original(cands.left_px, "left")
            on = np.array([cv2.pointPolygonTest(scene.target_polygon, (float(p[0]), float(p[1])), True) >= -3
                           for p in orig])
            print(f"draw {d}: {len(cands)} candidates ({len(base)} main), {on.sum()} on the target (main {on[:len(base)].sum()})")
            p = perception.params
            objs = group_objects(cands, xyz, rig, p["selection.group_radius_px"], p["selection.group_radius_m"], 1,
                                 p["selection.object_radius_m"])
            label = np.full(len(cands), -1)
            for k, o in enumerate(objs):
                label[list(o.members)] = k
            for i in np.flatnonzero(on):
                g = label[i]
                print(f"  {'main' if i < len(base) else 'corr'} px {np.round(cands.left_px[i], 1).tolist()} "
                      f"disp {cands.disparity_px[i]:.2f} xyz {np.round(xyz[i], 3).tolist()} group {g} "
                      f"(size {len(objs[g].members) if g >= 0 else 0})")


if __name__ == "__main__":
    main()
