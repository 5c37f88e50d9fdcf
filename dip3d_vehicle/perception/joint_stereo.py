"""The arm joints' disparity by matching image patches along rectified rows.

BlazePose places a landmark independently in each image; on the simulated diver its left/right
x differ from the true disparity by 10-35 px at 2-3 m (issue 14), i.e. tens of centimetres of
depth, which turns the triangulated arm by tens of degrees. Here each joint's right-image position
is instead found by normalised cross-correlation: the left image's patch around the joint is
searched along the same rectified row of the right image, within ``reach_px`` of the pose
backend's own right-image estimate, with a sub-pixel parabola at the peak. A joint whose best
score stays below ``min_score`` keeps the backend's estimate.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

__all__ = ["match_joint_disparity", "subpixel_peak"]


def _grey(patch: np.ndarray) -> np.ndarray:
    """Return a patch as float32 grey."""
    if patch.ndim == 3:
        patch = cv2.cvtColor(patch, cv2.COLOR_BGR2GRAY)
    return patch.astype(np.float32)


def subpixel_peak(scores: np.ndarray, k: int) -> float:
    """Return the parabola-refined position of peak ``k`` of a 1D score array."""
    if 0 < k < len(scores) - 1:
        a, b, c = scores[k - 1], scores[k], scores[k + 1]
        den = a - 2 * b + c
        if den < 0:
            return k + 0.5 * (a - c) / den
    return float(k)


def match_joint_disparity(left: np.ndarray, right: np.ndarray, left_xy: np.ndarray, right_xy: np.ndarray,
                          sign: int, half_px: int = 12, reach_px: float = 48.0,
                          min_score: float = 0.5) -> np.ndarray:
    """Return (N, 2) right-image joint positions matched from the left ones (rectified pixels).

    Args:
        left, right: rectified images.
        left_xy: (N, 2) joints in the left image.
        right_xy: (N, 2) the backend's estimates in the right image (the search is centred on them).
        sign: the rig's disparity sign (+1: the right image's content lies to the left).
        half_px: half side of the matched patch.
        reach_px: search +- this far around the backend's right x (disparity stays >= 0).
        min_score: lowest accepted normalised cross-correlation.
    """
    h, w = left.shape[:2]
    out = np.array(right_xy, dtype=np.float64, copy=True)
    for k, ((xl, yl), (xr, _)) in enumerate(zip(np.asarray(left_xy, float), np.asarray(right_xy, float))):
        x, y = int(round(xl)), int(round(yl))
        if not (half_px <= x < w - half_px and half_px <= y < h - half_px) or not math.isfinite(xr):
            continue
        lo, hi = xr - reach_px, xr + reach_px
        lo, hi = (lo, min(hi, xl)) if sign > 0 else (max(lo, xl), hi)  # disparity >= 0
        x0, x1 = int(math.floor(lo)) - half_px, int(math.ceil(hi)) + half_px + 1
        x0, x1 = max(0, x0), min(w, x1)
        if x1 - x0 < 2 * half_px + 3:
            continue
        template = _grey(left[y - half_px:y + half_px + 1, x - half_px:x + half_px + 1])
        if float(template.std()) < 1.0:
            continue
        strip = _grey(right[y - half_px:y + half_px + 1, x0:x1])
        scores = cv2.matchTemplate(strip, template, cv2.TM_CCOEFF_NORMED)[0]
        best = int(np.argmax(scores))
        if scores[best] < min_score:
            continue
        out[k] = (x0 + half_px + subpixel_peak(scores, best) + (xl - x), yl)
    return out
