"""Tests of the landmark smoother: a held pose's jitter shrinks, a moving arm is followed, a jump restarts it."""

from __future__ import annotations

import numpy as np

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator, PoseLandmarks, _smoother
from dip3d_vehicle.perception.blazepose_roi import Roi
from dip3d_vehicle.perception.landmark_smoothing import LandmarkSmoother, weight

SIZE_PX = 250.0   # the body's ROI side at 4.5-5 m in the simulator's images


def _default() -> LandmarkSmoother:
    """The schema's default setting."""
    return LandmarkSmoother(0.05, 5.0, 0.25)


def test_a_still_landmarks_jitter_shrinks_to_under_half():
    """White jitter of 2 px (BlazePose's at 4.5-5 m) on a held pose: the smoothed landmarks scatter less than half."""
    rng = np.random.default_rng(3)
    f = _default()
    truth = np.array([[800.0, 500.0], [830.0, 520.0], [860.0, 535.0]])
    raw = truth + rng.normal(0.0, 2.0, (200, 3, 2))
    out = np.array([f.smooth(x, SIZE_PX) for x in raw])
    assert np.std(out[20:] - truth) < 0.5 * np.std(raw[20:] - truth)


def test_a_raised_arm_is_followed_within_two_frames():
    """A wrist raised at 0.05 body sizes a frame (an arm raised in about a second at 5 Hz) lags under two frames' travel."""
    f = _default()
    start = np.array([[800.0, 500.0]])
    for k in range(5):
        f.smooth(start, SIZE_PX)
    step = np.array([[0.0, -0.05 * SIZE_PX]])
    for k in range(1, 11):
        out = f.smooth(start + k * step, SIZE_PX)
    assert np.linalg.norm(start + 10 * step - out) < 2.0 * np.linalg.norm(step)


def test_a_jump_starts_the_filter_again():
    """A landmark moving more than the jump (the model swapped sides) is taken as found, with no past frames."""
    f = _default()
    a = np.array([[800.0, 500.0], [900.0, 500.0]])
    f.smooth(a, SIZE_PX)
    swapped = a[::-1].copy()
    assert np.array_equal(f.smooth(swapped, SIZE_PX), swapped)


def test_weight_rises_with_the_cutoff():
    assert 0.0 < weight(0.05) < weight(0.3) < 1.0
    assert np.allclose(weight(np.array([0.05, 0.3])), [weight(0.05), weight(0.3)])


def _pose(xy: np.ndarray, detected: bool) -> PoseLandmarks:
    """A pose with these landmarks (33, 2), its ROI 250 px wide."""
    return PoseLandmarks(xy, np.zeros(33), np.ones(33), np.ones(33), 1.0, Roi((800.0, 500.0), SIZE_PX, 0.0),
                         np.zeros((2, 2)), detected=detected)


def test_the_estimator_smooths_a_tracked_pose_and_starts_again_on_a_detected_one():
    """Tracked frames are smoothed; a detected pose (a new track) and a reset are taken as they are."""
    est = BlazePoseEstimator(pose=None, smoother=_default())
    base = np.full((33, 2), 500.0)
    first = est._smoothed(_pose(base, True))
    assert np.array_equal(first.xy_px, base)
    tracked = est._smoothed(_pose(base + 4.0, False))
    assert np.all((tracked.xy_px > base) & (tracked.xy_px < base + 4.0))
    assert np.array_equal(est._smoothed(_pose(base + 8.0, True)).xy_px, base + 8.0)
    est.reset()
    assert np.array_equal(est._smoothed(_pose(base, False)).xy_px, base)
    held = _pose(base + 4.0, False)
    assert BlazePoseEstimator(pose=None)._smoothed(held) is held   # no smoother: each frame as found


def test_the_parameters_build_the_smoother():
    """``blazepose.smoothing*`` reach the estimator; off, it has none."""
    on = _smoother(load_params(overrides={"blazepose.smoothing": "true", "blazepose.smoothing_beta": "7"}))
    assert isinstance(on, LandmarkSmoother) and on.beta == 7.0 and on.min_cutoff == 0.05 and on.jump == 0.25
    assert _smoother(load_params(overrides={"blazepose.smoothing": "false"})) is None
