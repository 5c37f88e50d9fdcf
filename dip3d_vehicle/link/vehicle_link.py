"""The controller's MAVLink link to an ArduSub autopilot: single-threaded, tick-driven.

The mission loop calls, at any rate it likes::

    link = VehicleLink(params, clock); link.open()
    while running:
        link.poll()                                   # drain incoming, update state
        link.tick(command, perception_fresh=...)      # gate, then send at the configured rates
    link.close()                                      # neutral / zero, then close

Timing comes only from the injected Clock, so a simulator can run it faster than real time.

Identity: our own HEARTBEAT (1 Hz) from ``link.system_id`` / ``link.component_id`` (191, onboard
computer), type ONBOARD_CONTROLLER, autopilot INVALID. In ``manual_control`` mode, and only
there, MANUAL_CONTROL goes out with the autopilot's SYSID_MYGCS as system id, because ArduSub drops
pilot input from any other system; nothing else is ever sent with that id (see ``open()``'s
warning), and not even MANUAL_CONTROL while the ground station is lost: from ``link.gcs_timeout_s``
of GCS silence until a GCS HEARTBEAT is heard again, no message carries its id (not the stop
stream, not ``close()``, not after a reconnect), because ArduSub counts any MANUAL_CONTROL from that
id as ground-station contact and would clear its own GCS failsafe. So that the neutral sticks still
reach the autopilot, the link already disengages ("ground station quiet", a hold) when the GCS
HEARTBEAT is overdue by ``gcs_timeout_s - stop_zero_s`` (at least half the timeout): the stop
stream ends by the time the GCS is declared lost.

Liveness: ArduSub's HEARTBEAT is 1 Hz, too slow for "stop within 1 s of losing the autopilot".
The link asks for ATTITUDE at ``link.rate.attitude_hz`` (10 Hz) with SET_MESSAGE_INTERVAL and
counts ANY message from the configured autopilot as a sign of life; the autopilot is lost after
``link.autopilot_timeout_s`` (0.6 s) of silence. With a tick period T the last motion command then
goes out at most 0.6 s + T after the last message heard. The controller engages only after the
autopilot has been heard for 1 s without such a gap, so an autopilot that sends nothing but its
1 Hz HEARTBEAT (interval request refused or overridden) never gets motion commands at all.

Stopping: on every disengage the link streams the stop value (manual_control: centred sticks,
x = y = r = 0, z = 500; guided_velocity: zero velocity AND zero yaw rate, since ArduSub keeps a
GUIDED yaw rate forever) at the setpoint rate for ``link.stop_zero_s`` (1 s), the first one on
the same tick, then falls silent. Neutral sticks are needed because ArduSub keeps the last
MANUAL_CONTROL until its pilot-input failsafe (``FS_PILOT_TIMEOUT``, 3 s; 1 s while the controller holds
the sticks, ``link.max_command_hold_s``: ``command_hold.py``); silence afterwards hands the sticks back to the
pilot's own joystick (which also sends MANUAL_CONTROL from SYSID_MYGCS and would otherwise fight
ours) and lets the autopilot's own failsafes act. The link never sends a non-neutral command while
disengaged. See ``engage.py`` for when it engages and the re-engage (enable latch) policy. In guided_velocity a
turn goes out as a heading ahead of the last ATTITUDE.yaw (``guided_turns.py``), so after a link loss it
ends within about ``link.max_command_hold_s`` of turning; the velocity itself ends after the firmware's fixed 3 s.

Perception: a stale tick (the caller's flag, or the stamp older than ``link.perception_timeout_s``)
disengages on that tick. To engage the first time after the operator's enable, perception must have
been fresh without a break for 0.4 s ("perception starting" until then), so a just-starting pipeline
holds instead of flipping engaged / disengaged (seen at the start of ``run`` on 2 cores). After a
stale hold it resumes on the first fresh tick. While perception alone holds a controller that engaged on
this enable, the stop value streams on (not only for ``stop_zero_s``): silence would let the pilot-input
failsafe disarm a vehicle that only waits for its camera (issue 11 session 61).
"""

from __future__ import annotations

import logging
import math
from dataclasses import replace
from typing import Any, Mapping

from pymavlink import mavutil

from ..clock import Clock
from ..servo.command import VelocityCommand
from .autopilot_requests import AutopilotRequests, gcs_sysid_param
from .command_hold import CommandHold
from .connection import gcs_encoder, mavlink2, open_connection, url_kind
from .engage import PERCEPTION_HOLDS, EngageInputs, decide
from .guided_turns import GuidedTurns
from .link_config import ENGAGE_MODE_AUTO, LinkConfig
from .setpoints import NEUTRAL_STICKS, ZERO_GUIDED, GuidedVelocity, ManualControl, StickDither
from .signing import LinkSigning, load_key
from .state import AutopilotState, GcsState, LinkStats, mode_name
from .tcp_reconnect import TcpReconnect

__all__ = ["LinkConfig", "VehicleLink", "MAV_CMD_USER_1", "ENGAGE_MODE_AUTO"]

log = logging.getLogger("dip3d_vehicle.link")

MAV_CMD_USER_1 = 31010
"""COMMAND_LONG the operator sends to (link.system_id, link.component_id): param1 1 enable, 0 disable."""
_STOP_REPEAT_ON_CLOSE = 3
_MAX_MESSAGES_PER_POLL = 2000
_STEADY_S = 1.0  # engage only after the autopilot was heard without a gap for this long
_PERCEPTION_SETTLE_S = 0.4  # first engage (per enable) only after perception was fresh without a break this long


class VehicleLink:
    """MAVLink link to the autopilot: state tracking, engage gating and fixed-rate streaming.

    Args:
        params: a Params (or mapping of ``link.*`` keys; missing keys take the schema default).
        clock: the time source for every timeout and rate (WallClock onboard, SimClock in simulation).
        recorder: an object with ``mavlink_sent(msg)`` and ``mavlink_received(msg)`` (the run's
            ``mav.tlog``, ``dip3d_vehicle.record.recorder.RunRecorder``), called for every message, or None.

    Attributes:
        config: the resolved LinkConfig.
        autopilot: the configured autopilot as last heard.
        gcs: the ground station as last heard.
        stats: counters (ignored, rejected, sent by type).
        events: the story of the run, e.g. "t=12.30 disengaged: mode changed ALT_HOLD -> MANUAL".
        disengage_reason: why the controller last disengaged ("" before the first disengage).
        not_engaged_reason: why it is not engaged now ("" when engaged).
    """

    def __init__(self, params: Mapping[str, Any] | LinkConfig, clock: Clock, recorder: Any = None) -> None:
        self.config = params if isinstance(params, LinkConfig) else LinkConfig.from_params(params)
        self.clock = clock
        self.recorder = recorder  # mavlink_sent(msg) / mavlink_received(msg): the run's tlog (record/)
        c = self.config
        self.autopilot = AutopilotState(sysid=c.target_system, compid=c.target_component)
        self.gcs = GcsState(sysid=c.gcs_system_id)
        self.stats = LinkStats()
        self.events: list[str] = []
        self.disengage_reason = ""
        self.not_engaged_reason = "not opened"
        self._conn: Any = None
        self._gcs_mav: Any = None
        self._signing = LinkSigning()
        self._enabled = False
        self._engaged = False
        self._prev_inputs: EngageInputs | None = None
        self._stop_until_s: float | None = None
        self._next_setpoint_s = 0.0
        self._next_heartbeat_s = 0.0
        self._requests = AutopilotRequests(c, self._send, self._event, self._warn)
        self._hold = CommandHold(c, self._send, self._event, self._warn)  # the autopilot's FS_PILOT_TIMEOUT
        self._turns = GuidedTurns(c, self.stats, self._warn)  # GUIDED turns as headings: they end by themselves
        self._sent_setpoints = False
        self._tcp: TcpReconnect | None = None  # a tcp: link reopens itself from tick()
        self._fresh_since: float | None = None
        self._engaged_since_enable = False  # the perception settle applies until the first engagement
        self.firmware = "4.5"  # which stick tables: "4.7" once the autopilot answers MAV_GCS_SYSID
        self._dither = StickDither(self.firmware)  # speeds below the sticks' dead zones as pulses

    # ------------------------------------------------------------------ lifecycle

    @property
    def engaged(self) -> bool:
        """True while the controller's commands are being sent to the thrusters."""
        return self._engaged

    @property
    def operator_enabled(self) -> bool:
        """The operator's enable latch (cleared by the pilot taking the vehicle back, or a loss)."""
        return self._enabled

    def open(self) -> None:
        """Connect by ``link.url``, set up signing, announce ourselves; non-blocking.

        The autopilot is asked for SYSID_MYGCS and its message intervals as soon as it is heard
        (a ``udpin:`` link cannot send before a peer has spoken), and again whenever it reappears
        or reboots.

        Raises:
            LinkError: the URL is malformed or cannot be opened, or the signing key file is bad.
        """
        c = self.config
        if c.signing_key_file:
            self._signing.key = load_key(c.signing_key_file)
        self._conn = open_connection(c.url, c.system_id, c.component_id, c.baud)
        if url_kind(c.url) == "tcp":
            self._tcp = TcpReconnect(c, self.clock, self._signing, self._event)
            self._tcp.watch(self._conn)
        self._signing.setup(self._conn)
        now = self.clock.now()
        self._next_heartbeat_s = now + 1.0 / c.heartbeat_rate_hz
        self._next_setpoint_s = now
        self._enabled = c.auto_enable
        self.not_engaged_reason = "autopilot not heard"
        self._event(f"opened {c.url} as system {c.system_id} component {c.component_id}, output "
                    f"{c.output_mode} in {c.engage_mode}, signing {'on' if self._signing.key else 'off'}"
                    + (", enabled at start (link.auto_enable)" if c.auto_enable else ""))
        if c.output_mode == "manual_control":
            self._warn(
                "manual_control: MANUAL_CONTROL will be sent with the ground station's system id "
                f"(the autopilot's SYSID_MYGCS; {c.gcs_system_id} until it has been read), because ArduSub "
                "drops pilot input from any other system. ArduSub counts it as ground-station contact, so "
                "this controller watches the ground station's HEARTBEAT itself and stops sending "
                f"MANUAL_CONTROL {self._gcs_quiet_s():g} s after its last HEARTBEAT (neutral until "
                f"{c.gcs_timeout_s:g} s, then nothing with its id until it is heard again), leaving the "
                "autopilot's GCS failsafe to act. Nothing else (no HEARTBEAT) is ever sent with that id; "
                f"this controller's own id is {c.system_id}/{c.component_id}.")
        self._send_heartbeat()

    def close(self) -> None:
        """Send the stop value (neutral sticks / zero velocity and yaw rate) a few times, then close."""
        if self._conn is None:
            return
        if self._engaged or self._stop_until_s is not None or self._sent_setpoints:
            for _ in range(_STOP_REPEAT_ON_CLOSE):
                self._send_stop()
        if self._engaged:
            self._set_engaged(False, "link closed")
        if self.stats.turns_withheld:
            self._event(f"{self.stats.turns_withheld} GUIDED turns withheld: no ATTITUDE heading from the autopilot")
        if self.stats.gcs_id_withheld:
            self._event(f"{self.stats.gcs_id_withheld} MANUAL_CONTROL withheld: the ground station was lost, "
                        f"its system id is used only while it is heard")
        self._hold.restore()
        self._event("closed")
        try:
            self._conn.close()
        except OSError:
            pass
        self._conn = None

    # ------------------------------------------------------------------ operator

    def enable(self, source: str = "operator") -> None:
        """Give the operator's enable (the controller engages when every other condition holds)."""
        if not self._enabled:
            self._event(f"enabled by {source}")
        self._enabled = True

    def disable(self, source: str = "operator") -> None:
        """Withdraw the operator's enable; the controller disengages on the next tick."""
        if self._enabled:
            self._event(f"disabled by {source}")
        self._enabled = False

    # ------------------------------------------------------------------ incoming

    def poll(self) -> int:
        """Drain every waiting message without blocking and update the state.

        Returns:
            The number of messages accepted from the wire.
        """
        if self._conn is None:
            return 0
        now = self.clock.now()
        count = 0
        for _ in range(_MAX_MESSAGES_PER_POLL):
            try:
                msg = self._conn.recv_msg()
            except (OSError, ValueError) as exc:
                self._event(f"receive error on {self.config.url}: {exc}")
                break
            if msg is None:
                break
            if self.recorder is not None:
                self.recorder.mavlink_received(msg)
            if self._handle(msg, now):
                count += 1
        self._signing.count(self._conn, self.stats)
        return count

    def _handle(self, msg: Any, now: float) -> bool:
        """Dispatch one received message; return True when it was accepted."""
        kind = msg.get_type()
        if kind == "BAD_DATA":
            if "signature" not in str(getattr(msg, "reason", "")).lower():
                self.stats.bad_data += 1
            return False
        self.stats.received += 1
        src = (msg.get_srcSystem(), msg.get_srcComponent())
        from_autopilot = src == (self.autopilot.sysid, self.autopilot.compid)
        if kind == "COMMAND_LONG" and msg.target_system == self.config.system_id \
                and msg.target_component == self.config.component_id:
            self._on_command(msg, src)
        if from_autopilot:
            self._on_autopilot_message(msg, kind, now)
        elif kind == "HEARTBEAT" and src[0] == self.gcs.sysid and msg.type == mavutil.mavlink.MAV_TYPE_GCS:
            self.gcs = replace(self.gcs, last_heartbeat_s=now)
        elif kind == "COMMAND_LONG":
            pass
        elif kind == "HEARTBEAT":
            self.stats.ignored_heartbeats += 1
        elif src[0] != self.gcs.sysid:
            self.stats.ignored_from_others += 1
        return True

    def _on_autopilot_message(self, msg: Any, kind: str, now: float) -> None:
        """Update liveness and state from a message of the configured autopilot."""
        self.autopilot, appeared = self.autopilot.heard(now, getattr(msg, "time_boot_ms", None),
                                                        self.config.autopilot_timeout_s)
        if appeared:
            self._on_autopilot_appeared(appeared)
        if kind == "HEARTBEAT":
            self._on_autopilot_heartbeat(msg, now)
        elif kind == "PARAM_VALUE":
            self._on_param_value(msg)
        elif kind == "ATTITUDE" and math.isfinite(msg.yaw):
            self.autopilot = replace(self.autopilot, yaw_rad=float(msg.yaw), yaw_s=now)
        elif kind == "COMMAND_ACK" and msg.command == mavutil.mavlink.MAV_CMD_SET_MESSAGE_INTERVAL:
            self._requests.on_interval_ack(msg)

    def _on_autopilot_heartbeat(self, msg: Any, now: float) -> None:
        """Take mode, armed state and status from the autopilot's HEARTBEAT."""
        ap = self.autopilot
        armed = bool(msg.base_mode & mavutil.mavlink.MAV_MODE_FLAG_SAFETY_ARMED)
        mode = mode_name(msg.custom_mode)
        if ap.last_heartbeat_s is not None and mode != ap.mode:
            self._event(f"autopilot mode {ap.mode} -> {mode}")
        if ap.last_heartbeat_s is None or armed != ap.armed:
            self._event(f"autopilot {'armed' if armed else 'disarmed'} in {mode}")
        self.autopilot = replace(ap, last_heartbeat_s=now, mode_number=int(msg.custom_mode), mode=mode,
                                 armed=armed, system_status=int(msg.system_status))

    def _on_autopilot_appeared(self, why: str) -> None:
        """(Re)request message intervals and SYSID_MYGCS after first contact, a gap or a reboot."""
        self.autopilot = replace(self.autopilot, boots=self.autopilot.boots + 1)
        self._event(why + ": requesting message intervals and SYSID_MYGCS")
        self._requests.start(self.clock.now())
        self._hold.start(self.clock.now())

    def _on_param_value(self, msg: Any) -> None:
        """Take the ground station's system id from SYSID_MYGCS / MAV_GCS_SYSID; the pilot-input failsafe's
        parameters go to ``command_hold``."""
        if self._hold.on_param_value(msg):
            return
        param = gcs_sysid_param(msg)
        if param is None:
            return
        name, value = param
        first = not self.gcs.sysid_from_autopilot
        if value != self.gcs.sysid or first:
            self._event(f"{name} = {value} read from the autopilot (ground station system id)")
        if value != self.gcs.sysid and self._gcs_mav is not None:
            self._gcs_mav = None
        self.gcs = replace(self.gcs, sysid=value, sysid_from_autopilot=True)
        firmware = "4.7" if name == "MAV_GCS_SYSID" else "4.5"
        if firmware != self.firmware:
            self._event(f"{name} answered: ArduSub {firmware} stick tables")
            self.firmware = firmware
            self._dither = StickDither(firmware)
        self._requests.sysid_answered()
        if value == self.config.system_id and self.config.output_mode == "manual_control":
            self._warn(f"{name} = {value} is this controller's own system id (link.system_id): MANUAL_CONTROL "
                       f"would have to come from it and ArduSub would take our HEARTBEAT for the ground "
                       f"station's, hiding a lost ground station; manual_control refuses to engage. Give the "
                       f"controller another link.system_id or use guided_velocity.")

    def _on_command(self, msg: Any, src: tuple[int, int]) -> None:
        """Handle a COMMAND_LONG addressed to us: MAV_CMD_USER_1 enables/disables (GCS only)."""
        if msg.command != MAV_CMD_USER_1:
            self._send_ack(msg.command, mavutil.mavlink.MAV_RESULT_UNSUPPORTED, src)
            return
        if src[0] != self.gcs.sysid:
            self.stats.operator_commands_denied += 1
            self._event(f"operator command from system {src[0]} denied (only the ground station "
                        f"{self.gcs.sysid} may enable)")
            self._send_ack(msg.command, mavutil.mavlink.MAV_RESULT_DENIED, src)
            return
        if msg.param1 >= 0.5:
            self.enable(f"ground station {src[0]}/{src[1]}")
        else:
            self.disable(f"ground station {src[0]}/{src[1]}")
        self._send_ack(msg.command, mavutil.mavlink.MAV_RESULT_ACCEPTED, src)

    # ------------------------------------------------------------------ tick

    def tick(self, command: VelocityCommand | None, perception_fresh: bool,
             perception_stamp_s: float | None = None) -> bool:
        """Gate, then send whatever is due at the configured rates. Call poll() first.

        At most one setpoint goes out per call, so call this at least at ``link.setpoint_rate_hz``
        (e.g. 50 Hz) even when perception is slower: pass the servo's latest command each time.

        Args:
            command: the servo's command, or None for "no motion wanted" (neutral).
            perception_fresh: the caller's own verdict on perception.
            perception_stamp_s: the time (this link's clock) of the perception result behind
                ``command``; when given it is also stale after ``link.perception_timeout_s``.

        Returns:
            True when engaged after this tick.
        """
        if self._conn is None:
            return False
        now = self.clock.now()
        conn = self._tcp.reconnected(now, self._conn) if self._tcp is not None else None
        if conn is not None:
            self._conn, self._gcs_mav = conn, None
        fresh = perception_fresh and (perception_stamp_s is None
                                      or now - perception_stamp_s <= self.config.perception_timeout_s)
        if not fresh:
            self._fresh_since = None
        elif self._fresh_since is None:
            self._fresh_since = now
        inputs = self._inputs(now, fresh)
        decision = decide(self._prev_inputs, inputs)
        self._prev_inputs = inputs
        if decision.latched and self._enabled:
            self._event(f"operator enable cleared: {decision.reason}")
        if decision.latched and not self._engaged:
            self.disengage_reason = decision.reason  # e.g. "ground station quiet" became "... lost"
        self._enabled = decision.operator_enabled
        if not self._enabled:
            self._engaged_since_enable = False
        self.not_engaged_reason = decision.reason
        if decision.engaged:
            self._engaged_since_enable = True
        if decision.engaged != self._engaged:
            self._set_engaged(decision.engaged, decision.reason)
            self._next_setpoint_s = now  # act on this tick: first command, or first stop
        if now >= self._next_heartbeat_s:
            self._send_heartbeat()
            self._next_heartbeat_s = _next_time(self._next_heartbeat_s, 1.0 / self.config.heartbeat_rate_hz, now)
        if now >= self._next_setpoint_s:
            self._send_setpoint(now, command)
            self._next_setpoint_s = _next_time(self._next_setpoint_s, 1.0 / self.config.setpoint_rate_hz, now)
        self._requests.retry(now, self.gcs.sysid_from_autopilot)
        self._hold.update(now, self._engaged or self._perception_hold())
        return self._engaged

    def _inputs(self, now: float, perception_fresh: bool) -> EngageInputs:
        """Collect this tick's gate inputs."""
        c = self.config
        return EngageInputs(
            autopilot_alive=self.autopilot.alive(now, c.autopilot_timeout_s), armed=self.autopilot.armed,
            mode=self.autopilot.mode, engage_mode=c.engage_mode, operator_enabled=self._enabled,
            gcs_alive=self.gcs.alive(now, c.gcs_timeout_s), gcs_required=c.require_gcs,
            perception_fresh=perception_fresh, output_problem=self.output_problem(),
            autopilot_steady=self.autopilot.steady(now, c.autopilot_timeout_s, _STEADY_S),
            gcs_quiet=self.gcs.seen and not self.gcs.alive(now, self._gcs_quiet_s()),
            perception_steady=self._engaged_since_enable or (
                self._fresh_since is not None and now - self._fresh_since >= _PERCEPTION_SETTLE_S - 1e-9))

    def _gcs_quiet_s(self) -> float:
        """GCS silence after which the link holds, so the stop stream ends before the GCS is lost."""
        c = self.config
        return max(c.gcs_timeout_s - c.stop_zero_s, 0.5 * c.gcs_timeout_s)

    def gcs_id_allowed(self, now: float) -> bool:
        """Return True when MANUAL_CONTROL may carry the ground station's system id now.

        Only while the ground station is heard (its HEARTBEAT within ``link.gcs_timeout_s``); with
        ``link.require_gcs`` off also before any ground station was ever heard.
        """
        if self.gcs.seen:
            return self.gcs.alive(now, self.config.gcs_timeout_s)
        return not self.config.require_gcs

    def output_problem(self) -> str:
        """Return why the output path cannot be used now ("" when it can)."""
        if self.config.output_mode != "manual_control":
            return ""
        if not self.gcs.sysid_from_autopilot:
            if self._requests.sysid_given_up:
                return ("SYSID_MYGCS could not be read from the autopilot; ArduSub accepts MANUAL_CONTROL "
                        "only from that system id")
            return "SYSID_MYGCS not read yet"
        if self.gcs.sysid == self.config.system_id:
            return (f"SYSID_MYGCS = {self.gcs.sysid} is this controller's own system id; manual_control "
                    f"would hide a lost ground station")
        return ""

    def _set_engaged(self, engaged: bool, reason: str) -> None:
        """Record an engage/disengage transition and start the stop stream on disengage."""
        self._engaged = engaged
        self._dither.reset()
        now = self.clock.now()
        if engaged:
            self._stop_until_s = None
            self._event(f"engaged in {self.autopilot.mode} ({self.config.output_mode})")
        else:
            self.disengage_reason = reason
            self._stop_until_s = now + self.config.stop_zero_s
            self._event(f"disengaged: {reason}")

    def _send_setpoint(self, now: float, command: VelocityCommand | None) -> None:
        """Send the command while engaged, the stop value during the stop window and a perception hold, else
        nothing."""
        if self._engaged:
            cmd = command if command is not None else VelocityCommand()
            if self.config.output_mode == "manual_control":
                self._send_manual_control(self._dither.sticks(cmd))
            else:
                heading = self.autopilot.heading_rad(now, self.config.autopilot_timeout_s)
                self._send_guided(self._turns.setpoint(now, cmd, heading))
            return
        self._dither.reset()
        if self._perception_hold():
            self._send_stop()
        elif self._stop_until_s is not None:
            if now <= self._stop_until_s:
                self._send_stop()
            else:
                self._stop_until_s = None

    def _perception_hold(self) -> bool:
        """True while only perception (stale, or settling again) holds a controller that engaged on this enable: the
        stop value streams on, so ArduSub's pilot-input failsafe (``command_hold``) does not disarm a vehicle that
        only waits for its camera."""
        return self._enabled and self._engaged_since_enable and self.not_engaged_reason in PERCEPTION_HOLDS

    def _send_stop(self) -> None:
        """Send one stop value: centred sticks (manual_control) or zero velocity + yaw rate (guided)."""
        if self.config.output_mode == "manual_control":
            if self.output_problem() == "" or self._sent_setpoints:
                self._send_manual_control(NEUTRAL_STICKS)
        else:
            self._send_guided(ZERO_GUIDED)

    # ------------------------------------------------------------------ sending

    def send_message(self, msg: Any) -> None:
        """Send a non-motion message (e.g. STATUSTEXT, DO_SET_SERVO) with the controller's own identity.

        Motion commands go only through ``tick`` (engage gating); anything else the behaviour
        layer wants to say goes here: own system/component id, counted in ``stats``, never raises.
        """
        name = msg.get_type()
        if name in ("MANUAL_CONTROL", "SET_POSITION_TARGET_LOCAL_NED", "RC_CHANNELS_OVERRIDE"):
            raise ValueError(f"{name} is a motion command: send it through tick()")
        self._send(name, msg)

    def _send(self, name: str, msg: Any, encoder: Any = None) -> None:
        """Send one message with our identity (or ``encoder``'s), counting it; never raises on I/O."""
        if self._conn is None:
            return
        try:
            (encoder or self._conn.mav).send(msg)
        except OSError as exc:
            self._event(f"send error on {self.config.url}: {exc}")
            return
        self.stats.count_sent(name)
        if self.recorder is not None:
            self.recorder.mavlink_sent(msg)

    def _send_heartbeat(self) -> None:
        """Our own HEARTBEAT: onboard controller, no autopilot, active while engaged."""
        m = mavutil.mavlink
        status = m.MAV_STATE_ACTIVE if self._engaged else m.MAV_STATE_STANDBY
        self._send("HEARTBEAT", mavlink2.MAVLink_heartbeat_message(
            m.MAV_TYPE_ONBOARD_CONTROLLER, m.MAV_AUTOPILOT_INVALID, 0, 0, status, 3))

    def _send_manual_control(self, sticks: ManualControl) -> None:
        """MANUAL_CONTROL with the ground station's system id (ArduSub's rule); buttons always 0.

        Withheld (and counted) while the ground station is lost: see ``gcs_id_allowed``.
        """
        if self._conn is None:
            return
        if not self.gcs_id_allowed(self.clock.now()):
            self.stats.gcs_id_withheld += 1
            return
        if self._gcs_mav is None or self._gcs_mav.srcSystem != self.gcs.sysid:
            self._gcs_mav = gcs_encoder(self._conn, self.gcs.sysid, self.config.component_id)
        self._sent_setpoints = True
        self._send("MANUAL_CONTROL", mavlink2.MAVLink_manual_control_message(
            self.config.target_system, sticks.x, sticks.y, sticks.z, sticks.r, 0), self._gcs_mav)

    def _send_guided(self, sp: GuidedVelocity) -> None:
        """SET_POSITION_TARGET_LOCAL_NED: body-frame velocity + yaw rate (or heading + turn speed)."""
        c = self.config
        self._sent_setpoints = True
        self._send("SET_POSITION_TARGET_LOCAL_NED", mavlink2.MAVLink_set_position_target_local_ned_message(
            int(self.clock.now() * 1000) & 0xFFFFFFFF, c.target_system, c.target_component, sp.frame,
            sp.type_mask, 0.0, 0.0, 0.0, sp.vx_m_s, sp.vy_m_s, sp.vz_m_s, 0.0, 0.0, 0.0,
            0.0 if sp.yaw_rad is None else sp.yaw_rad, sp.yaw_rate_rad_s))

    def _send_ack(self, command: int, result: int, dest: tuple[int, int]) -> None:
        """COMMAND_ACK from our own identity to ``dest``."""
        self._send("COMMAND_ACK", mavlink2.MAVLink_command_ack_message(command, result, 0, 0, dest[0], dest[1]))

    # ------------------------------------------------------------------ story

    def _event(self, text: str) -> None:
        """Append ``text`` to the story of the run (with the clock time) and log it."""
        line = f"t={self.clock.now():.2f} {text}"
        self.events.append(line)
        log.info(line)

    def _warn(self, text: str) -> None:
        """An event that the operator must see: logged as a warning."""
        line = f"t={self.clock.now():.2f} WARNING {text}"
        self.events.append(line)
        log.warning(text)


def _next_time(scheduled_s: float, period_s: float, now_s: float) -> float:
    """Return the next send time on a fixed grid; resynchronise when the caller fell behind."""
    nxt = scheduled_s + period_s
    return nxt if nxt > now_s else now_s + period_s

