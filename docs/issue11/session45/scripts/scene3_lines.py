import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), "undetectable", 4, 0)):
        if k != 3: continue
        m = scene.frame.meta
        kp = m["keypoints_truth"]["left"]
        s, e, w = (np.array(kp[n]) for n in ("shoulder", "elbow", "wrist"))
        print("s e w px", s, e, w)
        j = m["joints_cam_m"]; print("joints cam", j)
        for pid, p in m["placards"].items():
            c = np.array(p["left_polygon_px"]).mean(0)
            for name, a, b in (("s->w", s, w), ("e->w", e, w)):
                u = (b - a) / np.linalg.norm(b - a); r = c - b
                print(pid, name, "along %.0f across %+.0f px angle %.1f deg" % (r @ u, r[0]*u[1]-r[1]*u[0], np.degrees(np.arctan2(r[0]*u[1]-r[1]*u[0], r @ u))), "range", round(p["range_m"], 2), "target" if pid == m["target_id"] else "")
            # 3D angle from shoulder
            S = np.array(j["shoulder"]) if isinstance(j, dict) else None
        print("pointing", m.get("pointing"))
