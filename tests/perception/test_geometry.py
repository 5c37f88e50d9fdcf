"""Property tests of the stereo geometry: original pixels -> rectified -> Q triangulation -> 3D.

Random calibrations (focal, size, principal point, small distortion, small rotation, baseline on
either side) and random 3D points visible in both cameras: projecting them with
``cv2.projectPoints``, mapping to rectified pixels with the rig and triangulating with Q must give
the points back, in front of the camera, whatever the sign conventions of Tx and of Q's f entry.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from hypothesis import event, given, settings, target
from hypothesis import strategies as st

from dip3d_vehicle.perception.calibration import StereoRig
from dip3d_vehicle.perception.triangulation import normalize_q, triangulate

N_POINTS = 40
DEPTH_TOL = 0.005  # 0.5 % of depth
SETTINGS = settings(derandomize=True, max_examples=150, deadline=None)
QUICK = settings(SETTINGS, max_examples=60)  # the cheaper companion properties


@dataclass(frozen=True)
class Scene:
    """A random calibration, its rig and 3D points (original left camera frame, metres)."""

    K1: np.ndarray
    D1: np.ndarray
    K2: np.ndarray
    D2: np.ndarray
    R: np.ndarray
    T: np.ndarray
    size: tuple[int, int]
    alpha: float
    points_m: np.ndarray

    def rig(self) -> StereoRig:
        """Return the rig of this calibration."""
        return StereoRig.from_parameters(self.K1, self.D1, self.K2, self.D2, self.R, self.T, self.size,
                                         alpha=self.alpha)


def _small(draw, bound: float) -> float:
    """Draw a float in [-bound, bound]."""
    return draw(st.floats(-bound, bound, allow_nan=False, allow_infinity=False))


def _camera(draw, w: int, h: int) -> tuple[np.ndarray, np.ndarray]:
    """Draw (K, D): focal 400-2000 px (field of view <= 90 deg), centre +-5 %, small distortion."""
    f = draw(st.floats(max(400.0, 0.5 * w), 2000.0))
    fy = f * draw(st.floats(0.995, 1.005))
    cx, cy = w / 2 + _small(draw, 0.05 * w), h / 2 + _small(draw, 0.05 * h)
    K = np.array([[f, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]])
    D = np.array([_small(draw, 0.1), _small(draw, 0.02), _small(draw, 0.002), _small(draw, 0.002), 0.0])
    return K, D


def _visible(points: np.ndarray, K: np.ndarray, D: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """Return which camera-frame points are in front and inside the image (undistorted and distorted)."""
    w, h = size
    z = points[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = K[0, 0] * points[:, 0] / z + K[0, 2]
        v = K[1, 1] * points[:, 1] / z + K[1, 2]
    px, _ = cv2.projectPoints(points.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D)
    px = px.reshape(-1, 2)
    inside = lambda x, y: (x >= 0) & (x <= w - 1) & (y >= 0) & (y <= h - 1)  # noqa: E731
    return (z > 0.1) & inside(u, v) & inside(px[:, 0], px[:, 1])


@st.composite
def scenes(draw) -> Scene:
    """Draw a stereo calibration and points at 1-5 m visible in both cameras."""
    w = draw(st.integers(640, 1600))
    h = int(round(w * 0.75))
    K1, D1 = _camera(draw, w, h)
    K2, D2 = _camera(draw, w, h)
    axis = np.array([_small(draw, 1.0), _small(draw, 1.0), _small(draw, 1.0)]) + np.array([1e-3, 0, 0])
    angle = np.deg2rad(draw(st.floats(0.0, 2.0)))
    R, _ = cv2.Rodrigues(axis / np.linalg.norm(axis) * angle)
    baseline = draw(st.floats(0.05, 0.3))
    right_of_left = draw(st.booleans())  # camera centre C = -R^T T to the right: T_x < 0
    T = np.array([-baseline if right_of_left else baseline, _small(draw, 0.05 * baseline),
                  _small(draw, 0.05 * baseline)])
    alpha = draw(st.sampled_from([0.0, 1.0, -1.0]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    n = 6 * N_POINTS
    depth = rng.uniform(1.0, 5.0, n)
    pix = np.c_[rng.uniform(0, w - 1, n), rng.uniform(0, h - 1, n)]
    rays = np.c_[(pix[:, 0] - K1[0, 2]) / K1[0, 0], (pix[:, 1] - K1[1, 2]) / K1[1, 1], np.ones(n)]
    pts = rays * depth[:, None]
    keep = _visible(pts, K1, D1, (w, h)) & _visible(pts @ R.T + T, K2, D2, (w, h))
    return Scene(K1, D1, K2, D2, R, T, (w, h), alpha, pts[keep][:N_POINTS])


def _project(points: np.ndarray, R: np.ndarray, T: np.ndarray, K: np.ndarray, D: np.ndarray) -> np.ndarray:
    """Project left-frame points into a camera at pose (R, T): original distorted pixels."""
    rvec, _ = cv2.Rodrigues(R)
    px, _ = cv2.projectPoints(points.reshape(-1, 1, 3), rvec, np.asarray(T, float), K, D)
    return px.reshape(-1, 2)


def _observe(scene: Scene, rig: StereoRig) -> tuple[np.ndarray, np.ndarray]:
    """Return the scene points' rectified (left, right) pixels."""
    left = _project(scene.points_m, np.eye(3), np.zeros(3), scene.K1, scene.D1)
    right = _project(scene.points_m, scene.R, scene.T, scene.K2, scene.D2)
    return rig.to_rectified(left, "left"), rig.to_rectified(right, "right")


@SETTINGS
@given(scenes())
def test_triangulation_recovers_points_in_the_original_frame(scene):
    n = len(scene.points_m)
    event(f"points in both views: {'none' if n == 0 else '1-9' if n < 10 else '10+'}")
    if len(scene.points_m) == 0:
        return  # a wide baseline at close range can leave no point in both views
    rig = scene.rig()
    event(f"right camera to the {'right' if rig.disparity_sign > 0 else 'left'}")
    left, right = _observe(scene, rig)
    assert np.max(np.abs(left[:, 1] - right[:, 1])) < 0.01  # rectified rows agree
    disparity = left[:, 0] - right[:, 0]
    assert np.all(np.sign(disparity) == rig.disparity_sign)
    xyz_rect = triangulate(normalize_q(rig.Q, rig.disparity_sign), left, disparity)
    xyz = xyz_rect @ rig.R1  # X_orig = R1^T X_rect, row-wise
    depth = scene.points_m[:, 2]
    rel = np.abs(xyz[:, 2] - depth) / depth
    target(float(rel.max()), label="max relative depth error")
    assert np.all(xyz_rect[:, 2] > 0)
    assert np.all(rel < DEPTH_TOL)
    assert np.all(np.linalg.norm(xyz - scene.points_m, axis=1) < DEPTH_TOL * depth)


@QUICK
@given(scenes())
def test_depth_is_positive_whatever_the_sign_conventions(scene):
    if len(scene.points_m) == 0:
        return
    rig = scene.rig()
    left, right = _observe(scene, rig)
    disparity = left[:, 0] - right[:, 0]
    expected = triangulate(normalize_q(rig.Q, rig.disparity_sign), left, disparity)
    negated = rig.Q.copy()
    negated[2, 3] = -negated[2, 3]  # the paper prints -f
    for Q in (rig.Q, negated):
        xyz = triangulate(normalize_q(Q, rig.disparity_sign), left, disparity)
        assert np.all(xyz[:, 2] > 0)
        np.testing.assert_allclose(xyz, expected, rtol=1e-9, atol=1e-12)


@QUICK
@given(scenes())
def test_prerectified_rig_triangulates_like_the_original(scene):
    if len(scene.points_m) == 0:
        return
    rig = scene.rig()
    rect = StereoRig.from_rectified(rig.P1, rig.P2, scene.size)
    left, right = _observe(scene, rig)
    assert rect.disparity_sign == rig.disparity_sign
    assert np.array_equal(rect.to_rectified(left, "left"), left)
    disparity = left[:, 0] - right[:, 0]
    a = triangulate(normalize_q(rig.Q, rig.disparity_sign), left, disparity)
    b = triangulate(normalize_q(rect.Q, rect.disparity_sign), left, disparity)
    np.testing.assert_allclose(b, a, rtol=1e-9, atol=1e-9)
