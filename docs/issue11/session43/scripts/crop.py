import sys, tempfile
from pathlib import Path
import numpy as np, cv2
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception.joint_stereo import patch_half_px
fam, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
want = {int(x) for x in sys.argv[4].split(",")}
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
        if k not in want: continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        td = arm.left_px[:, 0] - arm.right_px[:, 0]
        half = patch_half_px(float(np.median(td)), rig.baseline_m, 0.06)
        x, y = arm.left_px[0].round().astype(int)
        xr = int(round(x - td[0]))
        R = 90
        L = left[y-R:y+R, x-R:x+R].copy(); Rr = right[y-R:y+R, xr-R:xr+R].copy()
        for im in (L, Rr):
            cv2.rectangle(im, (R-half, R-half), (R+half, R+half), (0, 255, 0), 1)
        for j in (1, 2):
            ex, ey = (arm.left_px[j] - arm.left_px[0]).round().astype(int) + R
            cv2.circle(L, (int(ex), int(ey)), 3, (0, 0, 255), -1)
        out = np.hstack([L, Rr])
        out = cv2.resize(out, None, fx=2, fy=2, interpolation=cv2.INTER_NEAREST)
        cv2.imwrite(f"/tmp/s43/crop_{fam}_{seed0}_{k}.png", out)
        print(k, "half", half, "disp", td.round(1))
