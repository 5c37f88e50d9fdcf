"""Outcome of each SCENARIO:SEED given (optional KEY=VALUE sets after --):
    python docs/issue11/session58/scripts/outcomes.py SCENARIO:SEED ... [-- KEY=VALUE ...]"""
import sys
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params
args = sys.argv[1:]
sets = {}
if "--" in args:
    i = args.index("--"); sets = dict(a.split("=", 1) for a in args[i + 1:]); args = args[:i]
for spec in args:
    name, seed = spec.rsplit(":", 1)
    sc = load_scenario(name, int(seed))
    sim = Simulation(sc, sim_params(load_params(overrides=sets) if sets else load_params(), sc))
    try:
        res = sim.run()
    finally:
        sim.close()
    d = [x for x in res.decisions]
    print(f"{name.split('/')[-1]} s{seed}: {res.outcome} chosen {res.chosen_id} target {res.target_id} t {res.time_to_arrive_s} "
          f"decisions {[(x.get('kind'), x.get('posterior'), x.get('one_look')) for x in d] if d and isinstance(d[0], dict) else d}", flush=True)
