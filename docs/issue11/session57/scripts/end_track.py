"""Where the tracker's target is at the end of a mission (camera frame, metres; dead-reckoned when it was last seen
earlier) against every placard's true position then: the simulator's ``chosen_placard`` takes the placard within
0.5 m of it, arrived or not.

    PYTHONPATH=TREE python docs/issue11/session57/scripts/end_track.py SCENARIO SEED
"""
import sys
import numpy as np
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params
sc = load_scenario(sys.argv[1], int(sys.argv[2]))
sim = Simulation(sc, sim_params(load_params(), sc))
try:
    res = sim.run()
    bb = sim.mission.bb
    print(res.outcome, "tracker xyz at end", np.round(bb.tracker.xyz_m, 2), "last seen", bb.tracker.last_seen_s)
    for pid, info in sim.last_meta["placards"].items():
        print(pid, np.round(sim.rig.R1 @ np.asarray(info["xyz_cam_m"]), 2))
finally:
    sim.close()
