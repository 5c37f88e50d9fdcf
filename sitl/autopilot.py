"""An ArduSub-like autopilot on real MAVLink 2 sockets, stepping the vehicle dynamics on a Clock.

Behaves as ArduSub 4.5 does on every row of ``/work/shared/reference/ardusub_mavlink.md`` that the
controller relies on (HEARTBEAT, modes and refusals, arming, MANUAL_CONTROL with the SYSID_MYGCS
rule and joystick scaling, GUIDED SET_POSITION_TARGET_LOCAL_NED with its timeouts, message
intervals, parameters, failsafes, telemetry, signing). Messages and STATUSTEXTs are those seen on a
real ArduSub SITL (``ardusub_sitl_response.md``).

Use::

    ap = Autopilot(load_params(), SimClock(), listen=["tcp:127.0.0.1:0"])
    while ...:
        clock.advance(0.01); ap.step()      # lockstep with the other parties

``step()`` drains every socket without blocking, handles the messages, advances the dynamics to
``clock.now()`` in fixed sub-steps (``sim.physics_rate_hz``) and sends the telemetry that is due.
Simulation logic only ever reads the injected clock.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

from pymavlink.dialects.v20 import ardupilotmega as mavlink2

from dip3d_vehicle.clock import Clock
from dip3d_vehicle.config import load_params
from dip3d_vehicle.link.statustext import statustext_messages

from .dynamics import Dynamics, VehicleParams, VehicleState, wrap_pi
from .firmware_versions import firmware_profile
from .mavftp import FtpServer
from .mavlink_endpoint import Endpoint, Link
from .modes import (AUTO_YAW_SLEW_RAD_S, MODE_NUMBERS, MODES, POSITION_MODES, ControlGains, Controller,
                    GuidedTarget, PilotInput, joystick_to_pwm)
from .sys_status import sys_status_bits

__all__ = ["Autopilot", "Event", "ARDUSUB_PARAMS", "DEFAULT_INTERVALS_S"]

M = mavlink2

#: The simulated vehicle's own MAVLink parameters (values as read from ArduSub 4.5 SITL).
ARDUSUB_PARAMS: dict[str, float] = {
    "SYSID_THISMAV": 1, "SYSID_MYGCS": 255, "FS_PILOT_INPUT": 2, "FS_PILOT_TIMEOUT": 3.0,
    "FS_GCS_ENABLE": 2, "JS_GAIN_DEFAULT": 0.5, "JS_GAIN_MAX": 1.0, "JS_GAIN_MIN": 0.25,
    "JS_GAIN_STEPS": 4, "JS_THR_GAIN": 1.0, "RC_OVERRIDE_TIME": 3.0, "PILOT_SPEED_UP": 200,
    "PILOT_SPEED_DN": 0, "PILOT_ACCEL_Z": 200, "THR_DZ": 100, "ACRO_YAW_P": 3.375,
    "ATC_RATE_Y_MAX": 180, "ATC_ACCEL_Y_MAX": 110000, "WPNAV_SPEED": 100, "SIM_BUOYANCY": 1,
    "FRAME_CONFIG": 1, "MOT_FV_CPLNG_K": 1, "FS_LEAK_ENABLE": 1,
}
_PARAM_RANGES = {"FS_PILOT_TIMEOUT": (0.1, 3.0), "SYSID_MYGCS": (1, 255), "MAV_GCS_SYSID": (1, 255), "FS_PILOT_INPUT": (0, 2),
                 "FS_GCS_ENABLE": (0, 4), "JS_GAIN_DEFAULT": (0.1, 1.0), "RC_OVERRIDE_TIME": (-1, 120)}

#: Default stream intervals (ArduSub stream groups: EXTRA1 10 Hz, EXTRA2 10, POSITION 3, EXT_STAT 2,
#: RC_CHAN 2); None = not streamed unless asked for with SET_MESSAGE_INTERVAL.
DEFAULT_INTERVALS_S: dict[int, float | None] = {
    M.MAVLINK_MSG_ID_HEARTBEAT: 1.0, M.MAVLINK_MSG_ID_SYS_STATUS: 0.5, M.MAVLINK_MSG_ID_ATTITUDE: 0.1,
    M.MAVLINK_MSG_ID_GLOBAL_POSITION_INT: 1 / 3, M.MAVLINK_MSG_ID_LOCAL_POSITION_NED: 1 / 3,
    M.MAVLINK_MSG_ID_VFR_HUD: 0.1, M.MAVLINK_MSG_ID_RC_CHANNELS: 0.5,
    M.MAVLINK_MSG_ID_SCALED_PRESSURE2: None, M.MAVLINK_MSG_ID_SYSTEM_TIME: None,
}
_STREAM_GROUPS = {  # REQUEST_DATA_STREAM ids -> messages
    M.MAV_DATA_STREAM_EXTENDED_STATUS: [M.MAVLINK_MSG_ID_SYS_STATUS],
    M.MAV_DATA_STREAM_RC_CHANNELS: [M.MAVLINK_MSG_ID_RC_CHANNELS],
    M.MAV_DATA_STREAM_POSITION: [M.MAVLINK_MSG_ID_GLOBAL_POSITION_INT, M.MAVLINK_MSG_ID_LOCAL_POSITION_NED],
    M.MAV_DATA_STREAM_EXTRA1: [M.MAVLINK_MSG_ID_ATTITUDE],
    M.MAV_DATA_STREAM_EXTRA2: [M.MAVLINK_MSG_ID_VFR_HUD],
    M.MAV_DATA_STREAM_RAW_SENSORS: [M.MAVLINK_MSG_ID_SCALED_PRESSURE2],
}

_BASE_MODE = (M.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | M.MAV_MODE_FLAG_STABILIZE_ENABLED
              | M.MAV_MODE_FLAG_MANUAL_INPUT_ENABLED)  # 81 = 0x51, as ArduSub sends it
_FRAMES = {M.MAV_FRAME_LOCAL_NED, M.MAV_FRAME_LOCAL_OFFSET_NED, M.MAV_FRAME_BODY_NED,
           M.MAV_FRAME_BODY_OFFSET_NED, M.MAV_FRAME_BODY_FRD}
_POS_IGNORE, _VEL_IGNORE, _ACC_IGNORE = 0b111, 0b111000, 0b111000000
_YAW_IGNORE, _YAW_RATE_IGNORE = 1024, 2048
_EARTH_RADIUS_M = 6378137.0


@dataclass(frozen=True)
class Event:
    """Something the autopilot did, for tests: kind (statustext, mode, armed, ack, failsafe, ...)."""

    time_s: float
    kind: str
    detail: Any


class Autopilot:
    """ArduSub-like autopilot + vehicle dynamics, speaking MAVLink 2 on loopback TCP/UDP.

    Args:
        params: project parameters (``sim.*`` keys; default: ``load_params()``).
        clock: the time source (SimClock for lockstep, WallClock standalone).
        listen: listen URLs, ``tcp:HOST:PORT`` (first = serial 0) or ``udpin:HOST:PORT``; port 0
            picks a free port (see ``addresses``).
        has_position: the vehicle has a position estimate (DVL); default ``sim.has_position``.
        signing_key: 32-byte MAVLink 2 signing key, or None.
        sysid: vehicle system id; default ``sim.sysid``.
        initial_state: starting VehicleState (default: ``sim.initial_depth_m`` / ``initial_yaw_deg``).
        firmware: "4.5" / "4.7" behaviour (default ``sim.firmware``; see sitl/firmware_versions.py).
    """

    def __init__(self, params: Mapping[str, Any] | None = None, clock: Clock | None = None,
                 listen: list[str] | tuple[str, ...] = ("tcp:127.0.0.1:5760",),
                 has_position: bool | None = None, signing_key: bytes | None = None,
                 sysid: int | None = None, initial_state: VehicleState | None = None,
                 firmware: str | None = None) -> None:
        if clock is None:
            from dip3d_vehicle.clock import SimClock
            clock = SimClock()
        self.params = params if params is not None else load_params()
        p = self.params
        self.clock = clock
        self.sysid = int(sysid if sysid is not None else p["sim.sysid"])
        self.has_position = bool(p["sim.has_position"] if has_position is None else has_position)
        self.ap_params: dict[str, float] = dict(ARDUSUB_PARAMS, SYSID_THISMAV=self.sysid)
        self.firmware = fw = firmware_profile(p["sim.firmware"] if firmware is None else firmware)
        if fw.version != "4.5":  # 4.7 renamed the id parameters and added FS_GCS_TIMEOUT
            self.ap_params[fw.gcs_sysid_param] = self.ap_params.pop("SYSID_MYGCS")
            self.ap_params[fw.this_mav_param] = self.ap_params.pop("SYSID_THISMAV")
            self.ap_params["FS_GCS_TIMEOUT"] = fw.gcs_failsafe_timeout_s
        self.pilot_failsafe_enabled = bool(p["sim.pilot_input_failsafe"])
        self.gcs_timeout_s = float(p["sim.gcs_failsafe_timeout_s"]) if fw.version == "4.5" else fw.gcs_failsafe_timeout_s
        self.guided_timeout_s = float(p["sim.guided_velocity_timeout_s"])
        self.home = (float(p["sim.home_lat_deg"]), float(p["sim.home_lon_deg"]))
        self._dt = 1.0 / float(p["sim.physics_rate_hz"])
        vehicle = VehicleParams.from_params(p)
        if initial_state is None:
            initial_state = VehicleState(depth_m=float(p["sim.initial_depth_m"]),
                                         yaw_rad=math.radians(float(p["sim.initial_yaw_deg"])))
        self.dynamics = Dynamics(vehicle, initial_state)
        self.controller = Controller(vehicle, ControlGains.from_params(p), dt_s=self._dt)
        self.armed = False
        self.mode = MODE_NUMBERS["MANUAL"]
        self.pilot = PilotInput()
        self.guided = GuidedTarget()
        self.events: list[Event] = []
        self.ftp = FtpServer(lambda: self.ap_params, ARDUSUB_PARAMS)  # @PARAM/param.pck, as ArduSub serves it
        self._text_id = 0  # STATUSTEXT id of the last chunked text
        self.counters: dict[str, int] = {"manual_control_ignored": 0, "setpoints_ignored": 0,
                                         "messages_in": 0}
        self._t0 = clock.now()
        self._boot_t0 = self._t0  # time_boot_ms origin (reset by reboot(); physics keeps _t0)
        self._down_until_s: float | None = None  # rebooting: silent and deaf until then
        self.reboots = 0
        self._k = 0  # physics sub-steps done
        self._last_pilot_input_s = -math.inf
        self._fs_pilot = False
        self._gcs_seen = False
        self._gcs_last_s = -math.inf
        self._fs_gcs = False
        self._gcs_warn_s = -math.inf
        self.endpoint = Endpoint(list(listen), self.sysid, 1, signing_key,
                                 bool(p["sim.serial0_accepts_unsigned"]))
        self.endpoint.on_new_link = self._init_link
        for link in self.endpoint.links:
            self._init_link(link)

    # ----------------------------------------------------------------- public
    @property
    def state(self) -> VehicleState:
        """The vehicle's true state."""
        return self.dynamics.state

    @property
    def mode_name(self) -> str:
        """The current mode's ArduSub name."""
        return MODES.get(self.mode, str(self.mode))

    @property
    def addresses(self) -> list[str]:
        """The bound listen addresses (with the real port when 0 was asked)."""
        return list(self.endpoint.addresses)

    @property
    def time_boot_s(self) -> float:
        """Seconds since the autopilot (re)booted (on its clock)."""
        return self.clock.now() - self._boot_t0

    def step(self) -> None:
        """Read all sockets, handle messages, advance the dynamics to now, send due telemetry."""
        now = self.clock.now()
        rebooting = self._down_until_s is not None and now < self._down_until_s
        if self._down_until_s is not None and not rebooting:
            self._down_until_s = None
            self._boot_t0 = now
            self._event("booted", self.reboots)
        for link, msg in self.endpoint.poll():
            if rebooting:
                continue  # a rebooting autopilot hears nothing
            self.counters["messages_in"] += 1
            self._handle(link, msg, now)
        target_k = int(math.floor((now - self._t0) / self._dt + 1e-9))
        while self._k < target_k:
            t = self._t0 + self._k * self._dt
            self._control_step(t)
            self._k += 1
        if not rebooting:
            self._send_telemetry(now)

    def reboot(self, gap_s: float = 2.0) -> None:
        """Reboot as ArduSub does (e.g. a watchdog or the pilot's reboot button).

        Disarms at once, boots in MANUAL with default stream intervals and a new ``time_boot_ms``
        origin; for ``gap_s`` seconds it sends nothing (no HEARTBEAT) and ignores every message.
        Parameters (``ap_params``, e.g. SYSID_MYGCS) and the sockets are kept (the links stay
        connected, as to a router); signing keys are kept (ArduSub stores them).
        """
        now = self.clock.now()
        self.reboots += 1
        self._event("reboot", gap_s)
        self.armed = False
        self.mode = MODE_NUMBERS["MANUAL"]
        self.pilot, self.guided = PilotInput(), GuidedTarget()
        self.controller.depth_hold_m = None
        self._fs_pilot = self._fs_gcs = False
        self._gcs_seen, self._gcs_last_s = False, -math.inf
        self._last_pilot_input_s = now
        for link in self.endpoint.links:
            self._init_link(link)
        self._down_until_s = now + max(0.0, float(gap_s))

    def set_mode(self, mode: int) -> bool:
        """Change mode as a MAV_CMD_DO_SET_MODE would; return False (with STATUSTEXT) if refused."""
        if mode not in MODES:
            self.statustext(M.MAV_SEVERITY_WARNING, f"No such mode {mode}")
            return False
        booted_s = self.time_boot_s
        if mode in POSITION_MODES and (not self.has_position or booted_s < self.firmware.position_after_s):
            self.statustext(M.MAV_SEVERITY_WARNING, f"Mode change failed: {MODES[mode]} requires position")
            return False
        if mode == MODE_NUMBERS["ALT_HOLD"] and booted_s < self.firmware.alt_hold_after_s:
            self.statustext(M.MAV_SEVERITY_WARNING, "Mode change failed: ALT_HOLD need alt estimate")
            return False
        if mode != self.mode:
            self.controller.depth_hold_m = None
            if mode == MODE_NUMBERS["GUIDED"]:
                s = self.state
                self.guided = GuidedTarget(position_ned=(s.north_m, s.east_m, s.depth_m), position_z_set=True,
                                           yaw_rad=s.yaw_rad)
        self.mode = mode
        self._event("mode", MODES[mode])
        return True

    def arm(self, arm: bool) -> bool:
        """Arm or disarm as MAV_CMD_COMPONENT_ARM_DISARM would; return True when done."""
        if arm and not self.armed and self.time_boot_s < self.firmware.arm_after_s:
            self.statustext(M.MAV_SEVERITY_CRITICAL, "Arm: Battery 1 unhealthy")
            return False
        if arm and not self.armed:
            self.armed = True
            self._last_pilot_input_s = max(self._last_pilot_input_s, self.clock.now())
            self._fs_pilot = self._fs_gcs = False
            self.statustext(M.MAV_SEVERITY_INFO, "Arming motors")
            self._event("armed", True)
        elif not arm and self.armed:
            self.armed = False
            self.pilot = PilotInput()
            self.statustext(M.MAV_SEVERITY_INFO, "Disarming motors")
            self._event("armed", False)
        return True

    def statustext(self, severity: int, text: str) -> None:
        """Send a STATUSTEXT on every link and record it as an event."""
        self._event("statustext", text)
        self._text_id = self._text_id % 65535 + 1
        for msg in statustext_messages(severity, text, self._text_id):  # > 50 characters: chunks, as ArduPilot
            self.endpoint.broadcast(msg)

    def close(self) -> None:
        """Close all sockets."""
        self.endpoint.close()

    def __enter__(self) -> "Autopilot":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    @property
    def dropped_unsigned(self) -> int:
        """Messages dropped for a missing or wrong signature."""
        return self.endpoint.dropped_unsigned

    def events_of(self, kind: str) -> list[Any]:
        """Return the details of every event of one kind, in order."""
        return [e.detail for e in self.events if e.kind == kind]

    # ----------------------------------------------------------------- control
    def _control_step(self, t: float) -> None:
        self._check_failsafes(t)
        if t - self._last_pilot_input_s > self.ap_params["RC_OVERRIDE_TIME"] > 0:
            self.pilot = PilotInput()
        forces = self.controller.forces(self.mode, self.armed, self.pilot, self.guided, self.state, t,
                                        self.guided_timeout_s)
        if self.mode == MODE_NUMBERS["SURFACE"] and self.armed:
            forces = type(forces)(forces.x_n, forces.y_n, self.controller._heave_rate(-0.5, self.state),
                                  forces.yaw_nm)
        self.dynamics.step(self._dt, forces)

    def _check_failsafes(self, t: float) -> None:
        fs_input = int(self.ap_params["FS_PILOT_INPUT"])
        if self.pilot_failsafe_enabled and fs_input and self.armed and not self._fs_pilot:
            if t - self._last_pilot_input_s > self.ap_params["FS_PILOT_TIMEOUT"]:
                self._fs_pilot = True
                self._event("failsafe", "pilot_input")
                self.statustext(M.MAV_SEVERITY_CRITICAL, "Lost manual control")
                self.pilot = PilotInput()
                if fs_input == 2:
                    self.arm(False)
        fs_gcs = int(self.ap_params["FS_GCS_ENABLE"])
        if not fs_gcs or not self._gcs_seen or t - self._gcs_last_s <= self.gcs_timeout_s:
            self._fs_gcs = False
            return
        if t - self._gcs_warn_s > 30.0:
            self._gcs_warn_s = t
            self.statustext(M.MAV_SEVERITY_WARNING, f"MYGCS: {int(self.ap_params[self.firmware.gcs_sysid_param])}, heartbeat lost")
        if self._fs_gcs or not self.armed:
            return
        self._fs_gcs = True
        self._event("failsafe", "gcs")
        if fs_gcs == 2 or (fs_gcs == 3 and not self.set_mode(MODE_NUMBERS["ALT_HOLD"])) or (
                fs_gcs == 4 and not self.set_mode(MODE_NUMBERS["SURFACE"])):
            self.arm(False)

    # ----------------------------------------------------------------- messages
    def _event(self, kind: str, detail: Any) -> None:
        self.events.append(Event(self.clock.now(), kind, detail))

    def _init_link(self, link: Link) -> None:
        link.intervals_s = dict(DEFAULT_INTERVALS_S)
        link.next_due_s = {}

    def _handle(self, link: Link, msg: Any, now: float) -> None:
        kind = msg.get_type()
        handler = getattr(self, "_on_" + kind.lower(), None)
        if handler is not None:
            handler(link, msg, now)

    def _from_gcs(self, msg: Any) -> bool:
        return msg.get_srcSystem() == int(self.ap_params[self.firmware.gcs_sysid_param])

    def _for_me(self, target_system: int) -> bool:
        return target_system in (0, self.sysid)

    def _on_heartbeat(self, link: Link, msg: Any, now: float) -> None:
        if self._from_gcs(msg) and msg.get_srcSystem() != self.sysid:
            self._gcs_seen, self._gcs_last_s = True, now

    def _on_manual_control(self, link: Link, msg: Any, now: float) -> None:
        if not self._from_gcs(msg) or msg.target != self.sysid:
            self.counters["manual_control_ignored"] += 1
            return
        self._gcs_seen, self._gcs_last_s = True, now
        self._last_pilot_input_s = now
        self._fs_pilot = False
        pwm = joystick_to_pwm(msg.x, msg.y, msg.z, msg.r, self.ap_params["JS_GAIN_DEFAULT"],
                              self.ap_params["JS_THR_GAIN"])
        self.pilot = PilotInput(**pwm)

    def _on_rc_channels_override(self, link: Link, msg: Any, now: float) -> None:
        if not self._from_gcs(msg) or msg.target_system != self.sysid:
            self.counters["manual_control_ignored"] += 1
            return
        self._last_pilot_input_s = now
        self._fs_pilot = False

        def ch(v: int, old: int) -> int:
            return old if v in (0, 65535) else int(v)
        p = self.pilot
        self.pilot = PilotInput(forward=ch(msg.chan5_raw, p.forward), lateral=ch(msg.chan6_raw, p.lateral),
                                throttle=ch(msg.chan3_raw, p.throttle), yaw=ch(msg.chan4_raw, p.yaw))

    def _ack(self, link: Link, msg: Any, command: int, result: int) -> None:
        self._event("ack", (command, result))
        link.send(M.MAVLink_command_ack_message(command, result, 0, 0, msg.get_srcSystem(),
                                                msg.get_srcComponent()))

    def _on_command_long(self, link: Link, msg: Any, now: float) -> None:
        if self._for_me(msg.target_system):
            self._command(link, msg, msg.command, [msg.param1, msg.param2, msg.param3, msg.param4,
                                                   msg.param5, msg.param6, msg.param7])

    def _on_command_int(self, link: Link, msg: Any, now: float) -> None:
        if self._for_me(msg.target_system):
            self._command(link, msg, msg.command, [msg.param1, msg.param2, msg.param3, msg.param4,
                                                   msg.x, msg.y, msg.z])

    def _command(self, link: Link, msg: Any, command: int, p: list[float]) -> None:
        ok, failed = M.MAV_RESULT_ACCEPTED, M.MAV_RESULT_FAILED
        if command == M.MAV_CMD_COMPONENT_ARM_DISARM:
            result = ok if self.arm(p[0] == 1.0) else failed
        elif command == M.MAV_CMD_DO_SET_MODE:
            if not int(p[0]) & M.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED:
                result = M.MAV_RESULT_UNSUPPORTED
            else:
                result = ok if self.set_mode(int(p[1])) else failed
        elif command == M.MAV_CMD_SET_MESSAGE_INTERVAL:
            result = self._set_interval(link, int(p[0]), p[1])
        elif command == M.MAV_CMD_REQUEST_MESSAGE:
            result = ok if self._send_one(link, int(p[0]), self.clock.now()) else M.MAV_RESULT_DENIED
        elif command == M.MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES:
            self._send_one(link, M.MAVLINK_MSG_ID_AUTOPILOT_VERSION, self.clock.now())
            result = ok
        else:
            result = M.MAV_RESULT_UNSUPPORTED
        self._ack(link, msg, command, result)

    def _system_status(self, now: float) -> int:
        """HEARTBEAT.system_status: ACTIVE armed, STANDBY disarmed, CRITICAL (5) just after a 4.7 boot."""
        if now - self._boot_t0 < self.firmware.boot_status_s:
            return M.MAV_STATE_CRITICAL
        return M.MAV_STATE_ACTIVE if self.armed else M.MAV_STATE_STANDBY

    def _on_set_mode(self, link: Link, msg: Any, now: float) -> None:
        if msg.target_system != self.sysid:
            return
        if not msg.base_mode & M.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED:
            result = M.MAV_RESULT_UNSUPPORTED
        else:
            result = M.MAV_RESULT_ACCEPTED if self.set_mode(int(msg.custom_mode)) else M.MAV_RESULT_FAILED
        if self.firmware.acks_set_mode_message:  # 4.5 acks SET_MODE as command 11; 4.7 does not
            self._ack(link, msg, M.MAVLINK_MSG_ID_SET_MODE, result)

    def _on_set_position_target_local_ned(self, link: Link, msg: Any, now: float) -> None:
        if msg.target_system != self.sysid or self.mode != MODE_NUMBERS["GUIDED"]:
            self.counters["setpoints_ignored"] += 1
            return
        mask, frame = msg.type_mask, msg.coordinate_frame
        pos_ok, vel_ok, acc_ok = not mask & _POS_IGNORE, not mask & _VEL_IGNORE, not mask & _ACC_IGNORE
        if frame not in _FRAMES or acc_ok or not (pos_ok or vel_ok):
            self.counters["setpoints_ignored"] += 1
            return
        s = self.state
        body = frame in (M.MAV_FRAME_BODY_NED, M.MAV_FRAME_BODY_OFFSET_NED, M.MAV_FRAME_BODY_FRD)
        c, sn = (math.cos(s.yaw_rad), math.sin(s.yaw_rad)) if body else (1.0, 0.0)
        g = GuidedTarget(yaw_rad=self.guided.yaw_rad, yaw_rate_rad_s=self.guided.yaw_rate_rad_s,
                         yaw_slew_rad_s=self.guided.yaw_slew_rad_s, last_update_s=now)
        if pos_ok:
            n, e = msg.x * c - msg.y * sn, msg.x * sn + msg.y * c
            if frame != M.MAV_FRAME_LOCAL_NED:
                n, e, d = n + s.north_m, e + s.east_m, msg.z + s.depth_m
            else:
                d = msg.z
            g.position_ned, g.position_z_set = (n, e, d), True
        if vel_ok:
            g.velocity_ned = (msg.vx * c - msg.vy * sn, msg.vx * sn + msg.vy * c, msg.vz)
            g.velocity_z_set = True
        if not mask & _YAW_IGNORE:  # relative only in BODY_OFFSET_NED (ArduSub); a yaw rate is then its speed
            relative = frame == M.MAV_FRAME_BODY_OFFSET_NED
            g.yaw_rad, g.yaw_rate_rad_s = wrap_pi(msg.yaw + (s.yaw_rad if relative else 0.0)), None
            g.yaw_slew_rad_s = None if mask & _YAW_RATE_IGNORE or msg.yaw_rate == 0 else min(
                msg.yaw_rate, AUTO_YAW_SLEW_RAD_S)  # as ArduSub: a negative one turns away from the heading
        elif not mask & _YAW_RATE_IGNORE:
            g.yaw_rate_rad_s = msg.yaw_rate
        self.guided = g
        self._event("setpoint", (frame, mask))

    def _on_file_transfer_protocol(self, link: Link, msg: Any, now: float) -> None:
        if not self._for_me(msg.target_system):
            return
        sender = (msg.get_srcSystem(), msg.get_srcComponent())
        for payload in self.ftp.handle(sender, bytes(msg.payload)):
            link.send(M.MAVLink_file_transfer_protocol_message(0, sender[0], sender[1], list(payload)))

    def _param_value(self, name: str) -> Any:
        names = sorted(self.ap_params)
        return M.MAVLink_param_value_message(name.encode(), float(self.ap_params[name]),
                                             M.MAV_PARAM_TYPE_REAL32, len(names), names.index(name))

    def _on_param_request_read(self, link: Link, msg: Any, now: float) -> None:
        if not self._for_me(msg.target_system):
            return
        names = sorted(self.ap_params)
        name = msg.param_id if isinstance(msg.param_id, str) else msg.param_id.decode(errors="replace")
        name = name.rstrip("\x00")
        if msg.param_index >= 0:
            name = names[msg.param_index] if msg.param_index < len(names) else ""
        if name in self.ap_params:  # unknown names get no reply (as FS_GCS_TIMEOUT on 4.5)
            link.send(self._param_value(name))

    def _on_param_request_list(self, link: Link, msg: Any, now: float) -> None:
        if self._for_me(msg.target_system):
            for name in sorted(self.ap_params):
                link.send(self._param_value(name))

    def _on_param_set(self, link: Link, msg: Any, now: float) -> None:
        if not self._for_me(msg.target_system):
            return
        name = msg.param_id if isinstance(msg.param_id, str) else msg.param_id.decode(errors="replace")
        name = name.rstrip("\x00")
        if name not in self.ap_params or name == self.firmware.this_mav_param or not math.isfinite(msg.param_value):
            return
        lo, hi = _PARAM_RANGES.get(name, (-math.inf, math.inf))
        self.ap_params[name] = min(hi, max(lo, float(msg.param_value)))
        self._event("param", (name, self.ap_params[name]))
        self.endpoint.broadcast(self._param_value(name))

    def _on_request_data_stream(self, link: Link, msg: Any, now: float) -> None:
        if not self._for_me(msg.target_system):
            return
        ids = ([i for grp in _STREAM_GROUPS.values() for i in grp] if msg.req_stream_id == 0
               else _STREAM_GROUPS.get(msg.req_stream_id, []))
        for i in ids:
            rate = msg.req_message_rate
            link.intervals_s[i] = (1.0 / rate) if (msg.start_stop and rate > 0) else None
            link.next_due_s.pop(i, None)

    def _on_setup_signing(self, link: Link, msg: Any, now: float) -> None:
        if self.armed or not self._for_me(msg.target_system):
            return  # refused while armed
        key = bytes(msg.secret_key)
        self.endpoint.set_signing_key(key if any(key) else None)
        self._event("signing", any(key))

    def _set_interval(self, link: Link, msg_id: int, interval_us: float) -> int:
        if msg_id not in DEFAULT_INTERVALS_S:
            return M.MAV_RESULT_DENIED
        if interval_us < 0:
            link.intervals_s[msg_id] = None
        elif interval_us == 0:
            link.intervals_s[msg_id] = DEFAULT_INTERVALS_S[msg_id]
        else:
            link.intervals_s[msg_id] = interval_us / 1e6
        link.next_due_s.pop(msg_id, None)
        return M.MAV_RESULT_ACCEPTED

    # ----------------------------------------------------------------- telemetry
    def _send_telemetry(self, now: float) -> None:
        for link in self.endpoint.links:
            if link.kind == "udp" and link.udp_peer is None:
                continue
            for msg_id, interval in link.intervals_s.items():
                if interval is None:
                    continue
                due = link.next_due_s.get(msg_id, now)
                if now + 1e-9 >= due:
                    self._send_one(link, msg_id, now)
                    nxt = due + interval
                    link.next_due_s[msg_id] = nxt if nxt > now else now + interval

    def _send_one(self, link: Link, msg_id: int, now: float) -> bool:
        msg = self._telemetry(msg_id, now)
        if msg is None:
            return False
        link.send(msg)
        return True

    def _telemetry(self, msg_id: int, now: float) -> Any | None:
        s = self.state
        t_ms = int(round((now - self._boot_t0) * 1000)) & 0xFFFFFFFF
        heading_cd = int(round(math.degrees(s.yaw_rad) * 100)) % 36000
        if msg_id == M.MAVLINK_MSG_ID_HEARTBEAT:
            base = _BASE_MODE | (M.MAV_MODE_FLAG_SAFETY_ARMED if self.armed else 0)
            if self.mode == MODE_NUMBERS["GUIDED"]:
                base |= M.MAV_MODE_FLAG_GUIDED_ENABLED
            return M.MAVLink_heartbeat_message(M.MAV_TYPE_SUBMARINE, M.MAV_AUTOPILOT_ARDUPILOTMEGA, base,
                                               self.mode, self._system_status(now), 3)
        if msg_id == M.MAVLINK_MSG_ID_SYS_STATUS:
            present, enabled, health = sys_status_bits(self.mode, self.has_position)  # ArduSub's bits: no "fence breach"
            return M.MAVLink_sys_status_message(present, enabled, health, 100, 16000, 100, 90, 0, 0, 0, 0, 0, 0)
        if msg_id == M.MAVLINK_MSG_ID_ATTITUDE:
            return M.MAVLink_attitude_message(t_ms, 0.0, 0.0, s.yaw_rad, 0.0, 0.0, s.r_rad_s)
        if msg_id == M.MAVLINK_MSG_ID_GLOBAL_POSITION_INT:
            lat = lon = 0
            vn = ve = 0.0
            if self.has_position:
                lat_deg = self.home[0] + math.degrees(s.north_m / _EARTH_RADIUS_M)
                lon_deg = self.home[1] + math.degrees(s.east_m / (_EARTH_RADIUS_M * math.cos(math.radians(self.home[0]))))
                lat, lon, vn, ve = int(round(lat_deg * 1e7)), int(round(lon_deg * 1e7)), s.vn_m_s, s.ve_m_s
            alt_mm = int(round(-s.depth_m * 1000))
            return M.MAVLink_global_position_int_message(t_ms, lat, lon, alt_mm, alt_mm, int(round(vn * 100)),
                                                         int(round(ve * 100)), int(round(s.w_m_s * 100)), heading_cd)
        if msg_id == M.MAVLINK_MSG_ID_LOCAL_POSITION_NED:
            if not self.has_position:
                return None  # sent only once a horizontal position exists
            return M.MAVLink_local_position_ned_message(t_ms, s.north_m, s.east_m, s.depth_m, s.vn_m_s, s.ve_m_s, s.w_m_s)
        if msg_id == M.MAVLINK_MSG_ID_VFR_HUD:
            speed = math.hypot(s.u_m_s, s.v_m_s)
            return M.MAVLink_vfr_hud_message(speed, speed, heading_cd // 100, 0, -s.depth_m, -s.w_m_s)
        if msg_id == M.MAVLINK_MSG_ID_RC_CHANNELS:
            p = self.pilot
            ch = [1500, 1500, p.throttle, p.yaw, p.forward, p.lateral] + [1500] * 2 + [0] * 10
            return M.MAVLink_rc_channels_message(t_ms, 8, *ch, 255)
        if msg_id == M.MAVLINK_MSG_ID_SCALED_PRESSURE2:
            press_hpa = 1013.25 + s.depth_m * 1025.0 * 9.80665 / 100.0
            return M.MAVLink_scaled_pressure2_message(t_ms, press_hpa, 0.0, 1500)
        if msg_id == M.MAVLINK_MSG_ID_SYSTEM_TIME:
            return M.MAVLink_system_time_message(0, t_ms)
        if msg_id == M.MAVLINK_MSG_ID_AUTOPILOT_VERSION:
            caps = (M.MAV_PROTOCOL_CAPABILITY_MAVLINK2 | M.MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_LOCAL_NED
                    | M.MAV_PROTOCOL_CAPABILITY_COMMAND_INT | M.MAV_PROTOCOL_CAPABILITY_PARAM_FLOAT)
            return M.MAVLink_autopilot_version_message(caps, 0x04050000, 0, 0, 0, [0] * 8, [0] * 8, [0] * 8,
                                                       0, 0, self.sysid, [0] * 18)
        return None
