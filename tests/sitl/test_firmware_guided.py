"""GUIDED conformance on the real ArduSub SITL firmware (issue 13): the velocity setpoint times out, the
yaw rate does not, and an explicit zero stops the turn - the rows the built-in autopilot is held to in
tests/sitl/test_autopilot_protocol.py (test_guided_velocity_times_out_after_3s,
test_guided_yaw_rate_does_not_time_out).

The firmware gets the SITL's simulated external navigation as its position source
(sitl/ardusub_sitl.py EXTERNAL_NAV_PARAMS), so GUIDED is accepted a few seconds after boot instead of
~41 s with its simulated GPS (whose estimate is not usable for GUIDED at this depth). Driven in wall-clock
time as the ground station (heartbeat, neutral joystick) and as the controller (1/191 setpoints, BODY_NED);
speeds are the simulator's truth (SIM_STATE). Skipped with the reason when the binary is absent.
"""

from __future__ import annotations

import math
import time
from typing import Any

import pytest
from pymavlink.dialects.v20 import ardupilotmega as m2

from sitl.ardusub_sitl import EXTERNAL_NAV_ARGS, EXTERNAL_NAV_PARAMS, ArdusubSitl, SitlOptions
from sitl.firmware_mav import MavSocket
from sitl.firmware_world import pre_dive

from test_conformance import firmware_binary

INSTANCE = 34


class _Driver:
    """Heartbeat 1 Hz and neutral sticks 10 Hz as 255/190; setpoints 10 Hz as 1/191 while ``setpoint`` is set."""

    def __init__(self, m: MavSocket) -> None:
        self.m = m
        self.setpoint: tuple[float, float] | None = None  # (vx m/s, yaw rate rad/s)
        self._next_hb = self._next_mc = self._next_sp = 0.0
        self.last: dict[str, Any] = {}
        self.log: list[str] = []  # the firmware's STATUSTEXTs and mode changes, for a failure's message
        self._t0 = time.monotonic()

    def run(self, seconds: float) -> None:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            now = time.monotonic()
            if now >= self._next_hb:
                self.m.heartbeat()
                self._next_hb = now + 1.0
            if now >= self._next_mc:
                self.m.send(m2.MAVLink_manual_control_message(1, 0, 0, 500, 0, 0))
                self._next_mc = now + 0.1
            if self.setpoint is not None and now >= self._next_sp:
                vx, r = self.setpoint
                self.m.send(m2.MAVLink_set_position_target_local_ned_message(
                    0, 1, 1, 8, 1479, 0, 0, 0, vx, 0, 0, 0, 0, 0, 0, r), 1, 191)
                self._next_sp = now + 0.1
            for msg in self.m.pump():
                if msg.get_type() == "HEARTBEAT" and msg.type != m2.MAV_TYPE_SUBMARINE:
                    continue  # not the autopilot's: the simulated external navigation's (17/18, custom_mode 0), routed to us
                self._note(msg)
                self.last[msg.get_type()] = msg
            time.sleep(0.005)

    def _note(self, msg: Any) -> None:
        """Log a STATUSTEXT or a change of the autopilot's mode, with the seconds since the driver started."""
        t = time.monotonic() - self._t0
        kind = msg.get_type()
        if kind == "STATUSTEXT":
            self.log.append(f"{t:.1f} s: {msg.text}")
        elif kind == "HEARTBEAT" and "HEARTBEAT" in self.last and msg.custom_mode != self.last["HEARTBEAT"].custom_mode:
            self.log.append(f"{t:.1f} s: mode {self.last['HEARTBEAT'].custom_mode} -> {msg.custom_mode}")

    def speed_m_s(self) -> float:
        s = self.last["SIM_STATE"]
        return math.hypot(s.vn, s.ve)

    def yaw_rate_rad_s(self) -> float:
        return float(self.last["SIM_STATE"].zgyro)

    def mode(self) -> int:
        """Return the autopilot's mode (its last HEARTBEAT's custom_mode)."""
        return int(self.last["HEARTBEAT"].custom_mode)


def test_guided_velocity_times_out_and_yaw_rate_does_not_on_the_firmware() -> None:
    binary = firmware_binary()
    if binary is None:
        pytest.skip("no ArduSub SITL binary ($DIP3D_ARDUSUB or ../shared/ardusub-sitl/ardusub)")
    sitl = ArdusubSitl(SitlOptions(binary, instance=INSTANCE, extra_params=EXTERNAL_NAV_PARAMS,
                                   extra_args=EXTERNAL_NAV_ARGS))
    sock = sitl.start()
    try:
        waited_s = pre_dive(sock, 1.0, timeout_s=60.0, guided=True)
        assert waited_s < 30.0  # GUIDED within seconds of boot with external navigation (GPS: ~41 s)
        d = _Driver(MavSocket(sock))
        d.setpoint = (0.3, 0.0)
        d.run(5.0)
        moving = d.speed_m_s()
        d.setpoint = None  # the controller goes quiet: the velocity must time out (3 s)
        d.run(2.0)
        before_timeout = d.speed_m_s()
        d.run(4.0)
        after_timeout = d.speed_m_s()
        d.setpoint = (0.0, 0.3)
        d.run(4.0)
        turning = d.yaw_rate_rad_s()
        d.setpoint = None  # quiet again: the yaw rate is kept
        d.run(6.0)
        still_turning = d.yaw_rate_rad_s()
        d.setpoint = (0.0, 0.0)
        d.run(3.0)
        stopped = d.yaw_rate_rad_s()
        mode = d.mode()
    finally:
        status = sitl.stop()
    assert status == 0
    assert mode == 4, d.log  # GUIDED throughout
    assert moving > 0.15 and before_timeout > 0.1, (moving, before_timeout)
    assert after_timeout < 0.08, after_timeout
    assert turning > 0.2 and still_turning > 0.2, (turning, still_turning)  # never times out
    assert abs(stopped) < 0.05, stopped  # the explicit zero the controller sends on every stop
