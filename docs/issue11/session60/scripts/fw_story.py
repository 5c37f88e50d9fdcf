"""One paper_pool mission on the ArduSub SITL firmware: outcome, trajectory every 0.5 s (state, NED, yaw, distance to
the diver's body) and the story, as session 58's story.py does for the built-in autopilot:
    python docs/issue11/session60/scripts/fw_story.py SEED [manual_control|guided_velocity] [KEY=VALUE ...]"""
import logging
import sys
from pathlib import Path
from dip3d_vehicle.config import load_params
from sitl.ardusub_sitl import resolve_binary
from sitl.firmware_world import FirmwareSimulation
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
sys.path.insert(0, str(Path(__file__).parent))
from run_trace import print_run  # noqa: E402
seed, mode = int(sys.argv[1]), (sys.argv[2] if len(sys.argv) > 2 else "manual_control")
sets = dict(a.split("=", 1) for a in sys.argv[3:])
logging.getLogger("dip3d_vehicle.link").setLevel(logging.ERROR)
sc = load_scenario("paper_pool", seed)
params = sim_params(load_params(overrides=sets) if sets else load_params(), sc,
                    **{"link.output_mode": mode, "sitl.max_sim_time_s": 90.0})
sim = FirmwareSimulation(sc, params, resolve_binary("/work/shared/ardusub-sitl/ardusub"), speedup=0.5,
                         instance=70 + seed)
try:
    res = sim.run()
finally:
    sim.close()
print_run(sc, res, sim.trajectory)
