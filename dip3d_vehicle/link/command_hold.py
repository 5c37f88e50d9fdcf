"""How long the autopilot keeps acting on the controller's last MANUAL_CONTROL once the link goes quiet: ArduSub's
pilot-input failsafe, ``FS_PILOT_TIMEOUT`` (0.1-3 s, 3 s by default). The link reads it and, while the controller
holds the sticks (engaged, or streaming neutral through a perception hold), lowers it to ``link.max_command_hold_s``
(once its own stream has run ``STREAM_SETTLE_S``);
when the controller hands the sticks back, and at close, it puts the autopilot's own value back.

A cut link leaves ArduSub driving on the last sticks it received until that failsafe centres them ("Lost manual
control"; with ``FS_PILOT_INPUT`` 2, its default, it also disarms). ``RC_OVERRIDE_TIME`` does not end it on a vehicle
without an RC receiver: on the real firmware (ArduSub 4.7-dev SITL, ``tests/sitl/test_firmware_command_hold.py``,
``docs/issue11/session61/scripts/override_probe.py``) a forward stick stayed in force 2.97 s with
``RC_OVERRIDE_TIME`` 1 s and 0.96 s with ``FS_PILOT_TIMEOUT`` 1 s. Over 40 simulated link-cut missions with the 3 s
the vehicle ran on until the target was out of view at the operator's re-enable in 13 (12 past it), so the mission
could not resume, and one drifted to 0.12 m from the diver's body (issue 11 session 61). The controller streams
MANUAL_CONTROL at ``link.setpoint_rate_hz`` while it holds the sticks, so 1 s is 20 missed messages. Outside that the
pilot's own setting applies: a ground station that arms without a joystick stream keeps its 3 s to hand over.

Only for ``link.output_mode`` manual_control (GUIDED's velocity timeout, 3 s, is not a parameter). With
``FS_PILOT_INPUT`` 0 (failsafe off) a stale command stays until new input, which the controller can only warn about.
A value someone else sets while the controller runs is theirs: it is reported and left alone for the session. Each
hand-over is one parameter write on the autopilot; a controller that did not close cleanly leaves the shorter time.
"""

from __future__ import annotations

from typing import Any, Callable

from pymavlink import mavutil

from .autopilot_requests import param_name, param_read
from .connection import mavlink2
from .link_config import LinkConfig

__all__ = ["PARAM", "SWITCH", "STREAM_SETTLE_S", "CommandHold"]

PARAM = "FS_PILOT_TIMEOUT"
"""ArduSub's parameter: seconds without pilot input (MANUAL_CONTROL) before its pilot-input failsafe acts."""
SWITCH = "FS_PILOT_INPUT"
"""ArduSub's parameter: the pilot-input failsafe's action (0 off, 1 warn, 2 disarm; both centre the sticks)."""
STREAM_SETTLE_S = 0.5
"""The timeout is lowered only once the controller has held the sticks this long, s (10 MANUAL_CONTROL at 20 Hz):
the autopilot applies a new timeout at once against its last pilot input, so a lower one that arrives before the
controller's stream does ends a hand-over with "Lost manual control" (a disarm) whenever the pilot armed more than the
new timeout earlier without a joystick stream (issue 11 session 64: a lossy, reordering link put the PARAM_SET ahead
of the first MANUAL_CONTROL in 3 of 10 ``lossy_out_of_order`` missions, disarmed at the engage)."""
_RESTORE_REPEAT = 2  # PARAM_SET at close, sent twice (no answer is waited for)
_SAME_S = 1e-3


class CommandHold:
    """The autopilot's pilot-input timeout: read; ``link.max_command_hold_s`` while the controller holds the sticks,
    the autopilot's own value otherwise.

    Args:
        config: the link's LinkConfig (target ids, ``max_command_hold_s``, retry and give-up times).
        send: sends one message with the controller's own identity, ``send(type_name, msg)``.
        event: appends a line to the link's story of the run.
        warn: appends a warning the operator must see.

    Attributes:
        original_s: the autopilot's own value as first read (None until read), s.
        value_s: the latest value the autopilot reported, s.
    """

    def __init__(self, config: LinkConfig, send: Callable[[str, Any], None], event: Callable[[str], None],
                 warn: Callable[[str], None]) -> None:
        self.config = config
        self._send, self._event, self._warn = send, event, warn
        self.original_s: float | None = None
        self.value_s: float | None = None
        self._asked: set[float] = set()  # every value this session set
        self._others = False  # someone else set it: left alone
        self._switch: int | None = None  # FS_PILOT_INPUT as last read
        self._first_s: float | None = None
        self._last_s = -1e9
        self._given_up = False
        self._holding_since_s: float | None = None  # when the controller took the sticks (None: not holding)

    @property
    def applies(self) -> bool:
        """True for manual_control, the one output path whose stale commands this time governs."""
        return self.config.output_mode == "manual_control"

    def start(self, now: float) -> None:
        """Read the autopilot's values afresh (first contact, after a gap, after a reboot)."""
        if self.applies:
            self._first_s, self._given_up, self.value_s = now, False, None
            self._read(now)

    def on_param_value(self, msg: Any) -> bool:
        """Take a PARAM_VALUE; return True when it was the pilot-input timeout or switch (handled here)."""
        name = param_name(msg)
        if name not in (PARAM, SWITCH):
            return False
        if not self.applies:
            return True
        value = float(msg.param_value)
        if name == SWITCH:
            self._on_switch(int(round(value)))
        elif self.original_s is None:
            self.original_s = self.value_s = value
            self._event(f"{PARAM} = {value:g} s read from the autopilot: after a link loss it keeps the last "
                        f"MANUAL_CONTROL for {value:g} s")
            if self.config.max_command_hold_s <= 0 and value > 1.0:
                self._warn(f"{PARAM} = {value:g} s left as it is (link.max_command_hold_s 0): after a link loss the "
                           f"autopilot keeps the last MANUAL_CONTROL for {value:g} s")
        else:
            self._on_value(value)
        return True

    def _on_value(self, value: float) -> None:
        """A later report: one of ours confirmed, the autopilot's own value again, or someone else's setting."""
        known = [v for v in self._asked | {self.original_s} if abs(v - value) < _SAME_S]
        if known or self._others:
            if self.value_s is not None and abs(value - self.value_s) >= _SAME_S:
                self._event(f"{PARAM} = {value:g} s on the autopilot")
        else:
            self._others = True
            self._warn(f"{PARAM} = {value:g} s set by someone else: left as it is for this session")
        self.value_s = value

    def _on_switch(self, action: int) -> None:
        """Warn (once per value) when the pilot-input failsafe is off: nothing ends a stale command then."""
        if action == self._switch:
            return
        self._switch = action
        if action == 0:
            self._warn(f"{SWITCH} = 0: ArduSub's pilot-input failsafe is off, so after a link loss the last "
                       f"MANUAL_CONTROL stays in force until new input arrives (set {SWITCH} 1 or 2)")
        else:
            self._event(f"{SWITCH} = {action} read from the autopilot (pilot-input failsafe on)")

    def wanted_s(self, holding: bool) -> float | None:
        """The value the autopilot should have now (None: nothing to change): the limit while the controller holds
        the sticks and the autopilot's own value is longer, the autopilot's own value otherwise."""
        limit = self.config.max_command_hold_s
        if self.original_s is None or self._others or limit <= 0:
            return None
        return limit if holding and self.original_s > limit + _SAME_S else self.original_s

    def update(self, now: float, holding: bool) -> None:
        """Ask for the wanted value (``holding``: the controller holds the sticks; the limit once it has for
        ``STREAM_SETTLE_S``) until the autopilot reports it; re-read an unanswered read every ``link.param_retry_s``;
        warn once after ``param_give_up_s``."""
        if not self.applies:
            return
        if not holding:
            self._holding_since_s = None
        elif self._holding_since_s is None:
            self._holding_since_s = now
        if self.value_s is None:
            self._retry_read(now)
            return
        want = self.wanted_s(holding and now - self._holding_since_s >= STREAM_SETTLE_S - 1e-9)
        if want is None or abs(want - self.value_s) < _SAME_S or now - self._last_s < self.config.param_retry_s:
            return
        if want not in self._asked:
            self._event(f"{PARAM} to {want:g} s while the controller holds the sticks "
                        f"(link.max_command_hold_s; the autopilot's own {self.original_s:g} s otherwise)")
        self._asked.add(want)
        self._set(want)
        self._last_s = now

    def restore(self) -> None:
        """Put the autopilot's own value back if this session left another (at close; no answer awaited)."""
        want = self.wanted_s(False)
        if want is None or self.value_s is None or abs(want - self.value_s) < _SAME_S:
            return
        for _ in range(_RESTORE_REPEAT):
            self._set(want)
        self._event(f"{PARAM} put back to {want:g} s")

    def _retry_read(self, now: float) -> None:
        """Re-send an unanswered read; warn once when it stays unanswered."""
        c = self.config
        if self._first_s is not None and now - self._first_s > c.param_give_up_s and not self._given_up:
            self._given_up = True
            self._warn(f"{PARAM} could not be read in {c.param_give_up_s:g} s: after a link loss the autopilot "
                       f"keeps the last MANUAL_CONTROL for its own {PARAM} (ArduSub's default: 3 s) (still asking)")
        if self._first_s is not None and now - self._last_s >= c.param_retry_s:
            self._read(now)

    def _read(self, now: float) -> None:
        """PARAM_REQUEST_READ of the timeout and the failsafe's switch."""
        for name in (PARAM, SWITCH):
            self._send("PARAM_REQUEST_READ", param_read(self.config, name))
        self._last_s = now

    def _set(self, value_s: float) -> None:
        """PARAM_SET of the pilot-input timeout (REAL32)."""
        c = self.config
        self._send("PARAM_SET", mavlink2.MAVLink_param_set_message(
            c.target_system, c.target_component, PARAM.encode(), float(value_s),
            mavutil.mavlink.MAV_PARAM_TYPE_REAL32))
