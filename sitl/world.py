"""Geometry of the synthetic world: vehicle pose, camera mount, frames and projection.

Frames:

- World: NED, metres: ``north_m``, ``east_m``, ``down_m`` (depth, positive down).
- Vehicle body: forward, right, down (FRD); the vehicle only yaws (``yaw_rad`` 0 = facing north,
  clockwise seen from above positive), roll and pitch are zero.
- Camera mount: position in body axes (forward, right, down) and a pitch (positive = looking up,
  aerospace convention) and yaw (positive = to the right) of the left camera.
- Camera optical frame (OpenCV): x right, y down, z forward. The right camera follows OpenCV's
  stereo convention ``X_right = R X_left + T`` (T in metres).

A camera pose is stored as ``(R_cw, t_cw)`` with ``X_cam = R_cw @ X_world + t_cw``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import cv2
import numpy as np

__all__ = [
    "VehiclePose", "CameraPose", "rot_x", "rot_y", "rot_z", "R_BODY_FROM_OPTICAL",
    "left_camera_pose", "right_camera_pose", "project_pinhole", "project_distorted",
    "unit", "perpendicular_basis",
]


class VehiclePose(NamedTuple):
    """Vehicle pose in the world: NED position (metres) and yaw (rad, 0 = north, clockwise +)."""

    north_m: float
    east_m: float
    depth_m: float
    yaw_rad: float


class CameraPose(NamedTuple):
    """Camera extrinsics: ``X_cam = R_cw @ X_world + t_cw``; ``centre_w`` is the optical centre."""

    R_cw: np.ndarray
    t_cw: np.ndarray

    @property
    def centre_w(self) -> np.ndarray:
        """Optical centre in world (NED) coordinates, metres."""
        return -self.R_cw.T @ self.t_cw

    def to_cam(self, points_w) -> np.ndarray:
        """Map (N, 3) world points to (N, 3) camera-frame points, metres."""
        pts = np.asarray(points_w, dtype=np.float64).reshape(-1, 3)
        return pts @ self.R_cw.T + self.t_cw


def rot_x(a: float) -> np.ndarray:
    """Rotation matrix about x by ``a`` rad (right-handed)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(a: float) -> np.ndarray:
    """Rotation matrix about y by ``a`` rad (right-handed)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1.0, 0], [-s, 0, c]])


def rot_z(a: float) -> np.ndarray:
    """Rotation matrix about z by ``a`` rad (right-handed)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


R_BODY_FROM_OPTICAL = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
"""Columns: the optical x (right), y (down), z (forward) axes in body FRD axes (zero mount)."""


def left_camera_pose(pose: VehiclePose, mount_frd_m, mount_pitch_rad: float,
                     mount_yaw_rad: float = 0.0) -> CameraPose:
    """Return the left camera's pose for a vehicle pose and a camera mount.

    Args:
        pose: vehicle pose (NED, yaw).
        mount_frd_m: camera position in body axes (forward, right, down), metres.
        mount_pitch_rad: camera pitch, positive looking up.
        mount_yaw_rad: camera yaw relative to the body, positive to the right.

    Returns:
        The camera pose (world -> left optical frame).
    """
    R_wb = rot_z(pose.yaw_rad)
    # In FRD, a positive rotation about the right (y) axis lifts the forward axis: nose up.
    R_bc = rot_z(mount_yaw_rad) @ rot_y(mount_pitch_rad) @ R_BODY_FROM_OPTICAL
    R_wc = R_wb @ R_bc
    centre = np.array([pose.north_m, pose.east_m, pose.depth_m]) + R_wb @ np.asarray(mount_frd_m, float)
    R_cw = R_wc.T
    return CameraPose(R_cw, -R_cw @ centre)


def right_camera_pose(left: CameraPose, R: np.ndarray, T: np.ndarray) -> CameraPose:
    """Return the right camera's pose from the left one and OpenCV's ``X_right = R X_left + T``."""
    T = np.asarray(T, float).reshape(3)
    return CameraPose(R @ left.R_cw, R @ left.t_cw + T)


def project_pinhole(points_cam: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Project (N, 3) camera-frame points with an ideal pinhole ``K``; returns (N, 2) pixels."""
    z = points_cam[:, 2:3]
    u, v = points_cam[:, 0:1] / z, points_cam[:, 1:2] / z
    return np.hstack([K[0, 0] * u + K[0, 1] * v + K[0, 2], K[1, 1] * v + K[1, 2]])


def project_distorted(points_cam: np.ndarray, K: np.ndarray, D: np.ndarray) -> np.ndarray:
    """Project (N, 3) camera-frame points with lens distortion (cv2.projectPoints); (N, 2) px."""
    pts = np.asarray(points_cam, dtype=np.float64).reshape(-1, 1, 3)
    if len(pts) == 0:
        return np.zeros((0, 2))
    img, _ = cv2.projectPoints(pts, np.zeros(3), np.zeros(3), K, np.asarray(D, float).reshape(1, -1))
    return img.reshape(-1, 2)


def unit(v) -> np.ndarray:
    """Return ``v`` normalised (float64)."""
    v = np.asarray(v, dtype=np.float64)
    n = np.linalg.norm(v)
    return v / n if n > 0 else v


def perpendicular_basis(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return two unit vectors orthogonal to the unit vector ``d`` and to each other."""
    helper = np.array([0.0, 0.0, 1.0]) if abs(d[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    u = unit(np.cross(d, helper))
    return u, np.cross(d, u)
