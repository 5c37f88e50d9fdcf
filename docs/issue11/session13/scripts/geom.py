"""One frame per scene at 0 px: each object's angle from the measured arm (seen from the shoulder) and its probability.

Usage: PYTHONPATH=. python docs/issue11/session13/scripts/geom.py FAMILY SEED0 N_SCENES [KEY=VALUE ...]
(e.g. selection.keypoint_sigma_px=0.3 tells the selector the arm is nearly exact)
"""
import math
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, "tests/perception")
import scene_families as sf  # noqa: E402
sys.path.insert(0, "docs/issue11/session13/scripts")
from dip3d_vehicle.config import load_params  # noqa: E402
from points import SceneRun  # noqa: E402


def main() -> None:
    fam, seed0, n = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    params = load_params("default", overrides=tuple(sys.argv[4:]))
    with tempfile.TemporaryDirectory() as tmp:
        for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
            res = SceneRun(scene, params).decide(0.0, np.random.default_rng(0))
            if res.arm3d is None or res.selection is None:
                print(k, res.status)
                continue
            s, _, w = res.arm3d.xyz_m
            u = (w - s) / np.linalg.norm(w - s)
            sel = res.selection
            parts = []
            for i, o in enumerate(sel.objects):
                v = o.xyz_m - s
                angle = math.degrees(math.acos(float(np.clip(v @ u / np.linalg.norm(v), -1, 1))))
                parts.append(f"{angle:5.1f} deg p {sel.scores[i]:.2f} z {o.xyz_m[2]:.1f} m")
            print(f"{k} diver z {s[2]:.1f} m {res.status}: " + " | ".join(sorted(parts)) + f" | none {sel.none_probability:.2f}")


if __name__ == "__main__":
    main()
