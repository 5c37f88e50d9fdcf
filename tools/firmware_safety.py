"""Safety trials on the ArduSub SITL binary: a fault injected 1 s into the servo, then 3 s watched.

usage: .venv/bin/python tools/firmware_safety.py BINARY [--kinds autopilot_silent,mode_change,disarm,perception_stall]
       [--trials 10] [--out trials.jsonl]

Per trial (paper_pool, seed = trial number, manual_control): the safety numbers of
``Simulation.safety()`` measured on what the firmware received (tapped at the router): last motion
command after the fault (s), motion commands after the mode change / disarm was seen by the controller.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from dip3d_vehicle.config import load_params  # noqa: E402
from sitl.ardusub_sitl import resolve_binary  # noqa: E402
from sitl.firmware_world import FirmwareSimulation  # noqa: E402
from sitl.scenario import load_scenario  # noqa: E402
from sitl.simulation import Fault, sim_params  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("binary")
    ap.add_argument("--kinds", default="autopilot_silent,mode_change,disarm,perception_stall")
    ap.add_argument("--trials", type=int, default=10)
    ap.add_argument("--speedup", type=float, default=0.5)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    logging.getLogger("dip3d_vehicle.link").setLevel(logging.ERROR)
    binary = resolve_binary(a.binary)
    for trial in range(a.trials):
        for kind in a.kinds.split(","):
            sc = load_scenario("paper_pool", trial)
            params = sim_params(load_params(), sc, **{"sitl.max_sim_time_s": 60.0})
            sim = FirmwareSimulation(sc, params, binary, speedup=a.speedup, instance=100 + trial,
                                     fault=Fault(kind, 1.0, "servo", 3.0))
            try:
                r = sim.run()
            finally:
                sim.close()
            row = {"kind": kind, "trial": trial, "fault_at_s": r.fault["at_s"] if r.fault else None, **r.safety}
            print(json.dumps(row), flush=True)
            if a.out:
                with open(a.out, "a") as f:
                    f.write(json.dumps(row) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
