"""Per draw of some scenes: each joint's final disparity error against the truth (px, with its sigma) and the outcome.

    python docs/issue11/session44/scripts/scene_draws.py FAMILY N SEED NOISE DRAWS [SCENE[,SCENE...]] [KEY=VALUE ...]
"""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402

family, n, seed0, noise, draws = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
only = {int(x) for x in sys.argv[6].split(",")} if len(sys.argv) > 6 and "=" not in sys.argv[6] else set()
over = [a for a in sys.argv[6:] if "=" in a]
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        if only and k not in only:
            continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", over)
        td = arm.left_px[:, 0] - arm.right_px[:, 0]
        truth = scene.frame.meta["keypoints_truth"]
        rng = np.random.default_rng(seed0 + k)
        for d in range(draws):
            pose.provide(sf.noisy(truth, noise, rng))
            est = perception.estimate_arm(left, right)
            e = (est.left_px[:, 0] - est.right_px[:, 0]) - td
            sig = est.disparity_sigma_px if est.disparity_sigma_px is not None else np.full(3, np.nan)
            res = sf.decided(perception, left, right, base)
            sel = res.selection
            what = sf.outcome(scene, res, rig)
            tgt = getattr(sel.target, "object_id", None) if sel is not None and sel.target is not None else None
            conf = sel.confidence if sel is not None else float("nan")
            pn = sel.none_probability if sel is not None else float("nan")
            print(f"{family} {k:2d} d{d} err s {e[0]:+.2f}({sig[0]:.2f}) e {e[1]:+.2f}({sig[1]:.2f}) w {e[2]:+.2f}({sig[2]:.2f}) "
                  f"-> {what:15s} {res.status} conf {conf:.2f} none {pn:.2f}", flush=True)
