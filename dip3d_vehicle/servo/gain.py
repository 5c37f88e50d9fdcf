"""The adaptive gain of ViSP's ``vpAdaptiveGain``.

``lambda(x) = (l0 - linf) * exp(-l0' * x / (l0 - linf)) + linf`` where ``x`` is the infinity norm
of the error vector (``vpAdaptiveGain::operator()(const vpColVector &)`` calls
``value(x.infinityNorm())``). ``l0`` is the gain at zero error, ``linf`` the gain for a very large
error and ``l0'`` the slope of ``lambda`` at zero. As in ViSP, ``l0 == linf`` gives a constant gain.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["AdaptiveGain"]


@dataclass(frozen=True)
class AdaptiveGain:
    """Gain that is high near convergence and low for large errors (1/s).

    Attributes:
        l0: gain at zero error, 1/s.
        linf: gain at infinite error, 1/s.
        slope: l0', the magnitude of the slope d(lambda)/d|e| at zero error.
    """

    l0: float
    linf: float
    slope: float

    def __post_init__(self) -> None:
        if not (self.linf > 0.0 and self.l0 >= self.linf):
            raise ValueError(f"AdaptiveGain: need l0 >= linf > 0 (l0={self.l0!r}, linf={self.linf!r})")
        if not self.slope >= 0.0:
            raise ValueError(f"AdaptiveGain: slope = {self.slope!r}, expected >= 0")

    def value(self, norm: float) -> float:
        """Return lambda for an error norm (already reduced to a scalar, >= 0)."""
        a = self.l0 - self.linf
        if a <= np.finfo(float).eps:
            return self.linf + a
        return a * math.exp(-self.slope * float(norm) / a) + self.linf

    def __call__(self, error) -> float:
        """Return lambda(|error|_inf) for a scalar or an error vector, as ViSP does."""
        arr = np.abs(np.asarray(error, dtype=float))
        return self.value(float(arr.max()) if arr.size else 0.0)
