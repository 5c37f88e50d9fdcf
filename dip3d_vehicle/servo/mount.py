"""The camera mount: where the camera sits on the vehicle and how twists map between the two.

Body frame (vehicle): x forward, y right, z down; yaw rate positive clockwise seen from above
(about +z). Camera frame: x right, y down, z forward. The mount pitch is a rotation of the camera
about the body y axis by the right-hand rule, so a positive pitch tilts the optical axis UP
(aerospace nose-up convention); a camera looking down at the sea floor has a negative pitch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CameraMount", "VEHICLE_AXES"]

VEHICLE_AXES: tuple[str, ...] = ("surge", "sway", "heave", "yaw")
"""The vehicle axes the servo may command, in the order of the columns of ``vehicle_jacobian``."""

# Camera axes expressed in body axes for a forward-looking camera with zero pitch:
# camera x (right) = body y, camera y (down) = body z, camera z (forward) = body x.
_R_BODY_CAM0 = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def _skew(p: np.ndarray) -> np.ndarray:
    """Return the matrix [p]x with [p]x @ q = p x q."""
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


@dataclass(frozen=True)
class CameraMount:
    """Pose of the (rectified left) camera in the vehicle body frame.

    Attributes:
        forward_m, right_m, down_m: camera optical centre in body axes from the vehicle's
            reference point (the point whose velocity the autopilot controls, on the yaw axis), m.
        pitch_rad: camera tilt about the body y axis, positive = optical axis up, rad.
    """

    forward_m: float = 0.0
    right_m: float = 0.0
    down_m: float = 0.0
    pitch_rad: float = 0.0

    @property
    def position_m(self) -> np.ndarray:
        """Camera centre in body axes, m."""
        return np.array([self.forward_m, self.right_m, self.down_m], dtype=float)

    def rotation_body_from_camera(self) -> np.ndarray:
        """Return R (3x3) with ``p_body = R @ p_cam + position_m`` (columns: camera axes in body)."""
        c, s = math.cos(self.pitch_rad), math.sin(self.pitch_rad)
        r_y = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
        return r_y @ _R_BODY_CAM0

    def camera_from_body_twist(self) -> np.ndarray:
        """Return the 6x6 matrix mapping a body twist (v_b, w_b) to the camera twist (v_c, w_c).

        The camera centre moves with ``v_b + w_b x p`` (p = ``position_m``); both are then
        expressed in camera axes: ``v_c = R^T (v_b - [p]x w_b)``, ``w_c = R^T w_b``.
        """
        rt = self.rotation_body_from_camera().T
        out = np.zeros((6, 6))
        out[:3, :3] = rt
        out[:3, 3:] = -rt @ _skew(self.position_m)
        out[3:, 3:] = rt
        return out

    def vehicle_jacobian(self) -> np.ndarray:
        """Return the 6x4 camera twist per unit (surge m/s, sway m/s, heave m/s, yaw rate rad/s).

        Roll and pitch rates are taken as zero (the autopilot stabilises them).
        """
        return self.camera_from_body_twist()[:, [0, 1, 2, 5]]

    def camera_twist(self, surge_m_s: float = 0.0, sway_m_s: float = 0.0, heave_m_s: float = 0.0,
                     yaw_rate_rad_s: float = 0.0) -> np.ndarray:
        """Return the camera twist (vx, vy, vz, wx, wy, wz) for a vehicle velocity command."""
        return self.vehicle_jacobian() @ np.array([surge_m_s, sway_m_s, heave_m_s, yaw_rate_rad_s])

    def body_point(self, point_cam_m) -> np.ndarray:
        """Return a camera-frame point in body axes, m."""
        return self.rotation_body_from_camera() @ np.asarray(point_cam_m, dtype=float) + self.position_m

    def camera_point(self, point_body_m) -> np.ndarray:
        """Return a body-frame point in camera axes, m."""
        return self.rotation_body_from_camera().T @ (np.asarray(point_body_m, dtype=float) - self.position_m)
