"""The simulated ground station and its pilot (system 255, a small pymavlink client on the router).

1 Hz GCS HEARTBEAT; it arms, selects the engage mode and enables the controller with
MAV_CMD_USER_1, as a pilot would; it can also take the vehicle back (mode change, disarm, disable)
for the safety trials.
"""

from __future__ import annotations

from typing import Any

from pymavlink import mavutil
from pymavlink.dialects.v20 import ardupilotmega as m2

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.link import MAV_CMD_USER_1

__all__ = ["SimPilot", "GCS_SYSID", "GCS_COMPID"]

GCS_SYSID, GCS_COMPID = 255, 190
_MODES = {"STABILIZE": 0, "ALT_HOLD": 2, "GUIDED": 4, "MANUAL": 19}


class SimPilot:
    """The ground station and its pilot: heartbeat, arm + mode + enable, and taking over.

    Args:
        url: the router's client URL.
        clock: the simulation clock.
        engage_mode: the mode the pilot selects ("ALT_HOLD" or "GUIDED").
        arm_at_s: when the pilot hands the vehicle over.
    """

    def __init__(self, url: str, clock: SimClock, engage_mode: str, arm_at_s: float) -> None:
        self.conn = mavutil.mavlink_connection(url, source_system=GCS_SYSID, source_component=GCS_COMPID,
                                               dialect="ardupilotmega", autoreconnect=False)
        self.conn.mav = m2.MAVLink(self.conn, srcSystem=GCS_SYSID, srcComponent=GCS_COMPID)
        self.clock, self.engage_mode, self.arm_at_s = clock, engage_mode, arm_at_s
        self.heartbeats = True
        self.handed_over = False
        self.enable_acked = False
        self._next_hb = 0.0
        self._next_try = arm_at_s
        self.armed = False
        self.mode = ""
        self.statustexts: list[tuple[float, str]] = []
        from dip3d_vehicle.link.statustext import StatusTextAssembler
        self._texts = StatusTextAssembler()  # chunked STATUSTEXTs (id / chunk_seq) put back together
        # A pilot flying GUIDED has the joystick connected: it streams centred sticks (as QGC does),
        # which keeps ArduSub's pilot-input failsafe quiet; GUIDED ignores them. In ALT_HOLD the
        # controller's own MANUAL_CONTROL is the pilot input, and a second stream would fight it.
        self.joystick = engage_mode == "GUIDED"
        self._next_stick = 0.0
        self.acks: list[tuple[float, int, int]] = []

    def step(self) -> None:
        """Read the autopilot's / controller's messages; send heartbeat and hand-over commands when due."""
        now = self.clock.now()
        while True:
            msg = self.conn.recv_msg()
            if msg is None:
                break
            self._on(msg, now)
        if self.heartbeats and now >= self._next_hb:
            self.conn.mav.heartbeat_send(m2.MAV_TYPE_GCS, m2.MAV_AUTOPILOT_INVALID, 0, 0, 0)
            self._next_hb = now + 1.0
        if self.joystick and now >= self._next_stick:
            self.conn.mav.manual_control_send(1, 0, 0, 500, 0, 0)
            self._next_stick = now + 0.1
        if not self.handed_over and now >= self._next_try:
            self._next_try = now + 1.0
            if not self.armed:
                self.command(1, 1, m2.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)
            if self.mode != self.engage_mode:
                self.command(1, 1, m2.MAV_CMD_DO_SET_MODE, 1.0, float(_MODES[self.engage_mode]))
            if self.armed and self.mode == self.engage_mode:
                self.command(1, 191, MAV_CMD_USER_1, 1.0)
            if self.enable_acked:
                self.handed_over = True

    def _on(self, msg: Any, now: float) -> None:
        kind = msg.get_type()
        src = (msg.get_srcSystem(), msg.get_srcComponent())
        if kind == "HEARTBEAT" and src == (1, 1):
            self.armed = bool(msg.base_mode & m2.MAV_MODE_FLAG_SAFETY_ARMED)
            self.mode = {v: k for k, v in _MODES.items()}.get(msg.custom_mode, str(msg.custom_mode))
        elif kind == "STATUSTEXT":
            text = self._texts.add(msg)  # chunked texts (id / chunk_seq) put back together
            if text is not None:
                self.statustexts.append((now, f"{src[0]}/{src[1]}: {text}"))
        elif kind == "COMMAND_ACK" and getattr(msg, "target_system", GCS_SYSID) == GCS_SYSID:
            self.acks.append((now, msg.command, msg.result))
            if msg.command == MAV_CMD_USER_1 and src == (1, 191):
                self.enable_acked = msg.result == m2.MAV_RESULT_ACCEPTED

    def command(self, target_system: int, target_component: int, command: int, *params: float) -> None:
        """Send one COMMAND_LONG."""
        p = list(params) + [0.0] * (7 - len(params))
        self.conn.mav.command_long_send(target_system, target_component, command, 0, *p)

    def set_mode(self, name: str) -> None:
        """The pilot selects a mode (DO_SET_MODE)."""
        self.command(1, 1, m2.MAV_CMD_DO_SET_MODE, 1.0, float(_MODES[name]))

    def disarm(self) -> None:
        """The pilot disarms."""
        self.command(1, 1, m2.MAV_CMD_COMPONENT_ARM_DISARM, 0.0)

    def disable_controller(self) -> None:
        """The operator withdraws the controller's enable (MAV_CMD_USER_1 param1 0)."""
        self.command(1, 191, MAV_CMD_USER_1, 0.0)

    def close(self) -> None:
        """Close the connection."""
        try:
            self.conn.close()
        except OSError:
            pass
