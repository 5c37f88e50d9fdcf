"""For chosen scenes of a family (truth keypoints): why the pointed placard gives no unrecognised spot.

Prints the target's rectified left pixel, whether it lies in the corridor's wedge, the difference of Gaussians
there against the wedge's level, its rank among the responses, whether ``spots`` keeps it, and the right-image match.

Usage (from tests/perception):
  PYTHONPATH=../..:. python ../../docs/issue11/session71/scripts/why_no_spot.py FAMILY N SEED0 K [K...]
"""
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np

import scene_families as sf
from dip3d_vehicle.perception.joint_stereo import _grey, match_point


def main() -> None:
    family, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    wanted = {int(a) for a in sys.argv[4:]}
    with tempfile.TemporaryDirectory() as tmp:
        for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
            if k not in wanted:
                continue
            rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
            checked = perception.check_arm(arm)
            cands = perception.add_corridor(left, right, checked.arm, base)
            result = perception.decide(checked, cands, images=(left, right))
            poly = perception.corridor.wedge(checked.arm, left.shape[1], left.shape[0], rig)
            centre = scene.target_polygon.mean(axis=0)
            tx, ty = rig.to_rectified(centre[None], "left")[0] if hasattr(rig, "to_rectified") else centre
            inside = cv2.pointPolygonTest(poly.astype(np.float32), (float(tx), float(ty)), True)
            bf = perception.blobs
            resp = bf.responses(left, poly)
            d = np.hypot(resp[:, 0] - tx, resp[:, 1] - ty) if len(resp) else np.zeros(0)
            near = np.flatnonzero(d < 6)
            known = [base_px for base_px in ([cands.left_px[list(o.members)] for o in result.selection.objects]
                                             if result.selection else [])]
            spots, owners = bf.spots(resp, known, poly)
            ds = np.hypot(spots[:, 0] - tx, spots[:, 1] - ty) if len(spots) else np.zeros(0)
            fb = rig.focal_px * rig.baseline_m
            half = int(max(4, round(2.0 * bf.inner_sigma_px + 2)))
            m = match_point(left, right, int(round(tx)), int(round(ty)), fb / bf.max_depth_m, fb / bf.min_depth_m,
                            rig.disparity_sign, half, 0.0, 1.5)
            true_disp = fb / scene.frame.meta["placards"][scene.scenario.target_id]["xyz_cam_m"][2]
            # the wedge's own level, as _spots_in computes it per piece: report the response magnitude near the target
            g = cv2.resize(_grey(left), None, fx=0.5, fy=0.5, interpolation=cv2.INTER_AREA)
            dog = cv2.GaussianBlur(g, (0, 0), 1.0) - cv2.GaussianBlur(g, (0, 0), 2.5)
            y2, x2 = int(round(ty / 2)), int(round(tx / 2))
            patch = dog[y2 - 3:y2 + 4, x2 - 3:x2 + 4]
            print(f"k={k} width={scene.target_width_px:.0f}px range={scene.target_range_m:.1f}m target rect px "
                  f"({tx:.0f},{ty:.0f}) in wedge {inside:+.0f}px; |DoG| max near {np.abs(patch).max():.1f}; "
                  f"responses {len(resp)}, near the target: {[(int(i), round(float(resp[i, 2]), 1)) for i in near]}; "
                  f"weakest response {resp[:, 2].min() if len(resp) else float('nan'):.1f}; spots {len(spots)}, "
                  f"near the target {[(int(i), owners[i]) for i in np.flatnonzero(ds < 6)]}; "
                  f"match {None if m is None else tuple(round(float(v), 2) for v in m)} true disparity {true_disp:.1f}; "
                  f"status {result.status}")
            print("   spots kept:", [(round(float(x)), round(float(y))) for x, y in result.unrecognised.left_px])


if __name__ == "__main__":
    main()
