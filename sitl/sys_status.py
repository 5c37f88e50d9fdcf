"""SYS_STATUS sensor bits (present / enabled / healthy) as ArduSub 4.5 sets them.

From ArduPilot's ``GCS::update_sensor_status_flags`` (common to every vehicle) and
``GCS_Sub::update_vehicle_sensor_status_flags``, for a healthy vehicle in a pool: gyro,
accelerometer, compass, depth sensor (ABSOLUTE_PRESSURE: ArduSub reports only its water-pressure
sensor), AHRS, battery, logging, motor outputs (no safety switch) and pre-arm checks; ArduSub's
rate / attitude / yaw controllers always, depth and XY position control enabled and healthy only
in ALT_HOLD, AUTO, GUIDED, CIRCLE, SURFACE and POSHOLD; a DVL as VISION_POSITION.

The geofence: ArduSub ships with ``FENCE_ENABLE`` 0, so the fence is neither present nor enabled,
but its HEALTH bit is set whenever the fence has not failed (``!fence->sys_status_failed()``).
Ground stations read a present-and-healthy-then-unhealthy fence as a breach: MAVProxy prints
"fence breach" when that bit is clear, which is why it must be set.
"""

from __future__ import annotations

from pymavlink.dialects.v20 import ardupilotmega as M

__all__ = ["sys_status_bits", "DEPTH_XY_CONTROL_MODES"]

DEPTH_XY_CONTROL_MODES = frozenset({2, 3, 4, 7, 9, 16})
"""ALT_HOLD, AUTO, GUIDED, CIRCLE, SURFACE, POSHOLD: depth and XY position control enabled."""

_ALWAYS = (M.MAV_SYS_STATUS_SENSOR_3D_GYRO | M.MAV_SYS_STATUS_SENSOR_3D_ACCEL | M.MAV_SYS_STATUS_SENSOR_3D_MAG
           | M.MAV_SYS_STATUS_SENSOR_ABSOLUTE_PRESSURE | M.MAV_SYS_STATUS_AHRS | M.MAV_SYS_STATUS_SENSOR_BATTERY
           | M.MAV_SYS_STATUS_LOGGING | M.MAV_SYS_STATUS_SENSOR_MOTOR_OUTPUTS | M.MAV_SYS_STATUS_PREARM_CHECK
           | M.MAV_SYS_STATUS_SENSOR_ANGULAR_RATE_CONTROL | M.MAV_SYS_STATUS_SENSOR_ATTITUDE_STABILIZATION
           | M.MAV_SYS_STATUS_SENSOR_YAW_POSITION)
_CONTROL = M.MAV_SYS_STATUS_SENSOR_Z_ALTITUDE_CONTROL | M.MAV_SYS_STATUS_SENSOR_XY_POSITION_CONTROL


def sys_status_bits(mode: int, has_position: bool) -> tuple[int, int, int]:
    """Return (present, enabled, health) for a healthy ArduSub in ``mode`` (custom mode number)."""
    present = _ALWAYS | _CONTROL
    enabled = _ALWAYS
    health = _ALWAYS | M.MAV_SYS_STATUS_GEOFENCE  # fence not enabled, not failed: healthy
    if mode in DEPTH_XY_CONTROL_MODES:
        enabled |= _CONTROL
        health |= _CONTROL
    if has_position:
        dvl = M.MAV_SYS_STATUS_SENSOR_VISION_POSITION
        present, enabled, health = present | dvl, enabled | dvl, health | dvl
    return present, enabled, health
