"""The autopilot's pilot-input timeout (FS_PILOT_TIMEOUT): the link reads it, lowers it to ``link.max_command_hold_s``
while it holds the sticks and puts the autopilot's own value back when it hands them back and at close; a perception
hold streams neutral sticks. Over a real loopback socket against the project's simulated ArduSub (sitl.autopilot), in
SimClock lockstep."""

from __future__ import annotations

from typing import Any

import pytest

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.config import load_params
from dip3d_vehicle.errors import LinkError
from dip3d_vehicle.link import VehicleLink
from dip3d_vehicle.link.command_hold import STREAM_SETTLE_S
from dip3d_vehicle.link.link_config import LinkConfig
from dip3d_vehicle.servo.command import VelocityCommand
from sitl.autopilot import Autopilot

FORWARD = VelocityCommand(surge_m_s=0.3)


class _Pair:
    """The simulated autopilot and a VehicleLink to it, stepped together every 20 ms; no ground station needed
    (``link.require_gcs`` off), so the link engages once the autopilot is armed in ALT_HOLD and enabled."""

    def __init__(self, link_params: dict[str, Any], ap_params: dict[str, float] | None = None) -> None:
        self.clock = SimClock()
        self.ap = Autopilot(load_params(), self.clock, listen=["tcp:127.0.0.1:0"])
        self.ap.ap_params.update(ap_params or {})
        self.link = VehicleLink({"link.url": self.ap.addresses[0], "link.require_gcs": False, **link_params},
                                self.clock)
        self.link.open()
        self.sticks: list[tuple[float, int]] = []  # (time, forward PWM) of every MANUAL_CONTROL the autopilot took
        on_manual = self.ap._on_manual_control

        def record(link, msg, now):
            on_manual(link, msg, now)
            self.sticks.append((now, msg.x))
        self.ap._on_manual_control = record

    def run(self, seconds: float, command: VelocityCommand | None = None, fresh: bool = True) -> None:
        end = self.clock.now() + seconds
        while self.clock.now() < end - 1e-9:
            self.clock.advance(0.02)
            self.ap.step()
            self.link.poll()
            self.link.tick(command, perception_fresh=fresh)

    def engage(self) -> None:
        """Arm in ALT_HOLD, enable, and run until engaged."""
        self.run(1.5, fresh=False)
        assert self.ap.set_mode(2) and self.ap.arm(True)
        self.link.enable("test")
        self.run(1.5)
        assert self.link.engaged, self.link.not_engaged_reason

    def close(self) -> None:
        self.link.close()
        for _ in range(5):
            self.ap.step()
        self.ap.close()

    def timeout_s(self) -> float:
        return self.ap.ap_params["FS_PILOT_TIMEOUT"]

    def said(self, text: str) -> list[str]:
        return [e for e in self.link.events if text in e]


@pytest.fixture
def pair_factory():
    made: list[_Pair] = []

    def make(link_params: dict[str, Any] | None = None, ap_params: dict[str, float] | None = None) -> _Pair:
        made.append(_Pair(link_params or {}, ap_params))
        return made[-1]
    yield make
    for p in made:
        if p.link._conn is not None:
            p.close()


def test_read_but_left_alone_until_the_controller_holds_the_sticks(pair_factory):
    p = pair_factory()
    p.run(2.0, fresh=False)
    assert p.timeout_s() == 3.0
    assert p.said("FS_PILOT_TIMEOUT = 3 s read from the autopilot: after a link loss it keeps the last "
                  "MANUAL_CONTROL for 3 s")
    assert p.said("FS_PILOT_INPUT = 2 read from the autopilot (pilot-input failsafe on)")
    assert p.link.stats.sent.get("PARAM_SET", 0) == 0


def test_lowered_while_engaged_and_put_back_when_the_sticks_are_handed_back(pair_factory):
    p = pair_factory()
    p.engage()
    p.run(0.5, FORWARD)
    assert p.timeout_s() == pytest.approx(1.0)
    assert p.said("FS_PILOT_TIMEOUT to 1 s while the controller holds the sticks (link.max_command_hold_s; the "
                  "autopilot's own 3 s otherwise)")
    p.link.disable("test")
    p.run(0.5)
    assert not p.link.engaged and p.timeout_s() == 3.0
    p.close()
    assert p.timeout_s() == 3.0 and not p.said("put back")


def test_lowered_only_after_the_stream_reached_the_autopilot(pair_factory):
    """Armed 1.5 s before the hand-over, no joystick stream: a 1 s timeout that arrived ahead of the controller's first
    MANUAL_CONTROL would disarm at once ("Lost manual control"; issue 11 session 64, a reordering link). The PARAM_SET
    goes out only after ``STREAM_SETTLE_S`` of the stream."""
    p = pair_factory()
    p.run(1.5, fresh=False)
    assert p.ap.set_mode(2) and p.ap.arm(True)
    armed_s = p.clock.now()
    p.run(1.5, fresh=False)  # the pilot armed, then waited 1.5 s before the enable
    p.link.enable("test")
    for _ in range(100):  # engaged within 2 s (the perception settle)
        if p.link.engaged:
            break
        p.run(0.02)
    assert p.link.engaged, p.link.not_engaged_reason
    handed_s = p.clock.now()
    p.run(STREAM_SETTLE_S - 0.1)
    assert p.timeout_s() == 3.0 and p.link.stats.sent.get("PARAM_SET", 0) == 0
    assert min(t for t, _ in p.sticks) < handed_s + 0.05  # the stream began at the hand-over
    p.run(0.5, FORWARD)
    assert p.timeout_s() == pytest.approx(1.0)
    assert p.ap.armed and not p.ap.events_of("failsafe") and handed_s - armed_s > 1.0


def test_put_back_at_close(pair_factory):
    p = pair_factory()
    p.engage()
    p.run(0.5, FORWARD)
    p.close()
    assert p.timeout_s() == 3.0
    assert p.said("FS_PILOT_TIMEOUT put back to 3 s")


def test_a_perception_hold_streams_neutral_and_keeps_the_vehicle_armed(pair_factory):
    p = pair_factory()
    p.engage()
    p.run(0.5, FORWARD)
    t_stale = p.clock.now()
    p.run(5.0, FORWARD, fresh=False)  # the camera stalls for 5 s, longer than the stop stream and any failsafe
    held = [(t, x) for t, x in p.sticks if t > t_stale + 0.05]
    assert held and all(x == 0 for _, x in held)  # neutral only
    gaps = [b[0] - a[0] for a, b in zip(held, held[1:])]
    assert max(gaps) <= 0.1 and held[-1][0] > p.clock.now() - 0.1  # streamed to the end, no silence
    assert p.ap.armed and p.timeout_s() == pytest.approx(1.0)
    assert p.link.operator_enabled and p.link.not_engaged_reason == "perception stale"
    p.run(0.5, FORWARD)
    assert p.link.engaged and p.sticks[-1][1] > 0  # resumes at once


def test_a_link_cut_lets_the_stale_command_run_one_second(pair_factory):
    p = pair_factory()
    p.engage()
    p.run(1.0, FORWARD)
    cut = p.clock.now()
    p.link.poll, p.link.tick = (lambda: 0), (lambda *a, **k: False)  # the controller goes quiet
    p.run(3.0, FORWARD)
    lost = p.ap.events_of("failsafe")
    assert lost == ["pilot_input"] and not p.ap.armed
    last_forward = max(t for t, x in p.sticks if x > 0)
    assert last_forward <= cut + 0.05


def test_a_shorter_own_time_is_left_alone(pair_factory):
    p = pair_factory(ap_params={"FS_PILOT_TIMEOUT": 0.5})
    p.ap.pilot_failsafe_enabled = False  # no pilot's joystick here: 0.5 s would disarm before the link engages
    p.engage()
    p.run(0.5, FORWARD)
    p.close()
    assert p.timeout_s() == 0.5 and p.link.stats.sent.get("PARAM_SET", 0) == 0


def test_zero_leaves_it_and_warns(pair_factory):
    p = pair_factory({"link.max_command_hold_s": 0.0})
    p.engage()
    p.close()
    assert p.timeout_s() == 3.0 and p.link.stats.sent.get("PARAM_SET", 0) == 0
    assert [e for e in p.said("WARNING") if "FS_PILOT_TIMEOUT = 3 s left as it is" in e]


def test_another_limit_and_a_failsafe_that_is_off(pair_factory):
    p = pair_factory({"link.max_command_hold_s": 1.5}, {"FS_PILOT_INPUT": 0})
    p.engage()
    p.run(0.5, FORWARD)
    assert p.timeout_s() == pytest.approx(1.5)
    assert len([e for e in p.said("WARNING") if "FS_PILOT_INPUT = 0: ArduSub's pilot-input failsafe is off" in e]) == 1


def test_guided_velocity_neither_reads_nor_sets_it(pair_factory):
    p = pair_factory({"link.output_mode": "guided_velocity"})
    p.run(2.0)
    p.close()
    assert p.timeout_s() == 3.0
    assert not p.said("FS_PILOT")
    assert p.link.stats.sent.get("PARAM_SET", 0) == 0


def test_someone_elses_setting_is_left_alone(pair_factory):
    p = pair_factory()
    p.engage()
    p.run(0.5, FORWARD)
    sets = p.link.stats.sent["PARAM_SET"]
    p.ap.ap_params["FS_PILOT_TIMEOUT"] = 2.0  # the operator's own change, from the ground station
    p.link._conn.mav.param_request_read_send(1, 1, b"FS_PILOT_TIMEOUT", -1)  # its PARAM_VALUE reaches the link
    p.run(1.0, FORWARD)
    assert p.said("WARNING FS_PILOT_TIMEOUT = 2 s set by someone else: left as it is for this session")
    p.link.disable("test")
    p.run(1.0)
    p.close()
    assert p.timeout_s() == 2.0 and p.link.stats.sent["PARAM_SET"] == sets


def test_read_again_after_a_reboot(pair_factory):
    p = pair_factory()
    p.run(2.0, fresh=False)
    p.ap.reboot(gap_s=1.0)
    p.run(3.0, fresh=False)
    assert len(p.said("FS_PILOT_TIMEOUT = 3 s read")) == 1  # the first value stays the autopilot's own
    assert p.link.stats.sent["PARAM_REQUEST_READ"] >= 2 * 3 and p.link.stats.sent.get("PARAM_SET", 0) == 0


def test_too_short_a_limit_is_refused():
    with pytest.raises(LinkError, match=r"link.max_command_hold_s = 0.1: shorter than five setpoint periods"):
        LinkConfig.from_params({"link.max_command_hold_s": 0.1, "link.setpoint_rate_hz": 20.0})
    assert LinkConfig.from_params({"link.max_command_hold_s": 0.25}).max_command_hold_s == 0.25


def test_the_autopilot_drops_a_stale_command_after_the_pilot_input_timeout():
    """The simulated ArduSub keeps the last MANUAL_CONTROL for FS_PILOT_TIMEOUT, then centres the sticks and disarms
    (as the firmware does: tests/sitl/test_firmware_command_hold.py)."""
    from pymavlink import mavutil

    from dip3d_vehicle.link.connection import use_mavlink2

    for override_s in (3.0, 1.0):
        clock = SimClock()
        ap = Autopilot(load_params(), clock, listen=["tcp:127.0.0.1:0"])
        ap.ap_params["FS_PILOT_TIMEOUT"] = override_s
        gcs = mavutil.mavlink_connection(ap.addresses[0], source_system=255, source_component=190)
        use_mavlink2(gcs)
        try:
            ap.arm(True)
            forward, sent_s = [], 0.0
            for i in range(300):  # 6 s: sticks forward for 1 s, then nothing (the ground station's heartbeat goes on)
                if i % 50 == 0:
                    gcs.mav.heartbeat_send(mavutil.mavlink.MAV_TYPE_GCS, mavutil.mavlink.MAV_AUTOPILOT_INVALID, 0, 0, 0)
                if i < 50 and i % 5 == 0:
                    gcs.mav.manual_control_send(1, 500, 0, 500, 0, 0)
                    sent_s = clock.now()
                clock.advance(0.02)
                ap.step()
                forward.append((clock.now(), ap.pilot.forward - 1500))
            held_s = max(t for t, x in forward if x > 0) - sent_s
            assert override_s - 0.05 <= held_s <= override_s + 0.1, (override_s, held_s)
            assert not ap.armed  # FS_PILOT_INPUT 2
        finally:
            gcs.close()
            ap.close()
