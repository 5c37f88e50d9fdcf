"""One family scene: is the pointed (tiny) placard found as a spot, and where is it lost?

    PYTHONPATH=.:tests/perception:docs/issue11/session23/scripts python docs/issue11/session24/scripts/spot_trace.py FAMILY SEED0 SCENE [NOISE_PX DRAW]
"""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf
from draws import draws, nth_scene, scene_args


def main() -> None:
    """Print the wedge, the responses near the target, and what the finder made of them."""
    family, seed0, want, sigma, want_draw, _ = scene_args()
    from dip3d_vehicle.perception.selection import group_objects
    from dip3d_vehicle.perception.triangulation import triangulate
    from dip3d_vehicle.perception.blobs import wedge_offset
    from dip3d_vehicle.perception.joint_stereo import match_point
    import cv2
    with tempfile.TemporaryDirectory() as tmp:
        scene = nth_scene(Path(tmp), family, seed0, want)
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default")
        tgt = rig.R1 @ np.asarray(scene.frame.meta["placards"][scene.scenario.target_id]["xyz_cam_m"])
        tpx = (tgt[:2] / tgt[2]) * rig.focal_px + rig.principal_point_px
        print("target xyz", np.round(tgt, 2).tolist(), "rect px", np.round(tpx, 1).tolist(), "w", round(scene.target_width_px, 1))
        for d, kp, _ in draws(scene, seed0, want, sigma):
            if d != want_draw:
                continue
            pose.provide(kp)
            checked = perception.check_arm(perception.estimate_arm(left, right))
            arm = checked.arm
            cands = perception.add_corridor(left, right, arm, base)
            xyz = triangulate(perception.Q, cands.left_px, cands.disparity_px)
            p = perception.params
            objs = group_objects(cands, xyz, rig, p["selection.group_radius_px"], p["selection.group_radius_m"],
                                 p["selection.min_object_features"], p["selection.object_radius_m"])
            poly = perception.corridor.wedge(arm, left.shape[1], left.shape[0], rig)
            print("wedge", np.round(poly, 0).tolist())
            inside = cv2.pointPolygonTest(poly.astype(np.float32).reshape(-1, 1, 2), tuple(map(float, tpx)), True)
            print("target inside wedge (px from edge)", round(inside, 1), "offset", wedge_offset(poly, tpx[None]).round(2))
            resp = perception.blobs.responses(left, poly)
            near = resp[np.linalg.norm(resp[:, :2] - tpx, axis=1) < 25]
            rank = [int(np.flatnonzero((resp == r).all(axis=1))[0]) for r in near]
            print(len(resp), "responses; near target:", np.round(near, 1).tolist(), "ranks", rank)
            known = [cands.left_px[list(o.members)] for o in objs]
            spots, owners = perception.blobs.spots(resp, known, poly)
            for s, o in zip(spots, owners):
                if np.linalg.norm(s - tpx) < 25:
                    print("  kept as spot", np.round(s, 1).tolist(), "owners", o)
            fb = rig.focal_px * rig.baseline_m
            for x, y, _ in near:
                m = match_point(left, right, int(round(x)), int(round(y)), fb / 12.0, fb / 1.0, rig.disparity_sign, 6, 0.7, 1.5)
                print("  match", round(x), round(y), m, "true disp", round(fb / tgt[2], 2))


if __name__ == "__main__":
    main()
