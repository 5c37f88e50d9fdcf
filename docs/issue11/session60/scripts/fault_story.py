"""One faulted paper_pool mission (sitl.fault_mission): outcome, trajectory every 0.5 s (state, NED, yaw, distance to
the diver's body and to each placard's face) and the story:
    python docs/issue11/session60/scripts/fault_story.py PLAN SEED [KEY=VALUE ...]   (PYTHONPATH=TREE from TREE)"""
import sys
import numpy as np
from dip3d_vehicle.config import load_params
from sitl.clearance import body_distance_m, square_distance_m
from sitl.fault_mission import run_faulted_mission
plan, seed = sys.argv[1], int(sys.argv[2])
sets = dict(a.split("=", 1) for a in sys.argv[3:])
result, sim = run_faulted_mission("paper_pool", seed, plan, load_params(overrides=sets) if sets else load_params())
sc = sim.scenario
aim = np.asarray(sc.placard(result.target_id).centre_ned_m, float)
print(result.outcome, result.time_to_arrive_s, "closest diver", result.closest_diver_m, result.closest_m)
last = -1.0
for r in sim.trajectory:
    if r[0] - last >= 0.5 - 1e-9:
        last = r[0]
        faces = " ".join(f"{p.id}:{float(square_distance_m(np.array(r[1:4]), p)[0]):.2f}" for p in sc.placards)
        print(f"{r[0]:6.2f} {r[6]:14s} ned {np.round(r[1:4], 2)} yaw {np.degrees(r[4]):6.1f} "
              f"body {body_distance_m(r[1:4], sc.diver.joints(aim, r[0])):.2f} faces {faces}")
for line in result.story:
    if "pilot heard" not in line and "frames:" not in line:
        print(line)
