"""The servo's output: a body-frame velocity command for the vehicle."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["VelocityCommand", "NEUTRAL"]


@dataclass(frozen=True)
class VelocityCommand:
    """Body-frame velocity setpoint (vehicle axes: x forward, y right, z down; yaw clockwise from above).

    Attributes:
        surge_m_s: forward speed, m/s.
        sway_m_s: rightward speed, m/s.
        heave_m_s: downward speed, m/s (negative = rise).
        yaw_rate_rad_s: yaw rate, rad/s (positive = turn right / clockwise seen from above).
    """

    surge_m_s: float = 0.0
    sway_m_s: float = 0.0
    heave_m_s: float = 0.0
    yaw_rate_rad_s: float = 0.0

    def is_neutral(self) -> bool:
        """Return True when every axis is exactly zero."""
        return self.surge_m_s == 0.0 and self.sway_m_s == 0.0 and self.heave_m_s == 0.0 and self.yaw_rate_rad_s == 0.0


NEUTRAL = VelocityCommand()
"""All axes zero: what is sent whenever the controller stops commanding motion."""
