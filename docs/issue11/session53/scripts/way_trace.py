"""Each servo / arrive frame of one mission: the target, the servo's errors, the command sent (sway included) and the
way round the known objects the state follows (behaviours/clearance.py: its turn, stand-off, clearance, margin,
offset across the line of sight); with --truth, the known neighbours beside every placard's true position (camera
frame, metres). Session 52's version (before the way held short) is in history at d6ee9ad.

    PYTHONPATH=TREE python docs/issue11/session53/scripts/way_trace.py SCENARIO SEED T0 T1 [--truth] [KEY=VALUE ...]
"""
import sys

import numpy as np

import behaviours.approach_states as A
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params

args = [a for a in sys.argv[1:] if a != "--truth"]
truth = "--truth" in sys.argv
scenario, seed, t0, t1 = args[0], int(args[1]), float(args[2]), float(args[3])
sets = dict(a.split("=", 1) for a in args[4:])
sc = load_scenario(scenario, seed)
sim = Simulation(sc, sim_params(load_params(overrides=sets) if sets else load_params(), sc))
keep_clear = A._Steering.keep_clear


def traced(self, bb, command, st, dt):
    """The state's own keep_clear, printed with the way it was given."""
    out = keep_clear(self, bb, command, st, dt)
    t = bb.observation.stamp_s
    if t0 <= t <= t1:
        target = np.asarray(bb.target.xyz_m, float)
        nb = target + bb.tracker.neighbours_m
        e = bb.errors
        way = "direct" if st is None else (f"turn {np.degrees(st.way.angle_rad):+3.0f} std {st.way.standoff_m:.1f} "
                                           f"clr {st.way.clearance_m:.2f} margin {st.way.margin_m:+.2f} "
                                           f"off {st.offset_m:+.2f} cap {st.max_surge_m_s:.2f}")
        line = (f"{t:6.2f} {self.name:7s} tgt {np.round(target, 2)} px {e.pixel_px:4.0f} rng {e.range_m:+.3f} "
                f"cmd s{out.surge_m_s:+.2f} y{out.sway_m_s:+.2f} h{out.heave_m_s:+.2f} r{out.yaw_rate_rad_s:+.2f} "
                f"{way}")
        if truth:
            placards = {pid: sim.rig.R1 @ np.asarray(info["xyz_cam_m"]) for pid, info in sim.last_meta["placards"].items()}
            line += f" nb {np.round(nb, 2).tolist()} truth {[(k, np.round(v, 2).tolist()) for k, v in placards.items()]}"
        print(line)
    return out


A._Steering.keep_clear = traced
try:
    res = sim.run()
finally:
    sim.close()
print(res.outcome, res.time_to_arrive_s, res.closest_m, "diver", res.closest_diver_m, "held short", res.held_short_m)
for line in res.story:
    if "way" in line or "going round" in line or "holding short" in line:
        print(line)
