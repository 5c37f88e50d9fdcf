"""PointServo: the control law on a hand-computed case, limits, lost target, parameters."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dip3d_vehicle.config import load_params
from dip3d_vehicle.servo.command import NEUTRAL
from dip3d_vehicle.servo.gain import AdaptiveGain
from dip3d_vehicle.servo.ibvs import PointServo
from dip3d_vehicle.servo.mount import CameraMount

F, C = 500.0, (320.0, 240.0)


def _servo(**kw) -> PointServo:
    args = dict(focal_px=F, principal_point_px=C, desired_px=C, standoff_m=1.0,
                gain=AdaptiveGain(0.8, 0.3, 1.0), mount=CameraMount(), axes=("surge", "heave", "yaw"),
                max_speed=(10.0, 10.0, 10.0, 10.0), max_accel=(100.0, 100.0, 100.0, 100.0))
    args.update(kw)
    return PointServo(**args)


def test_law_hand_computed():
    # Target at pixel (420, 190), f = 500, centre (320, 240): x = 0.2, y = -0.1; depth Z = 2, Z* = 1.
    # e = (x - 0, y - 0, Z - Z*) = (0.2, -0.1, 1.0).  Forward camera at the origin, pitch 0:
    # surge -> camera vz, heave -> camera vy, yaw -> camera wy, so J (rows x, y, range; columns
    # surge, heave, yaw) takes these columns of L and of the depth row (see test_point_interaction):
    #   J = [[ 0.10,  0.0, -1.04],
    #        [-0.05, -0.5,  0.02],
    #        [-1.00,  0.0,  0.40]]
    # det J = 0.1 (-0.5 * 0.4) - 1.04 (-(-0.5)(-1)) = -0.02 + 0.52 = 0.5;  Cramer's rule:
    # J^-1 e = (-0.56, 0.15, -0.15) / 0.5 = (-1.12, 0.3, -0.3)
    # (check: row 1: 0.1(-1.12) - 1.04(-0.3) = 0.2; row 3: 1.12 + 0.4(-0.3) = 1.0).
    # lambda(|e|_inf = 1) = 0.5 exp(-2) + 0.3 = 0.367668;  u = -lambda J^-1 e.
    lam = 0.5 * math.exp(-2.0) + 0.3
    u = _servo().law((420.0, 190.0), 2.0)
    expected = [lam * 1.12, 0.0, -lam * 0.3, lam * 0.3]    # surge, sway, heave, yaw
    np.testing.assert_allclose(u, expected, rtol=1e-12)
    np.testing.assert_allclose(u, [0.411788, 0.0, -0.110300, 0.110300], atol=1e-6)
    # far -> forward; target above -> rise (heave < 0); target right -> turn right (yaw > 0)


def test_law_solves_the_feature_equation():
    servo = _servo(mount=CameraMount(0.3, 0.05, -0.1, -0.2), axes=("surge", "sway", "heave", "yaw"))
    J, features, axes = servo.jacobian((500.0, 300.0), 2.5)
    assert features == ["x", "y", "range"] and axes == ["surge", "sway", "heave", "yaw"]
    e = np.array([180.0 / F, 60.0 / F, 1.5])
    u = servo.law((500.0, 300.0), 2.5)
    np.testing.assert_allclose(J @ u, -servo.gain(e) * e, atol=1e-12)     # redundant: J pinv(J) = I


def test_update_saturates_and_rate_limits():
    servo = _servo(max_speed=(0.4, 0.3, 0.3, 0.2), max_accel=(0.3, 0.3, 0.3, 0.6))
    target, depth = (620.0, 40.0), 6.0             # large errors on every controlled axis
    raw = servo.law(target, depth)
    assert raw[0] > 0.4 and raw[2] < -0.3 and raw[3] > 0.2
    first = servo.update(target, depth, 0.1)
    assert (first.surge_m_s, first.heave_m_s, first.yaw_rate_rad_s) == pytest.approx((0.03, -0.03, 0.06))
    assert first.sway_m_s == 0.0
    for _ in range(50):
        cmd = servo.update(target, depth, 0.1)
    assert (cmd.surge_m_s, cmd.heave_m_s, cmd.yaw_rate_rad_s) == pytest.approx((0.4, -0.3, 0.2))
    # a reversal is rate limited too
    back = servo.update((20.0, 440.0), 0.5, 0.1)
    assert back.surge_m_s == pytest.approx(0.37) and back.yaw_rate_rad_s == pytest.approx(0.14)


def test_lost_target_gives_neutral_at_once_and_restarts_from_rest():
    servo = _servo(max_accel=(0.3, 0.3, 0.3, 0.6))
    for _ in range(20):
        servo.update((600.0, 300.0), 4.0, 0.1)
    assert servo.update(None, 4.0, 0.1) is NEUTRAL
    assert servo.last_errors is None
    again = servo.update((600.0, 300.0), 4.0, 0.1)
    assert again.surge_m_s == pytest.approx(0.03)


def test_missing_depth_drops_surge_only():
    servo = _servo()
    for depth in (None, float("nan"), -1.0):
        u = servo.law((420.0, 190.0), depth)
        assert u[0] == 0.0 and u[2] < 0 and u[3] > 0
    errs = servo.errors((420.0, 190.0), None)
    assert errs.range_m is None and errs.du_px == 100.0 and errs.dv_px == -50.0


def test_errors_and_deadband():
    servo = _servo(deadband_px=2.0, deadband_m=0.03)
    errs = servo.errors((321.5, 239.0), 1.02)
    assert errs.du_px == 1.5 and errs.dv_px == -1.0 and errs.range_m == pytest.approx(0.02)
    assert errs.pixel_px == pytest.approx(math.hypot(1.5, 1.0))
    assert np.all(servo.law((321.5, 239.0), 1.02) == 0.0)
    assert servo.update((321.5, 239.0), 1.02, 0.1).is_neutral()
    # outside the band the error is shrunk by it: (12 px, 0 px, 0.1 m) -> (10 px, 0, 0.07 m)
    J, _, _ = servo.jacobian((332.0, 240.0), 1.1)
    e = np.array([10.0 / F, 0.0, 0.07])
    np.testing.assert_allclose(J @ servo.law((332.0, 240.0), 1.1)[[0, 2, 3]], -servo.gain(e) * e, atol=1e-12)


def test_bad_dt():
    with pytest.raises(ValueError, match="dt_s"):
        _servo().update((320.0, 240.0), 1.0, 0.0)


def test_from_params_defaults():
    params = load_params()
    servo = PointServo.from_params(params, 800.0, (640.0, 360.0), image_size_px=(1280, 720))
    assert servo.axes == ("surge", "heave", "yaw")
    assert servo.desired_px == (640.0, 360.0) and servo.standoff_m == 1.0
    assert servo.gain(0.0) == pytest.approx(params["servo.gain_l0"])
    assert servo.mount.forward_m == params["servo.mount_forward_m"]
    np.testing.assert_allclose(servo.max_speed, [0.4, 0.3, 0.3, 0.5])
    other = PointServo.from_params(params.with_overrides({"servo.sway": True, "servo.desired_v_frac": 0.25}),
                                   800.0, (600.0, 350.0))
    assert other.axes == ("surge", "sway", "heave", "yaw") and other.desired_px == (600.0, 175.0)


def test_default_command_grows_with_the_error():
    # lambda(e) e must not fall as |e| grows (holds when linf >= (l0 - linf) exp(-2))
    gain = AdaptiveGain(*(load_params()[k] for k in ("servo.gain_l0", "servo.gain_linf", "servo.gain_slope")))
    e = np.linspace(0.0, 5.0, 2001)
    effort = np.array([gain(v) * v for v in e])
    assert np.all(np.diff(effort) > 0)


def test_speed_feedback_brakes_a_coasting_vehicle():
    """Issue 13: at the stand-off but still closing at 0.1 m/s (coasting in ALT_HOLD), surge asks reverse."""
    coasting = _servo(speed_gain=1.0, speed_filter_s=0.2)
    plain = _servo()
    for k in range(10):  # the target's range falls 0.02 m per 0.2 s frame, through the stand-off
        depth = 1.18 - 0.02 * k  # the last frame is at the stand-off
        cmd = coasting.update(C, depth, 0.2)
        ref = plain.update(C, depth, 0.2)
    assert cmd.surge_m_s < -0.05 and abs(ref.surge_m_s) < 0.01
    # at rest at the stand-off nothing changes; a lost target forgets the rate (no kick on re-acquiring)
    still = _servo(speed_gain=1.0)
    assert all(still.update(C, 1.0, 0.2).surge_m_s == 0.0 for _ in range(5))
    coasting.update(None, None, 0.2)
    assert coasting.update(C, 1.0, 0.2).surge_m_s == 0.0


def test_speed_feedback_parameters_are_checked():
    with pytest.raises(ValueError, match="speed_gain"):
        _servo(speed_gain=-1.0)
    with pytest.raises(ValueError, match="speed_filter_s"):
        _servo(speed_filter_s=0.0)
