"""Sweep variants on one family: same scenes, same draws; prints JSON counts per variant/band/noise."""
import sys, json, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
fam, seed0, n, draws = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
variants = [tuple(v.split(",")) if v else () for v in sys.argv[5:]]
out = {}
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
        truth = scene.frame.meta["keypoints_truth"]; rig = scene.scenario.rig()
        L, R = rig.rectify(scene.frame.left, scene.frame.right)
        base = None
        for vi, ov in enumerate(variants):
            pose = GivenKeypoints("right", truth)
            per = Perception(rig, load_params("default", overrides=ov), pose)
            if base is None:
                base = per.detector.detect(L, R, pose.estimate(L, R, rig), rig)
            rng = np.random.default_rng(seed0 + k)
            for sigma in (0.0, 1.0, 2.0, 4.0):
                for _ in range(draws if sigma else 1):
                    pose.provide(sf.noisy(truth, sigma, rng))
                    checked = per.check_arm(per.estimate_arm(L, R))
                    res = checked
                    if checked.status == "ok":
                        res = per.decide(checked, per.add_corridor(L, R, checked.arm, base))
                    key = f"{vi}|{'und' if fam == 'undetectable' else 'det'}|{scene.band}|{sigma:.0f}"
                    cell = out.setdefault(key, dict.fromkeys(sf.OUTCOMES, 0))
                    cell[sf.outcome(scene, res, rig)] += 1
print(json.dumps({"family": fam, "seed0": seed0, "variants": [list(v) for v in variants], "counts": out}))
