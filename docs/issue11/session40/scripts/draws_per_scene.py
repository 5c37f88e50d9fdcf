import os, sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
family, n, seed0, noise = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
want = [int(x) for x in sys.argv[5].split(",")]
over = sys.argv[6:]
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        if k not in want: continue
        truth = scene.frame.meta["keypoints_truth"]
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", over)
        rng = np.random.default_rng(seed0 + k)
        print("scene", k, "target", scene.frame.meta.get("target_id"), {pid: [round(c,2) for c in i["xyz_cam_m"]] for pid,i in scene.frame.meta["placards"].items()})
        print("  joints", {j: [round(c,3) for c in v] for j, v in scene.frame.meta["joints_cam_m"].items()})
        for _ in range(8):
            pose.provide(sf.noisy(truth, noise, rng))
            r = sf.decided(perception, left, right, base)
            sel = r.selection
            out = sf.outcome(scene, r, rig)
            a3 = r.arm3d
            js = "" if a3 is None else " ".join(f"{z:.2f}±{s:.2f}" for z, s in zip(a3.xyz_m[:,2], a3.depth_sigma_m))
            objs = "" if sel is None else " ".join(f"[{o.xyz_m[0]:.2f},{o.xyz_m[1]:.2f},{o.xyz_m[2]:.2f}]:{p:.2f}" for o, p in zip(sel.objects, sel.scores))
            un = r.unrecognised if hasattr(r, "unrecognised") else None; print("   spots", None if un is None else [(round(float(p[0])), round(float(p[1])), round(float(x[2]),2)) for p, x in zip(un.left_px, un.xyz_m)]); print(f"  {out:9s} {r.status:15s} none {sel.none_probability if sel else float('nan'):.2f} amb {sel.ambiguous if sel else None} z {js} | {objs}")
