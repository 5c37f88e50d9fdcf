"""The draw loop the session-44 scripts share: each family scene's truth arm and its noisy given arms."""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402


def noisy_draws(n, seed0, noise_px, draws, families=sf.FAMILIES):
    """Yield (family, k, draw, rig, left, right, perception, truth arm, given arm) per draw (rectified pixels).

    The truth keypoints plus ``noise_px`` of Gaussian noise in both images, drawn as the tally draws them
    (one generator per scene, seeded ``seed0 + k``).
    """
    with tempfile.TemporaryDirectory() as tmp:
        for family in families:
            for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
                rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
                truth = scene.frame.meta["keypoints_truth"]
                rng = np.random.default_rng(seed0 + k)
                for draw in range(draws):
                    pose.provide(sf.noisy(truth, noise_px, rng))
                    yield family, k, draw, rig, left, right, perception, arm, pose.estimate(left, right, rig)
