"""A tracked pose's landmarks smoothed over frames: a One Euro filter (Casiez et al., CHI 2012), per frame.

BlazePose's landmarks jitter from frame to frame: with the diver at 4.5-5 m (an arm of ~35 px) the arm's
left-image shoulder-to-wrist direction moved by a median 0.085 rad between frames of a held point, white
(lag-1 autocorrelation -0.15), where truth plus the scenario's noise moves it by 0.023 rad (issue 14); smoothed
with the schema's setting, 0.018 rad. Off by default (``blazepose.smoothing``: the missions did not change
beyond chance, issue 11 session 68). MediaPipe's own video graph smooths its pose landmarks the same way (a One Euro filter on
landmarks scaled by the body's size); here the filter runs in frames, not seconds (a pose frame carries no
stamp), and speeds are measured in body sizes (the ROI's side) per frame, so one setting holds at every range.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["LandmarkSmoother", "weight"]

DERIVATIVE_CUTOFF = 0.16
"""Cutoff of the filter's own speed estimate, cycles per frame (a new frame's weight 0.5)."""


def weight(cutoff_per_frame: float | np.ndarray) -> float | np.ndarray:
    """Return a new frame's weight in a first-order low-pass with this cutoff (cycles per frame; arrays too)."""
    r = 2.0 * math.pi * cutoff_per_frame
    return r / (1.0 + r)


class LandmarkSmoother:
    """One Euro filter over a tracked pose's (N, 2) landmark pixels, each coordinate on its own.

    Args:
        min_cutoff: cutoff at rest, cycles per frame (0.05: a still landmark's new frame weighs 0.24).
        beta: how fast the cutoff rises with a landmark's speed, cycles per frame per (body size per frame).
        jump: a landmark moving further than this in one frame (body sizes) restarts the filter from that
            frame: the pose model swapped sides or found someone else, not a motion to smooth.
    """

    def __init__(self, min_cutoff: float, beta: float, jump: float) -> None:
        self.min_cutoff = float(min_cutoff)
        self.beta = float(beta)
        self.jump = float(jump)
        self._xy: np.ndarray | None = None      # the last smoothed landmarks, pixels
        self._speed: np.ndarray | None = None   # their smoothed speed, body sizes per frame

    def reset(self) -> None:
        """Forget the past frames (a new track)."""
        self._xy = self._speed = None

    def smooth(self, xy_px: np.ndarray, size_px: float) -> np.ndarray:
        """Return this frame's smoothed landmarks (pixels) from its raw ones and the body's size (pixels)."""
        xy = np.asarray(xy_px, float)
        if self._xy is None or self._xy.shape != xy.shape or size_px <= 0:
            return self._restart(xy)
        step = (xy - self._xy) / size_px
        if np.max(np.hypot(step[:, 0], step[:, 1])) > self.jump:
            return self._restart(xy)
        self._speed = self._speed + weight(DERIVATIVE_CUTOFF) * (np.abs(step) - self._speed)
        new = weight(self.min_cutoff + self.beta * self._speed)
        self._xy = self._xy + new * (xy - self._xy)
        return self._xy.copy()

    def _restart(self, xy: np.ndarray) -> np.ndarray:
        """Start the filter at ``xy`` (pixels) and return it."""
        self._xy, self._speed = xy.copy(), np.zeros_like(xy)
        return xy.copy()
