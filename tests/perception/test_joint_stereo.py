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


def _stripes(disparity_px: int):
    """Return a pair whose left image has texture, and a band of horizontal stripes (aperture problem)."""
    left, right = _pair(disparity_px)
    stripes = np.zeros((40, 400, 3), np.uint8)
    stripes[::6] = 200                       # rows constant along x: no disparity can be told there
    left[150:190], right[150:190] = stripes, stripes
    return left, right


def test_joint_disparities_subpixel_within_the_arms_reach():
    from dip3d_vehicle.perception.joint_stereo import joint_disparities

    left, right = _pair(37)
    left_xy = np.array([[200.0, 100.0], [250.0, 60.0], [300.0, 120.0]])
    # body at disparity 33 px, f 920 px, B 0.12 m: depth 3.35 m; the reach covers 37 px
    out = joint_disparities(left, right, left_xy, 33.0, 1, 920.0, 0.12)
    assert out.matched.all()
    assert np.allclose(out.disparity_px, 37.0, atol=0.3)
    assert np.all(out.sigma_px <= 1.0)


def test_joint_disparities_falls_back_to_the_body_with_a_wide_sigma():
    from dip3d_vehicle.perception.joint_stereo import joint_disparities, reach_disparities

    left, right = _stripes(37)
    left_xy = np.array([[200.0, 100.0], [250.0, 170.0]])      # textured; horizontal stripes
    out = joint_disparities(left, right, left_xy, 33.0, 1, 920.0, 0.12)
    lo, hi = reach_disparities(33.0, 920.0 * 0.12)
    assert out.matched[0] and abs(out.disparity_px[0] - 37.0) < 0.3
    assert not out.matched[1] or out.sigma_px[1] > 5.0     # never a confident disparity on stripes
    if not out.matched[1]:
        assert out.disparity_px[1] == 33.0 and np.isclose(out.sigma_px[1], 0.25 * (hi - lo))


def test_joint_disparities_rejects_a_match_outside_the_reach():
    from dip3d_vehicle.perception.joint_stereo import joint_disparities

    left, right = _pair(80)                    # the content is at 80 px: far nearer than the body allows
    out = joint_disparities(left, right, np.array([[250.0, 100.0]]), 20.0, 1, 920.0, 0.12)
    assert not out.matched[0] and out.disparity_px[0] == 20.0


def test_shoulder_from_the_torso_side_on_and_facing():
    from dip3d_vehicle.perception.joint_stereo import shoulder_disparity

    f, b = 920.0, 0.12
    body = f * b / 3.0                          # torso centre 3 m away
    # side on (shoulders 0.38 m apart along the view: a few px apart in the image): the near one 0.19 m nearer
    near, near_sigma = shoulder_disparity(body, 5.0, True, f, b)
    far, _ = shoulder_disparity(body, 5.0, False, f, b)
    assert abs(f * b / near - 2.81) < 0.01 and abs(f * b / far - 3.19) < 0.01
    assert near_sigma < 1.0
    # facing the camera (0.38 m apart across the image): both at the torso's depth, with a wider sigma
    facing, facing_sigma = shoulder_disparity(body, 0.38 * f / 3.0, True, f, b)
    assert abs(facing - body) < 1e-6 and facing_sigma > near_sigma
