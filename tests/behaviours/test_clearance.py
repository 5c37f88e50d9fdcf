"""Keeping clear of the decision's other objects on the way to the target (behaviours/clearance.py)."""

from __future__ import annotations

import numpy as np
import pytest

from behaviours.clearance import approach_end_m, sidestep

TARGET = [0.0, 0.0, 2.0]  # 2 m ahead; with a 1 m stand-off the approach ends 1 m ahead


def test_the_approach_ends_the_stand_off_before_the_target_on_its_line_of_sight():
    np.testing.assert_allclose(approach_end_m([0.6, 0.0, 0.8], 0.5), [0.3, 0.0, 0.4])
    np.testing.assert_allclose(approach_end_m([0.0, 0.0, 0.5], 1.0), [0.0, 0.0, 0.0])  # already nearer


@pytest.mark.parametrize("objects", [
    np.zeros((0, 3)),
    [[0.8, 0.0, 1.0]],            # 0.8 m beside the stand-off point
    [[0.35, 0.0, 2.0]],           # the twin beside the target: the approach stops 1 m before both
    [[0.0, 0.0, 3.5]],            # behind the target
    [[np.nan, 0.0, 1.0]],         # no position
])
def test_objects_clear_of_the_approach_need_no_sidestep(objects):
    assert sidestep(TARGET, objects, 1.0, 0.6, 0.3) is None


@pytest.mark.parametrize("x, away", [(0.2, -1.0), (-0.2, 1.0), (0.0, 1.0)])
def test_an_object_beside_the_path_sways_the_vehicle_away_from_it(x, away):
    step = sidestep(TARGET, [[x, 0.0, 1.0]], 1.0, 0.6, 0.3)
    assert step is not None and step.clearance_m == pytest.approx(abs(x))
    assert np.sign(step.sway_m_s) == away and abs(step.sway_m_s) == pytest.approx(min(0.6 - abs(x), 0.3))
    assert step.surge_factor == 1.0  # 1 m ahead: time to go round it while advancing


def test_the_nearest_object_decides_and_one_just_ahead_stops_the_advance():
    step = sidestep(TARGET, [[0.5, 0.0, 1.0], [-0.1, 0.0, 0.3]], 1.0, 0.6, 0.3)
    assert step.index == 1 and step.sway_m_s > 0 and step.surge_factor == 0.0
    half = sidestep(TARGET, [[0.45, 0.0, 0.3]], 1.0, 0.6, 0.3)  # 0.3 ahead, 0.45 off: half the way to clear
    assert half.surge_factor == pytest.approx(0.5) and half.sway_m_s == pytest.approx(-0.15)


def test_no_clearance_asked_means_no_sidestep():
    assert sidestep(TARGET, [[0.0, 0.0, 1.0]], 1.0, 0.0, 0.3) is None


def test_an_object_the_camera_has_passed_still_lies_beside_the_hull():
    passed = [[0.3, 0.0, -0.2]]  # 0.2 m behind the camera, 0.3 m to the right
    assert sidestep(TARGET, passed, 1.0, 0.5, 0.3) is not None  # 0.36 m from the camera itself
    far_passed = [[0.4, 0.0, -0.4]]  # 0.57 m from the camera: clear of a path starting there...
    assert sidestep(TARGET, far_passed, 1.0, 0.5, 0.3) is None
    step = sidestep(TARGET, far_passed, 1.0, 0.5, 0.3, behind_m=0.5)  # ... not of the hull reaching 0.5 m back
    assert step is not None and step.clearance_m == pytest.approx(0.4) and step.sway_m_s < 0
    assert step.surge_factor == 1.0  # going on forward clears it: no hold for an object already passed
