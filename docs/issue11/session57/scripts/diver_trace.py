"""When and where the vehicle came near the diver: every 0.5 s of one mission, its state, NED position (metres), yaw
(degrees) and least distance to the diver's body axes (``sitl.clearance.body_distance_m``, metres); then the three
nearest body segments at a few times.

    PYTHONPATH=TREE python docs/issue11/session57/scripts/diver_trace.py SCENARIO SEED [KEY=VALUE ...]
"""
import sys

import numpy as np

from behaviours.clearance import distance_to_path_m
from dip3d_vehicle.config import load_params
from sitl.clearance import BODY_SEGMENTS, body_distance_m
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
print(res.outcome, "closest diver", res.closest_diver_m, "closest placards", res.closest_m)
rows, last = list(sim.trajectory), -1.0
for r in rows:
    if r[0] - last >= 0.5 - 1e-9:
        last = r[0]
        print(f"{r[0]:6.2f} {r[6]:14s} ned {np.round(r[1:4], 2)} yaw {np.degrees(r[4]):6.1f} "
              f"body {body_distance_m(r[1:4], sc.diver.joints(aim, r[0])):.2f}")
for t in (rows[len(rows) // 4][0], rows[len(rows) // 2][0], rows[-1][0]):
    r = min(rows, key=lambda q: abs(q[0] - t))
    j, p = sc.diver.joints(aim, r[0]), np.asarray(r[1:4], float).reshape(1, 3)
    near = sorted((float(distance_to_path_m(p, j[a], j[b])[0][0]), f"{a}-{b}") for a, b in BODY_SEGMENTS)[:3]
    print(f"t={r[0]:.1f} nearest segments: " + ", ".join(f"{s} {d:.2f}" for d, s in near))
