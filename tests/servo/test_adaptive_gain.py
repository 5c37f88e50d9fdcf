"""ViSP's adaptive gain: lambda(|e|_inf) = (l0 - linf) exp(-l0' |e| / (l0 - linf)) + linf."""

from __future__ import annotations

import math

import pytest

from dip3d_vehicle.servo.gain import AdaptiveGain


def test_values_against_the_formula():
    gain = AdaptiveGain(0.8, 0.3, 1.0)       # a = 0.5, b = l0'/a = 2
    assert gain(0.0) == pytest.approx(0.8)
    assert gain(0.3) == pytest.approx(0.5 * math.exp(-0.6) + 0.3)     # 0.574406...
    assert gain(0.3) == pytest.approx(0.574406, abs=1e-6)
    assert gain(1.0) == pytest.approx(0.5 * math.exp(-2.0) + 0.3)     # 0.367668...
    assert gain(100.0) == pytest.approx(0.3)


def test_vector_uses_the_infinity_norm():
    gain = AdaptiveGain(0.8, 0.3, 1.0)
    assert gain([0.1, -0.3, 0.2]) == pytest.approx(gain(0.3))
    assert gain([]) == pytest.approx(0.8)


def test_slope_at_zero_is_l0_prime():
    gain, h = AdaptiveGain(1.666, 0.1666, 1.666), 1e-7
    assert (gain(h) - gain(0.0)) / h == pytest.approx(-1.666, rel=1e-5)


def test_constant_gain_when_l0_equals_linf():
    gain = AdaptiveGain(0.5, 0.5, 3.0)
    assert gain(0.0) == gain(10.0) == pytest.approx(0.5)


@pytest.mark.parametrize("args", [(0.2, 0.3, 1.0), (0.5, 0.0, 1.0), (0.5, 0.3, -1.0)])
def test_invalid(args):
    with pytest.raises(ValueError):
        AdaptiveGain(*args)
