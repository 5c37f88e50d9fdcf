"""Sparse triangulation with OpenCV's Q matrix: [x, y, d, 1] -> (X, Y, Z) / W, metres."""

from __future__ import annotations

import numpy as np

__all__ = ["normalize_q", "triangulate"]


def normalize_q(Q: np.ndarray, disparity_sign: int = 1) -> np.ndarray:
    """Return Q with signs fixed so that a disparity of sign ``disparity_sign`` gives Z > 0.

    The paper prints ``-f`` in row 3 and Tx's sign convention varies between tools; rather than
    trust either, check the depth of a point on the optical axis and flip the f entry if needed.
    """
    Q = np.array(Q, dtype=np.float64, copy=True)
    probe = Q @ np.array([Q[0, 3] * -1.0, Q[1, 3] * -1.0, float(disparity_sign), 1.0])
    if probe[3] != 0 and probe[2] / probe[3] < 0:
        Q[2, 3] = -Q[2, 3]
    return Q


def triangulate(Q: np.ndarray, left_px, disparity_px) -> np.ndarray:
    """Return (N, 3) points in the rectified left camera frame, metres (NaN where W == 0).

    Args:
        Q: 4x4 reprojection matrix (from cv2.stereoRectify or a file).
        left_px: (N, 2) rectified left-image pixels.
        disparity_px: (N,) disparities x_left - x_right, pixels.
    """
    pts = np.asarray(left_px, dtype=np.float64).reshape(-1, 2)
    d = np.asarray(disparity_px, dtype=np.float64).reshape(-1)
    rows = np.empty((len(d), 4))  # [x, y, d, 1]; filled in place (np.c_ costs 3x the rest for one point)
    rows[:, :2], rows[:, 2], rows[:, 3] = pts, d, 1.0
    hom = rows @ np.asarray(Q, dtype=np.float64).T
    with np.errstate(divide="ignore", invalid="ignore"):
        xyz = hom[:, :3] / hom[:, 3:4]
    bad = ~np.isfinite(xyz).all(axis=1)
    if bad.any():
        xyz[bad] = np.nan
    return xyz
