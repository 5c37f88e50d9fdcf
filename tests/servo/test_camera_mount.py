"""Camera mount: body <-> camera axes and the vehicle-velocity -> camera-twist map."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from dip3d_vehicle.servo.interaction import depth_interaction, point_interaction
from dip3d_vehicle.servo.mount import CameraMount


def test_forward_camera_axes():
    # surge = camera +z, sway = camera +x, heave (down) = camera +y, yaw (cw from above) = about camera +y
    M = CameraMount().vehicle_jacobian()
    expected = np.zeros((6, 4))
    expected[2, 0] = expected[0, 1] = expected[1, 2] = expected[4, 3] = 1.0
    np.testing.assert_allclose(M, expected, atol=1e-15)


def test_pure_yaw_with_camera_ahead_of_the_yaw_axis():
    # camera 0.5 m ahead, yaw rate 0.2 rad/s clockwise: w x r = (0, 0, 0.2) x (0.5, 0, 0) = (0, 0.1, 0)
    # in body axes, i.e. 0.1 m/s to the right = camera +x; the camera turns at 0.2 rad/s about its +y.
    twist = CameraMount(forward_m=0.5).camera_twist(yaw_rate_rad_s=0.2)
    np.testing.assert_allclose(twist, [0.1, 0.0, 0.0, 0.0, 0.2, 0.0], atol=1e-15)


def test_pure_yaw_against_the_moving_camera_centre():
    mount, r, dt = CameraMount(forward_m=0.5, right_m=0.1, down_m=0.2, pitch_rad=-0.3), 0.2, 1e-6
    rot = lambda a: np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    velocity_world = (rot(r * dt) @ mount.position_m - rot(-r * dt) @ mount.position_m) / (2 * dt)
    v_cam = mount.rotation_body_from_camera().T @ velocity_world      # at yaw 0 world = body axes
    np.testing.assert_allclose(mount.camera_twist(yaw_rate_rad_s=r)[:3], v_cam, atol=1e-8)


def test_pitch_up_tilts_the_optical_axis_up():
    mount = CameraMount(pitch_rad=0.3)
    axis_body = mount.rotation_body_from_camera() @ [0.0, 0.0, 1.0]
    np.testing.assert_allclose(axis_body, [math.cos(0.3), 0.0, -math.sin(0.3)], atol=1e-15)
    # moving forward moves the up-tilted camera along its z and its (down-pointing) y
    np.testing.assert_allclose(mount.camera_twist(surge_m_s=1.0)[:3], [0.0, math.sin(0.3), math.cos(0.3)], atol=1e-15)


def test_point_round_trip():
    mount = CameraMount(0.3, -0.1, 0.2, 0.4)
    p = np.array([1.0, -2.0, 3.0])
    np.testing.assert_allclose(mount.body_point(mount.camera_point(p)), p, atol=1e-12)
    np.testing.assert_allclose(mount.camera_point(mount.position_m), 0.0, atol=1e-15)


def _features(mount: CameraMount, target_world: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """Return (x, y, Z) of a world point seen from a vehicle at pose (n, e, d, yaw)."""
    c, s = math.cos(pose[3]), math.sin(pose[3])
    rz = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    p_cam = mount.camera_point(rz.T @ (target_world - pose[:3]))
    return np.array([p_cam[0] / p_cam[2], p_cam[1] / p_cam[2], p_cam[2]])


def _step(pose: np.ndarray, u: np.ndarray, dt: float) -> np.ndarray:
    """Return the pose after moving with body velocity u = (surge, sway, heave, yaw rate) for dt (exact)."""
    n, e, d, yaw = pose
    # constant body velocity while turning at rate r, integrated in closed form (numerically
    # stable for r -> 0): the integral of (cos, sin)(yaw + r t) over dt is
    # dt * sinc(r dt / 2) * (cos, sin)(yaw + r dt / 2).
    mid, shrink = yaw + u[3] * dt / 2, dt * np.sinc(u[3] * dt / 2 / np.pi)
    dn = shrink * (u[0] * math.cos(mid) - u[1] * math.sin(mid))
    de = shrink * (u[0] * math.sin(mid) + u[1] * math.cos(mid))
    return np.array([n + dn, e + de, d + u[2] * dt, yaw + u[3] * dt])


@settings(max_examples=40, deadline=None)
@given(u=st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4),
       pitch=st.floats(-0.8, 0.8), fwd=st.floats(-0.5, 0.5), down=st.floats(-0.3, 0.3))
def test_vehicle_jacobian_predicts_feature_motion(u, pitch, fwd, down):
    mount = CameraMount(forward_m=fwd, right_m=0.05, down_m=down, pitch_rad=pitch)
    pose = np.array([0.0, 0.0, 5.0, 0.4])
    target = pose[:3] + np.array([2.5 * math.cos(0.5), 2.5 * math.sin(0.5), -0.4 - 2.0 * math.sin(pitch)])
    u, dt = np.array(u), 1e-6
    x, y, z = _features(mount, target, pose)
    assume(z > 0.5)
    rate = (_features(mount, target, _step(pose, u, dt)) - _features(mount, target, _step(pose, -u, dt))) / (2 * dt)
    L = np.vstack([point_interaction(x, y, z), depth_interaction(x, y, z)])
    np.testing.assert_allclose(rate, L @ mount.vehicle_jacobian() @ u, atol=1e-5)
