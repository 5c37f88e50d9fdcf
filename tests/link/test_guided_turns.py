"""GuidedTurns: a turn as a heading ahead; without a heading the turn is withheld, counted, and warned about once
when a run of withheld turns (no gap longer than link.autopilot_timeout_s) has lasted that timeout."""

from __future__ import annotations

import pytest

from dip3d_vehicle.config import load_params
from dip3d_vehicle.link.guided_turns import GuidedTurns
from dip3d_vehicle.link.link_config import LinkConfig
from dip3d_vehicle.link.state import LinkStats
from dip3d_vehicle.servo.command import VelocityCommand

TURN = VelocityCommand(surge_m_s=0.2, yaw_rate_rad_s=0.3)


def _turns(**overrides) -> tuple[GuidedTurns, LinkStats, list[str]]:
    said: list[str] = []
    config = LinkConfig.from_params(load_params(overrides={"link.output_mode": "guided_velocity", **overrides}))
    stats = LinkStats()
    return GuidedTurns(config, stats, said.append), stats, said


def _stream(turns: GuidedTurns, t0_s: float, t1_s: float, heading_rad: float | None) -> None:
    for k in range(int(round((t1_s - t0_s) * 10))):
        turns.setpoint(t0_s + k * 0.1, TURN, heading_rad)


def test_a_turn_is_a_heading_ahead_of_the_autopilots() -> None:
    turns, stats, said = _turns()
    sp = turns.setpoint(0.0, TURN, 1.0)
    assert (sp.type_mask, sp.yaw_rad, sp.yaw_rate_rad_s, sp.vx_m_s) == (455, pytest.approx(1.3), 0.3, 0.2)
    assert stats.turns_withheld == 0 and not said


def test_withheld_turns_are_said_once_after_a_run_as_long_as_the_timeout_and_a_gap_starts_a_new_run() -> None:
    turns, stats, said = _turns()
    _stream(turns, 0.0, 0.4, None)            # a link loss: 4 withheld, then disengaged
    assert stats.turns_withheld == 4 and not said
    _stream(turns, 5.0, 5.5, None)            # re-engaged 4.6 s later, still no heading: a new run
    assert not said
    _stream(turns, 5.5, 6.0, None)
    assert len(said) == 1 and "GUIDED turns withheld for 0." in said[0]   # not 5 s: the gap started a new run
    _stream(turns, 6.0, 9.0, None)
    _stream(turns, 9.0, 9.5, 0.0)             # a heading again: turns go out
    assert len(said) == 1 and stats.turns_withheld == 4 + 40


def test_hold_zero_sends_the_plain_yaw_rate_and_withholds_nothing() -> None:
    turns, stats, said = _turns(**{"link.max_command_hold_s": 0.0})
    sp = turns.setpoint(0.0, TURN, None)
    assert (sp.type_mask, sp.yaw_rate_rad_s) == (1479, 0.3)
    assert stats.turns_withheld == 0 and not said
