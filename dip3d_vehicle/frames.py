"""The stereo frame: what every source yields and every consumer takes."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["StereoFrame", "FrameGuard"]


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


class FrameGuard:
    """The perception boundary's check of each camera frame: reject what cannot be trusted.

    Rejected (counted in ``rejected`` by reason): a missing eye, an empty or black eye (every pixel
    below ``black_level``), a size other than ``image_size`` (w, h) or different between eyes, a
    stamp not later than the previous accepted frame's, an index not larger than the previous one.

    Args:
        image_size: expected (width, height), or None to learn it from the first frame.
        black_level: a frame whose brightest pixel is below this is black.
    """

    def __init__(self, image_size: tuple[int, int] | None = None, black_level: int = 8) -> None:
        self.image_size, self.black_level = image_size, black_level
        self.last_stamp_s: float | None = None
        self.last_index: int | None = None
        self.rejected: dict[str, int] = {}
        self.accepted = 0

    def check(self, frame: StereoFrame | None) -> str:
        """Return "" when ``frame`` may be processed, else the reason it is rejected (and count it)."""
        reason = self._reason(frame)
        if reason:
            self.rejected[reason] = self.rejected.get(reason, 0) + 1
            return reason
        self.accepted += 1
        self.last_stamp_s, self.last_index = frame.stamp_s, frame.index
        return ""

    def _reason(self, frame: StereoFrame | None) -> str:
        if frame is None:
            return "no frame"
        for eye in ("left", "right"):
            img = getattr(frame, eye)
            if img is None or not isinstance(img, np.ndarray) or img.ndim < 2 or img.size == 0:
                return f"{eye} eye missing"
        if frame.left.shape != frame.right.shape:
            return "eyes differ in size"
        h, w = frame.left.shape[:2]
        if self.image_size is None:
            self.image_size = (w, h)
        if (w, h) != tuple(self.image_size):
            return "wrong image size"
        if not math.isfinite(frame.stamp_s):
            return "stamp not finite"
        if self.last_stamp_s is not None and frame.stamp_s <= self.last_stamp_s:
            return "stamp not increasing"
        if self.last_index is not None and frame.index <= self.last_index:
            return "frame out of order"
        if int(frame.left.max()) < self.black_level or int(frame.right.max()) < self.black_level:
            return "black frame"
        return ""
