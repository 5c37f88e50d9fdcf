"""fam.py with noise in one image only: SIDE=left|right."""
import os, sys
import numpy as np
sys.path.insert(0, "tests/perception")
sys.path.insert(0, "docs/issue11/session33/scripts")
import scene_families as sf
import fam

side = os.environ["SIDE"]
def noisy(keypoints, sigma_px, rng):
    out = {"rectified": False, "source": "test"}
    for s in ("left", "right"):
        out[s] = {k: (np.asarray(v, float) + rng.normal(0.0, sigma_px, 2) * (s == side)).tolist()
                  for k, v in keypoints[s].items()}
    return out
sf.noisy = noisy
n, seed0 = int(sys.argv[1]), int(sys.argv[2])
noise = tuple(float(x) for x in sys.argv[3].split(","))
print(fam.summary(fam.tally_default(n, seed0, noise, sys.argv[4:]), f"{seed0} side={side}", noise))
