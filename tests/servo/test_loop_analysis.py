"""python-control loop analysis: margins of every axis for the default gains."""

from __future__ import annotations

import pytest

from dip3d_vehicle.config import load_params
from dip3d_vehicle.servo.analysis import (analytic_phase_margin_deg, discrete_margins, loop_margins,
                                          loop_transfer)
from dip3d_vehicle.servo.mount import VEHICLE_AXES


def _show(title: str, margins: dict) -> None:
    print(f"\n{title}")
    for axis, (gm_db, pm_deg, wc) in margins.items():
        print(f"  {axis:6s} gain margin {gm_db:6.2f} dB  phase margin {pm_deg:6.2f} deg  crossover {wc:5.3f} rad/s")


def test_default_phase_margin_at_least_45_deg():
    params = load_params()
    margins = loop_margins(params)
    _show(f"continuous, lambda = l0 = {params['servo.gain_l0']}, latency {params['servo.latency_s']} s "
          f"+ half period {params['servo.sample_period_s'] / 2} s", margins)
    assert set(margins) == set(VEHICLE_AXES)
    for axis, (gm_db, pm_deg, wc) in margins.items():
        assert pm_deg >= 45.0, axis
        assert gm_db >= 10.0, axis
        assert wc > 0.5, axis          # arrival is not sluggish: closed-loop bandwidth ~ l0


def test_python_control_matches_the_closed_form():
    params = load_params()
    delay = params["servo.latency_s"] + params["servo.sample_period_s"] / 2
    for axis, (_gm, pm_deg, wc) in loop_margins(params).items():
        pm_exact, wc_exact = analytic_phase_margin_deg(params["servo.gain_l0"], params[f"servo.tau_{axis}_s"], delay)
        assert pm_deg == pytest.approx(pm_exact, abs=0.2)
        assert wc == pytest.approx(wc_exact, rel=1e-3)


def test_sampled_loop_margins():
    params = load_params()
    margins = discrete_margins(params)
    _show(f"sampled at {params['servo.sample_period_s']} s (ZOH, latency in whole periods)", margins)
    assert all(pm >= 45.0 and gm >= 10.0 for gm, pm, _ in margins.values())


@pytest.mark.parametrize("latency", [0.15, 0.3])
def test_margin_over_the_expected_latency_range(latency):
    params = load_params().with_overrides({"servo.latency_s": latency})
    margins = loop_margins(params)
    _show(f"continuous, latency {latency} s", margins)
    assert all(pm >= 45.0 for _, pm, _ in margins.values())


def test_a_too_high_gain_is_flagged():
    params = load_params()
    assert loop_margins(params, gain=3.0)["yaw"][1] < 45.0
    assert loop_transfer(params, "surge").ninputs == 1
