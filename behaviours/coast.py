"""The vehicle's own motion under a command, for the tracker's dead reckoning.

The servo's commands are setpoints, not motion: in ALT_HOLD the horizontal sticks are thrust, so after a
neutral command the vehicle coasts on against its quadratic drag (from 0.3 m/s: 0.20 m in the first
second, 0.38 m in three, on the ArduSub SITL fit of ``sitl.dynamics``), and the yaw follows its rate loop
with a lag. A prediction from the commands alone stood still while the vehicle drifted on: 0.4 m off one
second after the target was lost, 0.6-0.7 m after three (issue 11 session 59). ``MotionModel`` carries the
vehicle's velocity from command to command: with thrust control (``link.output_mode`` manual_control) surge and
sway obey ``dv/dt = (c|c| - v|v|) / coast_m`` (``coast_m`` = the vehicle's mass over its quadratic drag: a
command ``c`` is the speed its thrust holds steady); under the autopilot's own velocity loop (GUIDED) they
lag first-order; the yaw rate lags first-order on both paths; heave follows the command at once (the depth
is held).

The tracker uses it with ``behaviour.track_reckoning`` vehicle, the default since issue 11 session 60 (``commands``
moves as commanded). The servo's margin round the diver (``behaviour.servo_diver_margin_m``) had been calibrated on
offsets carried by the commands: with this model's truer offsets and the old 0.3 m the least pass by the diver's body
over 333 simulated missions fell from 0.99 to 0.81 m, so the margin went to 0.4 m with it (1.06 m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

from dip3d_vehicle.servo.command import NEUTRAL, VelocityCommand

__all__ = ["MotionModel"]

STEP_S = 0.02
"""Integration step of the quadratic-drag axes, s."""


def _lagged(v0: float, c: float, dt_s: float, lag_s: float) -> tuple[float, float]:
    """Return (mean, final) speed over ``dt_s`` of a first-order lag ``lag_s`` from ``v0`` toward ``c``."""
    if lag_s <= 0.0:
        return c, c
    decay = math.exp(-dt_s / lag_s)
    return c + (v0 - c) * lag_s / dt_s * (1.0 - decay), c + (v0 - c) * decay


def _dragged(v0: float, c: float, dt_s: float, coast_m: float) -> tuple[float, float]:
    """Return (mean, final) speed over ``dt_s`` under thrust ``c|c|`` against quadratic drag (``coast_m``, m)."""
    n = max(1, math.ceil(dt_s / STEP_S))
    h, v, travelled = dt_s / n, v0, 0.0
    for _ in range(n):
        a = (c * abs(c) - v * abs(v)) / coast_m
        mid = v + 0.5 * h * a
        travelled += mid * h
        v += h * (c * abs(c) - mid * abs(mid)) / coast_m
    return travelled / dt_s, v


@dataclass(frozen=True)
class MotionModel:
    """How the vehicle's velocity follows the commands (all zero: it does as told at once, the old model).

    Attributes:
        coast_m: surge and sway under thrust control: mass over quadratic drag, m (0 = the lags below).
        surge_lag_s: surge's first-order lag under a velocity loop, s.
        sway_lag_s: sway's, s.
        yaw_lag_s: the yaw rate's first-order lag, s.
    """

    coast_m: float = 0.0
    surge_lag_s: float = 0.0
    sway_lag_s: float = 0.0
    yaw_lag_s: float = 0.0

    @classmethod
    def from_params(cls, params: Mapping) -> "MotionModel":
        """Build from ``behaviour.track_reckoning`` / ``track_coast_m``, ``link.output_mode`` and the servo's
        measured time constants (``servo.tau_surge_s``, ``tau_sway_s``, ``tau_yaw_s``)."""
        if params["behaviour.track_reckoning"] == "commands":
            return cls()
        thrust = params["link.output_mode"] == "manual_control"
        return cls(params["behaviour.track_coast_m"] if thrust else 0.0, params["servo.tau_surge_s"],
                   params["servo.tau_sway_s"], params["servo.tau_yaw_s"])

    def advance(self, velocity: VelocityCommand, command: VelocityCommand | None,
                dt_s: float) -> tuple[VelocityCommand, VelocityCommand]:
        """Return (the mean velocity over ``dt_s``, the velocity at its end), from ``velocity`` under ``command``
        (None: neutral); body-frame m/s and rad/s."""
        c = NEUTRAL if command is None else command
        if dt_s <= 0.0:
            return velocity, velocity
        if self.coast_m > 0.0:
            surge, sway = (_dragged(velocity.surge_m_s, c.surge_m_s, dt_s, self.coast_m),
                           _dragged(velocity.sway_m_s, c.sway_m_s, dt_s, self.coast_m))
        else:
            surge, sway = (_lagged(velocity.surge_m_s, c.surge_m_s, dt_s, self.surge_lag_s),
                           _lagged(velocity.sway_m_s, c.sway_m_s, dt_s, self.sway_lag_s))
        yaw = _lagged(velocity.yaw_rate_rad_s, c.yaw_rate_rad_s, dt_s, self.yaw_lag_s)
        mean = VelocityCommand(surge[0], sway[0], c.heave_m_s, yaw[0])
        return mean, VelocityCommand(surge[1], sway[1], c.heave_m_s, yaw[1])
