"""Cost of the tracker's zoom box: one ``track`` frame's processing (ms) with and without it.

    PYTHONPATH=. python docs/issue11/session38/scripts/track_cost.py SCENARIO SEED [REPEATS]

The frame is rendered at the scenario's start pose; the search box is the one ``Mission.track_roi`` builds around
the pointed placard (misses 0 and 1); the zoom box ``zoom_box``'s. Median / p90 over REPEATS (default 15) runs.
"""
import sys
import time

import numpy as np

from behaviours.loop import FrameProcessor
from behaviours.tracker import TrackRegion, zoom_box
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params

sc = load_scenario(sys.argv[1], int(sys.argv[2]))
repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 15
params = sim_params(load_params(), sc)
rig = sc.rig(params["calib.alpha"])
pose = GivenKeypoints("right")
proc = FrameProcessor(Perception(rig, params, pose), lambda f: pose.provide(f.meta["keypoints"]), pose_in_track=False)
v = sc.initial_vehicle_pose
size = tuple(sc.camera.image_size)
with StereoRenderer(sc, params) as r:
    frame = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, 2.5)
xyz = rig.R1 @ np.asarray(frame.meta["placards"][sc.target_id]["xyz_cam_m"])
f, (cx, cy) = rig.focal_px, rig.principal_point_px
u, vv = f * xyz[0] / xyz[2] + cx, f * xyz[1] / xyz[2] + cy
print(f"{sys.argv[1]} seed {sys.argv[2]}: target at {xyz.round(2)} m, {size}")
for misses in (0, 1):
    half = 200 * (2 if misses else 1) + f * 0.4 / xyz[2]
    d = f * abs(rig.baseline_m) / xyz[2]
    box = (int(max(0, u - half - 2 * d)), int(max(0, vv - half)), int(min(size[0], u + half)), int(min(size[1], vv + half)))
    z, zd = zoom_box(xyz, rig, size, 0.3, misses)
    for region in (TrackRegion(box), TrackRegion(box, z, zd)):
        proc.process(frame, "track", roi=region)
        ms = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            proc.process(frame, "track", roi=region)
            ms.append((time.perf_counter() - t0) * 1e3)
        print(f"misses {misses}: box {box[2] - box[0]}x{box[3] - box[1]} zoom {region.zoom}: "
              f"median {np.median(ms):.1f} ms, p90 {np.percentile(ms, 90):.1f} ms")
