"""The controller loop with the real link: a mission suspended by a lost autopilot resumes only after
the pilot's re-arm and re-enable (simulated autopilot, router and pilot; synthetic tracking frames)."""

from __future__ import annotations

import pytest

from behaviours.blackboard import Observation, TrackFrame
from behaviours.loop import Controller, build_mission
from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.config import load_params
from dip3d_vehicle.link import VehicleLink
from sitl.autopilot import Autopilot
from sitl.scenario import load_scenario
from sitl.simulation import Router, SimPilot
from synthetic_target import target_frame

STEP_S, FRAME_S = 0.02, 0.2


class _Loop:
    """Autopilot, router, pilot and the Controller in lockstep; a tracking frame of the target every 0.2 s."""

    def __init__(self, ap, router, pilot, controller, clock, frame: TrackFrame) -> None:
        self.ap, self.router, self.pilot, self.ctl, self.clock, self.frame = ap, router, pilot, controller, clock, frame
        self.records: list = []
        self._next_frame = 0.0

    def run(self, seconds: float, until=None) -> None:
        end = self.clock.now() + seconds
        while self.clock.now() < end - 1e-9:
            now = self.clock.advance(STEP_S)
            self.ap.step()
            self.router.step()
            self.pilot.step()
            obs = None
            if now + 1e-9 >= self._next_frame:
                self._next_frame = now + FRAME_S
                obs = Observation(now, len(self.records), track=self.frame)
            self.records.append(self.ctl.tick(obs))
            self.router.step()
            if until is not None and until():
                return

    def motion_since(self, t_s: float) -> list:
        """Ticks since ``t_s`` on which the link was engaged and streamed a motion command."""
        return [r for r in self.records if r.t_s >= t_s and r.engaged and r.command is not None
                and not r.command.is_neutral()]


@pytest.fixture
def loop():
    clock = SimClock()
    params = load_params()
    rig = load_scenario("paper_pool", 0).rig()
    with Autopilot(params, clock, listen=["tcp:127.0.0.1:0"]) as ap:
        router = Router(ap.addresses[0])
        link = VehicleLink(params.with_overrides({"link.url": router.address}), clock)
        link.open()
        pilot = SimPilot(router.address, clock, "ALT_HOLD", arm_at_s=0.2)
        mission = build_mission(params, rig, (1600, 1200))
        cands, pts, obj = target_frame(rig)
        try:
            yield _Loop(ap, router, pilot, Controller(link, mission, clock), clock, TrackFrame(cands, pts)), obj, cands
        finally:
            link.close()
            pilot.close()
            router.close()


def test_autopilot_loss_suspends_the_servo_and_only_the_re_enable_resumes_it(loop):
    lp, obj, cands = loop
    m, link = lp.ctl.mission, lp.ctl.link
    lp.run(5.0, until=lambda: m.state == "wait_for_diver")
    assert link.engaged and m.state == "wait_for_diver"
    m.bb.tracker.start(obj, cands, lp.clock.now())  # as select_target does with its winner
    m.machine.set_state("servo")
    m.behaviours["servo"].enter(m.bb)
    lp.run(1.0)
    assert m.state == "servo" and lp.motion_since(lp.clock.now() - 1.0)

    lp.router.mute_autopilot = True  # the link is cut: nothing from the autopilot reaches the controller
    onset = lp.clock.now()
    lp.run(2.0)
    assert not link.engaged and link.disengage_reason == "autopilot lost" and not link.operator_enabled
    assert m.state == "suspended" and m.bb.command is None
    assert not lp.motion_since(onset + 0.7)
    assert m.bb.tracker.active and not m.bb.tracker.lost  # still following the target

    lp.router.mute_autopilot = False  # the link is back, but nobody re-enabled the controller
    back = lp.clock.now()
    lp.run(3.0)
    assert lp.ctl.link.autopilot.alive(lp.clock.now(), 0.6)
    assert not link.engaged and m.state == "suspended" and not lp.motion_since(back)

    lp.pilot.handed_over = lp.pilot.enable_acked = False  # the pilot re-arms if needed and re-enables
    lp.pilot._next_try = lp.clock.now()
    reenable = lp.clock.now()
    lp.run(4.0, until=lambda: bool(lp.motion_since(reenable)))
    assert link.engaged and m.state == "servo"
    assert any("resuming the servo" in line for line in m.bb.story)
    assert lp.motion_since(reenable)
