"""GUIDED setpoints whose turn ends by itself when the link goes quiet.

ArduSub ends a GUIDED velocity setpoint 3 s after the last one but never ends a yaw rate: after a link loss the
vehicle would turn on at the last rate (real 4.7-dev SITL: 2.39 rad in the 8 s after the stream stopped), and no
parameter changes that. So a turn goes out as an absolute heading ahead of the vehicle's last ATTITUDE.yaw with the
turn speed as the yaw rate (``setpoints.guided_from_velocity``, type_mask 455): ArduSub turns toward it at that speed
while it is more than 5 deg away, then holds it. While the stream lasts the vehicle turns at the asked rate; after
it stops it turns at most the lead further, ``|r| x link.max_command_hold_s`` (at least 0.12 rad). Over 40 simulated
GUIDED link cuts the turn from the cut to the re-enable went from 53 deg (median) to 7 deg, and the arrivals from 24
to 40 (issue 11 session 62, ``docs/faults.md``).

Without a heading heard within ``link.autopilot_timeout_s`` the turn is withheld (the velocity still goes out):
counted, and warned about once when it lasts another timeout; a link loss disengages before that.
"""

from __future__ import annotations

import math
from typing import Callable

from ..servo.command import VelocityCommand
from .link_config import LinkConfig
from .setpoints import GuidedVelocity, guided_from_velocity
from .state import LinkStats

__all__ = ["GuidedTurns"]


class GuidedTurns:
    """GUIDED setpoints from velocity commands, each turn a heading ahead of the autopilot's (times in seconds).

    Args:
        config: the link's LinkConfig (``autopilot_timeout_s``, ``max_command_hold_s``: the heading's lead time;
            0 = a plain yaw rate).
        stats: the link's counters (``turns_withheld``).
        warn: the link's warning (the story and the log).
    """

    def __init__(self, config: LinkConfig, stats: LinkStats, warn: Callable[[str], None]) -> None:
        self.config, self.stats, self._warn = config, stats, warn
        self._withheld_since_s = 0.0  # the current run of withheld turns (no gap longer than the timeout)
        self._withheld_last_s: float | None = None
        self._said = False

    def setpoint(self, now_s: float, cmd: VelocityCommand, heading_rad: float | None) -> GuidedVelocity:
        """The setpoint for ``cmd`` given the autopilot's heading (rad, None = none heard within the timeout)."""
        hold_s, timeout_s = self.config.max_command_hold_s, self.config.autopilot_timeout_s
        turn = math.isfinite(cmd.yaw_rate_rad_s) and cmd.yaw_rate_rad_s != 0.0
        if heading_rad is None and hold_s > 0 and turn:
            self.stats.turns_withheld += 1
            if self._withheld_last_s is None or now_s - self._withheld_last_s > timeout_s:
                self._withheld_since_s = now_s
            self._withheld_last_s = now_s
            lasted_s = now_s - self._withheld_since_s
            if lasted_s >= timeout_s and not self._said:
                self._said = True
                self._warn(f"GUIDED turns withheld for {lasted_s:.1f} s: no ATTITUDE heading from the autopilot "
                           f"(a plain yaw rate would never end on a link loss)")
        elif heading_rad is not None:
            self._withheld_last_s = None
        return guided_from_velocity(cmd, heading_rad, hold_s)
