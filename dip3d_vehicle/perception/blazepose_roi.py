"""Regions of interest for BlazePose: letterbox, rotated square ROI from two points, crop maps.

Follows MediaPipe's ImageToTensorCalculator (ROI corners map onto tensor corners, bilinear),
AlignmentPointsRectsCalculator (centre = first point, size = twice the distance to the second,
rotation so that the second point is straight up, target angle 90 degrees) and
RectTransformationCalculator (square_long, scale 1.25). All coordinates are image pixels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

__all__ = ["Roi", "roi_from_points", "letterbox_matrix", "crop_matrix", "warp", "ROI_SCALE"]

ROI_SCALE = 1.25
"""Margin applied to the aligned square (RectTransformationCalculator scale_x/scale_y)."""

_TARGET_ANGLE_RAD = math.pi / 2


@dataclass(frozen=True)
class Roi:
    """A rotated square region of an image.

    Attributes:
        center_px: (x, y) centre, pixels.
        size_px: side length, pixels.
        rotation_rad: rotation, radians, in (-pi, pi]; positive turns the crop clockwise on screen.
    """

    center_px: tuple[float, float]
    size_px: float
    rotation_rad: float

    def shifted(self, dx_px: float, dy_px: float = 0.0) -> "Roi":
        """Return the same ROI moved by (dx, dy) pixels."""
        return Roi((self.center_px[0] + dx_px, self.center_px[1] + dy_px), self.size_px, self.rotation_rad)


def _normalize_radians(angle: float) -> float:
    """Wrap an angle to [-pi, pi), radians (MediaPipe's NormalizeRadians)."""
    return angle - 2 * math.pi * math.floor((angle + math.pi) / (2 * math.pi))


def roi_from_points(center_px: np.ndarray, scale_px: np.ndarray, scale: float = ROI_SCALE) -> Roi:
    """Return the ROI aligned on a centre point and a scale/rotation point, pixels.

    Used with the detector's keypoints 0/1 and with the landmark model's auxiliary points 33/34.
    """
    cx, cy = float(center_px[0]), float(center_px[1])
    dx, dy = float(scale_px[0]) - cx, float(scale_px[1]) - cy
    rotation = _normalize_radians(_TARGET_ANGLE_RAD - math.atan2(-dy, dx))
    return Roi((cx, cy), 2.0 * math.hypot(dx, dy) * scale, rotation)


def letterbox_matrix(width: int, height: int, size: int) -> np.ndarray:
    """Return the 2x3 affine map from image pixels to a ``size`` square letterbox, keeping aspect."""
    side = max(width, height)
    s = size / side
    return np.array([[s, 0.0, (side - width) / 2 * s], [0.0, s, (side - height) / 2 * s]])


def crop_matrix(roi: Roi, size: int) -> np.ndarray:
    """Return the 2x3 affine map from crop pixels (``size`` square) to image pixels."""
    c, s = math.cos(roi.rotation_rad), math.sin(roi.rotation_rad)
    k = roi.size_px / size
    lin = np.array([[c * k, -s * k], [s * k, c * k]])
    offset = np.asarray(roi.center_px, np.float64) - lin @ np.array([size / 2, size / 2])
    return np.c_[lin, offset]


def warp(image: np.ndarray, to_image: np.ndarray, size: int, border: int) -> np.ndarray:
    """Return the ``size`` square crop whose pixel (u, v) samples ``image`` at ``to_image @ [u, v, 1]``."""
    return cv2.warpAffine(image, to_image, (size, size), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                          borderMode=border, borderValue=0)

