"""One simulated run with a hook on every ``TargetTracker.update``, and the placards' true centres; shared by
``reckon.py`` and ``offsets.py``."""
from typing import Callable
import numpy as np
import behaviours.tracker as T
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params


def run_hooked(scenario: str, seed: int, sets: dict, hook: Callable) -> tuple:
    """Run ``scenario`` seed ``seed`` with parameter overrides ``sets``, calling ``hook(tracker, sim, stamp_s,
    predicted_xyz, found)`` after each tracker update; return (the run's result, the simulation)."""
    sc = load_scenario(scenario, seed)
    sim = Simulation(sc, sim_params(load_params(overrides=sets) if sets else load_params(), sc))
    orig = T.TargetTracker.update

    def update(self, candidates, xyz_m, stamp_s, command=None):
        pred = self.predicted_xyz(stamp_s, command)
        out = orig(self, candidates, xyz_m, stamp_s, command)
        hook(self, sim, stamp_s, pred, out)
        return out
    T.TargetTracker.update = update
    try:
        return sim.run(), sim
    finally:
        sim.close()
        T.TargetTracker.update = orig


def placards_cam_m(sim, meta: dict) -> dict:
    """Return each placard's true centre in the rectified left camera frame (metres), by id, from a frame's meta."""
    return {pid: sim.rig.R1 @ np.asarray(i["xyz_cam_m"]) for pid, i in meta["placards"].items()}
