"""Upper bound of averaging the two eyes' keypoints across the row: fam.py with the LEFT image's noise scaled.

    LEFT_X_SCALE=0.71 python docs/issue11/session41/scripts/fam_left_x.py N SEED NOISE [KEY=VALUE ...]

The left keypoints' noise (x and y) is multiplied by LEFT_X_SCALE (1/sqrt(2): the mean of two independent
eyes); the right image's noise stays at NOISE (pixels).
"""
import os
import sys

import numpy as np

sys.path.insert(0, "tests/perception")
sys.path.insert(0, "docs/issue11/session33/scripts")
import scene_families as sf  # noqa: E402
import fam  # noqa: E402

SCALE = float(os.environ.get("LEFT_X_SCALE", "0.71"))


def noisy(keypoints: dict, sigma_px: float, rng: np.random.Generator) -> dict:
    """Return keypoints with Gaussian noise; the left x noise scaled by SCALE."""
    out = {"rectified": False, "source": "test"}
    for side in ("left", "right"):
        out[side] = {}
        for k, v in keypoints[side].items():
            e = rng.normal(0.0, sigma_px, 2)
            if side == "left":
                e *= SCALE
            out[side][k] = (np.asarray(v, float) + e).tolist()
    return out


sf.noisy = noisy
if __name__ == "__main__":
    n, seed0 = int(sys.argv[1]), int(sys.argv[2])
    noise = tuple(float(x) for x in sys.argv[3].split(","))
    print(fam.summary(fam.tally_default(n, seed0, noise, sys.argv[4:]), f"{seed0} leftx{SCALE}", noise))
