"""VelocityCommand -> MAVLink setpoints: MANUAL_CONTROL sticks and GUIDED body-frame velocity.

Pure functions. The stick mapping inverts the speeds measured on a real ArduSub 4.5 SITL
(``reference/ardusub_sitl_response.md``, ALT_HOLD, default joystick gain 0.5) by piecewise-linear
interpolation through the measured points, with (0 m/s -> 0) added and the tables mirrored for
negative speeds (the SITL measured positive steps only; the vectored frame is symmetric). Speeds
beyond the largest measured one are clamped to full stick.

Between 0 and the first measured point the mapping is an interpolation, not a measurement; ArduSub's
throttle dead zone (THR_DZ) may swallow very small vertical commands.

Vertical has ArduSub's throttle dead zone (THR_DZ 100 on both versions): measured on the 4.7 SITL
(SIM_STATE vd, ALT_HOLD, 4 s steps) z = 450 / 400 give no motion (-0.02 / 0.005 m/s), z = 350 / 320 /
300 / 280 / 250 give 0.133 / 0.192 / 0.243 / 0.291 / 0.367 m/s down. The old table, a straight line
from (0, 500) to (0.36, 250), sent z = 396 for 0.15 m/s: nothing happened, and the controller could
not correct a vertical image error on the firmware (paper_pool stayed in servo for 60 s). The up
side mirrors the measured down side about 500 (the same dead zone; above the boot depth ArduSub
will not climb, so up steps were not measured here) and keeps 4.5's (-0.36, 750), (-0.90, 1000).

Yaw has a dead zone, measured on the ArduSub 4.7.0-dev SITL (``tools/measure_ardusub_sticks.py``,
steady SIM_STATE zgyro after 5 s, ALT_HOLD): r <= 115 gives no turn (0.002 rad/s), r = 130 / 171 /
210 / 250 / 350 / 500 give 0.044 / 0.097 / 0.154 / 0.211 / 0.354 / 0.574 rad/s. The old table, a
straight line from 0 to the 4.5 point r = 250 (0.214), asked r = 171 for 0.146 rad/s and got 0.097.
At the points both versions were measured (250, 500) they agree within 3 %, so the low end (the
same joystick/RC code) is used for both: ``YAW_TABLES["4.5"]`` is the 4.5 measurements with the 4.7
low end, ``YAW_TABLES["4.7"]`` the 4.7 measurements (its r = 1000 point is 4.5's). The link picks
the table by the firmware's GCS-sysid parameter name (MAV_GCS_SYSID: 4.7+, SYSID_MYGCS: 4.5).

Forward has the same kind of dead zone, measured on the 4.7 SITL (``tools/measure_ardusub_sticks.py
--axis x``, SIM_STATE body speed after 5 s, ALT_HOLD; docs/issue13/stick_measurements.jsonl): x <= 120
gives no thrust (the 0.01-0.03 m/s read there were the previous step's coasting: x = -120 read +0.026),
x = 130 / 140 / 150 / 160 / 200 / 250 / 388 give 0.115 / 0.144 / 0.154 / 0.164 / 0.206 / 0.258 / 0.398
m/s, symmetric (x = -160 / -250: -0.164 / -0.258). The old table, a straight line from 0 to (0.258, 250),
sent x = 97 for 0.1 m/s: nothing moved, and on the firmware the servo sat 0.15-0.18 m short of the
stand-off for 10 s asking 0.10 m/s (paper_pool seed 0). At 250 the two versions agree (0.258), so the
table is shared.

Speeds below an axis' first moving point cannot be held by any steady stick: ``StickDither`` (used by
the link) sends them as pulses of that point's stick whose duty gives the asked mean speed (first-order
sigma-delta at the setpoint rate, 20 Hz, well inside the vehicle's 0.36-0.6 s response), as a pilot
taps the stick to creep. ``manual_control_from_velocity`` itself stays the steady map.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..servo.command import VelocityCommand

__all__ = [
    "ManualControl", "GuidedVelocity", "NEUTRAL_STICKS", "ZERO_GUIDED",
    "SURGE_TABLE", "SWAY_TABLE", "YAW_TABLE", "YAW_TABLES", "HEAVE_TABLE", "FIRMWARES",
    "manual_control_from_velocity", "guided_from_velocity", "StickDither", "first_moving_point",
    "MAV_FRAME_BODY_NED", "TYPE_MASK_VELOCITY_YAW_RATE", "TYPE_MASK_VELOCITY_YAW", "GUIDED_MIN_YAW_AHEAD_RAD",
]

# (speed, stick) pairs measured in ALT_HOLD; stick x/y/r in -1000..1000.
SURGE_TABLE: tuple[tuple[float, float], ...] = (
    (0.0, 0.0), (0.002, 120.0), (0.115, 130.0), (0.144, 140.0), (0.164, 160.0), (0.206, 200.0), (0.258, 250.0),
    (0.398, 388.0), (0.516, 500.0), (1.032, 1000.0))
"""Forward x: true body speed m/s -> MANUAL_CONTROL.x."""
SWAY_TABLE: tuple[tuple[float, float], ...] = ((0.0, 0.0), (0.455, 500.0), (0.911, 1000.0))
"""Lateral y: true body speed m/s (right positive) -> MANUAL_CONTROL.y."""
_YAW_LOW_END = ((0.0, 0.0), (0.002, 115.0), (0.0435, 130.0), (0.097, 171.0), (0.154, 210.0))  # 4.7, dead zone
YAW_TABLES: dict[str, tuple[tuple[float, float], ...]] = {
    "4.5": _YAW_LOW_END + ((0.214, 250.0), (0.593, 500.0), (1.319, 1000.0)),
    "4.7": _YAW_LOW_END + ((0.211, 250.0), (0.354, 350.0), (0.574, 500.0), (1.319, 1000.0)),
}
"""Yaw r per firmware: yaw rate rad/s (clockwise from above positive) -> MANUAL_CONTROL.r."""
FIRMWARES = tuple(YAW_TABLES)
"""The ArduSub versions with their own tables."""
YAW_TABLE = YAW_TABLES["4.5"]
"""The 4.5 yaw table (the default before the firmware is known)."""
HEAVE_TABLE: tuple[tuple[float, float], ...] = (
    (-0.90, 1000.0), (-0.36, 750.0), (-0.291, 720.0), (-0.243, 700.0), (-0.192, 680.0), (-0.133, 650.0),
    (-0.005, 600.0), (0.0, 500.0), (0.005, 400.0), (0.133, 350.0), (0.192, 320.0), (0.243, 300.0),
    (0.291, 280.0), (0.36, 250.0), (0.97, 0.0))
"""Vertical z: downward speed m/s (negative = rise) -> MANUAL_CONTROL.z (0..1000, 500 neutral)."""

MAV_FRAME_BODY_NED = 8
"""Velocity frame used in GUIDED: x forward / y right rotated by yaw only, z down (as measured)."""
TYPE_MASK_VELOCITY_YAW_RATE = 1479
"""POSITION_TARGET_TYPEMASK: ignore position (1|2|4), acceleration (64|128|256) and yaw (1024);
use vx, vy, vz and yaw_rate. ArduSub keeps such a yaw rate forever: it never times out."""
TYPE_MASK_VELOCITY_YAW = 455
"""Ignore position and acceleration; use vx, vy, vz, yaw and yaw_rate. In BODY_NED the yaw is an absolute heading,
and ArduSub turns toward it at |yaw_rate| while it is more than 5 deg away, then holds it: a turn that ends by
itself when the stream stops (real 4.7 SITL, docs/issue11/session62/scripts/guided_yaw_probe.py)."""
GUIDED_MIN_YAW_AHEAD_RAD = 0.12
"""The least heading lead of a GUIDED turn, rad: beyond ArduSub's 5 deg (0.087 rad) band where it stops turning
at the given rate and holds the heading instead (tracked 0.009 of 0.05 rad/s with a 0.05 rad lead)."""


@dataclass(frozen=True)
class ManualControl:
    """MANUAL_CONTROL axes: x forward, y right, r yaw in -1000..1000; z 0..1000 with 500 neutral.

    ``buttons`` is always 0: ArduSub maps joystick buttons to actions (arm, disarm, mode changes).
    """

    x: int = 0
    y: int = 0
    z: int = 500
    r: int = 0
    buttons: int = 0

    def is_neutral(self) -> bool:
        """Return True for centred sticks (x = y = r = 0, z = 500)."""
        return self.x == 0 and self.y == 0 and self.r == 0 and self.z == 500


@dataclass(frozen=True)
class GuidedVelocity:
    """SET_POSITION_TARGET_LOCAL_NED content: body-frame velocity m/s and yaw rate rad/s, or with ``yaw_rad`` (an
    absolute heading, rad) a turn toward that heading at ``yaw_rate_rad_s`` (then >= 0)."""

    vx_m_s: float = 0.0
    vy_m_s: float = 0.0
    vz_m_s: float = 0.0
    yaw_rate_rad_s: float = 0.0
    yaw_rad: float | None = None
    frame: int = MAV_FRAME_BODY_NED

    @property
    def type_mask(self) -> int:
        """POSITION_TARGET_TYPEMASK: velocity + yaw rate, or velocity + heading + yaw rate with ``yaw_rad``."""
        return TYPE_MASK_VELOCITY_YAW_RATE if self.yaw_rad is None else TYPE_MASK_VELOCITY_YAW

    def is_zero(self) -> bool:
        """Return True when velocity and yaw rate are all zero (an explicit stop)."""
        return self.vx_m_s == 0.0 and self.vy_m_s == 0.0 and self.vz_m_s == 0.0 and self.yaw_rate_rad_s == 0.0


NEUTRAL_STICKS = ManualControl()
"""Centred sticks: what manual_control sends whenever it stops commanding motion."""
ZERO_GUIDED = GuidedVelocity()
"""Zero velocity AND zero yaw rate: ArduSub keeps the last GUIDED yaw rate forever otherwise."""


def _symmetric_interp(value: float, table: tuple[tuple[float, float], ...]) -> float:
    """Interpolate |value| through a (speed, stick) table from 0 and restore the sign; clamp at the end."""
    speeds = np.array([p[0] for p in table])
    sticks = np.array([p[1] for p in table])
    out = float(np.interp(abs(value), speeds, sticks))
    return out if value >= 0 else -out


def _finite(value: float) -> float:
    """Return ``value``, or 0.0 when it is NaN or infinite (a broken command must not move the vehicle)."""
    return float(value) if np.isfinite(value) else 0.0


def manual_control_from_velocity(cmd: VelocityCommand, firmware: str = "4.5") -> ManualControl:
    """Map a body-frame velocity command to MANUAL_CONTROL sticks through the measured responses.

    Args:
        cmd: the servo's velocity command (surge/sway/heave m/s, yaw rate rad/s).
        firmware: "4.5" or "4.7": which yaw table (see ``YAW_TABLES``).

    Returns:
        Sticks clamped to x, y, r in -1000..1000 and z in 0..1000 (500 neutral); a non-finite axis
        gives that axis' neutral. An all-zero command gives exactly ``NEUTRAL_STICKS``.

    Examples:
        >>> manual_control_from_velocity(VelocityCommand(surge_m_s=0.516))
        ManualControl(x=500, y=0, z=500, r=0, buttons=0)
    """
    x = _symmetric_interp(_finite(cmd.surge_m_s), SURGE_TABLE)
    y = _symmetric_interp(_finite(cmd.sway_m_s), SWAY_TABLE)
    r = _symmetric_interp(_finite(cmd.yaw_rate_rad_s), YAW_TABLES[firmware])
    heave = _finite(cmd.heave_m_s)
    z = float(np.interp(heave, [p[0] for p in HEAVE_TABLE], [p[1] for p in HEAVE_TABLE]))
    clamp = lambda v, lo, hi: int(round(min(max(v, lo), hi)))  # noqa: E731
    return ManualControl(x=clamp(x, -1000, 1000), y=clamp(y, -1000, 1000),
                         z=clamp(z, 0, 1000), r=clamp(r, -1000, 1000))


def guided_from_velocity(cmd: VelocityCommand, heading_rad: float | None = None, hold_s: float = 0.0,
                         max_speed_m_s: float = 2.0, max_yaw_rate_rad_s: float = 1.5) -> GuidedVelocity:
    """Map a velocity command to a GUIDED BODY_NED setpoint whose turn ends by itself ``hold_s`` after the last one.

    BODY_NED rotates x/y by the vehicle's yaw only and keeps z down, so heave is a plain down speed. ArduSub never
    times out a GUIDED yaw rate, so with ``hold_s`` > 0 a turn is sent as a heading ``|r| * hold_s`` (at least
    ``GUIDED_MIN_YAW_AHEAD_RAD``) ahead of ``heading_rad`` with the speed ``|r|``: while the setpoints keep coming
    the vehicle turns at r, and after they stop it turns at most that far. No turn without a known heading then.

    Args:
        cmd: the servo's velocity command.
        heading_rad: the vehicle's heading now (ATTITUDE.yaw), rad; None = unknown.
        hold_s: how long a turn may outlive the stream, s; 0 = a plain yaw rate (turns until told otherwise).
        max_speed_m_s: clamp for each linear axis, m/s.
        max_yaw_rate_rad_s: clamp for the yaw rate, rad/s.

    Returns:
        The setpoint with frame 8 and type_mask 1479 (no turn, or ``hold_s`` 0) or 455 (a heading); a non-finite
        axis becomes 0.
    """
    lim = lambda v, m: min(max(_finite(v), -m), m)  # noqa: E731
    rate = lim(cmd.yaw_rate_rad_s, max_yaw_rate_rad_s)
    yaw_rad = None
    if hold_s > 0 and rate != 0.0:
        if heading_rad is None or not np.isfinite(heading_rad):
            rate = 0.0
        else:
            ahead = heading_rad + math.copysign(max(abs(rate) * hold_s, GUIDED_MIN_YAW_AHEAD_RAD), rate)
            yaw_rad, rate = math.atan2(math.sin(ahead), math.cos(ahead)), abs(rate)
    return GuidedVelocity(vx_m_s=lim(cmd.surge_m_s, max_speed_m_s), vy_m_s=lim(cmd.sway_m_s, max_speed_m_s),
                          vz_m_s=lim(cmd.heave_m_s, max_speed_m_s), yaw_rate_rad_s=rate, yaw_rad=yaw_rad)


def first_moving_point(table: tuple[tuple[float, float], ...]) -> tuple[float, float]:
    """Return the (speed, stick) of a stick table's first point beyond its dead zone (speed >= 0.01)."""
    return next(p for p in table if p[0] >= 0.01)


_HEAVE_FIRST_DOWN = (0.133, 350.0)  # the throttle's first moving points (THR_DZ: z 400..600 does nothing)
_HEAVE_FIRST_UP = (-0.133, 650.0)


class StickDither:
    """Speeds below an axis' dead zone as pulses of its first moving stick (surge, yaw and heave).

    Per axis a first-order sigma-delta: each call adds ``|v| / v_first`` to an accumulator and sends
    the first moving stick (with the command's sign) while it reaches 0.5, taking 1 off; otherwise
    that axis is neutral. The mean speed then follows the command. At or above ``v_first`` the steady
    map is used. A zero axis (and any sign change) clears that axis' accumulator, and ``reset()``
    clears all of them: an all-zero command is always exactly ``NEUTRAL_STICKS``.

    Args:
        firmware: "4.5" or "4.7": which yaw table (see ``YAW_TABLES``).
    """

    def __init__(self, firmware: str = "4.5") -> None:
        self.firmware = firmware
        self._acc = {"surge": 0.0, "yaw": 0.0, "heave": 0.0}
        self._sign = {"surge": 0.0, "yaw": 0.0, "heave": 0.0}

    def reset(self) -> None:
        """Forget the accumulated remainders (on every stop and disengage)."""
        self._acc = {k: 0.0 for k in self._acc}
        self._sign = {k: 0.0 for k in self._sign}

    def _pulse(self, axis: str, value: float, first: float) -> float:
        """Return +-1.0 (pulse) or 0.0 for ``value`` of magnitude below ``first``, updating the accumulator."""
        acc = self._acc[axis]
        sign = math.copysign(1.0, value) if value != 0.0 else 0.0
        if sign != self._sign[axis]:
            acc = 0.0
        self._sign[axis] = sign
        acc += value / first
        out = 0.0
        if acc >= 0.5:
            out, acc = 1.0, acc - 1.0
        elif acc <= -0.5:
            out, acc = -1.0, acc + 1.0
        self._acc[axis] = acc
        return out

    def sticks(self, cmd: VelocityCommand) -> ManualControl:
        """Return this setpoint tick's sticks for ``cmd`` (call once per sent MANUAL_CONTROL)."""
        steady = manual_control_from_velocity(cmd, self.firmware)
        x, r, z = steady.x, steady.r, steady.z
        surge, yaw, heave = _finite(cmd.surge_m_s), _finite(cmd.yaw_rate_rad_s), _finite(cmd.heave_m_s)
        v_x, stick_x = first_moving_point(SURGE_TABLE)
        if abs(surge) < v_x:
            x = int(round(self._pulse("surge", surge, v_x) * stick_x))
        else:
            self._acc["surge"], self._sign["surge"] = 0.0, 0.0
        v_r, stick_r = first_moving_point(YAW_TABLES[self.firmware])
        if abs(yaw) < v_r:
            r = int(round(self._pulse("yaw", yaw, v_r) * stick_r))
        else:
            self._acc["yaw"], self._sign["yaw"] = 0.0, 0.0
        v_z, z_down = _HEAVE_FIRST_DOWN
        if abs(heave) < v_z:
            p = self._pulse("heave", heave, v_z)
            z = int(z_down) if p > 0 else int(_HEAVE_FIRST_UP[1]) if p < 0 else 500
        else:
            self._acc["heave"], self._sign["heave"] = 0.0, 0.0
        return ManualControl(x=x, y=steady.y, z=z, r=r)
