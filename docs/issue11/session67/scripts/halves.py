import sys
import numpy as np
import behaviours.tracker as tr
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params
orig = tr.TargetTracker.know_neighbours
def know(self, n, h=None):
    if len(n): print("neighbours", np.round(np.asarray(n), 2).tolist(), "half", None if h is None else np.round(np.asarray(h), 3).tolist())
    return orig(self, n, h)
tr.TargetTracker.know_neighbours = know
sc = load_scenario(sys.argv[1], int(sys.argv[2]))
print([(p.id, p.size_m) for p in sc.placards] if hasattr(sc, 'placards') else '')
sim = Simulation(sc, sim_params(load_params(), sc))
try:
    res = sim.run()
finally:
    sim.close()
print(res.outcome, res.closest_m)
