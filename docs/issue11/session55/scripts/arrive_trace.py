"""Each servo / arrive frame of one mission: the servo's pixel and range errors against the arrive tolerances, the
target's position (camera frame, metres) and the trigger the state returned, to see why arrive goes back to servo;
then the outcome and the mission's story (without the pilot's echoes).

    PYTHONPATH=TREE python docs/issue11/session55/scripts/arrive_trace.py SCENARIO SEED [KEY=VALUE ...]
"""
import sys

import numpy as np

import behaviours.approach_states as A
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params

scenario, seed = sys.argv[1], int(sys.argv[2])
sets = dict(a.split("=", 1) for a in sys.argv[3:])
sc = load_scenario(scenario, seed)
sim = Simulation(sc, sim_params(load_params(overrides=sets) if sets else load_params(), sc))


def traced(seen):
    """Wrap a state's ``seen`` to print its frame."""
    def run(self, bb, found):
        out = seen(self, bb, found)
        e, c = bb.errors, bb.config
        tgt = np.round(np.asarray(bb.target.xyz_m, float), 3)
        print(f"{bb.observation.stamp_s:6.2f} {self.name:6s} px {e.pixel_px:5.1f}/{c.arrive_tolerance_px:.0f} "
              f"rng {e.range_m:+.3f}/{c.arrive_tolerance_m:.2f} tgt {tgt} -> {out}")
        return out
    return run


A.Servo.seen = traced(A.Servo.seen)
A.Arrive.seen = traced(A.Arrive.seen)
try:
    res = sim.run()
finally:
    sim.close()
print(res.outcome, res.time_to_arrive_s)
for line in res.story:
    if "pilot heard" not in line:
        print(line)
