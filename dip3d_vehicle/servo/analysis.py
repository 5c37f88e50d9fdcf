"""Loop analysis of the servo with python-control: margins of each vehicle axis for given gains.

Model of one axis (small errors, so the adaptive gain is at its largest, ``l0``; saturation and
rate limits inactive). With ``u = -lambda pinv(J) e`` and ``de/dt = J v`` the error channels
decouple when the vehicle follows its commands; each axis then closes the loop

    L(s) = lambda * exp(-s T) / (s (tau s + 1))

where ``1/(tau s + 1)`` is the vehicle's velocity response to a setpoint (first order, time
constant = the measured t63, ``servo.tau_<axis>_s``), ``1/s`` integrates the velocity into the
feature, and ``T = servo.latency_s + servo.sample_period_s / 2`` is the perception latency plus
the mean delay of holding the command for one servo period (zero-order hold), approximated by
``control.pade``. ``discrete_margins`` checks the same loop sampled at the servo period instead
(exact ZOH discretisation, latency rounded up to whole periods).
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import control
import numpy as np

from .mount import VEHICLE_AXES

__all__ = ["loop_transfer", "loop_margins", "discrete_loop_transfer", "discrete_margins",
           "analytic_phase_margin_deg"]

PADE_ORDER = 5
"""Order of the Pade approximation of the latency (accurate in phase well past crossover)."""


def _axis_values(params: Mapping, axis: str, gain: float | None) -> tuple[float, float, float, float]:
    """Return (lambda, tau_s, latency_s, period_s) of one axis from the parameters."""
    if axis not in VEHICLE_AXES:
        raise ValueError(f"unknown axis {axis!r} (expected one of {VEHICLE_AXES})")
    lam = float(params["servo.gain_l0"] if gain is None else gain)
    return lam, float(params[f"servo.tau_{axis}_s"]), float(params["servo.latency_s"]), \
        float(params["servo.sample_period_s"])


def loop_transfer(params: Mapping, axis: str, gain: float | None = None) -> control.TransferFunction:
    """Return the continuous open-loop transfer function of one axis.

    Args:
        params: effective parameters (``servo.*``).
        axis: one of ``VEHICLE_AXES``.
        gain: loop gain lambda, 1/s; default ``servo.gain_l0`` (the largest the law uses).

    Returns:
        ``lambda * pade(T) / (s (tau s + 1))``.
    """
    lam, tau, latency, period = _axis_values(params, axis, gain)
    delay = latency + period / 2.0
    num, den = control.pade(delay, PADE_ORDER) if delay > 0 else ([1.0], [1.0])
    return lam * control.tf(num, den) * control.tf([1.0], [tau, 1.0, 0.0])


def _margins(loop) -> tuple[float, float, float]:
    """Return (gain margin dB, phase margin deg, gain crossover rad/s) of a loop.

    Sampled loops use the frequency-response method ('poly' is ill-conditioned for them).
    """
    method = "frd" if loop.isdtime(strict=True) else "best"
    gm, pm, _sm, _wpc, wgc, _wms = control.stability_margins(loop, method=method)
    gm_db = 20.0 * math.log10(gm) if gm is not None and np.isfinite(gm) and gm > 0 else math.inf
    return gm_db, float(pm), float(wgc)


def loop_margins(params: Mapping, axes: Sequence[str] = VEHICLE_AXES,
                 gain: float | None = None) -> dict[str, tuple[float, float, float]]:
    """Return ``{axis: (gain margin dB, phase margin deg, crossover rad/s)}`` of the continuous loops.

    Every axis is analysed, enabled or not (a disabled axis may be switched on by a profile).
    """
    return {axis: _margins(loop_transfer(params, axis, gain)) for axis in axes}


def discrete_loop_transfer(params: Mapping, axis: str, gain: float | None = None) -> control.TransferFunction:
    """Return the open loop sampled at ``servo.sample_period_s``: ZOH plant times ``z^-k`` latency.

    ``k = ceil(servo.latency_s / servo.sample_period_s)`` whole periods.
    """
    lam, tau, latency, period = _axis_values(params, axis, gain)
    plant = control.c2d(control.tf([1.0], [tau, 1.0, 0.0]), period, method="zoh")
    k = int(math.ceil(latency / period - 1e-9))
    delay = control.tf([1.0], [1.0] + [0.0] * k, period)
    return lam * plant * delay


def discrete_margins(params: Mapping, axes: Sequence[str] = VEHICLE_AXES,
                     gain: float | None = None) -> dict[str, tuple[float, float, float]]:
    """Return ``{axis: (gain margin dB, phase margin deg, crossover rad/s)}`` of the sampled loops."""
    return {axis: _margins(discrete_loop_transfer(params, axis, gain)) for axis in axes}


def analytic_phase_margin_deg(gain: float, tau_s: float, delay_s: float) -> tuple[float, float]:
    """Return (phase margin deg, crossover rad/s) of ``gain e^{-sT} / (s (tau s + 1))`` in closed form.

    Crossover solves ``w sqrt(1 + (w tau)^2) = gain``; the phase there is
    ``-90 deg - atan(w tau) - w T``. Used to cross-check python-control.
    """
    w2 = (-1.0 + math.sqrt(1.0 + 4.0 * tau_s ** 2 * gain ** 2)) / (2.0 * tau_s ** 2) if tau_s > 0 else gain ** 2
    w = math.sqrt(w2)
    return 90.0 - math.degrees(math.atan(w * tau_s) + w * delay_s), w
