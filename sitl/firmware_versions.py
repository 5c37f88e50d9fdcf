"""Where ArduSub 4.5 and 4.7 differ on the MAVLink side, as data for the built-in autopilot.

4.5: measured on an ArduSub 4.5.0-beta2 SITL (reference/ardusub_sitl_response.md). 4.7: measured on
the ArduSub 4.7.0-dev SITL in ../shared/ardusub-sitl (its README, and tests/sitl/test_conformance.py,
which runs the same checks on the built-in autopilot with either setting and on the binary).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["FirmwareProfile", "FIRMWARE_PROFILES", "firmware_profile"]


@dataclass(frozen=True)
class FirmwareProfile:
    """One ArduSub version's observable differences.

    Attributes:
        version: "4.5" or "4.7".
        gcs_sysid_param: the ground station's system id parameter (4.7 renamed SYSID_MYGCS).
        this_mav_param: the vehicle's own system id parameter (4.7 renamed SYSID_THISMAV).
        acks_set_mode_message: the SET_MODE *message* gets a COMMAND_ACK (DO_SET_MODE always does).
        boot_status_s: HEARTBEAT.system_status is 5 (CRITICAL) for this long after boot, then 3.
        alt_hold_after_s: ALT_HOLD refused ("need alt estimate") until this long after boot.
        arm_after_s: arming refused ("Battery 1 unhealthy") until this long after boot.
        position_after_s: with a position source, GUIDED etc. refused until this long after boot
            (the 4.7 SITL's EKF starts using its GPS ~41 s after boot).
        gcs_failsafe_timeout_s: the GCS failsafe's timeout (4.7: FS_GCS_TIMEOUT, 5 s).
    """

    version: str
    gcs_sysid_param: str
    this_mav_param: str
    acks_set_mode_message: bool
    boot_status_s: float
    alt_hold_after_s: float
    arm_after_s: float
    position_after_s: float
    gcs_failsafe_timeout_s: float


FIRMWARE_PROFILES = {
    "4.5": FirmwareProfile("4.5", "SYSID_MYGCS", "SYSID_THISMAV", True, 0.0, 0.0, 0.0, 0.0, 2.5),
    "4.7": FirmwareProfile("4.7", "MAV_GCS_SYSID", "MAV_SYSID", False, 2.0, 2.0, 5.0, 41.0, 5.0),
}


def firmware_profile(version: str) -> FirmwareProfile:
    """Return the profile of ``version`` ("4.5" / "4.7"); raise KeyError naming the choices."""
    try:
        return FIRMWARE_PROFILES[str(version)]
    except KeyError:
        raise KeyError(f"sim.firmware = {version!r}: expected one of {sorted(FIRMWARE_PROFILES)}") from None
