"""Clocks: the wall clock onboard, and a simulated clock the simulator can run faster than real time.

Everything that needs time (link timeouts, behaviour hold times, setpoint streaming, the simulated
autopilot) asks a Clock, never ``time.time()`` directly, so a closed-loop run can be accelerated.
"""

from __future__ import annotations

import time
from typing import Protocol

__all__ = ["Clock", "WallClock", "SimClock"]


class Clock(Protocol):
    """Something that tells the time in seconds (monotonic, arbitrary origin)."""

    def now(self) -> float:
        """Return the current time, seconds."""
        ...


class WallClock:
    """The real monotonic clock, seconds since an arbitrary origin."""

    def now(self) -> float:
        """Return time.monotonic(), seconds."""
        return time.monotonic()

    def sleep_until(self, t_s: float) -> None:
        """Sleep until ``t_s`` (seconds on this clock)."""
        dt = t_s - time.monotonic()
        if dt > 0:
            time.sleep(dt)


class SimClock:
    """A simulated clock advanced explicitly by the simulation loop, seconds."""

    def __init__(self, start_s: float = 0.0) -> None:
        self._t = float(start_s)

    def now(self) -> float:
        """Return the simulated time, seconds."""
        return self._t

    def advance(self, dt_s: float) -> float:
        """Move the clock forward by ``dt_s`` seconds (>= 0); return the new time."""
        if dt_s < 0:
            raise ValueError(f"SimClock cannot go backwards (dt_s={dt_s})")
        self._t += dt_s
        return self._t

    def sleep_until(self, t_s: float) -> None:
        """Jump to ``t_s`` if it is in the future (a simulated sleep)."""
        self._t = max(self._t, float(t_s))
