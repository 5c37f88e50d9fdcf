import sys, tempfile, time
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception"); sys.path.insert(0, "docs/issue11/session23/scripts")
import scene_families as sf, draws as dr
from dip3d_vehicle.perception import given_arm as GA
ts, tg = [], []
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), "far", 5, 500)):
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default")
        for d, kp, _ in dr.draws(scene, 500, k, 2.0):
            pose.provide(kp); arm = pose.estimate(left, right, rig)
            body = float(np.median(arm.left_px[:, 0] - arm.right_px[:, 0]))
            t0 = time.perf_counter(); perception.estimate_arm(left, right); ts.append(time.perf_counter() - t0)
            t0 = time.perf_counter(); GA.grid_disparity(left, right, arm.left_px[0], body, rig.disparity_sign, rig.focal_px, rig.baseline_m, 0.06); tg.append(time.perf_counter() - t0)
print(f"estimate_arm (with grid) median {1e3*np.median(ts):.2f} ms p90 {1e3*np.percentile(ts,90):.2f}; grid alone median {1e3*np.median(tg):.2f} ms p90 {1e3*np.percentile(tg,90):.2f}")
