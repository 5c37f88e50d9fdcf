"""The stereo frame: what every source yields and every consumer takes."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["StereoFrame"]


@dataclass(frozen=True)
class StereoFrame:
    """One stereo pair as captured (original, unrectified pixels unless the source says otherwise).

    Attributes:
        left: HxWx3 uint8 BGR image of the left camera.
        right: HxWx3 uint8 BGR image of the right camera.
        stamp_s: capture time, seconds (source clock).
        index: frame counter within the source.
        meta: free-form extras (e.g. simulator ground truth, file names).
    """

    left: np.ndarray
    right: np.ndarray
    stamp_s: float
    index: int = 0
    meta: dict = field(default_factory=dict)
