"""The frames every session-31 census reads: BlazePose as the mission runs it, on each seed's hold.

``held_frames`` renders each seed's frames from the vehicle's start pose while the arm is fully raised (every
``step_s`` of the hold), runs ``BlazePoseEstimator`` on the rectified pair (``pose.arm: auto``, as the mission),
and yields the frames where it found the arm, with the body's truth joints as a ``GivenKeypoints`` arm.
``census_args`` reads the scripts' common command line: OUT.jsonl SCENARIO[,...|FILE.yaml,...] SEEDS [STEP_S].
"""
from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import Iterator, Sequence

import numpy as np

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params


@dataclass
class CensusFrame:
    """One rendered, rectified frame where BlazePose found the arm (pixels, metres, seconds)."""

    scenario: str
    seed: int
    t_s: float
    sc: object             # the loaded scenario (diver, water)
    rig: object            # the rectified stereo rig
    est: BlazePoseEstimator
    left: np.ndarray
    right: np.ndarray
    arm: object            # BlazePose's ArmKeypoints
    landmarks: object      # BlazePose's left PoseLandmarks
    truth: object          # the body's joint centres as ArmKeypoints
    meta: dict             # the renderer's frame metadata (body_truth, ...)


def census_args(argv: Sequence[str]) -> tuple[str, list[str], range, float]:
    """Return (out path, scenario names, seeds, step in seconds) from OUT NAMES SEEDS [STEP_S]."""
    out, names, seeds = argv[1], argv[2].split(","), argv[3]
    a, b = (int(x) for x in seeds.split("-")) if "-" in seeds else (int(seeds), int(seeds))
    return out, names, range(a, b + 1), float(argv[4]) if len(argv) > 4 else 0.6


def held_frames(names: Sequence[str], seeds: Sequence[int], step_s: float = 0.6) -> Iterator[CensusFrame]:
    """Yield every frame of each scenario and seed's held arm where BlazePose found the arm."""
    for name in names:
        for seed in seeds:
            sc = load_scenario(name, seed)
            params = sim_params(load_params(), sc, **{"sitl.pose_source": "blazepose"})
            rig = sc.rig(params["calib.alpha"])
            est = BlazePoseEstimator.from_params(params)
            truth_pose = GivenKeypoints(sc.diver.arm)
            v, d = sc.initial_vehicle_pose, sc.diver
            with StereoRenderer(sc, params) as r:
                t = d.start_s
                while t < d.start_s + d.hold_s:
                    fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
                    t_frame, t = t, t + step_s
                    if d.raised_fraction(t_frame) < 0.99 or fr.meta["keypoints_truth"] is None:
                        continue
                    left, right = rig.rectify_image(fr.left, "left"), rig.rectify_image(fr.right, "right")
                    arm = est.estimate(left, right, rig)
                    if arm is None or est.last[0] is None:
                        continue
                    truth_pose.provide(fr.meta["keypoints_truth"])
                    yield CensusFrame(name, seed, t_frame, sc, rig, est, left, right, arm, est.last[0],
                                      truth_pose.estimate(left, right, rig), fr.meta)


if __name__ == "__main__":
    sys.exit("census_frames.py is imported by the census scripts beside it")
