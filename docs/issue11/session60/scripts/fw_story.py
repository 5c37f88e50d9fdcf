"""One paper_pool mission on the ArduSub SITL firmware: outcome, trajectory every 1 s (state, NED, yaw, distance to
the diver's body) and the story, as session 58's story.py does for the built-in autopilot:
    python docs/issue11/session60/scripts/fw_story.py SEED [manual_control|guided_velocity] [KEY=VALUE ...]"""
import logging
import sys
import numpy as np
from dip3d_vehicle.config import load_params
from sitl.ardusub_sitl import resolve_binary
from sitl.clearance import body_distance_m
from sitl.firmware_world import FirmwareSimulation
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
seed, mode = int(sys.argv[1]), (sys.argv[2] if len(sys.argv) > 2 else "manual_control")
sets = dict(a.split("=", 1) for a in sys.argv[3:])
logging.getLogger("dip3d_vehicle.link").setLevel(logging.ERROR)
sc = load_scenario("paper_pool", seed)
params = sim_params(load_params(overrides=sets) if sets else load_params(), sc,
                    **{"link.output_mode": mode, "sitl.max_sim_time_s": 90.0})
sim = FirmwareSimulation(sc, params, resolve_binary("/work/shared/ardusub-sitl/ardusub"), speedup=0.5,
                         instance=70 + seed)
try:
    res = sim.run()
finally:
    sim.close()
aim = np.asarray(sc.placard(res.target_id).centre_ned_m, float)
print(res.outcome, res.time_to_arrive_s, "closest diver", res.closest_diver_m, res.closest_m)
last = -1.0
for r in sim.trajectory:
    if r[0] - last >= 0.5 - 1e-9:
        last = r[0]
        print(f"{r[0]:6.2f} {r[6]:14s} ned {np.round(r[1:4], 2)} yaw {np.degrees(r[4]):6.1f} "
              f"body {body_distance_m(r[1:4], sc.diver.joints(aim, r[0])):.2f}")
for line in res.story:
    if "pilot heard" not in line and "frames:" not in line:
        print(line)
