"""The draw loop session 45's scripts share: each scene's drawn keypoints, set on the pose source one draw at a time.

Drawn as the families' tally draws them: the truth keypoints plus ``noise_px`` of Gaussian noise in both images, one
generator per scene seeded ``seed0 + k``. Run the scripts from the repository root.
"""
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402


def draws(families, n, seed0, noise_px, per_scene, overrides=(), only=None):
    """Yield (family, k, d, scene, rig, left, right, perception, truth arm, main pass) per draw, its keypoints set.

    ``only``: the scene indices to keep (None: all). The truth arm's disparities are ``arm.left_px[:, 0] -
    arm.right_px[:, 0]`` (rectified pixels).
    """
    with tempfile.TemporaryDirectory() as tmp:
        for family in families:
            for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
                if only is not None and k not in only:
                    continue
                rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", list(overrides))
                truth = scene.frame.meta["keypoints_truth"]
                rng = np.random.default_rng(seed0 + k)
                for d in range(per_scene):
                    pose.provide(sf.noisy(truth, noise_px, rng))
                    yield family, k, d, scene, rig, left, right, perception, arm, base
