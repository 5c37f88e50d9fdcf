"""Per frame of BlazePose in the loop: is the arm the mission reads raised, by the truth and by the mission's test?

    python docs/issue14/session29/scripts/raised_census.py OUT.jsonl SCENARIO[,SCENARIO...] SEEDS [STEP_S] [KEY=VALUE ...]

Renders each seed's frames from the vehicle's start pose, 0 to 45 s every STEP_S (default 0.4), runs the mission's
Perception with the BlazePose backend (``pose.arm: auto`` unless given), and writes one JSON line per frame: the
diver's raised fraction (truth), the result's status, the mission's ``arm_raised`` test (the 3D arm at least
``behaviour.min_raise_rad`` from straight down), the read arm's landmark visibilities (shoulder, elbow, wrist), its
image length over the torso's (shoulder to hip), the same in the landmarks' own 3D (x, y, z), the
hand's visibilities (pinky, index, thumb), and the angle of its image direction from straight down.
"""
import json, math, sys
import numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.pipeline import Perception
from dip3d_vehicle.perception.pose import ARM_INDICES
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
from sitl.pose_source import SimPose
from sitl.render import StereoRenderer
from behaviours.evidence import arm_direction, is_raised

out, names, seeds = sys.argv[1], sys.argv[2].split(","), sys.argv[3]
a, b = (int(x) for x in seeds.split("-")) if "-" in seeds else (int(seeds), int(seeds))
step = float(sys.argv[4]) if len(sys.argv) > 4 and "=" not in sys.argv[4] else 0.4
sets = dict(kv.split("=", 1) for kv in sys.argv[4:] if "=" in kv)
sets.setdefault("pose.arm", "auto")
HIP = {"right": 24, "left": 23}
with open(out, "w") as fh:
    for name in names:
        for seed in range(a, b + 1):
            sc = load_scenario(name, seed)
            params = sim_params(load_params(), sc, **{"sitl.pose_source": "blazepose", **sets})
            rig = sc.rig(params["calib.alpha"])
            pose = SimPose(params)
            perc = Perception(rig, params, pose, live=True)
            min_raise = float(params["behaviour.min_raise_rad"])
            v = sc.initial_vehicle_pose
            with StereoRenderer(sc, params) as r:
                for k in range(int(45.0 / step) + 1):
                    t = k * step
                    fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
                    pose.provide(fr.meta["keypoints"])
                    res = perc.process(fr.left, fr.right)
                    row = {"scenario": name, "seed": seed, "t": round(t, 2), "raised": round(sc.diver.raised_fraction(t), 2),
                           "status": res.status, "arm_raised": is_raised(arm_direction(res), min_raise)}
                    lm = pose.backend.last[0] if pose.backend is not None else None
                    if lm is not None and res.arm is not None:
                        side = res.arm.arm
                        sh, el, wr = ARM_INDICES[side]
                        row["side"] = side
                        row["vis"] = [round(float(lm.visibility[i]), 3) for i in (sh, el, wr)]
                        arm_len = float(np.linalg.norm(lm.xy_px[wr] - lm.xy_px[sh]))
                        torso = float(np.linalg.norm(lm.xy_px[HIP[side]] - lm.xy_px[sh]))
                        row["len_over_torso"] = round(arm_len / max(torso, 1.0), 3)
                        xyz = np.c_[lm.xy_px, lm.z_px]
                        row["len3d_over_torso3d"] = round(float(np.linalg.norm(xyz[wr] - xyz[sh]))
                                                          / max(float(np.linalg.norm(xyz[HIP[side]] - xyz[sh])), 1.0), 3)
                        row["hand_vis"] = [round(float(lm.visibility[i]), 3) for i in ((17, 19, 21) if side == "left" else (18, 20, 22))]
                        d = lm.xy_px[wr] - lm.xy_px[sh]
                        row["img_from_down_deg"] = round(math.degrees(math.atan2(abs(d[0]), d[1])), 1)
                    fh.write(json.dumps(row) + "\n")
            print(name, seed, "done", flush=True)
