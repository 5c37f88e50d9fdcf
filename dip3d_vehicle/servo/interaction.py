"""Interaction matrices of a point feature and of its stereo depth (pure functions).

Camera frame: x right, y down, z forward (optical axis). Camera twist order
``(vx, vy, vz, wx, wy, wz)``: linear velocity of the camera (m/s) then its angular velocity
(rad/s), both expressed in the camera frame. A static point seen at normalised image
coordinates ``(x, y)`` and depth ``Z`` moves as ``d/dt [x, y] = L_point @ twist`` and
``d/dt Z = L_depth @ twist`` (Chaumette & Hutchinson, "Visual servo control I", 2006).
"""

from __future__ import annotations

import numpy as np

__all__ = ["normalise", "point_interaction", "depth_interaction"]


def normalise(point_px: tuple[float, float], focal_px: float,
              principal_point_px: tuple[float, float]) -> tuple[float, float]:
    """Return the normalised image coordinates of a rectified pixel.

    Args:
        point_px: (u, v) rectified left-image pixel.
        focal_px: rectified focal length, pixels.
        principal_point_px: (cx, cy), pixels.

    Returns:
        (x, y) = ((u - cx) / f, (v - cy) / f).
    """
    cx, cy = principal_point_px
    return (float(point_px[0]) - cx) / focal_px, (float(point_px[1]) - cy) / focal_px


def point_interaction(x: float, y: float, depth_m: float) -> np.ndarray:
    """Return the 2x6 interaction matrix of the normalised point ``(x, y)`` at depth ``depth_m``.

    ``L = [[-1/Z, 0, x/Z, x*y, -(1+x^2), y], [0, -1/Z, y/Z, 1+y^2, -x*y, -x]]``.

    Raises:
        ValueError: when the depth is not a positive finite number.
    """
    z = _check_depth(depth_m)
    return np.array([
        [-1.0 / z, 0.0, x / z, x * y, -(1.0 + x * x), y],
        [0.0, -1.0 / z, y / z, 1.0 + y * y, -x * y, -x],
    ])


def depth_interaction(x: float, y: float, depth_m: float) -> np.ndarray:
    """Return the 1x6 interaction row of the point's depth: ``dZ/dt = [0, 0, -1, -y Z, x Z, 0] @ twist``.

    It is also the row of the range error ``e_z = Z - Z*`` (Z* constant).

    Raises:
        ValueError: when the depth is not a positive finite number.
    """
    z = _check_depth(depth_m)
    return np.array([[0.0, 0.0, -1.0, -y * z, x * z, 0.0]])


def _check_depth(depth_m: float) -> float:
    """Return ``depth_m`` as float; raise ValueError unless it is positive and finite."""
    z = float(depth_m)
    if not np.isfinite(z) or z <= 0.0:
        raise ValueError(f"depth_m = {depth_m!r}: expected a positive finite depth in metres")
    return z
