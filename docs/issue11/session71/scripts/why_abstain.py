"""Per scene and draw of one scene family: the default selector's status, P(nothing), the best objects' P, whether
they lie on the pointed placard, and their angles from the simulated arm's line (issue 11 session 71).

Usage (from tests/perception):
  PYTHONPATH=../..:. python ../../docs/issue11/session71/scripts/why_abstain.py FAMILY N SEED0 SIGMA DRAWS [KEY=VALUE...]
The draws replay the tally's random stream (scene_families.tally_family), so draw d at SIGMA is the tally's.
"""
import sys
import tempfile
from pathlib import Path

import numpy as np

import scene_families as sf


def arm_angle(scene, xyz_cam_m) -> float:
    """Return the angle (deg, seen from the shoulder) between the simulated arm's line and a point (camera frame)."""
    joints = {k: np.asarray(v, float) for k, v in scene.frame.meta["joints_cam_m"].items()}
    axis = joints["wrist"] - joints["shoulder"]
    d = np.asarray(xyz_cam_m, float) - joints["shoulder"]
    return float(np.degrees(np.arccos(np.clip(d @ axis / np.linalg.norm(d) / np.linalg.norm(axis), -1, 1))))


def describe(scene, result, rig, what: str) -> str:
    """Return one draw's line."""
    sel = result.selection
    if sel is None or not len(sel.objects):
        return f"{what:15s} status={result.status} no selection"
    post = np.asarray(sel.scores)
    px = rig.to_original(np.array([o.left_px for o in sel.objects]), "left")
    order = np.argsort(-post)[:3]
    tops = " ".join(f"{post[i]:.2f}{'T' if sf.target_detected(scene, px[i:i + 1]) else ''}"
                    f"@{arm_angle(scene, rig.R1.T @ sel.objects[i].xyz_m):.1f}" for i in order)
    spots = " ".join(f"{p:.2f}@{arm_angle(scene, rig.R1.T @ np.asarray(x)):.1f}" for x, p in sel.spots)
    target = arm_angle(scene, scene.frame.meta["placards"][scene.scenario.target_id]["xyz_cam_m"])
    return (f"{what:15s} status={result.status} none={sel.none_probability:.2f} conf={sel.confidence:.2f} "
            f"amb={sel.ambiguous} width={scene.target_width_px:.0f}px range={scene.target_range_m:.1f}m "
            f"target@{target:.1f} objects {tops} spots [{spots}]")


def main() -> None:
    family, n, seed0, sigma, draws = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
    overrides = sys.argv[6:]
    counts = {}
    with tempfile.TemporaryDirectory() as tmp:
        for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
            truth = scene.frame.meta["keypoints_truth"]
            rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", overrides)
            rng = np.random.default_rng(seed0 + k)
            for s in (0.0, 1.0, 2.0, 4.0):
                for d in range(draws if s > 0 else 1):
                    kp = sf.noisy(truth, s, rng)
                    if s != sigma:
                        continue
                    pose.provide(kp)
                    result = sf.decided(perception, left, right, base)
                    what = sf.outcome(scene, result, rig)
                    counts[what] = counts.get(what, 0) + 1
                    print(f"{family} k={k} d={d} " + describe(scene, result, rig, what))
    print(counts)


if __name__ == "__main__":
    main()
