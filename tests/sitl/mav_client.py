"""Helpers for pymavlink test clients of the simulated autopilot (shared by the sitl tests)."""

from __future__ import annotations

from pymavlink import mavutil

M = mavutil.mavlink


def send_manual(conn, x: int = 0, y: int = 0, z: int = 500, r: int = 0, target: int = 1) -> None:
    """Send one MANUAL_CONTROL (buttons 0)."""
    conn.mav.manual_control_send(target, x, y, z, r, 0)


def command_long(conn, command: int, *params: float, target: int = 1) -> None:
    """Send a COMMAND_LONG to the vehicle."""
    p = list(params) + [0.0] * (7 - len(params))
    conn.mav.command_long_send(target, 1, command, 0, *p)
