"""One whole mission under a fault plan: ``FaultSimulation``, ``run_faulted_mission``, ``make_simulation``.

The whole mission (``sitl.simulation.Simulation``) with a fault plan: the relay sits between the
controller and the router, camera faults act on the rendered frames before the ``FrameGuard``,
timed events act on the autopilot / pilot. ``FaultSimulation`` is built on first use, because
``sitl.simulation`` imports the whole perception stack.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from dip3d_vehicle.config import load_params
from dip3d_vehicle.link import VehicleLink

from .fault_events import FaultEvents
from .faults import CameraFaults, FaultPlan, FrameGuard, LossyRelay, load_fault_plan

__all__ = ["FaultSimulation", "run_faulted_mission", "make_simulation"]


def _fault_simulation_class():
    """Build FaultSimulation lazily (sitl.simulation imports the whole perception stack)."""
    from behaviours.loop import Controller
    from .simulation import Simulation

    class FaultSimulation(Simulation):
        """The whole mission (``sitl.simulation.Simulation``) under a fault plan.

        The relay (when the plan needs one) sits between the controller's VehicleLink and the router;
        camera faults act on each rendered frame, then the FrameGuard decides whether perception
        may see it (a rejected frame gives no observation: no 3D decision, perception goes stale);
        timed events act on the autopilot and the simulated pilot.
        """

        def __init__(self, scenario, params, plan: FaultPlan, **kw: Any) -> None:
            super().__init__(scenario, params, **kw)
            self.plan = plan
            self.relay = None
            if plan.needs_relay:
                self.relay = LossyRelay(self.router.address, plan.link, self.clock, plan.seed)
                self.link.close()
                self.router.step()
                self.link = VehicleLink(params.with_overrides({"link.url": self.relay.controller_url},
                                                              "fault relay"), self.clock)
                self.link.open()
                self.controller = Controller(self.link, self.mission, self.clock)
                relay, orig = self.relay, self.router.step

                def router_step() -> None:
                    orig()
                    relay.step()
                self.router.step = router_step
            self.camera = CameraFaults(self._render_now)
            self.guard = FrameGuard(tuple(scenario.camera.image_size))
            self.fault_events = FaultEvents(plan, self.ap, self.pilot, self.relay, self.camera)
            self.log_counts = {"frames": 0, "telemetry": 0}
            if self.log is not None:
                log, counts = self.log, self.log_counts
                orig_frame, orig_tel = log.frame, log.telemetry

                class _Counting:  # count what the simulation writes, to compare with what is read back
                    def frame(self, rec):
                        counts["frames"] += 1
                        orig_frame(rec)

                    def telemetry(self, rec):
                        counts["telemetry"] += 1
                        orig_tel(rec)

                    def __getattr__(self, name):
                        return getattr(log, name)
                self.log = _Counting()

        def _render_now(self, t_s: float):
            s = self.ap.state
            frame = self.renderer.render(s.north_m, s.east_m, s.depth_m, s.yaw_rad, t_s)
            self.last_frame, self.last_meta = frame, frame.meta
            return frame

        def _maybe_fault(self, now: float) -> None:
            super()._maybe_fault(now)
            self.fault_events.step(now, lambda st: next((t for t, s in self.mission.history if s == st), None))

        def _capture(self, now: float):
            frame = self.camera(now)
            if self.guard.check(frame):
                return None
            need = self.mission.needs
            roi = self.mission.track_roi(self.rig, self.scenario.camera.image_size) if need == "track" else None
            return self.processor.process(frame, need, now, roi)

        def close(self) -> None:
            super().close()
            if self.relay is not None:
                self.relay.close()

    return FaultSimulation


def __getattr__(name: str) -> Any:
    """Return ``FaultSimulation``, built on first use (the module's only lazy name)."""
    if name == "FaultSimulation":
        return _fault_simulation_class()
    raise AttributeError(name)


def run_faulted_mission(scenario: str = "paper_pool", seed: int = 0, plan: FaultPlan | str | Path | None = None,
                        params: Any = None, log: Any = None, **overrides: Any):
    """Run one whole mission under a fault plan (a FaultPlan or a plan file); return (result, simulation)."""
    from .scenario import load_scenario
    from .simulation import sim_params

    if plan is None or isinstance(plan, (str, Path)):
        plan = load_fault_plan(plan, seed=seed) if plan is not None else FaultPlan()
    base = params if params is not None else load_params()
    if plan.params:
        base = base.with_overrides(dict(plan.params), plan.source)
    sc = load_scenario(scenario, seed)
    sim = _fault_simulation_class()(sc, sim_params(base, sc, **overrides), plan, log=log)
    try:
        result = sim.run()
    finally:
        sim.close()
    return result, sim


def make_simulation(scenario: Any, params: Any, faults: str | Path | None, seed: int = 0, **kw: Any):
    """For ``dip3d-vehicle sitl --faults FILE``: a Simulation, or a FaultSimulation when a plan file is given.

    Raises:
        ScenarioError: the plan file is bad (names the file and the field).
    """
    if not faults:
        from .simulation import Simulation
        return Simulation(scenario, params, **kw)
    plan = load_fault_plan(faults, seed=seed)
    if plan.params:
        params = params.with_overrides(dict(plan.params), plan.source)
    return _fault_simulation_class()(scenario, params, plan, **kw)
