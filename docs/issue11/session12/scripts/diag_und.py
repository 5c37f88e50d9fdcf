"""Undetectable family per scene: outcomes at 0 px and 2 px, what was chosen and its confidence."""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
fam, seed0, n = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
ov = tuple(sys.argv[4:])
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
        truth = scene.frame.meta["keypoints_truth"]; rig = scene.scenario.rig()
        L, R = rig.rectify(scene.frame.left, scene.frame.right)
        pose = GivenKeypoints("right", truth)
        per = Perception(rig, load_params("default", overrides=ov), pose)
        arm = pose.estimate(L, R, rig)
        base = per.detector.detect(L, R, arm, rig)
        rng = np.random.default_rng(seed0 + k)
        # angles (deg from shoulder) of every placard to the true arm
        joints = {kk: np.asarray(v, float) for kk, v in scene.frame.meta["joints_cam_m"].items()}
        ax = joints["wrist"] - joints["shoulder"]; ax /= np.linalg.norm(ax)
        ang = {}
        for pid, info in scene.frame.meta["placards"].items():
            d = np.asarray(info["xyz_cam_m"], float) - joints["shoulder"]
            ang[pid] = float(np.degrees(np.arccos(np.clip(d @ ax / np.linalg.norm(d), -1, 1))))
        line = []
        for sigma in (0.0, 2.0):
            outs = []
            for _ in range(8 if sigma else 1):
                pose.provide(sf.noisy(truth, sigma, rng))
                checked = per.check_arm(per.estimate_arm(L, R))
                res = checked
                if checked.status == "ok":
                    res = per.decide(checked, per.add_corridor(L, R, checked.arm, base))
                o = sf.outcome(scene, res, rig)
                sel = res.selection
                tag = {"correct": "C", "abstained": "a", "confident_wrong": "W", "wrong": "w"}[o]
                if sel is not None and sel.target is not None and o != "correct":
                    tag += f"{sel.confidence:.2f}/n{sel.none_probability:.2f}"
                outs.append(tag)
            line.append(f"{sigma:.0f}px " + " ".join(outs))
        print(k, f"target {scene.target_range_m:.1f} m ang {ang[scene.scenario.target_id]:.1f}",
              "others", sorted(round(v, 1) for p, v in ang.items() if p != scene.scenario.target_id)[:3], "|", " | ".join(line), flush=True)
