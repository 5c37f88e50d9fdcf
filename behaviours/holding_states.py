"""The holding states: no motion toward a target while they wait for something (the link to engage,
the diver's arm to come down, the hold time, the operator's re-enable).

Idle before a mission, done after arriving, abort after giving up, suspended while the link stopped
commanding during the acknowledgement or the approach, nothing_there after a point at nothing, stopped after the diver's
stop gesture.
"""

from __future__ import annotations

from .acknowledge import Acknowledgement
from .blackboard import Blackboard
from .mission_state import MissionState, arm_raised, new_result, track_target

__all__ = ["Idle", "Done", "Abort", "Suspended", "NothingThere", "Stopped"]


class _ReleaseWatch(MissionState):
    """A state that waits for the diver's arm to be down ``release_frames`` frames in a row (a new request)."""

    lowered = 0

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        self.lowered = 0

    def arm_released(self, bb: Blackboard, raised: bool | None = None) -> bool:
        """Count this tick's new frame without the raised arm (reset on one with it); True once the arm is down.

        ``raised``: the frame's ``arm_raised``, when the caller already has it."""
        result = new_result(bb)
        if result is None:
            return False
        raised = arm_raised(bb, result) if raised is None else raised
        self.lowered = 0 if raised else self.lowered + 1
        if self.lowered >= bb.config.release_frames:
            bb.say("diver's arm down: ready for a new request")
            return True
        return False


class Idle(MissionState):
    """Disengaged (pilot in control, or not yet enabled): no motion; wait for the link to engage."""

    name = "idle"
    triggers = ("engage",)

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()

    def tick(self, bb: Blackboard) -> str | None:
        return "engage" if bb.engaged else None


class Done(_ReleaseWatch):
    """Arrived: stop, hold, report; a new request needs the diver's arm down first."""

    name = "done"
    triggers = ("released",)

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()
        bb.arrived = True
        bb.arrivals += 1
        e = bb.errors
        rng = bb.standoff_m + (e.range_m if e is not None and e.range_m is not None else 0.0)
        px = e.pixel_px if e is not None else float("nan")
        held = f" (held short by {bb.held_short_m:.1f} m)" if bb.held_short_m > 0 else ""
        bb.say(f"arrived: range {rng:.2f} m{held}, {px:.0f} px off", pilot=True)

    def tick(self, bb: Blackboard) -> str | None:
        return "released" if self.arm_released(bb) else None


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
    """The link stopped commanding during the acknowledgement or the approach (autopilot or ground station lost,
    the pilot took over): no motion, the target kept and tracked; when the link engages again, re-check and resume or
    start again.

    Entered only for disengage reasons that clear the operator's enable, so the link engages again
    only after a new enable; this state also checks that it saw the enable cleared, and never
    resumes otherwise. On re-engage: the target seen within ``behaviour.lost_grace_s`` and the
    suspension no longer than ``behaviour.resume_within_s`` -> ``resume`` (servo), or ``reacknowledge``
    (the whole acknowledgement again) when the suspension cut it short (``bb.ack_pending``); else
    ``expired`` (wait_for_diver). Not re-engaged within ``behaviour.resume_within_s`` -> ``disengage`` (idle,
    the target forgotten).
    """

    name = "suspended"
    triggers = ("resume", "reacknowledge", "expired", "disengage")
    needs = "track"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()
        self.enable_cleared = not bb.operator_enabled
        bb.say("suspended: holding, target kept", "warning", pilot=True)
        bb.say(f"resumes only after the operator's re-enable, within {bb.config.resume_within_s:g} s")

    def tick(self, bb: Blackboard) -> str | None:
        track_target(bb)
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
        bb.say(f"re-engaged after {away:.1f} s, target seen {bb.now_s - seen:.1f} s ago")
        if bb.ack_pending:
            bb.say("target tracked: acknowledging it again", pilot=True)
            return "reacknowledge"
        bb.say("target tracked: resuming the servo", pilot=True)
        return "resume"


class NothingThere(_ReleaseWatch):
    """Nothing detected where the diver points: no motion toward anything; tell them with a shake and the
    pilot with a STATUSTEXT, then wait for the arm to come down (a new point).

    A diver who keeps pointing after the shake insists (``insists``): the arm kept raised for
    ``behaviour.nothing_there_relook_s`` after it, once per point (``bb.relooks``) -> ``insisted``: the point is
    confirmed and decided again from fresh frames, with every bar as before and a clear one for an object
    (``SelectTarget.relook_unclear``); 0 s (the default since session 67): never, wait for the arm.
    """

    name = "nothing_there"
    triggers = ("released", "insisted")

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()
        bb.chosen = None
        self.raised_since_s: float | None = None
        self.misses = 0
        p = bb.decision.posterior.get("none", float("nan")) if bb.decision is not None else float("nan")
        bb.say(f"nothing detected where pointed (p {p:.2f})", "notice", pilot=True)
        bb.say("shaking: yaw left-right-left-right, then waiting for a new point")
        self.shake = Acknowledgement(bb.config, shake=True)
        self.shake.start(bb.now_s)

    def tick(self, bb: Blackboard) -> str | None:
        command, _, finished = self.shake.tick(bb.now_s)
        bb.set_command(None if finished else command)
        if not finished:
            return None
        result = new_result(bb)
        if result is None:
            return None
        raised = arm_raised(bb, result)
        if self.insists(bb, raised):
            return "insisted"
        return "released" if self.arm_released(bb, raised) else None

    def insists(self, bb: Blackboard, raised: bool) -> bool:
        """True once this tick's frame ends ``behaviour.nothing_there_relook_s`` of a raised arm after the shake
        (as in select_target, the arm counts as kept until ``behaviour.arm_lost_frames`` frames in a row miss
        it), when the point has a re-look left."""
        c = bb.config
        if c.nothing_there_relook_s <= 0.0 or bb.relooks >= 1:
            return False
        self.misses = 0 if raised else self.misses + 1
        if self.misses >= c.arm_lost_frames:
            self.raised_since_s = None
        elif raised and self.raised_since_s is None:
            self.raised_since_s = bb.observation.stamp_s
        if self.raised_since_s is None or bb.observation.stamp_s - self.raised_since_s < c.nothing_there_relook_s:
            return False
        bb.relooks += 1
        bb.fusion = None  # fresh frames: the first look's evidence is not counted twice
        bb.say(f"diver still pointing {c.nothing_there_relook_s:g} s after the shake: looking again", "notice",
               pilot=True)
        return True

    def exit(self, bb: Blackboard) -> None:
        bb.set_command(None)


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
