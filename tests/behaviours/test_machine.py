"""The mission machine: the table is consistent, and each state's logic on synthetic perception results."""

from __future__ import annotations

import math

import numpy as np
import pytest

from behaviours.acknowledge import ack_schedule
from behaviours.blackboard import BehaviourConfig, Observation, SetServo, StatusText, TrackFrame
from behaviours.evidence import VoteBox, angular_spread_rad, is_raised
from behaviours.loop import build_mission
from behaviours.machine import PERCEPTION_STALE, STATES, TRANSITIONS
from behaviours.states import STATE_CLASSES
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.pipeline import PerceptionResult
from dip3d_vehicle.perception.values import Arm3D, ArmKeypoints, Candidates, ObjectCandidate, Selection
from sitl.scenario import load_scenario

FRAME_S = 0.2


# ----------------------------------------------------------------------------- the table
def test_every_source_and_destination_is_a_state():
    for t in TRANSITIONS:
        sources = t["source"] if isinstance(t["source"], list) else [t["source"]]
        assert t["dest"] in STATES, t
        assert all(s in STATES for s in sources), t


def test_every_state_has_a_behaviour_and_every_trigger_it_returns_leaves_it():
    assert sorted(c.name for c in STATE_CLASSES) == sorted(STATES)
    table = {(s, t["trigger"]) for t in TRANSITIONS
             for s in (t["source"] if isinstance(t["source"], list) else [t["source"]])}
    for cls in STATE_CLASSES:
        for trigger in cls.triggers:
            assert (cls.name, trigger) in table, (cls.name, trigger)
        if cls.name != "idle":
            assert (cls.name, "disengage") in table


def test_every_state_is_reachable_from_idle():
    reach, frontier = {"idle"}, ["idle"]
    while frontier:
        s = frontier.pop()
        for t in TRANSITIONS:
            sources = t["source"] if isinstance(t["source"], list) else [t["source"]]
            if s in sources and t["dest"] not in reach:
                reach.add(t["dest"])
                frontier.append(t["dest"])
    assert reach == set(STATES)


def test_every_behaviour_parameter_is_in_the_schema():
    params = load_params()
    cfg = BehaviourConfig.from_params(params)
    for key in params:
        if key.startswith("behaviour."):
            assert getattr(cfg, key.split(".", 1)[1]) == params[key], key


# ----------------------------------------------------------------------------- helpers
@pytest.fixture(scope="module")
def rig():
    return load_scenario("paper_pool", 0).rig()


def _mission(rig, **over):
    params = load_params(overrides={k: str(v) for k, v in over.items()})
    m = build_mission(params, rig, (1600, 1200))
    m.bb.engaged = True
    return m


def _result(raised: bool = True, image_angle: float = 0.0, target_xyz=(0.5, 0.0, 2.0), confidence: float = 0.9,
            ambiguous: bool = False, status: str = "ok") -> PerceptionResult:
    """A perception result: an arm (raised or hanging) and optionally a chosen object."""
    shoulder = np.array([-0.5, 0.0, 2.5])
    direction = np.array([1.0, 0.0, 0.0]) if raised else np.array([0.1, 1.0, 0.0])
    direction /= np.linalg.norm(direction)
    xyz = np.array([shoulder, shoulder + 0.3 * direction, shoulder + 0.58 * direction])
    c, s = math.cos(image_angle), math.sin(image_angle)
    left = np.array([[500.0, 600.0], [500 + 100 * c, 600 + 100 * s], [500 + 190 * c, 600 + 190 * s]])
    arm = ArmKeypoints("right", left, left - [30.0, 0.0], np.ones(3), np.ones(3))
    arm3d = Arm3D(xyz, np.full(3, 0.05))
    if status != "ok":
        return PerceptionResult(status, "", arm, arm3d)
    obj = ObjectCandidate(np.array([1000.0, 600.0]), np.asarray(target_xyz, float), 0.02, (0, 1, 2))
    cands = Candidates(np.zeros((3, 2)), np.zeros((3, 2)), np.random.default_rng(0).random((3, 128), np.float32),
                       np.zeros(3))
    sel = Selection(0, (obj,), np.array([confidence]), confidence, math.inf, "default", ambiguous)
    return PerceptionResult("ok", "", arm, arm3d, cands, np.asarray([target_xyz] * 3, float), sel)


def _feed(m, results, t0: float = 0.0):
    """Tick the mission once per result at the frame rate; return the triggers fired."""
    fired = []
    for i, r in enumerate(results):
        m.bb.now_s = t0 + (i + 1) * FRAME_S
        m.bb.observation = Observation(m.bb.now_s, i, result=r)
        fired.append(m.tick())
        m.bb.observation = None
    return fired


def _to(m, state: str):
    m.machine.set_state(state)
    m.behaviours[state].enter(m.bb)


# ----------------------------------------------------------------------------- states
def test_idle_engages_only_when_the_link_is_engaged(rig):
    m = _mission(rig)
    m.bb.engaged = False
    assert m.tick() is None and m.state == "idle"
    m.bb.engaged = True
    assert m.tick() == "engage" and m.state == "wait_for_diver"


def test_wait_for_diver_needs_n_of_m_raised_frames(rig):
    m = _mission(rig, **{"behaviour.arm_seen_n": 3, "behaviour.arm_seen_m": 5})
    _to(m, "wait_for_diver")
    _feed(m, [_result(True), _result(False), _result(True), _result(False)])
    assert m.state == "wait_for_diver"
    _feed(m, [_result(True)])
    assert m.state == "confirm_point"


def test_confirm_point_needs_a_steady_direction_for_the_hold_time(rig):
    m = _mission(rig, **{"behaviour.steady_hold_s": 1.0, "behaviour.steady_angle_rad": 0.1})
    _to(m, "confirm_point")
    wobbly = [_result(True, image_angle=0.3 * (i % 2)) for i in range(10)]
    _feed(m, wobbly)
    assert m.state == "confirm_point"
    fired = _feed(m, [_result(True, image_angle=0.01 * (i % 2)) for i in range(6)], t0=2.0)
    assert fired[-1] == "steady" and m.state == "select_target"


def test_confirm_point_goes_back_when_the_arm_is_lowered(rig):
    m = _mission(rig, **{"behaviour.arm_lost_frames": 3})
    _to(m, "confirm_point")
    _feed(m, [_result(True), _result(False), _result(False)])
    assert m.state == "confirm_point"
    _feed(m, [_result(False)])
    assert m.state == "wait_for_diver"


def test_confirm_point_times_out(rig):
    m = _mission(rig, **{"behaviour.confirm_timeout_s": 1.0})
    _to(m, "confirm_point")
    m.bb.now_s = 1.5
    assert m.tick() == "timeout" and m.state == "wait_for_diver"


def test_select_target_clear_winner_is_acknowledged_and_tracked(rig):
    m = _mission(rig, **{"behaviour.vote_frames": 4, "behaviour.min_votes": 3})
    _to(m, "select_target")
    fired = _feed(m, [_result(target_xyz=(0.5, 0.0, 2.0 + 0.01 * i)) for i in range(4)])
    assert fired[-1] == "winner" and m.state == "acknowledge"
    assert m.bb.tracker.active and np.allclose(m.bb.chosen.xyz_m, [0.5, 0.0, 2.03])
    assert any(isinstance(o, StatusText) and "target chosen" in o.text for o in m.bb.outbox)


def test_select_target_split_or_ambiguous_votes_go_back_to_confirm(rig):
    m = _mission(rig, **{"behaviour.vote_frames": 4, "behaviour.min_votes": 3})
    _to(m, "select_target")
    split = [_result(target_xyz=(0.5, 0, 2.0)), _result(target_xyz=(1.5, 0, 3.0)),
             _result(target_xyz=(0.5, 0, 2.0)), _result(target_xyz=(1.5, 0, 3.0))]
    assert _feed(m, split)[-1] == "ambiguous" and m.state == "confirm_point"
    _to(m, "select_target")
    unsure = [_result(), _result(ambiguous=True, confidence=0.4), _result(ambiguous=True, confidence=0.4), _result()]
    assert _feed(m, unsure)[-1] == "ambiguous"


def test_disengage_from_any_state_goes_idle_but_stale_perception_only_holds(rig):
    for state in STATES:
        if state == "idle":
            continue
        m = _mission(rig)
        _to(m, state)
        m.bb.engaged, m.bb.hold_reason = False, PERCEPTION_STALE
        m.tick()
        assert m.state == state
        m.bb.hold_reason = "mode changed ALT_HOLD -> MANUAL"
        assert m.tick() == "disengage" and m.state == "idle" and m.bb.command is None


def test_acknowledge_nod_returns_to_the_start_heading_then_servo(rig):
    m = _mission(rig, **{"behaviour.ack_kind": "nod"})
    steps, total = ack_schedule(m.bb.config)
    net = sum(s.yaw_rate_rad_s * ((steps[i + 1].start_s if i + 1 < len(steps) else total) - s.start_s)
              for i, s in enumerate(steps))
    assert abs(net) < 1e-9
    _to(m, "acknowledge")
    rates = []
    t = 0.0
    while m.state == "acknowledge" and t < 10:
        t += 0.02
        m.bb.now_s = t
        m.tick()
        rates.append(m.bb.command.yaw_rate_rad_s if m.bb.command else 0.0)
    assert m.state == "servo" and max(rates) > 0 > min(rates)
    assert abs(t - total) < 0.05


def test_acknowledge_lights_flashes_the_servo_output(rig):
    m = _mission(rig, **{"behaviour.ack_kind": "lights", "behaviour.ack_flashes": 2})
    _to(m, "acknowledge")
    for k in range(200):
        m.bb.now_s = k * 0.02
        m.tick()
    servos = [o for o in m.bb.outbox if isinstance(o, SetServo)]
    assert [s.pwm for s in servos] == [1900, 1100, 1900, 1100] and m.bb.command is None


def test_lost_target_gives_up_after_the_timeout(rig):
    m = _mission(rig, **{"behaviour.lost_timeout_s": 2.0, "behaviour.abort_hold_s": 1.0})
    _to(m, "lost_target")
    for k in range(1, 120):
        m.bb.now_s = k * 0.02
        m.bb.observation = Observation(m.bb.now_s, k, track=TrackFrame(Candidates.empty(), np.zeros((0, 3))))
        m.tick()
    assert m.state == "abort" and m.bb.command is None
    m.bb.now_s += 1.1
    m.tick()
    assert m.state == "wait_for_diver"


def test_done_reports_and_waits_for_the_arm_to_come_down(rig):
    m = _mission(rig, **{"behaviour.release_frames": 3})
    _to(m, "done")
    assert m.bb.arrived and any(isinstance(o, StatusText) and "arrived" in o.text for o in m.bb.outbox)
    _feed(m, [_result(True)] * 5)
    assert m.state == "done"
    _feed(m, [_result(False)] * 3)
    assert m.state == "wait_for_diver"


# ----------------------------------------------------------------------------- evidence
def test_evidence_helpers():
    assert is_raised(np.array([1.0, 0.0, 0.0]), 0.9)
    assert not is_raised(np.array([0.1, 1.0, 0.0]) / math.hypot(0.1, 1.0), 0.9)
    assert not is_raised(None, 0.9)
    assert angular_spread_rad([np.array([1.0, 0.0])]) == 0.0
    box = VoteBox(0.3)
    for xyz in [(0, 0, 2), (0, 0, 2.1), (1, 0, 3)]:
        box.add(_result(target_xyz=xyz), 0.0)
    box.add(_result(status="no_candidates"), 0.0)
    d = box.decide(0.5, 2)
    assert d.winner is not None and d.share == 0.5 and d.empty_frames == 1
    assert box.decide(0.6, 2).winner is None
