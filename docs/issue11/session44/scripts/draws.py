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


def patch_match(left, right, x, y, body, sign, focal_px, baseline_m):
    """Return one 0.06 m patch's row match at (x, y): (signed disparity, sigma), pixels, or None (as ``match_arm``'s)."""
    from dip3d_vehicle.perception.joint_stereo import MATCH_MIN_SCORE, match_point, patch_half_px, reach_disparities
    d_lo, d_hi = reach_disparities(body, focal_px * baseline_m)
    got = match_point(left, right, int(round(x)), int(round(y)), d_lo, d_hi, sign, patch_half_px(body, baseline_m, 0.06),
                      MATCH_MIN_SCORE, 1.5)
    return None if got is None else (sign * got[0], got[1])
