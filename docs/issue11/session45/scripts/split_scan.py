import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf
from dip3d_vehicle.perception import selection as S
log = []
orig = S._weakly_joined
def wj(members, pairs, depth=2):
    out = orig(members, pairs, depth)
    if depth == 2 and len(out) > 1:
        log.append([len(p) for p in out])
    return out
S._weakly_joined = wj
seed0 = int(sys.argv[1])
with tempfile.TemporaryDirectory() as tmp:
    for family in sf.FAMILIES:
        for k, scene in enumerate(sf.scenes(Path(tmp), family, 20, seed0)):
            rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
            pose.provide(sf.noisy(scene.frame.meta["keypoints_truth"], 0.0, np.random.default_rng(0)))
            log.clear()
            r = sf.decided(perception, left, right, base)
            if log:
                print(family, k, "splits", log, "outcome", sf.outcome(scene, r, rig), flush=True)
