"""The tracker's model of the vehicle's motion under a command (behaviours/coast.py)."""

from __future__ import annotations

import math

import pytest

from behaviours.coast import MotionModel
from dip3d_vehicle.config import load_params
from dip3d_vehicle.servo.command import NEUTRAL, VelocityCommand
from sitl.dynamics import Dynamics, Forces, VehicleParams


def _travel(model: MotionModel, commands: list[tuple[VelocityCommand, float]], frame_s: float = 0.1) -> float:
    """Return the surge distance (m) the model predicts over a list of (command, duration_s), frame by frame."""
    v, x = NEUTRAL, 0.0
    for command, duration_s in commands:
        for _ in range(round(duration_s / frame_s)):
            mean, v = model.advance(v, command, frame_s)
            x += mean.surge_m_s * frame_s
    return x


def test_the_zero_model_moves_as_commanded():
    mean, end = MotionModel().advance(VelocityCommand(0.3, -0.1, 0.05, 0.2), VelocityCommand(0.1, 0.2, 0.0, -0.1), 0.5)
    assert mean == end == VelocityCommand(0.1, 0.2, 0.0, -0.1)
    assert MotionModel().advance(VelocityCommand(0.3), None, 0.5) == (NEUTRAL, NEUTRAL)


def test_after_neutral_the_vehicle_coasts_on_against_quadratic_drag():
    """From 0.3 m/s a neutral command leaves L ln(1 + v t / L) of travel (the analytic coast), not zero."""
    model = MotionModel(coast_m=0.25)
    for t_s in (1.0, 3.0):
        mean, end = model.advance(VelocityCommand(surge_m_s=0.3), NEUTRAL, t_s)
        assert mean.surge_m_s * t_s == pytest.approx(0.25 * math.log1p(0.3 * t_s / 0.25), rel=1e-3)
        assert end.surge_m_s == pytest.approx(0.3 / (1.0 + 0.3 * t_s / 0.25), rel=1e-3)
    held, _ = model.advance(VelocityCommand(sway_m_s=-0.2), VelocityCommand(sway_m_s=-0.2), 2.0)
    assert held.sway_m_s == pytest.approx(-0.2)  # a command is the speed its thrust holds steady


def test_a_velocity_loop_and_the_yaw_lag_first_order():
    model = MotionModel(surge_lag_s=0.5, yaw_lag_s=0.6)
    mean, end = model.advance(VelocityCommand(surge_m_s=0.4, yaw_rate_rad_s=0.2), NEUTRAL, 1.0)
    assert mean.surge_m_s == pytest.approx(0.4 * 0.5 * (1 - math.exp(-2.0)))
    assert end.yaw_rate_rad_s == pytest.approx(0.2 * math.exp(-1.0 / 0.6))
    assert mean.heave_m_s == 0.0


def test_the_model_follows_the_simulated_vehicle_in_alt_hold():
    """Thrust that holds the commanded speed, then none: the model's travel matches ``sitl.dynamics`` within 2 cm,
    where moving as commanded falls 0.2 m short."""
    params = load_params(overrides={"behaviour.track_reckoning": "vehicle"})
    vehicle = VehicleParams.from_params(params)
    dynamics, dt_s = Dynamics(vehicle), 0.01
    plan = [(VelocityCommand(surge_m_s=0.3), 3.0), (NEUTRAL, 3.0)]
    for command, duration_s in plan:
        for _ in range(round(duration_s / dt_s)):
            dynamics.step(dt_s, Forces(x_n=vehicle.surge.steady_force(command.surge_m_s)))
    truth_m = dynamics.state.north_m
    model = MotionModel.from_params(params)
    assert model.coast_m == params["behaviour.track_coast_m"]
    assert _travel(model, plan) == pytest.approx(truth_m, abs=0.02)
    assert truth_m - _travel(MotionModel(), plan) > 0.15


def test_the_model_is_chosen_by_the_control_path():
    vehicle = {"behaviour.track_reckoning": "vehicle"}
    guided = MotionModel.from_params(load_params(overrides={**vehicle, "link.output_mode": "guided_velocity"}))
    assert guided.coast_m == 0.0 and guided.surge_lag_s > 0.0
    commands = MotionModel.from_params(load_params(overrides={"behaviour.track_reckoning": "commands"}))
    assert commands == MotionModel()  # as commanded
    default = MotionModel.from_params(load_params())  # vehicle since issue 11 session 60
    assert default == MotionModel.from_params(load_params(overrides=vehicle)) and default.coast_m > 0.0
