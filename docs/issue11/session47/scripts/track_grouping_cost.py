"""Cost of the tracker's grouping with and without selection.target_max_extent_m, on rendered track frames.

    python docs/issue11/session47/scripts/track_grouping_cost.py SCENARIO SEEDS [REPEATS]

Each seed's start pose is rendered, processed as a track frame (full-frame features, as the tracker sees
them), and ``group_objects`` is timed with the tracker's settings (median of REPEATS calls), once with the
limit (0.6 m) and once without (inf); also the objects each gives and the chains wider than the limit.
"""
import sys, time
import numpy as np
from behaviours.loop import FrameProcessor
from behaviours.tracker import TrackerConfig
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.grouping import group_objects
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params


def timed(fn, repeats):
    """Return (median ms, last result) of ``repeats`` calls."""
    ms, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter(); out = fn(); ms.append((time.perf_counter() - t0) * 1e3)
    return float(np.median(ms)), out


name, seeds = sys.argv[1], sys.argv[2]
lo, hi = (int(x) for x in seeds.split("-")) if "-" in seeds else (int(seeds),) * 2
repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 5
for seed in range(lo, hi + 1):
    sc = load_scenario(name, seed)
    params = sim_params(load_params(), sc)
    rig = sc.rig(params["calib.alpha"])
    pose = GivenKeypoints("right")
    processor = FrameProcessor(Perception(rig, params, pose), lambda f: pose.provide(f.meta["keypoints"]))
    c = TrackerConfig.from_params(params)
    v = sc.initial_vehicle_pose
    with StereoRenderer(sc, params) as renderer:
        obs = processor.process(renderer.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, 1.0), "track")
    cands, xyz = obs.track.candidates, obs.track.xyz_m
    row = [f"{name} seed {seed}: {len(cands)} features"]
    for label, limit in (("limit", c.max_extent_m), ("none", np.inf)):
        ms, objs = timed(lambda: group_objects(cands, xyz, rig, c.group_radius_px, c.group_radius_m,
                                               c.min_object_features, c.object_radius_m, limit), repeats)
        row.append(f"{label} {ms:.1f} ms {len(objs)} objects")
    print(" | ".join(row), flush=True)
