"""The mission machine: the table is consistent, and each state's logic on synthetic perception results."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from behaviours.acknowledge import ack_schedule
from behaviours.blackboard import BehaviourConfig, Observation, SetServo, StatusText, TrackFrame
from behaviours.evidence import VoteBox, angular_spread_rad, is_raised
from behaviours.machine import PERCEPTION_STALE, STATES, SUSPEND_REASONS, SUSPENDABLE, TRANSITIONS
from behaviours.states import STATE_CLASSES
from dip3d_vehicle.config import load_params
from dip3d_vehicle.link.engage import LATCHING_REASONS
from dip3d_vehicle.perception.pipeline import PerceptionResult
from dip3d_vehicle.perception.values import Arm3D, ArmKeypoints, Candidates, ObjectCandidate, Selection
from dip3d_vehicle.servo.command import VelocityCommand
from sitl.scenario import load_scenario
from synthetic_target import target_frame
from mission_driver import engaged_mission, enter, feed



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


def _result(raised: bool = True, image_angle: float = 0.0, target_xyz=(0.5, 0.0, 2.0), confidence: float = 0.9,
            ambiguous: bool = False, status: str = "ok", joint_confidence: float = 1.0) -> PerceptionResult:
    """A perception result: an arm (raised or hanging; its joints' pose confidence) and optionally a chosen object."""
    shoulder = np.array([-0.5, 0.0, 2.5])
    direction = np.array([1.0, 0.0, 0.0]) if raised else np.array([0.1, 1.0, 0.0])
    direction /= np.linalg.norm(direction)
    xyz = np.array([shoulder, shoulder + 0.3 * direction, shoulder + 0.58 * direction])
    c, s = math.cos(image_angle), math.sin(image_angle)
    left = np.array([[500.0, 600.0], [500 + 100 * c, 600 + 100 * s], [500 + 190 * c, 600 + 190 * s]])
    conf = np.array([1.0, 1.0, joint_confidence])
    arm = ArmKeypoints("right", left, left - [30.0, 0.0], conf, conf.copy())
    arm3d = Arm3D(xyz, np.full(3, 0.05))
    if status != "ok":
        return PerceptionResult(status, "", arm, arm3d)
    obj = ObjectCandidate(np.array([1000.0, 600.0]), np.asarray(target_xyz, float), 0.02, (0, 1, 2))
    cands = Candidates(np.zeros((3, 2)), np.zeros((3, 2)), np.random.default_rng(0).random((3, 128), np.float32),
                       np.zeros(3))
    sel = Selection(0, (obj,), np.array([confidence]), confidence, math.inf, "default", ambiguous)
    return PerceptionResult("ok", "", arm, arm3d, cands, np.asarray([target_xyz] * 3, float), sel)


# ----------------------------------------------------------------------------- states
def test_idle_engages_only_when_the_link_is_engaged(rig):
    m = engaged_mission(rig)
    m.bb.engaged = False
    assert m.tick() is None and m.state == "idle"
    m.bb.engaged = True
    assert m.tick() == "engage" and m.state == "wait_for_diver"


def test_wait_for_diver_needs_n_of_m_raised_frames(rig):
    m = engaged_mission(rig, **{"behaviour.arm_seen_n": 3, "behaviour.arm_seen_m": 5})
    enter(m, "wait_for_diver")
    feed(m, [_result(True), _result(False), _result(True), _result(False)])
    assert m.state == "wait_for_diver"
    feed(m, [_result(True)])
    assert m.state == "confirm_point"


def test_an_arm_folded_up_over_the_shoulder_that_the_pose_source_is_unsure_of_is_not_raised(rig):
    """BlazePose folds a hanging arm it cannot see up over the shoulder, at a lower visibility: such frames
    neither start confirm_point nor keep a point alive; a sure folded arm, or an unsure arm held out, does."""
    m = engaged_mission(rig, **{"behaviour.arm_seen_n": 3, "behaviour.arm_seen_m": 5, "behaviour.arm_lost_frames": 3,
                                "behaviour.min_arm_confidence": 0.85, "behaviour.folded_arm_rad": 0.785})
    up = -math.pi / 2  # the wrist straight above the shoulder in the image
    enter(m, "wait_for_diver")
    feed(m, [_result(True, image_angle=up, joint_confidence=0.7) for _ in range(5)])
    assert m.state == "wait_for_diver"
    feed(m, [_result(True, image_angle=up, joint_confidence=0.9) for _ in range(3)], t0=1.0)
    assert m.state == "confirm_point"
    feed(m, [_result(True, image_angle=up, joint_confidence=0.7) for _ in range(3)], t0=2.0)
    assert m.state == "wait_for_diver"
    feed(m, [_result(True, image_angle=0.2, joint_confidence=0.7) for _ in range(3)], t0=3.0)
    assert m.state == "confirm_point"


def test_confirm_point_needs_a_steady_direction_for_the_hold_time(rig):
    m = engaged_mission(rig, **{"behaviour.steady_hold_s": 1.0, "behaviour.steady_angle_rad": 0.1})
    enter(m, "confirm_point")
    wobbly = [_result(True, image_angle=0.3 * (i % 2)) for i in range(10)]
    feed(m, wobbly)
    assert m.state == "confirm_point"
    fired = feed(m, [_result(True, image_angle=0.01 * (i % 2)) for i in range(6)], t0=2.0)
    assert fired[-1] == "steady" and m.state == "select_target"


def test_confirm_point_goes_back_when_the_arm_is_lowered(rig):
    m = engaged_mission(rig, **{"behaviour.arm_lost_frames": 3})
    enter(m, "confirm_point")
    feed(m, [_result(True), _result(False), _result(False)])
    assert m.state == "confirm_point"
    feed(m, [_result(False)])
    assert m.state == "wait_for_diver"


def test_confirm_point_times_out(rig):
    m = engaged_mission(rig, **{"behaviour.confirm_timeout_s": 1.0})
    enter(m, "confirm_point")
    m.bb.now_s = 1.5
    assert m.tick() == "timeout" and m.state == "wait_for_diver"


def test_select_target_clear_winner_is_acknowledged_and_tracked(rig):
    m = engaged_mission(rig, **{"behaviour.vote_frames": 4, "behaviour.min_votes": 3})
    enter(m, "select_target")
    fired = feed(m, [_result(target_xyz=(0.5, 0.0, 2.0 + 0.01 * i)) for i in range(4)])
    assert fired[-1] == "winner" and m.state == "acknowledge"
    # the chosen position is the frames' probability-weighted mean (the fused geometry); the tracker
    # starts from the latest sighting
    assert m.bb.tracker.active and np.allclose(m.bb.chosen.xyz_m, [0.5, 0.0, 2.015])
    assert np.allclose(m.bb.chosen.obj.xyz_m, [0.5, 0.0, 2.03])
    assert any(isinstance(o, StatusText) and "target chosen" in o.text for o in m.bb.outbox)


def _two_objects(target_xyz=(0.5, 0.0, 2.0), other_xyz=(0.5, -0.35, 2.0)) -> PerceptionResult:
    """A frame whose selector gives the target 0.85 and another object 0.1."""
    r = _result(target_xyz=target_xyz)
    other = ObjectCandidate(np.array([1000.0, 450.0]), np.asarray(other_xyz, float), 0.02, (2,))
    sel = replace(r.selection, objects=(r.selection.objects[0], other), scores=np.array([0.85, 0.1]), confidence=0.85)
    return replace(r, selection=sel)


@pytest.mark.parametrize("known", [True, False])
def test_the_tracker_starts_with_the_decisions_other_objects_as_neighbours(rig, known):
    """The fused hypotheses besides the winner go to the tracker as offsets from the winner; with
    ``behaviour.track_neighbours`` it refuses an object nearer one of them than the target's prediction (the servo
    keeps clear of them either way)."""
    m = engaged_mission(rig, **{"behaviour.vote_frames": 4, "behaviour.min_votes": 3,
                                "behaviour.track_neighbours": known})
    enter(m, "select_target")
    fired = feed(m, [_two_objects() for _ in range(4)])
    assert fired[-1] == "winner" and m.bb.tracker.active
    np.testing.assert_allclose(m.bb.tracker.neighbours_m, [[0.0, -0.35, 0.0]], atol=1e-9)
    assert m.bb.tracker.config.refuse_neighbours is known
    # the diver's body points go along as offsets too (kept clear of by the servo): shoulder (-0.5, 0, 2.5), elbow,
    # wrist, the hand 0.15 m past the wrist and the hips 0.5 m below the shoulder, all from the winner (0.5, 0, 2.0)
    np.testing.assert_allclose(m.bb.tracker.diver_m, [[-1.0, 0.0, 0.5], [-0.7, 0.0, 0.5], [-0.42, 0.0, 0.5],
                                                      [-0.27, 0.0, 0.5], [-1.0, 0.5, 0.5]], atol=1e-9)


def test_select_target_split_or_ambiguous_votes_go_back_to_confirm(rig):
    # the fused decision keeps gathering frames until behaviour.select_timeout_s, then goes back
    m = engaged_mission(rig, **{"behaviour.vote_frames": 4, "behaviour.min_votes": 3, "behaviour.select_timeout_s": 2.0,
                         "behaviour.second_look_max_tries": 0})  # (the second look: test_point_decision.py)
    enter(m, "select_target")
    split = [_result(target_xyz=(0.5, 0, 2.0)), _result(target_xyz=(1.5, 0, 3.0))] * 5
    fired = feed(m, split + [None])
    assert "winner" not in fired and fired[-1] == "ambiguous" and m.state == "confirm_point"
    m = engaged_mission(rig, **{"behaviour.vote_frames": 4, "behaviour.min_votes": 3, "behaviour.select_timeout_s": 0.9})
    enter(m, "select_target")
    unsure = [_result(), _result(ambiguous=True, confidence=0.4), _result(ambiguous=True, confidence=0.4), _result()]
    fired = feed(m, unsure + [None])
    assert "winner" not in fired and fired[-1] == "ambiguous"


def test_disengage_goes_idle_or_suspends_with_a_target_but_stale_perception_only_holds(rig):
    for state in STATES:
        if state in ("idle", "suspended"):
            continue
        m = engaged_mission(rig)
        enter(m, state)
        m.bb.engaged, m.bb.hold_reason = False, PERCEPTION_STALE
        m.tick()
        assert m.state == state
        m.bb.hold_reason = "mode changed ALT_HOLD -> MANUAL"
        if state in SUSPENDABLE:
            assert m.tick() == "suspend" and m.state == "suspended" and m.bb.command is None
        else:
            assert m.tick() == "disengage" and m.state == "idle" and m.bb.command is None


def test_an_operator_disable_or_another_cause_still_ends_theengaged_mission(rig):
    for reason in ("not enabled by the operator", "SYSID_MYGCS not read yet", ""):
        m = engaged_mission(rig)
        enter(m, "servo")
        m.bb.engaged, m.bb.hold_reason = False, reason
        assert m.tick() == "disengage" and m.state == "idle", reason


def test_acknowledge_nod_returns_to_the_start_heading_then_servo(rig):
    m = engaged_mission(rig, **{"behaviour.ack_kind": "nod"})
    steps, total = ack_schedule(m.bb.config)
    net = sum(s.yaw_rate_rad_s * ((steps[i + 1].start_s if i + 1 < len(steps) else total) - s.start_s)
              for i, s in enumerate(steps))
    assert abs(net) < 1e-9
    enter(m, "acknowledge")
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
    m = engaged_mission(rig, **{"behaviour.ack_kind": "lights", "behaviour.ack_flashes": 2})
    enter(m, "acknowledge")
    for k in range(200):
        m.bb.now_s = k * 0.02
        m.tick()
    servos = [o for o in m.bb.outbox if isinstance(o, SetServo)]
    assert [s.pwm for s in servos] == [1900, 1100, 1900, 1100] and m.bb.command is None


def test_lost_target_gives_up_after_the_timeout(rig):
    m = engaged_mission(rig, **{"behaviour.lost_timeout_s": 2.0, "behaviour.abort_hold_s": 1.0})
    enter(m, "lost_target")
    for k in range(1, 120):
        m.bb.now_s = k * 0.02
        m.bb.observation = Observation(m.bb.now_s, k, track=TrackFrame(Candidates.empty(), np.zeros((0, 3))))
        m.tick()
    assert m.state == "abort" and m.bb.command is None
    m.bb.now_s += 1.1
    m.tick()
    assert m.state == "wait_for_diver"


def test_done_reports_and_waits_for_the_arm_to_come_down(rig):
    m = engaged_mission(rig, **{"behaviour.release_frames": 3})
    enter(m, "done")
    assert m.bb.arrived and any(isinstance(o, StatusText) and "arrived" in o.text for o in m.bb.outbox)
    feed(m, [_result(True)] * 5)
    assert m.state == "done"
    feed(m, [_result(False)] * 3)
    assert m.state == "wait_for_diver"


# ----------------------------------------------------------------------------- suspend and resume
def _servoing(rig, **over):
    """A mission servoing to a tracked target (seen at t = 0), engaged and enabled."""
    m = engaged_mission(rig, **over)
    cands, pts, obj = target_frame(rig)
    m.bb.tracker.start(obj, cands, 0.0)
    m.bb.operator_enabled = True
    enter(m, "servo")
    return m, TrackFrame(cands, pts)


def _tick_at(m, t: float, track: TrackFrame | None = None):
    """One tick at ``t`` with an optional tracking frame captured then; return the trigger fired. Perception is fresh
    as the loop judges it: the newest frame at most ``behaviour.perception_stale_s`` old."""
    m.bb.now_s = t
    m.bb.observation = Observation(t, int(t * 50), track=track) if track is not None else None
    last = m.bb.observation or m.bb.last_observation
    m.bb.perception_fresh = last is not None and t - last.stamp_s <= m.bb.config.perception_stale_s
    out = m.tick()
    if m.bb.observation is not None:
        m.bb.last_observation = m.bb.observation
    m.bb.observation = None
    return out


def _lose_link(m, t: float, reason: str = "autopilot lost") -> str | None:
    """The link disengages for a latching reason: the enable is cleared (as engage.decide does)."""
    m.bb.engaged, m.bb.hold_reason, m.bb.operator_enabled = False, reason, False
    return _tick_at(m, t)


def _reenable(m) -> None:
    """Pilot re-arms / selects the mode, the operator re-enables: the link engages again."""
    m.bb.engaged, m.bb.hold_reason, m.bb.operator_enabled = True, "", True


def test_suspend_reasons_are_the_links_enable_clearing_reasons():
    assert set(SUSPEND_REASONS) == set(LATCHING_REASONS)
    suspend = next(t for t in TRANSITIONS if t["trigger"] == "suspend")
    assert set(suspend["source"]) == set(SUSPENDABLE) and suspend["dest"] == "suspended"


@pytest.mark.parametrize("reason", ["autopilot lost", "ground station lost", "disarmed",
                                    "mode changed ALT_HOLD -> MANUAL"])
@pytest.mark.parametrize("state", ["servo", "lost_target", "arrive"])
def test_a_loss_during_the_approach_stops_motion_at_once_and_keeps_the_target(rig, state, reason):
    m, frame = _servoing(rig)
    enter(m, state)
    m.bb.set_command(VelocityCommand(surge_m_s=0.2))
    assert _lose_link(m, 0.1, reason) == "suspend"
    assert m.state == "suspended" and m.bb.command is None and m.needs == "track"
    assert m.bb.tracker.active and not m.bb.tracker.lost
    assert any("suspending the mission" in line and reason in line for line in m.bb.story)
    assert any(isinstance(o, StatusText) and "suspended" in o.text for o in m.bb.outbox)
    # while suspended it keeps tracking the target, commands nothing, and stays until re-engaged
    for k in range(1, 20):
        m.bb.hold_reason = "autopilot not heard"
        assert _tick_at(m, 0.1 + 0.2 * k, frame) is None
        assert m.state == "suspended" and m.bb.command is None
    assert m.bb.tracker.misses == 0 and m.bb.tracker.last_seen_s == pytest.approx(0.1 + 0.2 * 19)


def test_a_perception_hold_keeps_the_servo_command_but_the_reckoning_stops_with_the_vehicle(rig):
    """Stale perception holds the state (its ``command`` kept) while the link sends only its stop value: the tracker
    and its search box reckon with what the vehicle does (issue 11 session 61, ``camera_black`` seed 5: the servo's
    approach carried on for 3.3 s in the prediction, which then sat on the placard in front)."""
    m, frame = _servoing(rig)
    for k in range(1, 4):
        _tick_at(m, 0.2 * k, frame)
    command, target = m.bb.command, m.bb.tracker.xyz_m.copy()
    assert command is not None and command.surge_m_s > 0.05 and m.bb.command_in_force == command
    m.bb.engaged, m.bb.hold_reason = False, "perception stale"
    _tick_at(m, 3.6)  # no frame for 3 s
    assert m.state == "servo" and m.bb.command == command and m.bb.command_in_force is None
    held = m.bb.tracker.predicted_xyz(3.6, m.bb.command_in_force)
    driven = m.bb.tracker.predicted_xyz(3.6, command)
    assert target[2] - held[2] < 0.5 * (target[2] - driven[2])  # coasting from its speed, not driving on


def test_re_engaged_after_the_re_enable_with_the_target_tracked_resumes_the_servo(rig):
    m, frame = _servoing(rig, **{"behaviour.resume_within_s": 30.0})
    _lose_link(m, 0.1)
    for k in range(1, 40):  # 8 s suspended, the target still seen
        _tick_at(m, 0.1 + 0.2 * k, frame)
    _reenable(m)
    assert _tick_at(m, 8.0, frame) == "resume" and m.state == "servo"
    assert any("resuming the servo" in line for line in m.bb.story)
    _tick_at(m, 8.2, frame)
    assert m.bb.command is not None and not m.bb.command.is_neutral()  # servoing to the kept target again


def test_a_loss_during_the_acknowledgement_suspends_and_the_re_enable_acknowledges_again(rig):
    """A link cut during the nod kept the decision only if the diver still pointed at the re-enable (issue 11 session
    63's ``cut_acknowledge`` probe: 1/5 reached, the mission ended in idle): it suspends instead, and resuming plays
    the whole acknowledgement again before the servo."""
    m, frame = _servoing(rig, **{"behaviour.resume_within_s": 30.0})
    enter(m, "acknowledge")
    _, total_s = ack_schedule(m.bb.config)
    assert _tick_at(m, 0.4, frame) is None and m.bb.command is not None  # mid-nod: yawing
    assert _lose_link(m, 0.5) == "suspend" and m.state == "suspended" and m.bb.command is None
    for k in range(1, 20):
        _tick_at(m, 0.5 + 0.2 * k, frame)
    _reenable(m)
    assert _tick_at(m, 4.5, frame) == "reacknowledge" and m.state == "acknowledge"
    assert any("acknowledging it again" in line for line in m.bb.story)
    fired = [_tick_at(m, 4.5 + 0.1 * k, frame) for k in range(1, int(total_s / 0.1) + 3)]
    assert fired.count("acked") == 1 and m.state in ("servo", "arrive")
    assert fired.index("acked") >= int(total_s / 0.1) - 1  # the whole nod again, not its remainder
    # a suspension after the acknowledgement ended resumes the servo straight away
    enter(m, "servo")
    _lose_link(m, 6.0 + total_s)
    _reenable(m)
    assert _tick_at(m, 6.2 + total_s, frame) == "resume" and m.state == "servo"


def test_a_disable_during_the_acknowledgement_ends_the_mission(rig):
    """Only the enable-clearing losses suspend; the operator's own disable ends the mission, as in every state."""
    m, frame = _servoing(rig)
    enter(m, "acknowledge")
    m.bb.engaged, m.bb.hold_reason = False, "not enabled by the operator"
    assert _tick_at(m, 0.3, frame) == "disengage" and m.state == "idle" and m.bb.command is None


def test_re_engaged_with_the_target_lost_goes_back_to_wait_for_diver_and_says_so(rig):
    m, frame = _servoing(rig, **{"behaviour.track_lost_frames": 3})
    _lose_link(m, 0.1)
    empty = TrackFrame(Candidates.empty(), np.zeros((0, 3)))
    for k in range(1, 10):
        _tick_at(m, 0.1 + 0.2 * k, empty)
    assert m.bb.tracker.lost
    _reenable(m)
    assert _tick_at(m, 2.2, empty) == "expired" and m.state == "wait_for_diver" and m.bb.command is None
    assert any("target not tracked" in line for line in m.bb.story)
    assert any(isinstance(o, StatusText) and "not resuming" in o.text for o in m.bb.outbox)


def test_re_engaged_with_the_target_not_seen_recently_goes_back_to_wait_for_diver(rig):
    m, _ = _servoing(rig, **{"behaviour.lost_grace_s": 1.0})
    _lose_link(m, 0.1)
    _tick_at(m, 2.0)  # no frames at all while suspended: the last sighting is 2 s old
    _reenable(m)
    assert _tick_at(m, 2.02) == "expired" and m.state == "wait_for_diver"


def test_re_engaged_too_late_goes_back_to_wait_for_diver(rig):
    m, frame = _servoing(rig, **{"behaviour.resume_within_s": 5.0})
    _lose_link(m, 0.1)
    _reenable(m)
    m.bb.engaged = False  # re-enabled, but still not engaged (not armed yet)
    m.bb.hold_reason = "not armed"
    for k in range(1, 25):
        _tick_at(m, 0.1 + 0.2 * k, frame)
    m.bb.engaged = True
    assert _tick_at(m, 5.2, frame) == "expired" and m.state == "wait_for_diver"
    assert any("target forgotten" in line for line in m.bb.story)


def test_not_re_engaged_within_the_resume_time_forgets_the_target(rig):
    m, frame = _servoing(rig, **{"behaviour.resume_within_s": 3.0})
    _lose_link(m, 0.1)
    fired = [_tick_at(m, 0.1 + 0.2 * k, frame) for k in range(1, 20)]
    assert "disengage" in fired and m.state == "idle" and m.bb.command is None
    _reenable(m)
    assert _tick_at(m, 4.2) == "engage" and m.state == "wait_for_diver"


def test_never_resumes_without_the_operator_s_re_enable(rig):
    m, frame = _servoing(rig)
    m.bb.engaged, m.bb.hold_reason = False, "disarmed"  # the enable was NOT seen cleared
    _tick_at(m, 0.1)
    assert m.state == "suspended"
    for k in range(1, 5):
        _tick_at(m, 0.1 + 0.2 * k, frame)
    m.bb.engaged, m.bb.hold_reason = True, ""  # engaged again, but no enable cycle was ever seen
    assert _tick_at(m, 1.2, frame) == "expired" and m.state == "wait_for_diver" and m.bb.command is None
    assert any("without re-enable" in line for line in m.bb.story)


def test_stale_perception_while_suspended_keeps_it_suspended(rig):
    m, frame = _servoing(rig)
    _lose_link(m, 0.1)
    m.bb.hold_reason = PERCEPTION_STALE
    assert _tick_at(m, 0.5) is None and m.state == "suspended"


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


@pytest.mark.parametrize("clearance_m", [0.6, 0.0])
def test_the_servo_goes_round_a_known_object_beside_its_way(rig, clearance_m):
    """``behaviour.servo_clearance_m``: a known neighbour 0.15 m right of the stand-off point sways the vehicle left
    (the way round it ends turned left about the target), ramped by the servo's sway acceleration limit and told
    once; with 0 the servo goes straight."""
    m, frame = _servoing(rig, **{"behaviour.servo_clearance_m": clearance_m})
    m.bb.tracker.know_neighbours(np.array([[0.15, 0.0, -1.0]]))  # the target is at (0.3, 0, 2.0)
    sways = []
    for k in range(1, 6):
        _tick_at(m, 0.2 * k, frame)
        sways.append(m.bb.command.sway_m_s)
    told = [s for s in m.bb.story if "going round, the stand-off turned" in s and s.endswith("left about the target")]
    if clearance_m:
        ramp = float(m.bb.servo.max_accel[1]) * 0.2
        assert sways[0] == pytest.approx(-ramp) and all(b <= a for a, b in zip(sways, sways[1:])) and len(told) == 1
        assert min(sways) >= -float(m.bb.servo.max_speed[1]) - 1e-9
    else:
        assert sways == [0.0] * 5 and not told


def test_the_servo_keeps_clear_of_the_diver(rig):
    """The diver's hand 0.2 m right of the stand-off point (``tracker.diver_m``) turns the way left, and the pilot is
    told it is the diver (kept as far as an object: no body margin)."""
    m, frame = _servoing(rig, **{"behaviour.servo_clearance_m": 0.6, "behaviour.servo_diver_margin_m": 0.0})
    m.bb.tracker.diver_m = np.array([[0.2, 0.0, -1.0]])  # the target is at (0.3, 0, 2.0)
    for k in range(1, 4):
        _tick_at(m, 0.2 * k, frame)
    assert m.bb.command.sway_m_s < 0
    assert any("the diver at" in s and "going round" in s for s in m.bb.story)


@pytest.mark.parametrize("margin_m, turned", [(0.0, False), (0.3, True)])
def test_the_diver_is_kept_further_than_an_object_by_the_body_margin(rig, margin_m, turned):
    """A point of the diver 0.8 m left of the direct way: clear of the 0.6 m an object needs, so no sway without the
    body margin (``behaviour.servo_diver_margin_m``); with 0.3 m it must pass 0.9 m away and the way turns right. The
    same point as an object (a known neighbour) never turns the way."""
    for diver in (True, False):
        m, frame = _servoing(rig, **{"behaviour.servo_clearance_m": 0.6, "behaviour.servo_diver_margin_m": margin_m})
        point = np.array([[-0.95, 0.0, -1.0]])  # the target is at (0.3, 0, 2.0): the point at (-0.65, 0, 1.0)
        if diver:
            m.bb.tracker.diver_m = point
        else:
            m.bb.tracker.know_neighbours(point)
        for k in range(1, 4):
            _tick_at(m, 0.2 * k, frame)
        assert (m.bb.command.sway_m_s > 0) == (turned and diver), (diver, m.bb.command)


@pytest.mark.parametrize("half_m, turned", [(0.0, False), (0.25, True)])
def test_an_object_is_kept_clear_from_its_edge(rig, half_m, turned):
    """A known neighbour 0.8 m left of the direct way: clear of the 0.6 m clearance as a point, but an object
    whose features span 0.5 m across (its edge 0.25 m nearer, ``tracker.neighbours_half_m``) turns the way right."""
    m, frame = _servoing(rig, **{"behaviour.servo_clearance_m": 0.6})
    m.bb.tracker.know_neighbours(np.array([[-0.95, 0.0, -1.0]]), [half_m])  # the target is at (0.3, 0, 2.0)
    for k in range(1, 4):
        _tick_at(m, 0.2 * k, frame)
    assert (m.bb.command.sway_m_s > 0) == turned, m.bb.command


def test_the_servo_holds_short_when_no_way_keeps_clear(rig):
    """Objects either side of the stand-off point, every way to it nearer than 0.6 m to one of them: the servo's
    stand-off grows (held on the blackboard, never shrinking while the target is the same) to the shortest with a
    clear way, and the pilot is told once."""
    m, frame = _servoing(rig, **{"behaviour.servo_clearance_m": 0.6})
    m.bb.tracker.know_neighbours(np.array([[-0.1, 0.0, -1.2], [-0.6, 0.0, -1.2]]))  # the target is at (0.3, 0, 2.0)
    held = []
    for k in range(1, 6):
        _tick_at(m, 0.2 * k, frame)
        held.append(m.bb.held_short_m)
    assert held[0] > 0 and held == sorted(held)
    assert m.bb.servo.standoff_m == pytest.approx(m.bb.config.standoff_m + held[-1])
    assert m.bb.errors.range_m == pytest.approx(2.0 - m.bb.servo.standoff_m, abs=0.02)
    assert len([s for s in m.bb.story if "holding short" in s]) == 1


def _arriving(rig, **over):
    """A mission in arrive (hold 1.5 s), engaged and enabled, tracking a target 1 m ahead at the servo's goal pixel;
    return it and that pixel (u, v)."""
    m = engaged_mission(rig, **{"behaviour.arrive_hold_s": 1.5, **over})
    u, v = m.bb.servo.desired_px
    cands, _, obj = target_frame(rig, xyz=(0.0, 0.0, 1.0), px=(u, v))
    m.bb.tracker.start(obj, cands, 0.0)
    m.bb.operator_enabled = True
    enter(m, "arrive")
    return m, (u, v)


@pytest.mark.parametrize("step_m, clearance_m, held", [(0.0, 0.6, True), (0.012, 0.6, False), (0.0, 0.0, False)])
def test_arrive_settles_through_a_centimetre_of_range_jitter_but_not_while_coasting(rig, step_m, clearance_m, held):
    """With the sidestep on, arrive's range rate is also taken over ``SETTLE_WINDOW_S``: a standing vehicle whose
    target's stereo range jitters by 1 cm per frame (0.05 m/s frame to frame) is settled; one coasting at 0.06 m/s
    (1.2 cm per frame) is not. With it off, the frame-to-frame rate alone decides, as before."""
    m, (u, v) = _arriving(rig, **{"behaviour.servo_clearance_m": clearance_m})
    for k in range(1, 16):  # 3 s, all inside the 0.1 m range tolerance
        depth = 1.0 + 0.01 * (k % 2) if not step_m else 1.08 - step_m * k
        c, p, _ = target_frame(rig, xyz=(0.0, 0.0, depth), px=(u, v))
        _tick_at(m, 0.2 * k, TrackFrame(c, p))
        if m.state != "arrive":
            break
    assert (m.state == "done") is held, m.bb.story[-3:]


@pytest.mark.parametrize("jump_frames, outcome", [((4,), "done"), (tuple(range(4, 16)), "servo")])
def test_arrive_judges_the_errors_over_its_window_not_one_frame(rig, jump_frames, outcome):
    """The tracked centre of a placard can jump to another part of it for a frame (70 px, past tolerance x
    hysteresis): arrive neither goes back to servo nor restarts the hold for one such frame, and holds in the time it
    would have without it. A centre that stays off (the vehicle drifted) is ``drifted`` within the window (1 s)."""
    m, (u, v) = _arriving(rig)
    states = []
    for k in range(1, 16):  # 3 s at the stand-off
        c, p, _ = target_frame(rig, xyz=(0.0, 0.0, 1.0), px=(u, v + (70.0 if k in jump_frames else 0.0)))
        _tick_at(m, 0.2 * k, TrackFrame(c, p))
        states.append(m.state)
        if m.state != "arrive":
            break
    assert m.state == outcome, m.bb.story[-3:]
    if outcome == "done":
        assert len(states) == 10  # held at 2.0 s: inside from the second frame (the rate needs two), 1.5 s hold
    else:
        assert len(states) <= 7  # back to servo by 1.4 s, 0.6 s after the centre moved


def _beside_the_way(m, short_m: float) -> np.ndarray:
    """An object beside the middle of the direct way to the tracked target, ``short_m`` nearer it than the
    clearance (negative: farther), as an offset from the target (metres)."""
    from behaviours.clearance import HULL_HALF_LENGTH_M, approach_end_m

    target = np.asarray(m.bb.tracker.xyz_m, float)
    start = np.array([0.0, 0.0, -(m.bb.servo.mount.forward_m + HULL_HALF_LENGTH_M)])
    d = approach_end_m(target, m.bb.standoff_m) - start
    across = np.array([d[2], 0.0, -d[0]]) / math.hypot(d[0], d[2])
    return (start + d / 2 + across * (m.bb.config.servo_clearance_m - short_m) - target)[None]


def test_the_servo_keeps_the_direct_way_while_it_falls_short_by_less_than_the_band(rig):
    """A way on the edge of clear does not flip: the direct way, taken, stays while an object comes 0.03 m inside the
    clearance (a fresh plan would turn), and is left at 0.09 m inside."""
    m, frame = _servoing(rig, **{"behaviour.servo_clearance_m": 0.6})
    sways = []
    for k, short in enumerate((-0.1, 0.03, 0.09), start=1):
        m.bb.tracker.know_neighbours(_beside_the_way(m, short))
        _tick_at(m, 0.2 * k, frame)
        sways.append(m.bb.command.sway_m_s)
    assert sways[0] == sways[1] == 0.0 and sways[2] != 0.0
    enter(m, "servo")  # a fresh plan: no direct way taken on the last frame
    m.bb.tracker.know_neighbours(_beside_the_way(m, 0.03))
    _tick_at(m, 0.8, frame)
    assert m.bb.command.sway_m_s != 0.0


def _hidden_and_lost(rig, beside=(), **over):
    """A servoing mission whose target (0.3, 0, 2.0) a known object on its line of sight, halfway, now hides (and
    objects at ``beside``, camera frame): empty tracking frames until lost_target; return the mission, the time
    reached (s), the target's frame and an empty frame."""
    m, frame = _servoing(rig, **{"behaviour.lost_grace_s": 0.5, "behaviour.lost_timeout_s": 2.0, **over})
    # the hider at (0.17, 0, 1.0): 2 cm right of the line of sight
    m.bb.tracker.know_neighbours(np.array([[0.17, 0.0, 1.0], *beside]) - [0.3, 0.0, 2.0])
    empty = TrackFrame(Candidates.empty(), np.zeros((0, 3)))
    t = 0.0
    while m.state != "lost_target":
        t += 0.2
        _tick_at(m, t, empty)
        assert t < 3.0
    return m, t, frame, empty


def test_a_target_lost_behind_a_known_object_is_looked_for_from_a_step_to_the_side(rig):
    """The known object leans right of the line of sight: the vehicle sways left (away) at
    ``behaviour.look_round_speed_m_s`` until the commanded distance clears the line by 0.3 m, then stops; it gives
    up ``behaviour.lost_timeout_s`` after the step, not before."""
    m, t0, _, empty = _hidden_and_lost(rig)
    assert any("stepping" in s and "left to look round it" in s for s in m.bb.story)
    step_m = float(next(s for s in m.bb.story if "stepping" in s).split("stepping ")[1].split(" m")[0])
    assert 0.2 < step_m < 0.8
    sways, t = [], t0
    while m.state == "lost_target":
        t += 0.1
        _tick_at(m, t, empty if round(t * 10) % 2 else None)
        sways.append((t, 0.0 if m.bb.command is None else m.bb.command.sway_m_s))
    moving = [s for _, s in sways if s]
    assert moving and all(s == pytest.approx(-0.15) for s in moving)
    assert sum(-s * 0.1 for _, s in sways) == pytest.approx(step_m, abs=0.1)
    assert m.state == "abort" and t - t0 == pytest.approx(2.0 + step_m / 0.15, abs=0.25)


def test_with_look_round_off_or_no_safe_step_a_lost_target_is_waited_for_holding_still(rig):
    """Off (``behaviour.look_round_max_m`` 0), or objects 0.6 m either side of the camera (a step either way would
    bring the hull nearer one than ``behaviour.servo_clearance_m``): the vehicle holds still as before."""
    for beside, over in (((), {"behaviour.look_round_max_m": 0.0}), (([-0.6, 0.0, 0.0], [0.6, 0.0, 0.0]), {})):
        m, t, _, empty = _hidden_and_lost(rig, beside, **over)
        assert any("holding and looking for it" in s for s in m.bb.story), over
        while m.state == "lost_target":
            t += 0.2
            _tick_at(m, t, empty)
            assert m.bb.command is None or m.state != "lost_target"
        assert m.state == "abort"


def test_a_target_seen_again_during_the_step_goes_back_to_the_servo(rig):
    m, t, frame, empty = _hidden_and_lost(rig)
    _tick_at(m, t + 0.2, empty)
    assert m.bb.command is not None and m.bb.command.sway_m_s < 0
    assert _tick_at(m, t + 0.4, frame) == "reacquired" and m.state == "servo"


def test_lost_target_searches_round_the_prediction_and_the_whole_frame_in_turn(rig):
    m, t, _, empty = _hidden_and_lost(rig)
    size = (1600, 1200)
    boxes = []
    for k in range(4):
        _tick_at(m, t + 0.2 * (k + 1), empty)
        boxes.append(m.track_roi(rig, size))
    assert sum(b is None for b in boxes) == 2 and sum(b is not None for b in boxes) == 2
