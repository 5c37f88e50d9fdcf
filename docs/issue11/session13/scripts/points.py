"""Record held points on the scene families: per frame, the selector's probabilities with a truth label.

A "point" is FRAMES consecutive frames of one scene: the same rendered arm (the diver's 5 deg
pointing error, shared) with fresh keypoint noise per frame, each frame decided again with the
mean arm of the last ``behaviour.fusion_arm_frames`` frames, as the mission does
(``behaviours/pointing_states._fuse_frame``). Each output line is one point:
{"family", "scene", "band", "noise", "point", "frames": [{"status", "none", "objects": [[x, y, z, p, on_target]]}]}
``fuse.py`` replays fusion rules over these lines without running perception again.

Usage: PYTHONPATH=. python docs/issue11/session13/scripts/points.py FAMILY SEED0 N_SCENES POINTS FRAMES [KEY=VALUE ...]
(environment SKIP=K: record only scenes K.. of the N; the same scenes and draws as a full run)
"""
import json
import os
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np

sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402
from dip3d_vehicle.config import load_params  # noqa: E402
from dip3d_vehicle.perception.held_arm import HeldArm, decide_held  # noqa: E402
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints  # noqa: E402
from dip3d_vehicle.perception.pipeline import Perception  # noqa: E402

NOISE_PX = (1.0, 2.0, 4.0)


class SceneRun:
    """One rendered scene's rectified pair, truth keypoints and candidates, decided frame by frame."""

    def __init__(self, scene, params) -> None:
        self.truth = scene.frame.meta["keypoints_truth"]
        self.rig = scene.scenario.rig()
        self.left, self.right = self.rig.rectify(scene.frame.left, scene.frame.right)
        self.pose = GivenKeypoints("right", self.truth)
        self.perception = Perception(self.rig, params, self.pose)
        self.base = self.perception.detector.detect(self.left, self.right,
                                                    self.pose.estimate(self.left, self.right, self.rig), self.rig)

    def decide(self, sigma_px: float, rng: np.random.Generator):
        """Return the perception result of one frame with ``sigma_px`` of keypoint noise."""
        per, L, R = self.perception, self.left, self.right
        self.pose.provide(sf.noisy(self.truth, sigma_px, rng))
        res = per.check_arm(per.estimate_arm(L, R))
        return per.decide(res, per.add_corridor(L, R, res.arm, self.base)) if res.status == "ok" else res


def on_target(scene, obj, rig) -> bool:
    """Return True when an object's left-image point lies on the pointed placard."""
    px = rig.to_original(np.asarray(obj.left_px, float)[None, :], "left")[0]
    return cv2.pointPolygonTest(scene.target_polygon, (float(px[0]), float(px[1])), False) >= 0


def frame_record(scene, res, rig) -> dict:
    """Return one frame's status, "none" probability and labelled objects."""
    sel = res.selection
    rec = {"status": res.status, "none": None, "objects": []}
    if sel is not None and res.status in ("ok", "nothing_on_ray"):
        rec["none"] = float(sel.none_probability)
        scores = np.nan_to_num(np.asarray(sel.scores, float), nan=0.0)
        rec["objects"] = [[*map(float, o.xyz_m), float(scores[i]), on_target(scene, o, rig)]
                          for i, o in enumerate(sel.objects)]
    return rec


def main() -> None:
    fam, seed0, n, points, frames = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
    overrides = tuple(sys.argv[6:])
    params = load_params("default", overrides=overrides)
    window = int(params["behaviour.fusion_arm_frames"])
    skip = int(os.environ.get("SKIP", "0"))
    with tempfile.TemporaryDirectory() as tmp:
        for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
            if k < skip:
                continue
            run = SceneRun(scene, params)
            rng = np.random.default_rng(seed0 + k)
            for sigma in NOISE_PX:
                for p in range(points):
                    held, recs = HeldArm(window), []
                    for _ in range(frames):
                        res = run.decide(sigma, rng)
                        if res.status in ("ok", "nothing_on_ray") and res.arm is not None and window > 1:
                            held.add(res.arm)
                            res = decide_held(run.perception, held.mean(), len(held), res)
                        recs.append(frame_record(scene, res, run.rig))
                    print(json.dumps({"family": fam, "scene": k, "band": scene.band, "noise": sigma, "point": p,
                                      "frames": recs}), flush=True)


if __name__ == "__main__":
    main()
