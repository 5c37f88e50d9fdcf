"""Outcome, trajectory every 1 s (state, NED position, yaw, distance to the diver body) and the story of one run:
    python docs/issue11/session58/scripts/story.py SCENARIO SEED [KEY=VALUE ...]  (the installed tree or PYTHONPATH=TREE)"""
import sys
import numpy as np
from dip3d_vehicle.config import load_params
from sitl.clearance import body_distance_m
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params
scenario, seed = sys.argv[1], int(sys.argv[2])
sets = dict(a.split("=", 1) for a in sys.argv[3:])
sc = load_scenario(scenario, seed)
sim = Simulation(sc, sim_params(load_params(overrides=sets) if sets else load_params(), sc))
try:
    res = sim.run()
finally:
    sim.close()
aim = np.asarray(sc.placard(res.target_id).centre_ned_m, float)
print(res.outcome, res.time_to_arrive_s, "closest diver", res.closest_diver_m, res.closest_m)
last = -1.0
for r in sim.trajectory:
    if r[0] - last >= 1.0 - 1e-9:
        last = r[0]
        print(f"{r[0]:6.2f} {r[6]:14s} ned {np.round(r[1:4], 2)} yaw {np.degrees(r[4]):6.1f} body {body_distance_m(r[1:4], sc.diver.joints(aim, r[0])):.2f}")
for line in res.story:
    if "pilot heard" not in line:
        print(line)
