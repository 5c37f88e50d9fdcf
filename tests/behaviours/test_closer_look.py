"""Issue 11: the opt-in closer look: before acting on an object while "nothing detected" keeps a share of
the point (counted as one look), advance toward where the arm points and decide again from there."""

from __future__ import annotations

import math

import numpy as np
import pytest

from behaviours.blackboard import StatusText
from behaviours.close_in import horizontal_range_m, path_clearance_m, plan_closer_look, pointed_point
from behaviours.second_look import _in_view
from sitl.scenario import load_scenario
from mission_driver import engaged_mission, enter, feed, move_until_trigger
from test_close_in import F_PX, PP_PX, _frame

NEAR_SHOULDER = np.array([-0.6, -0.3, 2.5])
"""A diver 2.5 m away (nearer than behaviour.decide_max_range_m: no close in toward the diver)."""


@pytest.fixture(scope="module")
def rig():
    return load_scenario("paper_pool", 0).rig()


def _arm_xyz(shoulder=NEAR_SHOULDER) -> np.ndarray:
    d = np.array([0.5, 0.2, -0.84])
    d /= np.linalg.norm(d)
    return np.array([shoulder, shoulder + 0.3 * d, shoulder + 0.58 * d])


def test_the_pointed_point_is_on_the_ray_beyond_the_wrist_nearest_the_object():
    arm = _arm_xyz()
    d = (arm[2] - arm[0]) / np.linalg.norm(arm[2] - arm[0])
    obj = np.array([0.5, 0.1, 2.0])
    p = pointed_point(arm, obj)
    assert np.linalg.norm(np.cross(p - arm[0], d)) < 1e-9 and (obj - p) @ d == pytest.approx(0.0, abs=1e-9)
    assert np.allclose(pointed_point(arm, arm[0] - d), arm[2])  # an object behind the hand: the wrist itself


def test_the_closer_look_advances_toward_the_pointed_point_keeping_everything_in_view_and_clear():
    arm, obj = _arm_xyz(), np.array([0.5, 0.1, 2.0])
    keep = np.array([obj, [0.45, 0.1, 3.0]])
    step = plan_closer_look(arm, obj, keep, 1.2, 0.3, F_PX, PP_PX, 80.0, 0.2)
    assert step is not None and step.toward == "pointed" and step.distance_m >= 0.2
    aim = pointed_point(arm, obj)
    c = np.asarray(step.offset_m)
    assert c[1] == 0.0 and aim[0] * c[2] - aim[2] * c[0] == pytest.approx(0.0, abs=1e-9)  # level, straight at it
    assert horizontal_range_m(aim - c) >= 1.2 - 1e-9 and step.range_before_m == pytest.approx(horizontal_range_m(aim))
    assert _in_view(np.vstack([aim, arm, keep]) - c, F_PX, PP_PX, 80.0)
    assert path_clearance_m(np.vstack([keep, arm]), c) >= 0.3
    # an object beside the camera that a step forward would lose: no step at all
    assert plan_closer_look(arm, obj, np.vstack([keep, [-0.35, 0.0, 0.6]]), 1.2, 0.3, F_PX, PP_PX, 80.0, 0.2) is None


def _mission(rig, **over):
    return engaged_mission(rig, **{"behaviour.select_timeout_s": 1.0, "behaviour.close_in_speed_m_s": 0.15,
                                   "behaviour.second_look_settle_s": 0.6, "behaviour.close_in_min_step_m": 0.2,
                                   **over})


def _near(none_p: float = 0.2):
    return _frame(shoulder=NEAR_SHOULDER, scores=(1.0 - none_p,), none_p=none_p)


def test_off_by_default_a_lean_with_nothing_detected_beside_it_is_acted_on(rig):
    m = _mission(rig)
    enter(m, "select_target")
    assert feed(m, [_near()] * 4)[-1] == "winner" and m.bb.close_ins == 0


def test_with_nothing_detected_holding_its_share_the_vehicle_looks_closer_first_then_decides(rig):
    m = _mission(rig, **{"behaviour.closer_look_min_none": 0.1})
    enter(m, "select_target")
    fired = feed(m, [_near()] * 4)
    assert fired[-1] == "close_in" and m.state == "close_in" and m.bb.close_ins == 1
    assert not m.bb.decided  # the decision it looked closer about was not acted on
    step = m.bb.close_in_step
    assert step.toward == "pointed" and step.distance_m >= 0.2
    assert any(isinstance(o, StatusText) and "looking closer" in o.text for o in m.bb.outbox)
    trig, cmds = move_until_trigger(m, _near(), 2000)
    assert trig == "closer" and m.state == "select_target" and m.bb.fusion.frames == []
    moving = [c for c in cmds if c is not None]
    assert moving and all(c.heave_m_s == 0 and c.yaw_rate_rad_s == 0 for c in moving)
    travelled = sum(math.hypot(c.surge_m_s, c.sway_m_s) for c in moving) * 0.02
    assert travelled == pytest.approx(step.distance_m, abs=0.03)
    assert feed(m, [_near()] * 4, t0=m.bb.now_s)[-1] == "winner"  # one advance per point: now it acts
    assert [d["kind"] for d in m.bb.decided] == ["object"]


def test_a_point_sure_of_its_object_or_without_tries_does_not_look_closer(rig):
    m = _mission(rig, **{"behaviour.closer_look_min_none": 0.3})
    enter(m, "select_target")
    assert feed(m, [_near(0.2)] * 4)[-1] == "winner"  # "nothing" 0.2 < 0.3
    m = _mission(rig, **{"behaviour.closer_look_min_none": 0.1, "behaviour.close_in_max_tries": 0})
    enter(m, "select_target")
    assert feed(m, [_near()] * 4)[-1] == "winner"
