"""Point and depth interaction matrices: a hand-computed case and finite differences."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from dip3d_vehicle.servo.interaction import depth_interaction, normalise, point_interaction


def test_point_interaction_hand_computed():
    # x = 0.2, y = -0.1, Z = 2:  1/Z = 0.5, x/Z = 0.1, y/Z = -0.05, x*y = -0.02,
    # 1 + x^2 = 1.04, 1 + y^2 = 1.01.
    L = point_interaction(0.2, -0.1, 2.0)
    expected = np.array([
        [-0.5, 0.0, 0.1, -0.02, -1.04, -0.1],
        [0.0, -0.5, -0.05, 1.01, 0.02, -0.2],
    ])
    np.testing.assert_allclose(L, expected, atol=1e-15)


def test_depth_interaction_hand_computed():
    # [0, 0, -1, -y Z, x Z, 0] with x = 0.2, y = -0.1, Z = 2.
    np.testing.assert_allclose(depth_interaction(0.2, -0.1, 2.0), [[0.0, 0.0, -1.0, 0.2, 0.4, 0.0]], atol=1e-15)


def test_normalise():
    assert normalise((420.0, 190.0), 500.0, (320.0, 240.0)) == pytest.approx((0.2, -0.1))


@pytest.mark.parametrize("depth", [0.0, -1.0, float("nan"), float("inf")])
def test_bad_depth_raises(depth):
    with pytest.raises(ValueError, match="depth_m"):
        point_interaction(0.0, 0.0, depth)
    with pytest.raises(ValueError, match="depth_m"):
        depth_interaction(0.0, 0.0, depth)


def _moved(point_cam: np.ndarray, twist: np.ndarray, dt: float) -> np.ndarray:
    """Return a static point in the camera frame after the camera moved with ``twist`` for dt."""
    rot = Rotation.from_rotvec(twist[3:] * dt).as_matrix()   # new camera axes in old ones
    return rot.T @ (point_cam - twist[:3] * dt)


@settings(max_examples=60, deadline=None)
@given(
    x=st.floats(-0.6, 0.6), y=st.floats(-0.5, 0.5), z=st.floats(0.5, 8.0),
    twist=st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6),
)
def test_finite_difference(x, y, z, twist):
    twist = np.array(twist)
    point = np.array([x * z, y * z, z])
    dt = 1e-6
    # central difference: move forward and backward along the twist
    after, before = _moved(point, twist, dt), _moved(point, -twist, dt)
    rate_xy = ((after[:2] / after[2]) - (before[:2] / before[2])) / (2 * dt)
    rate_z = (after[2] - before[2]) / (2 * dt)
    np.testing.assert_allclose(rate_xy, point_interaction(x, y, z) @ twist, atol=1e-5)
    np.testing.assert_allclose(rate_z, (depth_interaction(x, y, z) @ twist)[0], atol=1e-5)
