"""Is the hanging arm taken for a raised one? BlazePose in the loop on a scenario's frames after the diver lowers the arm.

    python docs/issue14/session29/scripts/hanging.py SCENARIO SEED [T0 T1 STEP]

Renders from the vehicle's start pose, frames from T0 to T1 (default: 1 s before the end of the hold to 6 s after),
runs the mission's Perception with the BlazePose backend, and prints per frame: the diver's raised fraction, the
result's status, the 3D arm's angle from straight down (the mission's ``is_raised`` reads it), the image-only bound on
that angle (the shoulder-to-wrist drop in the image, in metres at the shoulder's depth, over the arm's longest span),
and the joints' depths.
"""
import math, sys
import numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.pipeline import Perception
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
from sitl.pose_source import SimPose
from sitl.render import StereoRenderer
from behaviours.evidence import arm_direction
from dip3d_vehicle.perception.pointing_fit import _PointingFit, _rays

name, seed = sys.argv[1], int(sys.argv[2])
sc = load_scenario(name, seed)
params = sim_params(load_params(), sc, **{"sitl.pose_source": "blazepose"})
d = sc.diver
t0 = float(sys.argv[3]) if len(sys.argv) > 3 else d.start_s + d.hold_s - 1.0
t1 = float(sys.argv[4]) if len(sys.argv) > 4 else d.start_s + d.hold_s + 6.0
step = float(sys.argv[5]) if len(sys.argv) > 5 else 0.2
rig = sc.rig(params["calib.alpha"])
pose = SimPose(params)
perc = Perception(rig, params, pose, live=True)
span_m = float(params["selection.upperarm_max_m"]) + float(params["selection.forearm_max_m"]) if "selection.upperarm_max_m" in params else 0.7
v = sc.initial_vehicle_pose
print(f"{name} seed {seed}: hold {d.start_s:.1f}-{d.start_s + d.hold_s:.1f} s, raise {d.raise_s} s")
with StereoRenderer(sc, params) as r:
    t = t0
    while t <= t1 + 1e-9:
        fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
        pose.provide(fr.meta["keypoints"])
        res = perc.process(fr.left, fr.right)
        dirn = arm_direction(res)
        ang = math.degrees(math.acos(float(np.clip(dirn @ [0, 1, 0], -1, 1)))) if dirn is not None else float("nan")
        bound = float("nan")
        if res.arm3d is not None and res.arm is not None:
            s, w = res.arm.joint("shoulder", "left"), res.arm.joint("wrist", "left")
            zs = float(res.arm3d.xyz_m[0, 2])
            drop_m = (w[1] - s[1]) * zs / rig.focal_px
            bound = math.degrees(math.acos(float(np.clip(drop_m / span_m, -1, 1))))
        z = np.round(res.arm3d.xyz_m[:, 2], 2).tolist() if res.arm3d is not None else None
        cost = float("nan")
        if res.arm3d is not None and res.arm is not None:
            sel = perc.selector
            jp = np.c_[res.arm.left_px[:, 0], (res.arm.left_px[:, 1] + res.arm.right_px[:, 1]) / 2.0]
            ks = sel.model.keypoint_sigma_m if res.arm.keypoint_sigma_m is None else float(res.arm.keypoint_sigma_m)
            cost = _PointingFit(_rays(jp, rig), res.arm3d.xyz_m[:, 2], res.arm3d.depth_sigma_m, sel.model, ks).arm_cost()
        print(f"t {t:5.1f} raised {d.raised_fraction(t):.2f} status {res.status:20s} from-down {ang:5.1f} deg  image bound <= {bound:5.1f} deg  arm cost {cost:7.1f}  z {z}", flush=True)
        t += step
