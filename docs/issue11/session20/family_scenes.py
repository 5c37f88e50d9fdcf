"""Per scene of one generated family: every draw's outcome, choice, confidence, P(nothing), spots.

    PYTHONPATH=.:tests/perception python docs/issue11/session20/family_scenes.py FAMILY N SEED0 [NOISE_PX] [KEY=VALUE ...]

Truth keypoints plus Gaussian noise (the families' own draws, 8 per noise level), profile ``default``.
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf


def main() -> None:
    """Print one line per draw."""
    family, n, seed0 = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    sigma = float(sys.argv[4]) if len(sys.argv) > 4 else 2.0
    overrides = sys.argv[5:]
    with tempfile.TemporaryDirectory() as tmp:
        for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
            truth = scene.frame.meta["keypoints_truth"]
            rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", overrides)
            rng = np.random.default_rng(seed0 + k)
            for s in (0.0, 1.0, 2.0, 4.0):
                for d in range(8 if s > 0 else 1):
                    pose.provide(sf.noisy(truth, s, rng))
                    if s != sigma:
                        continue
                    result = sf.decided(perception, left, right, base)
                    sel = result.selection
                    out = sf.outcome(scene, result, rig)
                    line = (f"scene {k:2d} {scene.band} w{scene.target_width_px:5.1f}px margin "
                            f"{sf.pointing_margin_deg(scene):5.1f} draw {d} {out:15s} {result.status:15s}")
                    if sel is not None:
                        spots = len(getattr(result, "unrecognised", ()) or ())
                        line += (f" conf {sel.confidence:.2f} none {sel.none_probability:.2f} amb {int(sel.ambiguous)}"
                                 f" objs {len(sel.objects)} spots {spots}")
                    print(line, flush=True)


if __name__ == "__main__":
    main()
