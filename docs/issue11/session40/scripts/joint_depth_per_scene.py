"""Per scene: outcomes, each joint's final depth error mean (m), and the 3D arm direction error (deg), 2 px draws (fam order)."""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
family, n, seed0, noise = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
over = sys.argv[5:]
L = {"correct": "c", "abstained": "a", "wrong": "w", "confident_wrong": "W"}
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        truth = scene.frame.meta["keypoints_truth"]
        J = scene.frame.meta["joints_cam_m"]; T = np.array([J["shoulder"], J["elbow"], J["wrist"]])
        tdir = (T[2]-T[0])/np.linalg.norm(T[2]-T[0])
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", over)
        rng = np.random.default_rng(seed0 + k)
        outs, errs, angs = [], [], []
        for _ in range(8):
            pose.provide(sf.noisy(truth, noise, rng))
            r = sf.decided(perception, left, right, base)
            o = L[sf.outcome(scene, r, rig)]
            outs.append("n" if o == "a" and r.status == "nothing_on_ray" else o)
            if r.arm3d is not None:
                X = r.arm3d.xyz_m; errs.append(X[:, 2] - T[:, 2])
                d = (X[2]-X[0])/np.linalg.norm(X[2]-X[0]); angs.append(np.degrees(np.arccos(np.clip(d@tdir, -1, 1))))
        e = np.mean(errs, axis=0) if errs else [np.nan]*3
        print(f"{k:2d} {np.linalg.norm(T[0]):.1f}m {''.join(outs)} dz S/E/W {e[0]:+.2f} {e[1]:+.2f} {e[2]:+.2f}  ang med {np.median(angs) if angs else np.nan:.1f}", flush=True)
