"""One faulted paper_pool mission: the simulated autopilot's first events (arming, parameter writes, failsafes) and
when the controller's MANUAL_CONTROL reached it:
    PYTHONPATH=TREE python docs/issue11/session64/scripts/autopilot_events.py PLAN SEED"""
import sys
import sitl.autopilot as A
from dip3d_vehicle.config import load_params
from sitl.fault_mission import run_faulted_mission

arrivals = []
_take = A.Autopilot._on_manual_control


def _recorded(self, link, msg, now):
    arrivals.append(now)
    return _take(self, link, msg, now)


A.Autopilot._on_manual_control = _recorded
result, sim = run_faulted_mission("paper_pool", int(sys.argv[2]), sys.argv[1], load_params())
for e in sim.ap.events[:24]:
    print(f"{e.time_s:6.2f} {e.kind} {e.detail}")
print("MANUAL_CONTROL arrivals before 4 s:", [round(t, 2) for t in arrivals if t < 4.0])
