"""The tracker's dead-reckoned yaw since its start against the vehicle's true yaw change, per second:
    python docs/issue11/session59/scripts/yaw_reckon.py SCENARIO SEED [KEY=VALUE ...]"""
import math
import sys
import behaviours.tracker as T
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params

scenario, seed = sys.argv[1], int(sys.argv[2])
sets = dict(a.split("=", 1) for a in sys.argv[3:])
sc = load_scenario(scenario, seed)
sim = Simulation(sc, sim_params(load_params(overrides=sets) if sets else load_params(), sc))
orig_start, orig_update, state = T.TargetTracker.start, T.TargetTracker.update, {}


def start(self, *a, **k):
    state["yaw0"], state["last"], state["errs"] = sim.trajectory[-1][4], -1.0, []
    return orig_start(self, *a, **k)


def update(self, candidates, xyz_m, stamp_s, command=None):
    out = orig_update(self, candidates, xyz_m, stamp_s, command)
    true = math.remainder(sim.trajectory[-1][4] - state["yaw0"], 2 * math.pi)
    err = math.degrees(self.yawed_rad - true)
    state["errs"].append(abs(err))
    if stamp_s - state["last"] >= 1.0 - 1e-9:
        state["last"] = stamp_s
        print(f"{stamp_s:6.2f} reckoned {math.degrees(self.yawed_rad):7.2f} true {math.degrees(true):7.2f} deg "
              f"err {err:+.2f}")
    return out


T.TargetTracker.start, T.TargetTracker.update = start, update
try:
    res = sim.run()
finally:
    sim.close()
e = sorted(state.get("errs", []))
print(res.outcome, res.time_to_arrive_s, f"yaw error median {e[len(e) // 2]:.2f} max {e[-1]:.2f} deg over {len(e)} frames"
      if e else "")
