"""The pointing shoulder's depth from the head's match and the torso's turn (``pose.match_disparity_shoulder``)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from dip3d_vehicle.perception.shoulder_model import (HEAD_BEFORE_SHOULDERS_M, SHOULDER_WIDTH_M, head_torso_shoulder,
                                                     mirrored_shoulder_px, side_log_odds, two_way)

F_PX, B_M, CX_PX = 920.0, 0.12, 640.0


def _project_x(point_m: np.ndarray) -> float:
    """Return a camera-frame point's image x (pixels)."""
    return CX_PX + F_PX * point_m[0] / point_m[2]


@pytest.mark.parametrize("centre_m", [(0.0, 0.0, 2.5), (1.2, 0.0, 3.0), (-0.9, 0.0, 4.5)])
@pytest.mark.parametrize("turn_rad", [0.3, 0.7, 1.1, 1.5])
def test_the_head_and_the_torsos_turn_place_the_shoulder_on_either_side(centre_m, turn_rad):
    fb = F_PX * B_M
    centre = np.array(centre_m)
    half = 0.5 * SHOULDER_WIDTH_M[0]
    head = (fb / (centre[2] - HEAD_BEFORE_SHOULDERS_M), 0.3)      # the head's surface, before the shoulders' line
    head_px = (_project_x(centre), 100.0)
    for side in (-1.0, 1.0):                                      # the shoulder turned toward / away from the camera
        shoulder = centre + half * np.array([math.cos(turn_rad), 0.0, side * math.sin(turn_rad)])
        near, far = head_torso_shoulder(head, head_px, (_project_x(shoulder), 180.0), F_PX, B_M, CX_PX, 2.0)
        truth = fb / shoulder[2]
        mine = near if side < 0 else far
        # exact where one turn fits the image offset (the diver in the middle of the image); off the middle two
        # turns may fit and the shoulder lies between them, the truth within its sigma
        assert abs(mine[0] - truth) < (0.05 if centre[0] == 0.0 else mine[1])
        assert abs((far if side < 0 else near)[0] - truth) > 0.5 * fb / centre[2] ** 2 * half * math.sin(turn_rad)
        for d, sigma in (near, far):
            assert 0.02 < sigma * centre[2] ** 2 / fb < 0.25      # metres: a few centimetres, up to a turn's doubt


def test_a_torso_facing_the_camera_puts_the_shoulder_at_the_heads_depth_on_either_side():
    fb = F_PX * B_M
    head = (fb / (3.0 - HEAD_BEFORE_SHOULDERS_M), 0.3)
    half_px = 0.5 * SHOULDER_WIDTH_M[0] * F_PX / 3.0
    near, far = head_torso_shoulder(head, (CX_PX, 100.0), (CX_PX + 1.05 * half_px, 180.0), F_PX, B_M, CX_PX, 2.0)
    assert near[0] == pytest.approx(far[0]) == pytest.approx(fb / 3.0)   # wider than half a shoulder: no turn


def test_the_side_is_weighed_by_the_evidence():
    near, far = (40.0, 0.5), (36.0, 0.5)
    assert side_log_odds((36.2, 1.0), near, far) > 2.0 > -2.0 > side_log_odds((39.9, 1.0), near, far)
    assert abs(side_log_odds((38.0, 1.0), near, far)) < 1e-9
    mean, sigma = two_way(near, far, 0.5)
    assert mean == pytest.approx(38.0) and sigma > 2.0             # undecided: between the two, as wide as their gap
    assert mirrored_shoulder_px((500.0, 90.0), (560.0, 160.0)).tolist() == [440.0, 160.0]


def _plane_pair(disparity_px: int):
    """A textured rectified pair: every pixel at one disparity (right content to the left)."""
    rng = np.random.default_rng(4)
    left = (rng.random((200, 400, 3)) * 255).astype(np.uint8)
    left = np.repeat(np.repeat(left[::4, ::4], 4, 0), 4, 1)[:200, :400]
    right = np.zeros_like(left)
    right[:, :400 - disparity_px] = left[:, disparity_px:]
    return left, right


def test_match_arm_takes_the_shoulder_from_the_head_and_the_torso_when_asked():
    from dip3d_vehicle.perception.given_arm import match_arm
    from dip3d_vehicle.perception.values import ArmKeypoints

    left, right = _plane_pair(37)
    left[70:131, 160:241] = 90                                    # the shoulder's patch: flat wetsuit
    right[70:131, 123:204] = 90
    fb = F_PX * B_M
    half_px = 0.5 * SHOULDER_WIDTH_M[0] * 37.0 / B_M              # half a shoulder width at the plane's depth
    joints = np.array([[200.0, 100.0], [250.0, 60.0], [300.0, 120.0]])
    arm = ArmKeypoints("right", joints, joints - [33.0, 0.0], np.ones(3), np.ones(3), "test",
                       extra_left_px={"head": (200.0 - half_px, 40.0)})  # facing the camera: the head half a width over
    kw = dict(floor_px=1.0, given_sigma_px=2.8, principal_px=(200.0, 100.0))
    patch = match_arm(arm, left, right, 1, F_PX, B_M, **kw)
    torso = match_arm(arm, left, right, 1, F_PX, B_M, shoulder_from="head_torso", **kw)
    assert patch.disparity_matched[0] and torso.disparity_matched[0]
    expected = fb / (fb / 37.0 + HEAD_BEFORE_SHOULDERS_M)         # the plane is the head's surface
    assert abs(torso.left_px[0, 0] - torso.right_px[0, 0] - expected) < 0.6
    assert torso.disparity_sigma_px[0] < 0.6 * patch.disparity_sigma_px[0]   # sharper than the head's 0.15 m stand-in
    assert np.array_equal(torso.right_px[1:], patch.right_px[1:])  # the elbow and the wrist as before
    no_head = replace(arm, extra_left_px={})
    assert np.array_equal(match_arm(no_head, left, right, 1, F_PX, B_M, shoulder_from="head_torso", **kw).right_px,
                          match_arm(no_head, left, right, 1, F_PX, B_M, **kw).right_px)
