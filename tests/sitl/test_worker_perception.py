"""A wall-clock simulation perceives through the one PerceptionWorker (sitl/worker_perception.py)."""

from __future__ import annotations

from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import Simulation, sim_params
from sitl.worker_perception import WorkerPerception


class ThreadedSimulation(WorkerPerception, Simulation):
    """The lockstep world paced at real time, with perception in the worker thread (as the firmware world)."""


def test_results_come_from_the_worker_with_their_capture_stamps():
    sc = load_scenario("paper_pool", 1)
    params = sim_params(load_params(), sc, **{"sitl.max_sim_time_s": 3.0})
    sim = ThreadedSimulation(sc, params, speed=1.0)
    stamps = []
    tick = sim.controller.tick

    def spy(observation=None):
        if observation is not None:
            stamps.append((sim.clock.now(), observation.stamp_s))
        return tick(observation)

    sim.controller.tick = spy
    try:
        sim.run()
    finally:
        sim.close()
    c = sim.perception_worker.counters
    assert c.submitted >= 10 and c.processed >= 2 and c.errors == 0   # 3 s of the scenario's camera
    assert sim.controller.observations == len(stamps) >= 2
    assert all(0.0 < now - stamp < 10.0 for now, stamp in stamps)     # a real, positive latency (loaded CI: slow)
    assert [s for _, s in stamps] == sorted(s for _, s in stamps)     # each result once, in order
    assert sim.perception_worker._thread is None                       # stopped by close()
