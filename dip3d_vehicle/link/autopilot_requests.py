"""What the link asks of the autopilot and waits for: the ground station's system id (SYSID_MYGCS,
MAV_GCS_SYSID on ArduSub 4.7+) by PARAM_REQUEST_READ, and the message rates by
MAV_CMD_SET_MESSAGE_INTERVAL; each re-sent every ``link.param_retry_s`` until answered.

The SYSID_MYGCS read is given up (reported once, still asked) after ``link.param_give_up_s``; a
SET_MESSAGE_INTERVAL after three unacknowledged tries. Everything is asked afresh whenever the
autopilot is first heard, heard again after a gap, or rebooted (``AutopilotRequests.start``).
"""

from __future__ import annotations

from collections import deque
from typing import Any, Callable

from pymavlink import mavutil

from .connection import mavlink2
from .link_config import LinkConfig

__all__ = ["GCS_SYSID_PARAMS", "AutopilotRequests", "gcs_sysid_param", "param_name", "param_read"]

GCS_SYSID_PARAMS = ("SYSID_MYGCS", "MAV_GCS_SYSID")  # ArduSub <= 4.6, and 4.7+
"""The autopilot parameters that hold the ground station's system id."""
_INTERVAL_TRIES = 3


def param_name(msg: Any) -> str:
    """Return a PARAM_VALUE's name without its NUL padding."""
    name = msg.param_id
    return (name.decode(errors="replace") if isinstance(name, bytes) else str(name)).rstrip("\x00")


def param_read(config: LinkConfig, name: str) -> Any:
    """PARAM_REQUEST_READ of parameter ``name`` on the configured autopilot."""
    return mavlink2.MAVLink_param_request_read_message(config.target_system, config.target_component,
                                                       name.encode(), -1)


def gcs_sysid_param(msg: Any) -> tuple[str, int] | None:
    """Return (name, value) of a PARAM_VALUE for SYSID_MYGCS / MAV_GCS_SYSID, or None for any other."""
    name = param_name(msg)
    if name not in GCS_SYSID_PARAMS:
        return None
    return name, int(round(msg.param_value))


class AutopilotRequests:
    """The link's pending requests to the autopilot: sent, matched to their answers, retried, given up.

    Args:
        config: the link's resolved LinkConfig (target ids, rates, retry and give-up times).
        send: sends one message with the controller's own identity, ``send(type_name, msg)``.
        event: appends a line to the link's story of the run.
        warn: appends a warning the operator must see.

    Attributes:
        sysid_given_up: True once SYSID_MYGCS went unanswered for ``link.param_give_up_s``.
    """

    def __init__(self, config: LinkConfig, send: Callable[[str, Any], None], event: Callable[[str], None],
                 warn: Callable[[str], None]) -> None:
        self.config = config
        self._send, self._event, self._warn = send, event, warn
        self.sysid_given_up = False
        self._sysid_first_s: float | None = None
        self._sysid_last_s: float | None = None
        self._intervals_pending: deque[list] = deque()

    def start(self, now: float) -> None:
        """Ask for every configured message interval and the ground station's system id afresh."""
        self._intervals_pending.clear()
        for name, hz in self.config.rates_hz:
            self._intervals_pending.append([name, hz, now, 1])
            self._send_interval(name, hz)
        self._sysid_first_s = now
        self.sysid_given_up = False
        self._request_gcs_sysid(now)

    def sysid_answered(self) -> None:
        """The autopilot answered the SYSID_MYGCS read: stop the give-up clock."""
        self._sysid_first_s = None

    def on_interval_ack(self, msg: Any) -> None:
        """Match a SET_MESSAGE_INTERVAL acknowledgement to the oldest pending request."""
        if not self._intervals_pending:
            return
        name, hz, _, _ = self._intervals_pending.popleft()
        if msg.result != mavutil.mavlink.MAV_RESULT_ACCEPTED:
            self._event(f"SET_MESSAGE_INTERVAL {name} {hz:g} Hz refused by the autopilot (result {msg.result})")

    def retry(self, now: float, sysid_known: bool) -> None:
        """Re-send an unanswered SYSID_MYGCS read / SET_MESSAGE_INTERVAL; give up after a while."""
        c = self.config
        if self._sysid_first_s is not None and not sysid_known:
            if now - self._sysid_first_s > c.param_give_up_s and not self.sysid_given_up:
                self.sysid_given_up = True
                if c.output_mode == "manual_control":
                    self._warn(f"SYSID_MYGCS could not be read from the autopilot in {c.param_give_up_s:g} s: "
                               f"ArduSub accepts MANUAL_CONTROL only from that system id, so manual_control "
                               f"will not engage (still asking)")
            if self._sysid_last_s is not None and now - self._sysid_last_s >= c.param_retry_s:
                self._request_gcs_sysid(now)
        for item in list(self._intervals_pending):
            name, hz, sent_s, tries = item
            if now - sent_s >= c.param_retry_s:
                if tries >= _INTERVAL_TRIES:
                    self._intervals_pending.remove(item)
                    self._event(f"SET_MESSAGE_INTERVAL {name} not acknowledged after {tries} tries")
                else:
                    item[2], item[3] = now, tries + 1
                    self._send_interval(name, hz)

    def _send_interval(self, name: str, hz: float) -> None:
        """MAV_CMD_SET_MESSAGE_INTERVAL for message ``name`` at ``hz``."""
        c, m = self.config, mavutil.mavlink
        msg_id = getattr(m, f"MAVLINK_MSG_ID_{name}")
        self._send("COMMAND_LONG", mavlink2.MAVLink_command_long_message(
            c.target_system, c.target_component, m.MAV_CMD_SET_MESSAGE_INTERVAL, 0,
            float(msg_id), 1e6 / hz, 0, 0, 0, 0, 0))

    def _request_gcs_sysid(self, now: float) -> None:
        """PARAM_REQUEST_READ for SYSID_MYGCS (and MAV_GCS_SYSID, its 4.7+ name)."""
        for name in GCS_SYSID_PARAMS:
            self._send("PARAM_REQUEST_READ", param_read(self.config, name))
        self._sysid_last_s = now
