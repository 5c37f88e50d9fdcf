"""Arm joints' disparity by patch matching along rectified rows."""

from __future__ import annotations

import numpy as np

from dip3d_vehicle.perception.joint_stereo import match_joint_disparity


def _pair(disparity_px: float):
    rng = np.random.default_rng(4)
    left = (rng.random((200, 400, 3)) * 255).astype(np.uint8)
    left = np.repeat(np.repeat(left[::4, ::4], 4, 0), 4, 1)[:200, :400]  # blobs a few px wide
    shift = int(disparity_px)
    right = np.zeros_like(left)
    right[:, :400 - shift] = left[:, shift:]  # right content lies to the left (sign +1)
    return left, right


def test_recovers_the_disparity_from_a_wrong_guess():
    left, right = _pair(37)
    left_xy = np.array([[200.0, 100.0], [250.0, 60.0], [300.0, 150.0]])
    guess = left_xy - [[37 - 25, 0], [37 + 30, 0], [37, 0]]   # the backend's right x off by -25 / +30 / 0 px
    out = match_joint_disparity(left, right, left_xy, guess, sign=1)
    assert np.allclose(left_xy[:, 0] - out[:, 0], 37, atol=0.3)
    assert np.allclose(out[:, 1], left_xy[:, 1])


def test_keeps_the_backends_estimate_where_nothing_matches():
    left, _ = _pair(37)
    flat = np.full_like(left, 90)
    left_xy = np.array([[200.0, 100.0], [5.0, 100.0]])          # a flat right image; a joint at the border
    guess = left_xy - [[30.0, 0.0], [3.0, 1.0]]
    out = match_joint_disparity(left, flat, left_xy, guess, sign=1)
    assert np.array_equal(out, guess)
