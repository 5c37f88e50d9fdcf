"""Can the blob finder see a family scene's pointed placard? Its placards, the corridor's spots nearest it, its pixels.

    PYTHONPATH=.:tests/perception python docs/issue11/session26/scripts/target_spot.py FAMILY SCENE SEED0

E.g. ``undetectable 3 0`` (scene 3 of ``test_open_set_families_never_confidently_wrong``): the pointed placard
is 7.7 px wide at 4.85 m and 3-10 grey levels from the water around it; the nearest spot the corridor's
difference of Gaussians finds is 128 px away, on placard 4. Nothing there can speak for "nothing detected".
"""
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np

import scene_families as sf


def main() -> None:
    """Print the placards (rectified px, depth), the spots nearest the pointed one and the grey levels around it."""
    family, want, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    with tempfile.TemporaryDirectory() as tmp:
        scene = list(sf.scenes(Path(tmp), family, want + 1, seed0))[want]
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", ())
        target = scene.scenario.target_id
        centre = None
        for pid, p in scene.frame.meta["placards"].items():
            xyz = rig.R1 @ np.asarray(p["xyz_cam_m"])
            px = rig.focal_px * xyz[:2] / xyz[2] + np.asarray(rig.principal_point_px)
            width = float(np.ptp(np.asarray(p["left_polygon_px"])[:, 0]))
            print(f"placard {pid}{'*' if pid == target else ' '} rectified px {np.round(px, 1).tolist()} "
                  f"depth {xyz[2]:.2f} m, {width:.1f} px wide")
            centre = px if pid == target else centre
        poly = perception.corridor.wedge(arm, left.shape[1], left.shape[0], rig)
        spots = perception.blobs.responses(left, poly)
        d = np.linalg.norm(spots[:, :2] - centre, axis=1)
        print(f"{len(spots)} spots in the corridor; nearest the pointed placard:",
              [(np.round(spots[i], 1).tolist(), round(float(d[i]), 1)) for i in np.argsort(d)[:3]])
        grey = cv2.cvtColor(left, cv2.COLOR_BGR2GRAY) if left.ndim == 3 else left
        x, y = int(round(centre[0])), int(round(centre[1]))
        patch = grey[y - 15:y + 16, x - 15:x + 16].astype(float)
        print(f"grey levels within 15 px of it: min {patch.min():.0f} median {np.median(patch):.0f} max {patch.max():.0f}")


if __name__ == "__main__":
    main()
