"""VelocityCommand -> MANUAL_CONTROL / GUIDED setpoints: measured points, limits, signs."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from dip3d_vehicle.link.setpoints import (GUIDED_MIN_YAW_AHEAD_RAD, HEAVE_TABLE, NEUTRAL_STICKS, SURGE_TABLE, StickDither, SWAY_TABLE, YAW_TABLE, YAW_TABLES,
                                          ZERO_GUIDED, guided_from_velocity, manual_control_from_velocity)
from dip3d_vehicle.servo.command import NEUTRAL, VelocityCommand

speeds = st.floats(min_value=-5, max_value=5, allow_nan=False)


def test_zero_command_is_exactly_neutral_sticks() -> None:
    assert manual_control_from_velocity(NEUTRAL) == NEUTRAL_STICKS
    assert NEUTRAL_STICKS.is_neutral() and NEUTRAL_STICKS.z == 500 and NEUTRAL_STICKS.buttons == 0


@pytest.mark.parametrize("speed, stick", [(0.258, 250), (0.516, 500), (1.032, 1000)])
def test_surge_hits_measured_points(speed: float, stick: int) -> None:
    assert manual_control_from_velocity(VelocityCommand(surge_m_s=speed)).x == stick
    assert manual_control_from_velocity(VelocityCommand(surge_m_s=-speed)).x == -stick


@pytest.mark.parametrize("speed, stick", [(0.455, 500), (0.911, 1000)])
def test_sway_hits_measured_points(speed: float, stick: int) -> None:
    assert manual_control_from_velocity(VelocityCommand(sway_m_s=speed)).y == stick


@pytest.mark.parametrize("rate, stick", [(0.214, 250), (0.593, 500), (1.319, 1000)])
def test_yaw_hits_measured_points(rate: float, stick: int) -> None:
    assert manual_control_from_velocity(VelocityCommand(yaw_rate_rad_s=rate)).r == stick
    assert manual_control_from_velocity(VelocityCommand(yaw_rate_rad_s=-rate)).r == -stick


@pytest.mark.parametrize("heave, z", [(-0.90, 1000), (-0.36, 750), (0.36, 250), (0.97, 0), (0.0, 500)])
def test_heave_hits_measured_points_down_positive(heave: float, z: int) -> None:
    assert manual_control_from_velocity(VelocityCommand(heave_m_s=heave)).z == z


def test_tables_are_monotonic() -> None:
    for table in (SURGE_TABLE, SWAY_TABLE, YAW_TABLE):
        assert all(a[0] < b[0] and a[1] < b[1] for a, b in zip(table, table[1:]))
    assert all(a[0] < b[0] and a[1] > b[1] for a, b in zip(HEAVE_TABLE, HEAVE_TABLE[1:]))


@given(speeds, speeds, speeds, speeds)
def test_sticks_always_in_range_with_zero_buttons(vx: float, vy: float, vz: float, r: float) -> None:
    s = manual_control_from_velocity(VelocityCommand(vx, vy, vz, r))
    assert -1000 <= s.x <= 1000 and -1000 <= s.y <= 1000 and -1000 <= s.r <= 1000 and 0 <= s.z <= 1000
    assert s.buttons == 0
    # never the opposite sign; beyond 1 mm/s always the commanded sign (below that rounding may give 0)
    assert s.x * vx >= 0 and (s.z - 500) * vz <= 0
    assert abs(vx) <= 1e-3 or (s.x > 0) == (vx > 0)
    assert abs(vz) <= 1e-3 or (s.z < 500) == (vz > 0)


@given(st.floats(min_value=0, max_value=2), st.floats(min_value=0, max_value=2))
def test_surge_mapping_monotonic(a: float, b: float) -> None:
    lo, hi = sorted((a, b))
    assert manual_control_from_velocity(VelocityCommand(surge_m_s=lo)).x <= \
        manual_control_from_velocity(VelocityCommand(surge_m_s=hi)).x


def test_non_finite_axes_are_neutral() -> None:
    s = manual_control_from_velocity(VelocityCommand(math.nan, math.inf, -math.inf, math.nan))
    assert s == NEUTRAL_STICKS
    g = guided_from_velocity(VelocityCommand(math.nan, 0.0, 0.0, math.inf))
    assert g.is_zero()


def test_guided_setpoint_frame_mask_and_clamp() -> None:
    g = guided_from_velocity(VelocityCommand(0.3, -0.2, 0.1, 9.0))
    assert (g.frame, g.type_mask) == (8, 1479)
    assert (g.vx_m_s, g.vy_m_s, g.vz_m_s, g.yaw_rate_rad_s) == (0.3, -0.2, 0.1, 1.5)
    assert ZERO_GUIDED.is_zero() and ZERO_GUIDED.yaw_rate_rad_s == 0.0


def test_a_guided_turn_is_a_heading_ahead_that_ends_by_itself() -> None:
    """ArduSub never times out a GUIDED yaw rate: with a hold time the turn is a heading |r| x hold ahead (at least
    GUIDED_MIN_YAW_AHEAD_RAD, beyond the firmware's 5 deg angle-hold band) and the speed |r|."""
    g = guided_from_velocity(VelocityCommand(0.2, 0.0, 0.0, -0.3), heading_rad=1.0, hold_s=1.0)
    assert (g.type_mask, g.yaw_rad, g.yaw_rate_rad_s) == (455, pytest.approx(0.7), pytest.approx(0.3))
    assert g.vx_m_s == pytest.approx(0.2)
    slow = guided_from_velocity(VelocityCommand(yaw_rate_rad_s=0.02), heading_rad=0.0, hold_s=1.0)
    assert (slow.yaw_rad, slow.yaw_rate_rad_s) == (pytest.approx(GUIDED_MIN_YAW_AHEAD_RAD), pytest.approx(0.02))
    wrapped = guided_from_velocity(VelocityCommand(yaw_rate_rad_s=0.5), heading_rad=math.pi - 0.1, hold_s=1.0)
    assert wrapped.yaw_rad == pytest.approx(-math.pi + 0.4)


def test_a_guided_turn_needs_a_known_heading_and_no_turn_is_a_plain_zero_rate() -> None:
    unknown = guided_from_velocity(VelocityCommand(0.2, 0.0, 0.0, 0.3), heading_rad=None, hold_s=1.0)
    assert (unknown.type_mask, unknown.yaw_rate_rad_s, unknown.vx_m_s) == (1479, 0.0, pytest.approx(0.2))
    straight = guided_from_velocity(VelocityCommand(0.2, 0.0, 0.0, 0.0), heading_rad=1.0, hold_s=1.0)
    assert (straight.type_mask, straight.yaw_rate_rad_s, straight.yaw_rad) == (1479, 0.0, None)
    plain = guided_from_velocity(VelocityCommand(0.0, 0.0, 0.0, -0.3), heading_rad=1.0, hold_s=0.0)
    assert (plain.type_mask, plain.yaw_rate_rad_s) == (1479, pytest.approx(-0.3))


def test_type_mask_matches_pymavlink_bits() -> None:
    from pymavlink import mavutil

    m = mavutil.mavlink
    mask = (m.POSITION_TARGET_TYPEMASK_X_IGNORE | m.POSITION_TARGET_TYPEMASK_Y_IGNORE
            | m.POSITION_TARGET_TYPEMASK_Z_IGNORE | m.POSITION_TARGET_TYPEMASK_AX_IGNORE
            | m.POSITION_TARGET_TYPEMASK_AY_IGNORE | m.POSITION_TARGET_TYPEMASK_AZ_IGNORE
            | m.POSITION_TARGET_TYPEMASK_YAW_IGNORE)
    assert mask == 1479 and m.MAV_FRAME_BODY_NED == 8
    assert mask & ~m.POSITION_TARGET_TYPEMASK_YAW_IGNORE == 455


@pytest.mark.parametrize("firmware", ["4.5", "4.7"])
def test_yaw_small_rates_account_for_the_dead_zone(firmware: str) -> None:
    """Issue 13: r = 171 gave 0.097 rad/s on the 4.7 SITL (the old table assumed 0.146)."""
    assert abs(manual_control_from_velocity(VelocityCommand(yaw_rate_rad_s=0.097), firmware).r - 171) <= 1
    assert abs(manual_control_from_velocity(VelocityCommand(yaw_rate_rad_s=0.146), firmware).r - 205) <= 3
    assert manual_control_from_velocity(VelocityCommand(yaw_rate_rad_s=-0.0435), firmware).r == -130


@pytest.mark.parametrize("rate, stick", [(0.211, 250), (0.354, 350), (0.574, 500)])
def test_yaw_4_7_hits_its_measured_points(rate: float, stick: int) -> None:
    assert manual_control_from_velocity(VelocityCommand(yaw_rate_rad_s=rate), "4.7").r == stick
    t = YAW_TABLES["4.7"]
    assert all(a[0] < b[0] and a[1] < b[1] for a, b in zip(t, t[1:]))


def test_small_heave_is_outside_arudsubs_throttle_dead_zone() -> None:
    """Issue 13: 0.15 m/s down mapped to z = 396, inside THR_DZ (z 400..600 does nothing on the SITL)."""
    assert manual_control_from_velocity(VelocityCommand(heave_m_s=0.15)).z < 400
    assert manual_control_from_velocity(VelocityCommand(heave_m_s=-0.15)).z > 600
    assert abs(manual_control_from_velocity(VelocityCommand(heave_m_s=0.192)).z - 320) <= 1


@pytest.mark.parametrize("speed, stick", [(0.115, 130), (0.144, 140), (0.164, 160), (0.206, 200), (0.258, 250),
                                          (-0.164, -160)])
def test_surge_hits_the_4_7_measured_points_above_its_dead_zone(speed: float, stick: int) -> None:
    """Issue 13: x <= 120 gives no thrust on the 4.7 SITL; the old table sent x = 97 for 0.1 m/s."""
    assert manual_control_from_velocity(VelocityCommand(surge_m_s=speed), "4.7").x == stick


def _mean_speed(dither: StickDither, cmd: VelocityCommand, ticks: int = 200) -> tuple[float, float, float]:
    """Mean (surge m/s, yaw rad/s, heave m/s) the pulses stand for, through the measured tables."""
    surge = yaw = heave = 0.0
    for _ in range(ticks):
        s = dither.sticks(cmd)
        surge += math.copysign(dict((p[1], p[0]) for p in SURGE_TABLE)[abs(s.x)], s.x) if s.x else 0.0
        yaw += math.copysign(dict((p[1], p[0]) for p in YAW_TABLES["4.7"])[abs(s.r)], s.r) if s.r else 0.0
        heave += {350: 0.133, 650: -0.133, 500: 0.0}[s.z]
    return surge / ticks, yaw / ticks, heave / ticks


@pytest.mark.parametrize("surge, yaw, heave", [(0.05, 0.02, 0.06), (-0.03, -0.01, -0.1), (0.11, 0.04, 0.13)])
def test_dither_mean_follows_speeds_inside_the_dead_zones(surge: float, yaw: float, heave: float) -> None:
    """Below the first moving stick every pulse is that stick (a steady one would do nothing); the mean follows."""
    d = StickDither("4.7")
    mean = _mean_speed(d, VelocityCommand(surge_m_s=surge, heave_m_s=heave, yaw_rate_rad_s=yaw))
    assert mean == pytest.approx((surge, yaw, heave), abs=0.003)
    for _ in range(20):
        s = d.sticks(VelocityCommand(surge_m_s=surge, heave_m_s=heave, yaw_rate_rad_s=yaw))
        assert s.x in (0, 130, -130) and s.r in (0, 130, -130) and s.z in (350, 500, 650)


def test_dither_zero_is_neutral_at_once_and_steady_above_the_dead_zone() -> None:
    d = StickDither("4.7")
    for _ in range(7):
        d.sticks(VelocityCommand(surge_m_s=0.05, yaw_rate_rad_s=0.03, heave_m_s=0.1))
    assert d.sticks(VelocityCommand()) == NEUTRAL_STICKS  # no pulse left over after a stop
    assert d.sticks(VelocityCommand(surge_m_s=0.01)) == NEUTRAL_STICKS  # the remainder was cleared
    big = VelocityCommand(surge_m_s=0.3, heave_m_s=0.2, yaw_rate_rad_s=0.2)
    assert d.sticks(big) == manual_control_from_velocity(big, "4.7")
    d.reset()
    assert d.sticks(VelocityCommand(surge_m_s=-0.05)).x == 0 and d.sticks(VelocityCommand(surge_m_s=-0.05)).x == -130
