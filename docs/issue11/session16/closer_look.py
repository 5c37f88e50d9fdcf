"""What a look from nearer would show (near_miss: the 4 cm placard found?), and the selector's lean, per viewpoint.

For each seed, frames of the held point are rendered from the vehicle's start pose moved forward
(north) by each offset, and the perception core (``default``, the simulator's truth keypoints plus
its noise, as the missions' default pose source) decides each: whether the diver's three arm
joints are in both images, whether a candidate lies on the pointed (undetectable at the start) placard,
and p(pointed placard) / p(best other placard) / p(nothing detected). One frame, no fusion.

Usage (from the repository root):
    PYTHONPATH=. python docs/issue11/session16/closer_look.py SCENARIO SEEDS FRAMES OFFSET_M [OFFSET_M ...]
e.g. ``near_miss 0-9 2 0 0.6 1.0 1.4``.
"""
from __future__ import annotations

import json
import sys

import numpy as np

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from sitl.arm_eval import _placard_probabilities
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params


def _on_target(result, meta: dict, rig, radius_m: float = 0.1) -> int:
    """Return how many kept candidate points lie within ``radius_m`` of the pointed placard's centre (metres)."""
    if len(result.candidates_xyz_m) == 0:
        return 0
    centre = rig.R1 @ np.asarray(meta["placards"][meta["target_id"]]["xyz_cam_m"])
    return int(np.sum(np.linalg.norm(result.candidates_xyz_m - centre, axis=1) < radius_m))


def viewpoint(scenario: str, seed: int, frames: int, forward_m: float) -> list[dict]:
    """Return one row per frame of a scenario's seed seen from ``forward_m`` ahead of the start pose."""
    sc = load_scenario(scenario, seed)
    params = sim_params(load_params(), sc)
    rig = sc.rig(params["calib.alpha"])
    pose = GivenKeypoints(sc.diver.arm)
    core = Perception(rig, params, pose)
    v = sc.initial_vehicle_pose
    rows = []
    with StereoRenderer(sc, params) as renderer:
        for k in range(frames):
            t = sc.diver.start_s + 0.5 + k / float(params["sitl.camera_rate_hz"])
            frame = renderer.render(v.north_m + forward_m, v.east_m, v.depth_m, v.yaw_rad, t)
            kp = frame.meta.get("keypoints")
            pose.provide(kp)
            res = core.process(frame.left, frame.right)
            probs = None
            if res.selection is not None and res.selection.method == "default":
                probs = _placard_probabilities(res.selection, frame.meta, rig)
            rows.append({"scenario": scenario, "seed": seed, "forward_m": forward_m, "position": sc.diver.position_name,
                         "arm_in_view": kp is not None, "status": res.status,
                         "on_target": _on_target(res, frame.meta, rig), "p_pointed_other_none": probs})
    return rows


def main(argv: list[str]) -> None:
    lo, _, hi = argv[1].partition("-")
    for seed in range(int(lo), int(hi or lo) + 1):
        for off in argv[3:]:
            for row in viewpoint(argv[0], seed, int(argv[2]), float(off)):
                print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
