"""Per scene (0 px): the wrist's raw match error (px, + = in front) and after the hand share, against arm geometry."""
import sys, math
import numpy as np
sys.path.insert(0, "docs/issue11/session43/scripts")
from raw_scenes import raw_scenes, sf  # noqa: E402
from dip3d_vehicle.perception.given_arm import WRIST_HAND_SHARE  # noqa: E402
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
rows = []
for family, k, m, rig, arm, td, raw in raw_scenes(sf.FAMILIES, n, seed0):
    if not raw.matched[2]:
        continue
    e_raw = raw.disparity_px[2] - td[2]
    corr = raw.disparity_px[2] - WRIST_HAND_SHARE * (raw.disparity_px[2] - td[0])
    e_corr = corr - td[2]
    j = m["joints_cam_m"]
    S, E, W = (np.array(j[x]) for x in ("shoulder", "elbow", "wrist"))
    fore = W - E
    tilt_f = math.degrees(math.asin(np.clip(fore[2] / np.linalg.norm(fore), -1, 1)))
    u = (arm.left_px[2] - arm.left_px[1]); ang = math.degrees(math.atan2(abs(u[1]), abs(u[0])))
    rows.append((e_raw, e_corr, tilt_f, ang, td[2], raw.sigma_px[2], raw.score[2]))
    print(f"{family:14s}{k:3d} d {td[2]:5.1f} raw {e_raw:+.2f} corr {e_corr:+.2f} fore_tilt {tilt_f:+6.1f} img_angle {ang:5.1f} sig {raw.sigma_px[2]:.2f} score {raw.score[2]:.2f}", flush=True)
a = np.array(rows, float)
for i, name in ((2, "fore_tilt"), (3, "img_angle"), (4, "disp"), (5, "sigma"), (6, "score")):
    print(name, "corr raw %.2f corr %.2f" % (np.corrcoef(a[:, i], a[:, 0])[0, 1], np.corrcoef(a[:, i], a[:, 1])[0, 1]))
print("|corr| med %.2f p90 %.2f  |raw| med %.2f p90 %.2f" % (np.median(abs(a[:, 1])), np.percentile(abs(a[:, 1]), 90), np.median(abs(a[:, 0])), np.percentile(abs(a[:, 0]), 90)))
