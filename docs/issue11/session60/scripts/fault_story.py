"""One faulted paper_pool mission (sitl.fault_mission): outcome, trajectory every 0.5 s (state, NED, yaw, distance to
the diver's body and to each placard's face) and the story:
    python docs/issue11/session60/scripts/fault_story.py PLAN SEED [KEY=VALUE ...]   (PYTHONPATH=TREE from TREE)"""
import sys
from pathlib import Path
from dip3d_vehicle.config import load_params
from sitl.fault_mission import run_faulted_mission
sys.path.insert(0, str(Path(__file__).parent))
from run_trace import print_run  # noqa: E402
plan, seed = sys.argv[1], int(sys.argv[2])
sets = dict(a.split("=", 1) for a in sys.argv[3:])
result, sim = run_faulted_mission("paper_pool", seed, plan, load_params(overrides=sets) if sets else load_params())
print_run(sim.scenario, result, sim.trajectory, faces=True)
