"""Per scene (0 px): the shoulder's raw match offset (m, + = surface in front of the joint) against body geometry."""
import sys, math
import numpy as np
sys.path.insert(0, "docs/issue11/session43/scripts")
from raw_scenes import raw_scenes, sf  # noqa: E402
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
fams = sys.argv[3].split(",") if len(sys.argv) > 3 else list(sf.FAMILIES)
rows = []
for family, k, m, rig, arm, td, raw in raw_scenes(fams, n, seed0):
    if not raw.matched[0]:
        continue
    f, b = rig.focal_px, rig.baseline_m
    zt = f * b / abs(td[0]); zr = f * b / abs(raw.disparity_px[0])
    bt = m["body_truth"]["xyz_cam_m"]
    j = m["joints_cam_m"]
    S = np.array(j["shoulder"]); W = np.array(j["wrist"]); E = np.array(j["elbow"])
    names = [n_ for n_ in bt if n_.endswith("shoulder")]
    # the pointing shoulder is the one at joints_cam_m shoulder
    other = [np.array(bt[n_]) for n_ in names if np.linalg.norm(np.array(bt[n_]) - S) > 1e-3][0]
    width = np.linalg.norm(other - S)
    turn = math.degrees(math.asin(np.clip((other[2] - S[2]) / width, -1, 1)))  # + : other shoulder farther
    arm_tilt = math.degrees(math.asin(np.clip((W[2] - S[2]) / np.linalg.norm(W - S), -1, 1)))
    elev = math.degrees(math.atan2(-(W[1] - S[1]), np.hypot(W[0] - S[0], W[2] - S[2])))
    nose = np.array(bt["nose"])
    rows.append((family, k, zt, zt - zr, turn, arm_tilt, elev, nose[2] - S[2], float(raw.sigma_px[0]), float(raw.score[0])))
    print(f"{family:14s}{k:3d} Z {zt:.2f} off {zt-zr:+.3f} turn {turn:+6.1f} tilt {arm_tilt:+6.1f} elev {elev:+6.1f} nose-dz {nose[2]-S[2]:+.3f} sig {raw.sigma_px[0]:.2f} score {raw.score[0]:.2f}", flush=True)
a = np.array([r[2:] for r in rows], float)
for i, name in enumerate(("Z", "turn", "tilt", "elev", "nose_dz", "sigma", "score")):
    col = a[:, 0 if i == 0 else i + 1]
    print(name, "corr with offset %.2f" % np.corrcoef(col, a[:, 1])[0, 1])
