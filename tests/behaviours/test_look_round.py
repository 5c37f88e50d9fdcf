"""Looking round an object that hides a lost target: which object hides it, the sideways step that clears the line
of sight, and that the step never brings the hull nearer an object than the way keeps it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from behaviours.look_round import CLEAR_OF_HIDER_M, hider, look_round_m, safe_step_m, step_clear_m


def _offset_after(step_m: float, target, obj) -> float:
    """The object's horizontal distance from the line of sight after the camera moved ``step_m`` along x."""
    cam = np.array([step_m, 0.0])
    t, o = np.array([target[0], target[2]]) - cam, np.array([obj[0], obj[2]]) - cam
    u = t / np.linalg.norm(t)
    return abs(o[0] * u[1] - o[1] * u[0])


def test_an_object_on_the_line_of_sight_before_the_target_hides_it_and_the_nearest_one_is_named():
    target = [0.3, 0.0, 3.0]
    on_line = [0.15, 0.05, 1.5]  # halfway, 5 cm below the line
    assert hider(target, [[1.0, 0.0, 1.5], on_line]) == 1
    assert hider(target, [[0.24, 0.0, 2.4], on_line]) == 1  # both on the line: the nearer the camera
    assert hider(target, [[0.6, 0.0, 1.5]]) is None  # 0.3 m off the line
    assert hider(target, [[0.33, 0.0, 3.3], [0.0, 0.0, -0.5]]) is None  # beyond the target, behind the camera
    assert hider(target, [[0.15, 0.6, 1.5]]) is None  # well below the line of sight
    assert hider(target, np.zeros((0, 3))) is None


@pytest.mark.parametrize("target, obj", [([0.0, 0.0, 3.0], [0.05, 0.0, 1.5]), ([0.6, 0.0, 2.8], [0.2, 0.1, 1.0]),
                                         ([-0.9, 0.0, 2.5], [-0.5, 0.0, 1.5]), ([0.0, 0.0, 3.0], [0.0, 0.0, 2.0])])
def test_the_step_leaves_the_line_of_sight_clear_of_the_hider_by_what_was_asked(target, obj):
    near = step_clear_m(target, obj, CLEAR_OF_HIDER_M)
    far = step_clear_m(target, obj, CLEAR_OF_HIDER_M, -near)
    assert near * far < 0 and abs(far) >= abs(near) - 1e-9 > 0  # the other side is past the hider: longer
    for step in (near, far):
        assert _offset_after(step, target, obj) == pytest.approx(CLEAR_OF_HIDER_M, abs=0.02), step


def test_the_shorter_step_goes_away_from_the_side_the_hider_leans_to():
    assert step_clear_m([0.0, 0.0, 3.0], [0.05, 0.0, 1.5], 0.3) == pytest.approx(-0.5, abs=0.02)  # hider right: step left
    assert step_clear_m([0.0, 0.0, 3.0], [-0.05, 0.0, 1.5], 0.3) == pytest.approx(0.5, abs=0.02)
    assert step_clear_m([0.0, 0.0, 3.0], [0.5, 0.0, 1.5], 0.3) == 0.0  # already clear


def test_a_step_whose_path_passes_nearer_an_object_than_asked_is_not_safe():
    objects = np.array([[-0.5, 0.0, 0.3]])  # 0.3 m ahead, 0.5 m left of the camera
    assert safe_step_m(0.4, objects, np.array([0.6]), 0.45)  # right: away from it
    assert not safe_step_m(-0.4, objects, np.array([0.6]), 0.45)  # left: to 0.3 m from it
    # an object already nearer than asked is kept no nearer than it is
    assert safe_step_m(0.3, np.array([[0.0, 0.0, -0.1]]), np.array([0.6]), 0.45)
    assert not safe_step_m(0.3, np.array([[0.35, 0.0, 0.1]]), np.array([0.6]), 0.45)


def test_look_round_takes_the_other_side_when_the_shorter_is_not_safe_and_none_longer_than_allowed():
    target, obj = [0.0, 0.0, 3.0], [0.05, 0.0, 1.5]
    kept = np.array([obj])
    needed = np.array([0.6])
    assert look_round_m(target, kept, needed, 0.45, 2.0) == pytest.approx(-0.5, abs=0.02)
    blocked = np.array([obj, [-0.9, 0.0, 0.2]])  # something close on the left
    step = look_round_m(target, blocked, np.array([0.6, 0.6]), 0.45, 2.0)
    assert step > 0 and step == pytest.approx(step_clear_m(target, obj, CLEAR_OF_HIDER_M, 1.0))
    assert look_round_m(target, blocked, np.array([0.6, 0.6]), 0.45, 0.5) == 0.0  # the right side: 0.7 m
    assert look_round_m(target, kept, needed, 0.45, 0.0) == 0.0  # off
    assert look_round_m(target, np.array([[0.8, 0.0, 1.5]]), needed, 0.45, 2.0) == 0.0  # nothing hides it
    assert not math.isnan(look_round_m([0.0, 0.0, 0.0], kept, needed, 0.45, 2.0))


def test_the_modules_examples_hold():
    import doctest

    from behaviours import look_round

    result = doctest.testmod(look_round)
    assert result.attempted >= 2 and result.failed == 0
