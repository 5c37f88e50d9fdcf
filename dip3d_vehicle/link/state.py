"""What the link knows about its peers: the autopilot, the ground station, and counters."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

__all__ = ["SUB_MODES", "mode_name", "mode_number", "AutopilotState", "GcsState", "LinkStats"]

SUB_MODES: dict[int, str] = {
    0: "STABILIZE", 1: "ACRO", 2: "ALT_HOLD", 3: "AUTO", 4: "GUIDED", 7: "CIRCLE", 9: "SURFACE",
    16: "POSHOLD", 19: "MANUAL", 20: "MOTOR_DETECT", 21: "SURFTRAK",
}
"""ArduSub custom_mode numbers (HEARTBEAT.custom_mode) and their names."""


def mode_name(number: int | None) -> str:
    """Return the ArduSub mode name of ``number`` ("" when None, "MODE<n>" when unknown)."""
    if number is None:
        return ""
    return SUB_MODES.get(int(number), f"MODE{int(number)}")


def mode_number(name: str) -> int:
    """Return the ArduSub mode number of ``name``; raise KeyError when unknown."""
    for number, known in SUB_MODES.items():
        if known == name:
            return number
    raise KeyError(name)


@dataclass(frozen=True)
class AutopilotState:
    """The configured autopilot as last heard (times on the link's clock, seconds).

    Attributes:
        sysid, compid: whose messages these are (the configured target).
        last_message_s: time of the last message of any type from it (liveness), None = never.
        heard_since_s: start of the current run of messages without a gap longer than the timeout.
        last_heartbeat_s: time of its last HEARTBEAT, None = never.
        mode_number: HEARTBEAT.custom_mode, None = unknown.
        mode: the mode's name ("" = unknown).
        armed: HEARTBEAT.base_mode has MAV_MODE_FLAG_SAFETY_ARMED (128).
        system_status: HEARTBEAT.system_status (MAV_STATE).
        time_boot_ms: the largest recent time_boot_ms seen (reboot detection), None = none.
        boots: how many times it appeared (first contact, reappearance, reboot).
        yaw_rad, yaw_s: its heading (ATTITUDE.yaw, rad) and when it was heard; None = never.
    """

    sysid: int
    compid: int
    last_message_s: float | None = None
    heard_since_s: float | None = None
    last_heartbeat_s: float | None = None
    mode_number: int | None = None
    mode: str = ""
    armed: bool = False
    system_status: int = 0
    time_boot_ms: int | None = None
    boots: int = 0
    yaw_rad: float | None = None
    yaw_s: float | None = None

    def heading_rad(self, now_s: float, timeout_s: float) -> float | None:
        """Return the heading (rad) if heard within ``timeout_s`` of ``now_s``, else None."""
        if self.yaw_s is None or now_s - self.yaw_s > timeout_s:
            return None
        return self.yaw_rad

    def alive(self, now_s: float, timeout_s: float) -> bool:
        """Return True when a message arrived within ``timeout_s`` before ``now_s``."""
        return self.last_message_s is not None and now_s - self.last_message_s <= timeout_s

    def steady(self, now_s: float, timeout_s: float, settle_s: float) -> bool:
        """Return True when alive and heard without a gap for at least ``settle_s``."""
        return (self.alive(now_s, timeout_s) and self.heard_since_s is not None
                and now_s - self.heard_since_s >= settle_s)

    def heard(self, now_s: float, boot_ms: int | None, timeout_s: float) -> tuple["AutopilotState", str]:
        """Return the state after a message at ``now_s`` and why the autopilot (re)appeared ("" = it did not)."""
        ap = self
        gap = None if ap.last_message_s is None else now_s - ap.last_message_s
        rebooted = False
        if boot_ms is not None:
            rebooted = ap.time_boot_ms is not None and boot_ms + 1000 < ap.time_boot_ms
            ap = replace(ap, time_boot_ms=int(boot_ms))
        restarted = gap is None or rebooted or gap > timeout_s
        ap = replace(ap, last_message_s=now_s, heard_since_s=now_s if restarted else ap.heard_since_s)
        if gap is None:
            return ap, "autopilot first heard"
        if rebooted:
            return ap, f"autopilot rebooted (time_boot_ms went back to {boot_ms})"
        if gap > timeout_s:
            return ap, f"autopilot heard again after {gap:.2f} s"
        return ap, ""


@dataclass(frozen=True)
class GcsState:
    """The ground station (HEARTBEATs of type GCS from its system id).

    Attributes:
        sysid: the ground station's system id (SYSID_MYGCS once read).
        sysid_from_autopilot: True once SYSID_MYGCS (or MAV_GCS_SYSID) was read from the autopilot.
        last_heartbeat_s: time of its last HEARTBEAT, None = never seen.
    """

    sysid: int
    sysid_from_autopilot: bool = False
    last_heartbeat_s: float | None = None

    @property
    def seen(self) -> bool:
        """True once a ground-station heartbeat was seen."""
        return self.last_heartbeat_s is not None

    def alive(self, now_s: float, timeout_s: float) -> bool:
        """Return True when a ground-station heartbeat arrived within ``timeout_s``."""
        return self.last_heartbeat_s is not None and now_s - self.last_heartbeat_s <= timeout_s


@dataclass
class LinkStats:
    """Counters for the story of the run and the security checks.

    Attributes:
        received: messages accepted (right signature when signing is on).
        ignored_heartbeats: HEARTBEATs from systems/components that are neither the autopilot nor a GCS.
        ignored_from_others: other non-GCS messages not from the configured autopilot that were ignored.
        rejected_unsigned: unsigned messages dropped because signing is on.
        rejected_bad_signature: signed messages with a wrong key or replayed timestamp.
        bad_data: unparsable bytes/packets.
        operator_commands_denied: MAV_CMD_USER_1 from a sender that is not the ground station.
        gcs_id_withheld: MANUAL_CONTROL not sent because the ground station was lost (or never heard):
            its system id is used only while it is heard.
        turns_withheld: GUIDED setpoints sent without their turn: no ATTITUDE heading heard within
            ``link.autopilot_timeout_s`` (a turn is sent as a heading ahead of it).
        sent: messages sent, by type name.
    """

    received: int = 0
    ignored_heartbeats: int = 0
    ignored_from_others: int = 0
    rejected_unsigned: int = 0
    rejected_bad_signature: int = 0
    bad_data: int = 0
    operator_commands_denied: int = 0
    gcs_id_withheld: int = 0
    turns_withheld: int = 0
    sent: dict[str, int] = field(default_factory=dict)

    def count_sent(self, name: str) -> None:
        """Add one to the sent counter of message type ``name``."""
        self.sent[name] = self.sent.get(name, 0) + 1
