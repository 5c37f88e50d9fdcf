"""The behaviour of each mission state: small classes with enter / tick / exit.

The machine (``machine.py``) decides which state runs; a state only looks at the blackboard,
sets the command and returns a trigger name (or None to stay). ``needs`` tells the loop which
perception the state wants: ``full`` (the perception core: diver, pointing, selection) or
``track`` (full-frame features for the tracker; no pose needed while the vehicle moves).
Time is ``bb.now_s`` (the loop's clock); nothing here sleeps or starts a timer.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from dip3d_vehicle.perception.held_arm import HeldArm
from dip3d_vehicle.servo.command import VelocityCommand

from .acknowledge import Acknowledgement
from .blackboard import Blackboard
from .close_in import CloseInStep, horizontal_range_m, plan_close_in
from .evidence import VoteBox, angular_spread_rad, arm_direction, image_direction, is_raised

from .fusion import NONE, FrameEvidence, FusedDecision, PointFusion
from .second_look import LookStep, plan_second_look
from .tracker import TrackedTarget

__all__ = ["MissionState", "Idle", "WaitForDiver", "ConfirmPoint", "SelectTarget", "Acknowledge",
           "Servo", "LostTarget", "Arrive", "Done", "Abort", "Suspended", "NothingThere", "Stopped", "SecondLook",
           "CloseIn", "STATE_CLASSES"]


class MissionState:
    """Base class: one state's behaviour. Subclasses override what they need."""

    name = "state"
    needs = "full"
    triggers: tuple[str, ...] = ()

    def __init__(self) -> None:
        self.entered_s = 0.0

    def enter(self, bb: Blackboard) -> None:
        """Called on entry (after the previous state's exit)."""
        self.entered_s = bb.now_s

    def tick(self, bb: Blackboard) -> str | None:
        """One loop tick; return a trigger name to leave, or None to stay."""
        return None

    def exit(self, bb: Blackboard) -> None:
        """Called on exit."""

    def elapsed(self, bb: Blackboard) -> float:
        """Seconds since entry."""
        return bb.now_s - self.entered_s


def _new_result(bb: Blackboard):
    """Return this tick's new perception-core result, or None."""
    obs = bb.observation
    return None if obs is None else obs.result


def _raised(bb: Blackboard, result) -> bool:
    """Return True when a result shows a raised pointing arm."""
    return is_raised(arm_direction(result), bb.config.min_raise_rad)


def _track(bb: Blackboard) -> tuple[bool, TrackedTarget | None]:
    """Feed a new tracking frame to the tracker: (was there a new frame, the target or None)."""
    obs = bb.observation
    if obs is None or obs.track is None:
        return False, None
    found = bb.tracker.update(obs.track.candidates, obs.track.xyz_m, obs.stamp_s, bb.command)
    if found is not None:
        bb.target = found
    return True, found


def _fuse(bb: Blackboard, result, direction) -> FrameEvidence | None:
    """Add a raised-arm frame to the point's fused evidence; restart it when the pointing moved.

    The point's direction is the mean left-image arm direction of its fused frames; a frame more
    than ``behaviour.steady_angle_rad`` away from it starts a new point.
    """
    c = bb.config
    if bb.fusion is None:
        bb.fusion = PointFusion(c.vote_radius_m, c.fusion_temper, c.fusion_floor_p, c.fusion_no_objects_none_p,
                                c.fusion_max_effective_frames, c.fusion_min_shared_posterior,
                                shared_rule=c.fusion_shared_rule)
    fusion = bb.fusion
    if direction is not None and fusion.direction is not None:
        mean = fusion.direction / max(float(np.linalg.norm(fusion.direction)), 1e-9)
        if angular_spread_rad([mean, direction]) * 2 > c.steady_angle_rad and fusion.frames:
            bb.say(f"pointing moved: fused evidence of {len(fusion.frames)} frames restarted")
            fusion.reset()
    arm_frames = 1
    if bb.decide_held is not None and c.fusion_arm_frames > 1 and result.arm is not None \
            and result.status in ("ok", "nothing_on_ray"):
        if fusion.held_arm.arms.maxlen != c.fusion_arm_frames:
            fusion.held_arm = HeldArm(c.fusion_arm_frames)
        fusion.held_arm.add(result.arm)
        arm_frames = len(fusion.held_arm)
        result = bb.decide_held(fusion.held_arm.mean(), arm_frames, result)
    part = fusion.add(result, bb.observation.stamp_s, arm_frames)
    if part is not None and direction is not None:
        fusion.direction = direction.copy() if fusion.direction is None else fusion.direction + direction
    return part


def _tell_decision(bb: Blackboard, decision: FusedDecision) -> None:
    """Put the fused posterior, the hypotheses and each frame's part in the story (and the log)."""
    fusion = bb.fusion
    bb.decision = decision
    bb.say(f"fused posterior over {decision.frames} frames (weight {fusion.weight:.2f}): {decision.summary()}")
    bb.say(f"hypotheses: {fusion.describe()}")
    bb.say("frames: " + "; ".join(f.summary() for f in fusion.frames))


class Idle(MissionState):
    """Disengaged (pilot in control, or not yet enabled): no motion; wait for the link to engage."""

    name = "idle"
    triggers = ("engage",)

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()

    def tick(self, bb: Blackboard) -> str | None:
        return "engage" if bb.engaged else None


class WaitForDiver(MissionState):
    """Hold still until a raised arm is seen in N of the last M frames."""

    name = "wait_for_diver"
    triggers = ("arm_seen",)

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.set_command(None)
        bb.fusion = None  # a new point starts its evidence afresh
        bb.second_looks = 0
        bb.close_ins = 0
        self.history: deque[bool] = deque(maxlen=bb.config.arm_seen_m)

    def tick(self, bb: Blackboard) -> str | None:
        result = _new_result(bb)
        if result is None:
            return None
        self.history.append(_raised(bb, result))
        if sum(self.history) >= bb.config.arm_seen_n:
            bb.say(f"diver's arm raised in {sum(self.history)} of the last {len(self.history)} frames")
            return "arm_seen"
        return None


class _ArmWatch(MissionState):
    """A state that gives up when the diver's arm is down for ``arm_lost_frames`` frames in a row."""

    misses = 0

    def arm_gone(self, bb: Blackboard, raised: bool, why: str) -> bool:
        """Count a frame without the raised arm (reset on one with it); True once the arm is gone."""
        self.misses = 0 if raised else self.misses + 1
        if self.misses >= bb.config.arm_lost_frames:
            bb.say(why)
            return True
        return False


class ConfirmPoint(_ArmWatch):
    """Wait until the pointing direction (in the left image) stays within an angle for a hold time."""

    name = "confirm_point"
    triggers = ("steady", "arm_lost", "timeout")

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.set_command(None)
        self.window: list[tuple[float, np.ndarray]] = []
        self.misses = 0

    def tick(self, bb: Blackboard) -> str | None:
        c = bb.config
        if self.elapsed(bb) > c.confirm_timeout_s:
            bb.say(f"no steady pointing in {c.confirm_timeout_s:g} s")
            return "timeout"
        result = _new_result(bb)
        if result is None:
            return None
        if self.arm_gone(bb, is_raised(arm_direction(result), c.min_raise_rad), "diver lowered the arm or left"):
            return "arm_lost"
        if self.misses:
            return None
        direction = image_direction(result)
        stamp = bb.observation.stamp_s
        _fuse(bb, result, direction)
        self.window.append((stamp, direction))
        spread = angular_spread_rad([d for _, d in self.window])
        if spread > c.steady_angle_rad:
            self.window = [(stamp, direction)]
            return None
        if stamp - self.window[0][0] >= c.steady_hold_s and len(self.window) >= 2:
            bb.say(f"pointing steady for {stamp - self.window[0][0]:.1f} s (spread {spread:.3f} rad)")
            return "steady"
        return None


class SelectTarget(_ArmWatch):
    """Fuse the point's frames into one posterior (nothing detected included); decide when it is clear.

    The evidence gathered since the point began (confirm_point's frames too) is kept across an
    ``ambiguous`` round trip through confirm_point while the diver keeps pointing the same way.
    A winning object -> ``winner``; "nothing detected" winning -> ``nothing_there``; no clear
    winner within ``behaviour.select_timeout_s``: the diver farther than ``behaviour.decide_max_range_m``
    -> ``close_in`` (while tries are left and a safe advance exists); two objects close ->
    ``second_look`` (while tries are left and a step separates them); else ``ambiguous``.
    """

    name = "select_target"
    triggers = ("winner", "nothing_there", "close_in", "second_look", "ambiguous", "arm_lost")

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.set_command(None)
        self.box = VoteBox(bb.config.vote_radius_m)
        self.misses = 0
        self.added = 0
        self.last_arm3d = None

    def tick(self, bb: Blackboard) -> str | None:
        c = bb.config
        if self.elapsed(bb) > c.select_timeout_s:
            return self.undecided(bb)
        result = _new_result(bb)
        if result is None:
            return None
        if self.arm_gone(bb, _raised(bb, result), "diver lowered the arm or left while selecting"):
            return "arm_lost"
        if self.misses:
            return None
        self.box.add(result, bb.observation.stamp_s)
        self.last_arm3d = result.arm3d if result.arm3d is not None else self.last_arm3d
        self.added += _fuse(bb, result, image_direction(result)) is not None
        if self.added == 0 or len(bb.fusion.frames) < c.vote_frames:
            return None
        decision = bb.fusion.decide(c.fusion_min_posterior, c.min_votes)
        bb.decision = decision
        if decision.kind == "undecided":
            return None
        _tell_decision(bb, decision)
        if decision.kind == "none":
            return "nothing_there"
        w = bb.fusion.as_vote(decision.winner)
        bb.chosen = w
        bb.tracker.start(w.obj, w.candidates, w.stamp_s)
        bb.target = bb.tracker.last
        xyz = ", ".join(f"{v:.2f}" for v in w.xyz_m)
        bb.say(f"target chosen at ({xyz}) m, p {decision.posterior[decision.best]:.2f}", pilot=True)
        bb.say(f"votes: {self.box.summary()}")
        return "winner"

    def undecided(self, bb: Blackboard) -> str:
        """No clear winner in time: say why and what the evidence was."""
        c = bb.config
        fusion = bb.fusion
        if fusion is None or not fusion.frames:
            bb.say(f"no decision in {c.select_timeout_s:g} s: no usable frame", "notice", pilot=True)
            return "ambiguous"
        decision = fusion.decide(c.fusion_min_posterior, c.min_votes)
        _tell_decision(bb, decision)
        advance = self.close_in_step(bb)
        if advance is not None:
            bb.close_in_step = advance
            return "close_in"
        step = self.look_step(bb, decision)
        if step is not None:
            bb.look_step = step
            return "second_look"
        bb.say(f"ambiguous: {decision.reason}", "notice", pilot=True)
        return "ambiguous"

    def close_in_step(self, bb: Blackboard) -> CloseInStep | None:
        """Return the advance toward a diver beyond ``behaviour.decide_max_range_m``, or None (near, no tries left, unsafe)."""
        c, arm3d = bb.config, self.last_arm3d
        if arm3d is None or bb.close_ins >= c.close_in_max_tries or bb.fusion is None:
            return None
        rng = horizontal_range_m(arm3d.xyz_m[0])
        if rng <= c.decide_max_range_m:
            return None
        keep = [h.xyz_m for h in bb.fusion.hypotheses]
        step = plan_close_in(arm3d.xyz_m[[0, 2]], np.reshape(keep, (-1, 3)), c.decide_max_range_m,
                             c.close_in_standoff_m, c.close_in_clearance_m, bb.servo.focal_px,
                             bb.servo.principal_point_px, c.second_look_margin_px, c.close_in_min_step_m,
                             max_descent_m=c.close_in_max_descent_m)
        if step is None:
            bb.say(f"diver {rng:.1f} m away (> {c.decide_max_range_m:g} m), but no advance keeps every candidate "
                   f"in view and clear")
        return step

    def look_step(self, bb: Blackboard, decision: FusedDecision) -> LookStep | None:
        """Return the second look's step when two objects are close and a step separates them, else None."""
        c, post = bb.config, decision.posterior
        if bb.second_looks >= c.second_look_max_tries or decision.second is None or NONE in (decision.best,
                                                                                              decision.second):
            return None
        if min(post[decision.best], post[decision.second]) < c.second_look_min_p:
            return None
        arm3d = self.last_arm3d
        if arm3d is None:
            return None
        a, b = bb.fusion.hypothesis(decision.best), bb.fusion.hypothesis(decision.second)
        step = plan_second_look(a.xyz_m, b.xyz_m, arm3d.xyz_m[[0, 2]], c.second_look_step_m, bb.servo.focal_px,
                                bb.servo.principal_point_px, c.second_look_margin_px)
        if step is None:
            bb.say(f"{decision.best} and {decision.second} close, but no step keeps all in view and separates them")
        return step


class Acknowledge(MissionState):
    """Tell the diver the decision (nod or lights), keeping the target tracked."""

    name = "acknowledge"
    triggers = ("acked",)
    needs = "track"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        self.ack = Acknowledgement(bb.config)
        self.ack.start(bb.now_s)
        self.start_xyz = None if bb.tracker.xyz_m is None else bb.tracker.xyz_m.copy()
        bb.say(f"acknowledging with {bb.config.ack_kind}")

    def tick(self, bb: Blackboard) -> str | None:
        _track(bb)
        command, servos, finished = self.ack.tick(bb.now_s)
        bb.set_command(command)
        bb.outbox.extend(servos)
        if finished and self.start_xyz is not None:  # the nod ends at the heading it began at
            bb.tracker.rewind(self.start_xyz, bb.now_s)
        return "acked" if finished else None

    def exit(self, bb: Blackboard) -> None:
        bb.set_command(None)


class Servo(MissionState):
    """Visual servo to the tracked target; hold still through short losses."""

    name = "servo"
    triggers = ("centred", "lost", "give_up")
    needs = "track"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.servo.reset()
        self.last_update_s: float | None = None

    def tick(self, bb: Blackboard) -> str | None:
        c = bb.config
        if self.elapsed(bb) > c.servo_timeout_s:
            bb.say(f"target not reached in {c.servo_timeout_s:g} s", "warning", pilot=True)
            return "give_up"
        new, found = _track(bb)
        if not new:
            return None
        if found is None:
            bb.stop()
            last = bb.tracker.last_seen_s
            if last is not None and bb.observation.stamp_s - last > c.lost_grace_s:
                return "lost"
            return None
        stamp = bb.observation.stamp_s
        dt = stamp - self.last_update_s if self.last_update_s is not None else 0.2
        self.last_update_s = stamp
        bb.set_command(bb.servo.update(tuple(found.left_px), float(found.xyz_m[2]), max(dt, 1e-3)))
        bb.errors = bb.servo.last_errors
        return "centred" if within(bb, 1.0) else None


def within(bb: Blackboard, factor: float) -> bool:
    """Return True when the last servo errors are inside the arrive tolerances times ``factor``."""
    e, c = bb.errors, bb.config
    if e is None or e.range_m is None:
        return False
    return e.pixel_px <= c.arrive_tolerance_px * factor and abs(e.range_m) <= c.arrive_tolerance_m * factor


class LostTarget(MissionState):
    """Target not seen for a while: hold still and look for it; give up after a timeout."""

    name = "lost_target"
    triggers = ("reacquired", "give_up")
    needs = "track"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()
        bb.say("target lost: holding and looking for it", "warning", pilot=True)

    def tick(self, bb: Blackboard) -> str | None:
        if self.elapsed(bb) > bb.config.lost_timeout_s:
            return "give_up"
        _, found = _track(bb)
        if found is not None:
            bb.say(f"target re-acquired ({found.matches} matches)")
            return "reacquired"
        return None


class Arrive(MissionState):
    """Centred and at the stand-off: keep correcting; done once inside tolerance and settled for the hold time.

    Settled: the target's range changes by less than ``behaviour.arrive_max_range_rate_m_s`` between
    frames (in ALT_HOLD nothing brakes the vehicle horizontally: a coasting vehicle is not arrived).
    Leaving tolerance x hysteresis goes back to servo; in between, the hold time restarts.
    """

    name = "arrive"
    triggers = ("held", "drifted", "lost", "give_up")
    needs = "track"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        self.last_update_s: float | None = None
        self.last_range_m: float | None = None
        self.inside_since: float | None = None

    def tick(self, bb: Blackboard) -> str | None:
        c = bb.config
        if self.elapsed(bb) > c.servo_timeout_s:
            bb.say(f"could not settle at the target in {c.servo_timeout_s:g} s", "warning", pilot=True)
            return "give_up"
        new, found = _track(bb)
        if not new:
            return None
        if found is None:
            bb.stop()
            self.inside_since = None
            return "lost" if bb.tracker.lost else None
        stamp = bb.observation.stamp_s
        dt = stamp - self.last_update_s if self.last_update_s is not None else 0.2
        bb.set_command(bb.servo.update(tuple(found.left_px), float(found.xyz_m[2]), max(dt, 1e-3)))
        bb.errors = bb.servo.last_errors
        if not within(bb, c.arrive_hysteresis):
            return "drifted"
        rng = bb.errors.range_m
        rate = abs(rng - self.last_range_m) / max(dt, 1e-3) if self.last_range_m is not None else float("inf")
        self.last_update_s, self.last_range_m = stamp, rng
        if within(bb, 1.0) and rate <= c.arrive_max_range_rate_m_s:
            if self.inside_since is None:
                self.inside_since = stamp
            if stamp - self.inside_since >= c.arrive_hold_s:
                return "held"
        else:
            self.inside_since = None
        return None


class Done(MissionState):
    """Arrived: stop, hold, report; a new request needs the diver's arm down first."""

    name = "done"
    triggers = ("released",)

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()
        bb.arrived = True
        bb.arrivals += 1
        e = bb.errors
        rng = bb.config.standoff_m + (e.range_m if e is not None and e.range_m is not None else 0.0)
        px = e.pixel_px if e is not None else float("nan")
        bb.say(f"arrived: range {rng:.2f} m, {px:.0f} px off", pilot=True)
        self.lowered = 0

    def tick(self, bb: Blackboard) -> str | None:
        result = _new_result(bb)
        if result is None:
            return None
        self.lowered = 0 if _raised(bb, result) else self.lowered + 1
        if self.lowered >= bb.config.release_frames:
            bb.say("diver's arm down: ready for a new request")
            return "released"
        return None


class Abort(MissionState):
    """Give up on the target: stop, tell the pilot, hold, then wait for the diver again."""

    name = "abort"
    triggers = ("reset",)

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()
        bb.chosen = None
        bb.say("aborted: holding", "warning", pilot=True)

    def tick(self, bb: Blackboard) -> str | None:
        return "reset" if self.elapsed(bb) >= bb.config.abort_hold_s else None


class Suspended(MissionState):
    """The link stopped commanding during the approach (autopilot or ground station lost, the pilot took
    over): no motion, the target kept and tracked; when the link engages again, re-check and resume or
    start again.

    Entered only for disengage reasons that clear the operator's enable, so the link engages again
    only after a new enable; this state also checks that it saw the enable cleared, and never
    resumes otherwise. On re-engage: the target seen within ``behaviour.lost_grace_s`` and the
    suspension no longer than ``behaviour.resume_within_s`` -> ``resume`` (servo); else ``expired``
    (wait_for_diver). Not re-engaged within ``behaviour.resume_within_s`` -> ``disengage`` (idle,
    the target forgotten).
    """

    name = "suspended"
    triggers = ("resume", "expired", "disengage")
    needs = "track"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()
        self.enable_cleared = not bb.operator_enabled
        bb.say("suspended: holding, target kept", "warning", pilot=True)
        bb.say(f"resumes only after the operator's re-enable, within {bb.config.resume_within_s:g} s")

    def tick(self, bb: Blackboard) -> str | None:
        _track(bb)
        self.enable_cleared = self.enable_cleared or not bb.operator_enabled
        away, limit = self.elapsed(bb), bb.config.resume_within_s
        if not bb.engaged:
            if away > limit:
                bb.say(f"not re-enabled in {limit:g} s: target forgotten", "warning", pilot=True)
                return "disengage"
            return None
        if not self.enable_cleared:
            bb.say("re-engaged without re-enable: not resuming", "warning", pilot=True)
            return "expired"
        if away > limit:
            bb.say(f"re-engaged after {away:.1f} s > {limit:g} s: target forgotten", "notice", pilot=True)
            return "expired"
        seen = bb.tracker.last_seen_s if bb.tracker.active else None
        if seen is None or bb.tracker.lost or bb.now_s - seen > bb.config.lost_grace_s:
            bb.say("target not tracked: not resuming", "notice", pilot=True)
            ago = "never" if seen is None else f"{bb.now_s - seen:.1f} s ago"
            bb.say(f"re-engaged after {away:.1f} s, target last seen {ago}: waiting for the diver")
            return "expired"
        bb.say("target tracked: resuming the servo", pilot=True)
        bb.say(f"re-engaged after {away:.1f} s, target seen {bb.now_s - seen:.1f} s ago")
        return "resume"


class NothingThere(MissionState):
    """Nothing detected where the diver points: no motion toward anything; tell them with a shake and the
    pilot with a STATUSTEXT, then wait for the arm to come down (a new point)."""

    name = "nothing_there"
    triggers = ("released",)

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()
        bb.chosen = None
        p = bb.decision.posterior.get("none", float("nan")) if bb.decision is not None else float("nan")
        bb.say(f"nothing detected where pointed (p {p:.2f})", "notice", pilot=True)
        bb.say("shaking: yaw left-right-left-right, then waiting for a new point")
        self.shake = Acknowledgement(bb.config, shake=True)
        self.shake.start(bb.now_s)
        self.lowered = 0

    def tick(self, bb: Blackboard) -> str | None:
        command, _, finished = self.shake.tick(bb.now_s)
        bb.set_command(None if finished else command)
        result = _new_result(bb)
        if not finished or result is None:
            return None
        self.lowered = 0 if _raised(bb, result) else self.lowered + 1
        if self.lowered >= bb.config.release_frames:
            bb.say("diver's arm down: ready for a new request")
            return "released"
        return None

    def exit(self, bb: Blackboard) -> None:
        bb.set_command(None)


class SecondLook(_ArmWatch):
    """Two objects stay close: step sideways / vertically (``bb.look_step``) to see them apart, settle,
    then decide again from there (the fused evidence restarts: a new viewpoint). The diver gone from the
    view (``arm_lost_frames`` frames without the raised arm) -> stop, back to waiting (holding)."""

    name = "second_look"
    triggers = ("looked", "arm_lost")

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        c, step = bb.config, bb.look_step
        bb.second_looks += 1
        self.misses = 0
        if step is None:  # nothing planned: no motion, decide again at once
            self.move_s, self.command = 0.0, None
            return
        self.move_s = c.second_look_step_m / c.second_look_speed_m_s
        v = c.second_look_speed_m_s
        dx, dy, _ = step.offset_m
        n = max(abs(dx), abs(dy), 1e-9)
        self.command = VelocityCommand(sway_m_s=v * dx / n, heave_m_s=v * dy / n)
        bb.say(f"second look {bb.second_looks}: {c.second_look_step_m:.2f} m {step.direction}", "notice", pilot=True)
        bb.say(f"second look: separation {step.before_rad:.3f} -> {step.after_rad:.3f} rad")

    def tick(self, bb: Blackboard) -> str | None:
        c = bb.config
        moving = self.elapsed(bb) < self.move_s
        bb.set_command(self.command if moving else None)
        result = _new_result(bb)
        if result is not None and self.arm_gone(bb, _raised(bb, result), "diver left the view during the second look"):
            bb.stop()
            return "arm_lost"
        if self.elapsed(bb) >= self.move_s + c.second_look_settle_s:
            if bb.fusion is not None:
                bb.fusion.reset()
            bb.say("second look done: deciding again from here")
            return "looked"
        return None

    def exit(self, bb: Blackboard) -> None:
        bb.stop()


class CloseIn(_ArmWatch):
    """The diver is too far for the arm's tilt to be measured: advance toward them (``bb.close_in_step``),
    settle, then decide again from there (the fused evidence restarts: a new viewpoint).

    The advance was planned to end no nearer the diver than ``behaviour.close_in_standoff_m``, with
    every object hypothesis in view and none on the path; it is commanded as surge and sway at
    ``behaviour.close_in_speed_m_s`` (with heave when it sinks, ``behaviour.close_in_max_descent_m``)
    for its length over that speed (heading kept), then nothing for
    ``behaviour.second_look_settle_s``. The diver gone from the view (``arm_lost_frames`` frames
    without the raised arm) -> stop, back to waiting (holding).
    """

    name = "close_in"
    triggers = ("closer", "arm_lost")

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        c, step = bb.config, bb.close_in_step
        bb.close_ins += 1
        self.misses = 0
        if step is None:  # nothing planned: no motion, decide again at once
            self.move_s, self.command = 0.0, None
            return
        v = c.close_in_speed_m_s
        dx, dy, dz = step.offset_m
        n = max(math.sqrt(dx * dx + dy * dy + dz * dz), 1e-9)
        self.move_s = step.distance_m / v
        self.command = VelocityCommand(surge_m_s=v * dz / n, sway_m_s=v * dx / n, heave_m_s=v * dy / n)
        down = f", {step.descent_m:.2f} m down" if step.descent_m > 0 else ""
        bb.say(f"diver {step.range_before_m:.1f} m away: closing in {step.distance_m:.2f} m to "
               f"{step.range_after_m:.1f} m{down} before deciding", "notice", pilot=True)
        bb.say(f"close in: the diver's shoulder seen from {math.degrees(step.elevation_after_rad):.1f} deg below")

    def tick(self, bb: Blackboard) -> str | None:
        c = bb.config
        moving = self.elapsed(bb) < self.move_s
        bb.set_command(self.command if moving else None)
        result = _new_result(bb)
        if result is not None and self.arm_gone(bb, _raised(bb, result), "diver left the view while closing in"):
            bb.stop()
            return "arm_lost"
        if self.elapsed(bb) >= self.move_s + c.second_look_settle_s:
            if bb.fusion is not None:
                bb.fusion.reset()
            bb.say("closed in: deciding again from here")
            return "closer"
        return None

    def exit(self, bb: Blackboard) -> None:
        bb.stop()


class Stopped(MissionState):
    """The diver's stop gesture: hold (neutral, the link stays engaged and the enable kept), mission over.

    Left only when the link disengages (the operator's disable; a new enable starts a new mission).
    """

    name = "stopped"
    needs = "track"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()
        bb.chosen = None
        bb.say("stop gesture: holding, mission ended", "warning", pilot=True)

    def tick(self, bb: Blackboard) -> str | None:
        bb.set_command(None)
        return None


STATE_CLASSES: tuple[type[MissionState], ...] = (Idle, WaitForDiver, ConfirmPoint, SelectTarget, Acknowledge,
                                                 Servo, LostTarget, Arrive, Done, Abort, Suspended, NothingThere,
                                                 Stopped, SecondLook, CloseIn)
"""Every state's behaviour class, by ``name``."""
