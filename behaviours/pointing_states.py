"""The pointing states: wait for the diver, confirm the point, select the target, and the two bounded
moves (second look, close in) that let the selection decide again from a better viewpoint.

The frames of confirm_point and select_target are fused into one decision over the point
(``fusion.py``); the evidence restarts when the pointing moves or the viewpoint changes.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from dip3d_vehicle.perception.held_arm import HeldArm
from dip3d_vehicle.perception.values import Arm3D
from dip3d_vehicle.servo.command import VelocityCommand

from .blackboard import Blackboard
from .close_in import CloseInStep, horizontal_range_m, plan_close_in
from .evidence import VoteBox, angular_spread_rad, image_direction
from .fusion import NONE, FrameEvidence, FusedDecision, Hypothesis, PointFusion
from .mission_state import MissionState, arm_raised, new_result
from .second_look import MIN_GAIN_RAD, LookStep, plan_second_look
from .weak_lean import WeakLean, is_weak, two_view_p

__all__ = ["WaitForDiver", "ConfirmPoint", "SelectTarget", "SecondLook", "CloseIn"]


def _fuse_frame(bb: Blackboard, result, direction) -> FrameEvidence | None:
    """Add a raised-arm frame to the point's fused evidence; restart it when the pointing moved.

    The point's direction is the mean left-image arm direction of its fused frames; a frame more
    than ``behaviour.steady_angle_rad`` away from it starts a new point.
    """
    c = bb.config
    if bb.fusion is None:
        bb.fusion = PointFusion(c.vote_radius_m, c.fusion_temper, c.fusion_floor_p, c.fusion_no_objects_none_p,
                                c.fusion_max_effective_frames, c.fusion_min_shared_posterior,
                                shared_rule=c.fusion_shared_rule,
                                min_pose_shared_posterior=c.fusion_min_pose_shared_posterior,
                                recall_s=c.fusion_recall_s, max_extent_m=c.target_max_extent_m,
                                spot_support=c.fusion_spot_support)
    fusion = bb.fusion
    if direction is not None and fusion.direction is not None:
        mean = fusion.direction / max(float(np.linalg.norm(fusion.direction)), 1e-9)
        if angular_spread_rad([mean, direction]) * 2 > c.steady_angle_rad and fusion.frames:
            bb.say(f"pointing moved: fused evidence of {len(fusion.frames)} frames restarted")
            fusion.reset()
            bb.weak_lean = None
    arm_frames, stamp = 1, bb.observation.stamp_s
    if bb.decide_held is not None and result.arm is not None:
        arm, held = result.arm, c.fusion_arm_frames > 1 and result.status in ("ok", "nothing_on_ray")
        if held:
            if fusion.held_arm.arms.maxlen != c.fusion_arm_frames:
                fusion.held_arm = HeldArm(c.fusion_arm_frames)
            fusion.held_arm.add(result.arm)
            arm_frames, arm = len(fusion.held_arm), fusion.held_arm.mean()
        recalled = fusion.recall(result, stamp)
        if held or recalled is not None:
            result = bb.decide_held(arm, arm_frames, result, recalled)
    part = fusion.add(result, stamp, arm_frames)
    if part is not None and direction is not None:
        fusion.direction = direction.copy() if fusion.direction is None else fusion.direction + direction
    return part


def _neighbours_m(bb: Blackboard, winner: Hypothesis) -> tuple[np.ndarray, np.ndarray]:
    """Return the fusion's other hypotheses as offsets from the winner's (camera frame, metres, (K, 3)) and their
    half spans across the line of sight (metres, (K,)): the tracker's known neighbours (refused as the target with
    ``behaviour.track_neighbours``, kept clear of by the servo with ``behaviour.servo_clearance_m`` from their
    edges)."""
    others = [h for h in bb.fusion.hypotheses if h is not winner]
    return (np.array([h.xyz_m - winner.xyz_m for h in others], float).reshape(-1, 3),
            np.array([h.across_m / 2.0 for h in others], float))


HAND_BEYOND_WRIST_M = 0.15
"""Where the pointing hand's fingertips reach past the wrist, along the forearm, m."""

HIP_BELOW_SHOULDER_M = 0.5
"""Where the diver's hips are below the shoulder (the camera's y, down), m."""


def diver_points_m(arm3d: Arm3D | None) -> np.ndarray:
    """Return points of the diver's body to keep clear of (camera frame, metres, (J, 3)): the triangulated
    shoulder, elbow and wrist, the pointing hand past the wrist and the hips below the shoulder; none without an arm."""
    if arm3d is None:
        return np.zeros((0, 3))
    shoulder, elbow, wrist = (np.asarray(p, float) for p in arm3d.xyz_m)
    forearm = wrist - elbow
    n = float(np.linalg.norm(forearm))
    hand = wrist + HAND_BEYOND_WRIST_M * forearm / n if n > 1e-6 else wrist
    points = np.array([shoulder, elbow, wrist, hand, shoulder + [0.0, HIP_BELOW_SHOULDER_M, 0.0]])
    return points[np.all(np.isfinite(points), axis=1)]


def _tell_decision(bb: Blackboard, decision: FusedDecision) -> None:
    """Put the fused posterior, the hypotheses and each frame's part in the story (and the log)."""
    fusion = bb.fusion
    bb.decision = decision
    bb.say(f"fused posterior over {decision.frames} frames (weight {fusion.weight:.2f}): {decision.summary()}")
    bb.say(f"hypotheses: {fusion.describe()}")
    bb.say("frames: " + "; ".join(f.summary() for f in fusion.frames))


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
        bb.relooks = 0
        bb.weak_lean = None
        self.history: deque[bool] = deque(maxlen=bb.config.arm_seen_m)

    def tick(self, bb: Blackboard) -> str | None:
        result = new_result(bb)
        if result is None:
            return None
        self.history.append(arm_raised(bb, result))
        if sum(self.history) >= bb.config.arm_seen_n:
            bb.say(f"diver's arm raised in {sum(self.history)} of the last {len(self.history)} frames")
            return "arm_seen"
        return None


class _ArmWatch(MissionState):
    """A state that gives up when the diver's arm is down for ``arm_lost_frames`` frames in a row."""

    misses = 0

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        self.misses = 0

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

    def tick(self, bb: Blackboard) -> str | None:
        c = bb.config
        if self.elapsed(bb) > c.confirm_timeout_s:
            bb.say(f"no steady pointing in {c.confirm_timeout_s:g} s")
            return "timeout"
        result = new_result(bb)
        if result is None:
            return None
        if self.arm_gone(bb, arm_raised(bb, result), "diver lowered the arm or left"):
            return "arm_lost"
        if self.misses:
            return None
        direction = image_direction(result)
        stamp = bb.observation.stamp_s
        _fuse_frame(bb, result, direction)
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
    -> ``close_in`` (while tries are left and a safe advance exists); a winner that is weak counted as
    one look with the diver farther than ``behaviour.decide_max_range_m`` -> ``close_in`` first
    (``weak_close_in_step``); else, when the point had no second look yet (a close in before it included), a
    weak winner takes a second look first if a step keeps it, the strongest other object and the diver in view
    (``behaviour.weak_look_again``, ``weak_look_step``), and a weak winner from there that is not the one
    before the step is not acted on (``views_disagree``: undecided, ambiguous at the timeout); two
    objects close at the timeout -> ``second_look`` (while tries are left and a step separates them); one
    object close to "nothing detected" at the timeout -> ``second_look`` (a step that shows the arm more from
    the side: ``arm_view_step``); else ``ambiguous``.
    """

    name = "select_target"
    triggers = ("winner", "nothing_there", "close_in", "second_look", "ambiguous", "arm_lost")

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.set_command(None)
        self.box = VoteBox(bb.config.vote_radius_m)
        self.added = 0
        self.last_arm3d = None
        self.doubts: list[str] = []  # why a decision was not acted on (each told once), for the ambiguous timeout

    def tick(self, bb: Blackboard) -> str | None:
        c = bb.config
        if self.elapsed(bb) > c.select_timeout_s:
            return self.undecided(bb)
        result = new_result(bb)
        if result is None:
            return None
        if self.arm_gone(bb, arm_raised(bb, result), "diver lowered the arm or left while selecting"):
            return "arm_lost"
        if self.misses:
            return None
        self.box.add(result, bb.observation.stamp_s)
        self.last_arm3d = result.arm3d if result.arm3d is not None else self.last_arm3d
        self.added += _fuse_frame(bb, result, image_direction(result)) is not None
        if self.added == 0 or len(bb.fusion.frames) < c.vote_frames:
            return None
        decision = bb.fusion.decide(c.fusion_min_posterior, c.min_votes)
        bb.decision = decision
        if decision.kind == "undecided" or self.views_disagree(bb, decision) or self.relook_unclear(bb, decision):
            return None
        _tell_decision(bb, decision)
        move = self.move_before_weak(bb, decision)
        if move is not None:
            return move
        bb.decided.append(decision.record(bb.now_s))
        if decision.kind == "none":
            return "nothing_there"
        w = bb.fusion.as_vote(decision.winner)
        bb.chosen = w
        neighbours_m, neighbours_half_m = _neighbours_m(bb, decision.winner)
        bb.tracker.start(w.obj, w.candidates, w.stamp_s, w.pool, neighbours_m,
                         diver_points_m(self.last_arm3d) - decision.winner.xyz_m, neighbours_half_m)
        bb.target = bb.tracker.last
        bb.held_short_m = 0.0
        xyz = ", ".join(f"{v:.2f}" for v in w.xyz_m)
        bb.say(f"target chosen at ({xyz}) m, p {decision.posterior[decision.best]:.2f} "
               f"(one look {decision.one_look:.2f})", pilot=True)
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
        why = self.doubts[0] if self.doubts else decision.reason
        bb.say(f"ambiguous: {why}", "notice", pilot=True)
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

    def weak_close_in_step(self, bb: Blackboard, decision: FusedDecision) -> CloseInStep | None:
        """Return the advance to make before acting on a weak object decision at range, or None (act on it).

        Weak at range: its posterior with the frames counted as one is below ``behaviour.close_in_one_look``,
        with the diver farther than ``behaviour.decide_max_range_m``; such a lean rests on the arm's
        tilt toward the camera, whose stereo error falls with the square of the range. An advance that
        cuts that error by less than ``behaviour.close_in_weak_min_error_cut`` is not worth the delay.
        """
        c = bb.config
        if not is_weak(decision, c.close_in_one_look):
            return None
        step = self.close_in_step(bb)
        if step is None:
            return None
        cut = 1.0 - (step.range_after_m / max(step.range_before_m, 1e-9)) ** 2
        if cut < c.close_in_weak_min_error_cut:
            bb.say(f"{decision.best} only {decision.one_look:.2f} counted as one look, but closing in "
                   f"{step.distance_m:.2f} m would cut the arm's depth error by {cut:.0%} only: not closing in")
            return None
        bb.say(f"{decision.best} only {decision.one_look:.2f} counted as one look "
               f"(< {c.close_in_one_look:g}): closer before deciding", "notice", pilot=True)
        return step

    def move_before_weak(self, bb: Blackboard, decision: FusedDecision) -> str | None:
        """Return the move to make before acting on a weak object decision ("close_in", "second_look"), or None.

        A weak decision gets a nearer view (close in; at range the bar is the higher ``behaviour.close_in_one_look``)
        and one second look per point (under ``behaviour.close_in_weak_one_look``), taken from as far: the weak
        winner is kept on the blackboard (``bb.weak_lean``) and the new view must agree with it (``views_disagree``).
        A winner still weak after the close in takes the second look too: from 2.5-3 m its frames still share the
        arm's error, and fused 0.91 from a one look of 0.53 went to the wrong placard (issue 11 session 69,
        variant_9_19 seed 2, zoom off, one prior share per target).
        """
        c = bb.config
        advance = self.weak_close_in_step(bb, decision)
        if advance is not None:
            bb.close_in_step = advance
            return "close_in"
        if not c.weak_look_again or not is_weak(decision, c.close_in_weak_one_look):
            return None
        if bb.weak_lean is not None:
            return None  # the point had its second look already
        step = self.weak_look_step(bb, decision)
        if step is None:
            return None
        positions = {k: h.xyz_m for k in decision.one_look_posterior if (h := bb.fusion.hypothesis(k)) is not None}
        bb.look_step, bb.weak_lean = step, WeakLean.of(decision, positions)
        bb.say(f"{decision.best} only {decision.one_look:.2f} counted as one look (< {c.close_in_weak_one_look:g}): "
               f"a second look before deciding", "notice", pilot=True)
        return "second_look"

    def weak_look_step(self, bb: Blackboard, decision: FusedDecision) -> LookStep | None:
        """Return the second look's step between a weak winner and the strongest other object, or None.

        Any step that keeps them and the diver in view will do (the one that sets them farthest apart): the
        new view is wanted for the arm's own errors, which differ from there, not only to see two objects
        apart. None when the point's second looks are used up, no other object was seen or no step fits.
        """
        if bb.second_looks >= bb.config.second_look_max_tries:
            return None
        post = decision.one_look_posterior
        others = sorted((k for k in post if k not in (decision.best, NONE)), key=post.get, reverse=True)
        return self.separating_step(bb, decision.best, others[0], -math.inf) if others else None

    def views_disagree(self, bb: Blackboard, decision: FusedDecision) -> bool:
        """True when the winner is not the weak winner seen before the last move and does not outweigh it (said once
        per state): a weak winner, or a clear one below ``behaviour.close_in_weak_one_look`` against the lean with
        the two views taken as two looks (``two_view_p``).

        The same: the hypothesis the fusion matches to where that winner should be seen from here (the
        nearest within ``behaviour.vote_radius_m``).
        """
        c, lean = bb.config, bb.weak_lean
        if not c.weak_look_again or lean is None or not lean.moves or decision.kind != "object":
            return False
        same = bb.fusion.match(lean.xyz_m)
        weak = is_weak(decision, c.close_in_weak_one_look)
        if same is not None and same.key == decision.best:
            if weak:
                bb.say(f"{same.key} leads again from the new view ({decision.one_look:.2f} counted as one look), "
                       f"{float(np.linalg.norm(same.xyz_m - lean.xyz_m)):.2f} m from where {lean.key} was expected: "
                       f"the two views agree")
            return False
        post = decision.one_look_posterior
        both = two_view_p(decision.one_look, post.get(same.key if same is not None else NONE, 0.0),
                          lean.p_at(decision.winner.xyz_m, c.vote_radius_m), lean.one_look)
        if not weak and both >= c.close_in_weak_one_look:
            return False
        if self.doubt("the views before and after the move lean to different objects"):
            moves = " and ".join(m.replace("_", " ") for m in lean.moves)
            where = (f"{same.key} from here" if same is not None
                     else f"no object within {c.vote_radius_m:g} m of where it should be seen")
            bb.say(f"{decision.best} leads {decision.one_look:.2f} counted as one look after the {moves}, {both:.2f} "
                   f"with the view before it, where {lean.key} led ({lean.one_look:.2f}), {where}: the two views "
                   f"disagree, not acting", "notice", pilot=True)
        return True

    def doubt(self, why: str) -> bool:
        """Record why a decision is not acted on; True the first time (tell it then)."""
        if why in self.doubts:
            return False
        self.doubts.append(why)
        return True

    def relook_unclear(self, bb: Blackboard, decision: FusedDecision) -> bool:
        """True when a fresh look after "nothing there" (``bb.relooks``) leans to an object under
        ``behaviour.nothing_there_relook_one_look`` counted as one look (said once per state): it contradicts the
        first look, so it is not acted on unless it is clear."""
        c = bb.config
        if not bb.relooks or decision.kind != "object" or decision.one_look is None:
            return False
        if decision.one_look >= c.nothing_there_relook_one_look:
            return False
        if self.doubt("the fresh look after \"nothing there\" leans to an object, but not clearly"):
            bb.say(f"{decision.best} leads {decision.one_look:.2f} counted as one look in the fresh look after "
                   f"\"nothing there\" (< {c.nothing_there_relook_one_look:g}): the two looks disagree, not acting",
                   "notice", pilot=True)
        return True

    def look_step(self, bb: Blackboard, decision: FusedDecision) -> LookStep | None:
        """Return the second look's step when the two leading hypotheses are close and a step helps, else None.

        Two objects: the step that separates them. An object against "nothing detected": the step that shows
        the line from the diver's wrist to it most from the side (``arm_view_step``).
        """
        c, post = bb.config, decision.posterior
        if bb.second_looks >= c.second_look_max_tries or decision.second is None:
            return None
        if min(post[decision.best], post[decision.second]) < c.second_look_min_p:
            return None
        if NONE not in (decision.best, decision.second):
            return self.separating_step(bb, decision.best, decision.second)
        return self.arm_view_step(bb, decision.second if decision.best == NONE else decision.best)

    def arm_view_step(self, bb: Blackboard, key: str) -> LookStep | None:
        """Return the step that opens the angle between the diver's wrist and object ``key`` most, or None.

        Split between one object and "nothing detected", a point rests on the arm's tilt toward the camera
        (the stereo depth of its joints); seen more from the side, the line from the wrist to the object is
        longer in the image and that tilt counts for less. The object and the diver stay in view; None when no
        step opens the angle by ``MIN_GAIN_RAD`` (issue 11 session 71: variant_43_10 from pixels, the pointed placard
        against "nothing" at 0.6 / 0.4 over 146 frames and four rounds, the vehicle never moving).
        """
        obj = bb.fusion.hypothesis(key)
        if self.last_arm3d is None or obj is None:
            return None
        return self._step_apart(bb, obj.xyz_m, self.last_arm3d.xyz_m[2], MIN_GAIN_RAD,
                                f"{key} against nothing detected, but no step keeps all in view and shows the arm "
                                f"more from the side")

    def separating_step(self, bb: Blackboard, key_a: str, key_b: str,
                        min_gain_rad: float = MIN_GAIN_RAD) -> LookStep | None:
        """Return the step that best separates two object hypotheses with the diver kept in view, or None.

        None also when no step opens their separation by ``min_gain_rad`` (radians).
        """
        a, b = bb.fusion.hypothesis(key_a), bb.fusion.hypothesis(key_b)
        if self.last_arm3d is None or a is None or b is None:
            return None
        return self._step_apart(bb, a.xyz_m, b.xyz_m, min_gain_rad,
                                f"{key_a} and {key_b} close, but no step keeps all in view and separates them")

    def _step_apart(self, bb: Blackboard, a_xyz: np.ndarray, b_xyz: np.ndarray, min_gain_rad: float,
                    why_none: str) -> LookStep | None:
        """Return the step that opens the angle between two points (camera frame, metres) most, both and the diver
        (``last_arm3d``'s shoulder and wrist) kept in view, or None (saying ``why_none``) when none opens it by
        ``min_gain_rad`` (radians)."""
        c = bb.config
        step = plan_second_look(a_xyz, b_xyz, self.last_arm3d.xyz_m[[0, 2]], c.second_look_step_m, bb.servo.focal_px,
                                bb.servo.principal_point_px, c.second_look_margin_px, min_gain_rad)
        if step is None:
            bb.say(why_none)
        return step


class _MoveThenDecide(_ArmWatch):
    """A bounded move (``command`` for ``move_s``), a settle of ``behaviour.second_look_settle_s``, then
    ``done_trigger``: decide again from there (the fused evidence restarts: a new viewpoint).

    Subclasses count the try (``take_step``) and plan the move (``start_move``); nothing planned means no
    motion and deciding again at once.
    The diver gone from the view (``arm_lost_frames`` frames without the raised arm) -> stop, ``arm_lost``.
    """

    done_trigger: str
    done_text = "deciding again from here"
    left_view_text = "diver left the view"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        self.move_s: float = 0.0
        self.command: VelocityCommand | None = None
        step = self.take_step(bb)
        if step is not None:
            self.start_move(bb, step)
        if bb.weak_lean is not None:  # a weak winner to compare from the new view: where it will be seen
            bb.weak_lean = bb.weak_lean.moved(step.offset_m if step is not None else (0.0, 0.0, 0.0), self.name)

    def take_step(self, bb: Blackboard) -> LookStep | CloseInStep | None:
        """Count this try on the blackboard and return its planned step (None: nothing planned)."""
        raise NotImplementedError

    def start_move(self, bb: Blackboard, step: LookStep | CloseInStep) -> None:
        """Set ``command`` and ``move_s`` for ``step`` and tell the story."""
        raise NotImplementedError

    def tick(self, bb: Blackboard) -> str | None:
        moving = self.elapsed(bb) < self.move_s
        bb.set_command(self.command if moving else None)
        result = new_result(bb)
        if result is not None and self.arm_gone(bb, arm_raised(bb, result), self.left_view_text):
            bb.stop()
            return "arm_lost"
        if self.elapsed(bb) >= self.move_s + bb.config.second_look_settle_s:
            if bb.fusion is not None:
                bb.fusion.reset()
            bb.say(self.done_text)
            return self.done_trigger
        return None

    def exit(self, bb: Blackboard) -> None:
        bb.stop()


class SecondLook(_MoveThenDecide):
    """Two objects stay close: step sideways / vertically (``bb.look_step``) to see them apart, settle,
    then decide again from there (the fused evidence restarts: a new viewpoint). The diver gone from the
    view (``arm_lost_frames`` frames without the raised arm) -> stop, back to waiting (holding)."""

    name = "second_look"
    triggers = ("looked", "arm_lost")
    done_trigger = "looked"
    done_text = "second look done: deciding again from here"
    left_view_text = "diver left the view during the second look"

    def take_step(self, bb: Blackboard) -> LookStep | None:
        """Count this second look and return its planned step."""
        bb.second_looks += 1
        return bb.look_step

    def start_move(self, bb: Blackboard, step: LookStep) -> None:
        """Step ``behaviour.second_look_step_m`` at ``behaviour.second_look_speed_m_s`` (sway / heave)."""
        c = bb.config
        self.move_s = c.second_look_step_m / c.second_look_speed_m_s
        v = c.second_look_speed_m_s
        dx, dy, _ = step.offset_m
        n = max(abs(dx), abs(dy), 1e-9)
        self.command = VelocityCommand(sway_m_s=v * dx / n, heave_m_s=v * dy / n)
        bb.say(f"second look {bb.second_looks}: {c.second_look_step_m:.2f} m {step.direction}", "notice", pilot=True)
        bb.say(f"second look: separation {step.before_rad:.3f} -> {step.after_rad:.3f} rad")


class CloseIn(_MoveThenDecide):
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
    done_trigger = "closer"
    done_text = "closed in: deciding again from here"
    left_view_text = "diver left the view while closing in"

    def take_step(self, bb: Blackboard) -> CloseInStep | None:
        """Count this advance and return its planned step; a weak lean from farther is dropped (the nearer view decides)."""
        bb.close_ins += 1
        bb.weak_lean = None
        return bb.close_in_step

    def start_move(self, bb: Blackboard, step: CloseInStep) -> None:
        """Advance ``step.distance_m`` at ``behaviour.close_in_speed_m_s`` (surge, sway, heave)."""
        v = bb.config.close_in_speed_m_s
        dx, dy, dz = step.offset_m
        n = max(math.sqrt(dx * dx + dy * dy + dz * dz), 1e-9)
        self.move_s = step.distance_m / v
        self.command = VelocityCommand(surge_m_s=v * dz / n, sway_m_s=v * dx / n, heave_m_s=v * dy / n)
        down = f", {step.descent_m:.2f} m down" if step.descent_m > 0 else ""
        bb.say(f"diver {step.range_before_m:.1f} m away: closing in {step.distance_m:.2f} m to "
               f"{step.range_after_m:.1f} m{down} before deciding", "notice", pilot=True)
        bb.say(f"close in: the diver's shoulder seen from {math.degrees(step.elevation_after_rad):.1f} deg below")
