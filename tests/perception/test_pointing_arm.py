"""pose.arm auto: the arm held away from the body is the one read (synthetic landmarks, no model)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from dip3d_vehicle.perception.pointing_arm import AUTO_ARM_MARGIN_RAD, arm_elevation_rad, pointing_arm

# BlazePose indices: shoulders 11 (left) / 12 (right), elbows 13 / 14, wrists 15 / 16, hips 23 / 24.
_SHOULDER = {"left": np.array([560.0, 400.0]), "right": np.array([440.0, 400.0])}
_HIP = {"left": np.array([540.0, 700.0]), "right": np.array([460.0, 700.0])}
_INDEX = {"left": (11, 13, 15, 23), "right": (12, 14, 16, 24)}


def _pose(raise_deg: dict[str, float], visibility: float = 0.9, turn_deg: float = 0.0):
    """Landmarks of a diver whose arms are raised ``raise_deg`` from the torso (sideways, outward).

    ``turn_deg`` rotates the whole body in the image (a diver swimming on their side or horizontally).
    """
    xy = np.zeros((33, 2))
    for side, (s, e, w, h) in _INDEX.items():
        out = 1.0 if side == "left" else -1.0            # the image's left/right of the body
        a = math.radians(raise_deg[side])
        direction = np.array([out * math.sin(a), math.cos(a)])   # 0 deg: straight down the torso
        xy[s], xy[h] = _SHOULDER[side], _HIP[side]
        xy[e], xy[w] = _SHOULDER[side] + 130.0 * direction, _SHOULDER[side] + 260.0 * direction
    t = math.radians(turn_deg)
    rot = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    xy = (xy - [500.0, 550.0]) @ rot.T + [500.0, 550.0]
    return SimpleNamespace(xy_px=xy, z_px=np.zeros(33), visibility=np.full(33, visibility))


@pytest.mark.parametrize("turn_deg", [0.0, 90.0, 180.0, -35.0])
def test_the_raised_arm_is_picked_whatever_the_divers_attitude(turn_deg):
    assert pointing_arm(_pose({"right": 95.0, "left": 10.0}, turn_deg=turn_deg)) == "right"
    assert pointing_arm(_pose({"right": 10.0, "left": 95.0}, turn_deg=turn_deg)) == "left"


def test_elevation_is_the_angle_between_torso_and_arm():
    pose = _pose({"right": 80.0, "left": 0.0})
    # the torso line runs from the shoulder to that side's hip, a little inward: a few degrees off vertical
    torso = math.degrees(math.atan2(20.0, 300.0))
    assert math.degrees(arm_elevation_rad(pose, "right")) == pytest.approx(80.0 + torso, abs=1e-6)
    assert math.degrees(arm_elevation_rad(pose, "left")) == pytest.approx(torso, abs=1e-6)


def test_an_arm_the_model_does_not_see_counts_as_hanging():
    pose = _pose({"right": 20.0, "left": 120.0})
    pose.visibility[[13, 15]] = 0.1          # the left elbow and wrist hidden behind the body
    assert arm_elevation_rad(pose, "left") == 0.0
    assert pointing_arm(pose) == "right"


def test_the_last_frames_arm_is_kept_unless_the_other_is_clearly_higher():
    close = math.degrees(AUTO_ARM_MARGIN_RAD) / 2.0
    pose = _pose({"right": 90.0, "left": 90.0 + close})
    assert pointing_arm(pose, previous="right") == "right"
    assert pointing_arm(pose, previous="left") == "left"
    clear = _pose({"right": 90.0, "left": 90.0 + 2.0 * math.degrees(AUTO_ARM_MARGIN_RAD)})
    assert pointing_arm(clear, previous="right") == "left"


def test_a_torso_of_no_length_gives_no_elevation():
    pose = _pose({"right": 90.0, "left": 0.0})
    pose.xy_px[24] = pose.xy_px[12]
    assert arm_elevation_rad(pose, "right") == 0.0
