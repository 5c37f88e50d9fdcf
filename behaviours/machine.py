"""The mission state machine: one table of states and triggers, driven by explicit ticks.

Read the whole mission here::

    idle --engage--> wait_for_diver --arm_seen--> confirm_point --steady--> select_target
    select_target --winner--> acknowledge --acked--> servo --centred--> arrive --held--> done
    done --released--> wait_for_diver                      (a new request needs the arm lowered)
    confirm_point/select_target --arm_lost--> wait_for_diver; confirm_point --timeout--> wait_for_diver
    select_target --ambiguous--> confirm_point
    servo/arrive --lost--> lost_target --reacquired--> servo; arrive --drifted--> servo
    servo/arrive/lost_target --give_up--> abort --reset--> wait_for_diver
    acknowledge/servo/arrive/lost_target --suspend--> suspended      (autopilot / ground station lost, pilot took over)
    suspended --resume--> servo      (re-engaged after the operator's re-enable, target still tracked and fresh)
    suspended --reacknowledge--> acknowledge      (the same, but suspended before the acknowledgement finished)
    suspended --expired--> wait_for_diver      (re-engaged, but the target is lost or too much time passed)
    every state but idle --disengage--> idle    (the link stopped commanding: operator disable, other causes)
    select_target --nothing_there--> nothing_there --released--> wait_for_diver   (shake, STATUSTEXT, no motion)
    nothing_there --insisted--> confirm_point   (with behaviour.nothing_there_relook_s, off by default: one fresh look per point)
    select_target --second_look--> second_look --looked--> select_target   (a bounded step; diver gone: arm_lost)
    select_target --close_in--> close_in --closer--> select_target   (a far diver: a bounded advance; diver gone: arm_lost)
    every state but idle/stopped --stop_gesture--> stopped   (both wrists above the head >= 1 s: neutral, enable kept)

Stale perception only holds the current state. A disengage for one of ``SUSPEND_REASONS`` (each
clears the operator's enable in ``dip3d_vehicle/link/engage.py``, so the link engages again only
after a new enable) suspends a mission that has a target instead of ending it; any other disengage
ends the mission (idle). The stop gesture is watched before every state's tick (``gesture.py``), on
every frame: full frames' arm and tracking frames' pose.

The ``transitions`` library holds the table (``queued=True``, no auto transitions, no Timeout
extension: every timeout is checked against the loop's clock in the state's own ``tick``). Each
state's behaviour is a small class with enter / tick / exit, in ``pointing_states.py``,
``approach_states.py`` or ``holding_states.py`` (gathered in ``states.py``).
"""

from __future__ import annotations

from transitions import Machine

from dip3d_vehicle.link.engage import LATCHING_REASONS, PERCEPTION_HOLDS, PERCEPTION_STALE

from .blackboard import Blackboard
from .gesture import StopGestureWatch
from .tracker import TrackRegion, project_px, zoom_box
from .states import STATE_CLASSES, MissionState

__all__ = ["STATES", "TRANSITIONS", "Mission", "PERCEPTION_STALE", "SUSPEND_REASONS", "SUSPENDABLE"]

STATES: list[str] = ["idle", "wait_for_diver", "confirm_point", "select_target", "acknowledge", "servo",
                     "lost_target", "arrive", "done", "abort", "suspended", "nothing_there", "stopped",
                     "second_look", "close_in"]
"""Every mission state."""

TRANSITIONS: list[dict] = [
    {"trigger": "engage", "source": "idle", "dest": "wait_for_diver"},
    {"trigger": "arm_seen", "source": "wait_for_diver", "dest": "confirm_point"},
    {"trigger": "steady", "source": "confirm_point", "dest": "select_target"},
    {"trigger": "timeout", "source": "confirm_point", "dest": "wait_for_diver"},
    {"trigger": "arm_lost", "source": ["confirm_point", "select_target", "second_look", "close_in"],
     "dest": "wait_for_diver"},
    {"trigger": "ambiguous", "source": "select_target", "dest": "confirm_point"},
    {"trigger": "winner", "source": "select_target", "dest": "acknowledge"},
    {"trigger": "nothing_there", "source": "select_target", "dest": "nothing_there"},
    {"trigger": "second_look", "source": "select_target", "dest": "second_look"},
    {"trigger": "looked", "source": "second_look", "dest": "select_target"},
    {"trigger": "close_in", "source": "select_target", "dest": "close_in"},
    {"trigger": "closer", "source": "close_in", "dest": "select_target"},
    {"trigger": "acked", "source": "acknowledge", "dest": "servo"},
    {"trigger": "centred", "source": "servo", "dest": "arrive"},
    {"trigger": "drifted", "source": "arrive", "dest": "servo"},
    {"trigger": "lost", "source": ["servo", "arrive"], "dest": "lost_target"},
    {"trigger": "reacquired", "source": "lost_target", "dest": "servo"},
    {"trigger": "give_up", "source": ["servo", "arrive", "lost_target"], "dest": "abort"},
    {"trigger": "held", "source": "arrive", "dest": "done"},
    {"trigger": "released", "source": ["done", "nothing_there"], "dest": "wait_for_diver"},
    {"trigger": "insisted", "source": "nothing_there", "dest": "confirm_point"},
    {"trigger": "reset", "source": "abort", "dest": "wait_for_diver"},
    {"trigger": "suspend", "source": ["acknowledge", "servo", "lost_target", "arrive"], "dest": "suspended"},
    {"trigger": "resume", "source": "suspended", "dest": "servo"},
    {"trigger": "reacknowledge", "source": "suspended", "dest": "acknowledge"},
    {"trigger": "expired", "source": "suspended", "dest": "wait_for_diver"},
    {"trigger": "disengage", "source": [s for s in STATES if s != "idle"], "dest": "idle"},
    {"trigger": "stop_gesture", "source": [s for s in STATES if s not in ("idle", "stopped")], "dest": "stopped"},
]
"""The whole machine: trigger, source state(s), destination."""

HOLD_REASONS = PERCEPTION_HOLDS
"""Not-engaged reasons that only hold the mission: stale perception, and perception settling after it."""

SUSPEND_REASONS: tuple[str, ...] = LATCHING_REASONS
"""Not-engaged reasons (prefixes) that suspend a mission with a target: the link's latching reasons,
each of which clears the operator's enable (so the link engages again only after a new enable)."""
GCS_QUIET = "ground station quiet"
"""The link's hold 1 s before it declares the ground station lost (so its neutral sticks still carry
the GCS id): it suspends the mission like the loss that follows, without clearing the enable."""

SUSPENDABLE: tuple[str, ...] = ("acknowledge", "servo", "lost_target", "arrive")
"""States with a chosen target that a suspend reason suspends instead of ending the mission (acknowledge since
issue 11 session 64: a link cut during the nod ended the mission, and the diver, who had seen the nod begin, had
lowered the arm by the re-enable, so the decision was lost)."""


class Mission:
    """The model the machine drives: holds the states' behaviours and the blackboard.

    Args:
        bb: the shared context.

    Attributes:
        state: the current state's name (managed by ``transitions``).
        history: (time, state) of every state entered, starting with ("idle").
    """

    def __init__(self, bb: Blackboard) -> None:
        self.bb = bb
        self.behaviours: dict[str, MissionState] = {cls.name: cls() for cls in STATE_CLASSES}
        self.history: list[tuple[float, str]] = [(bb.now_s, "idle")]
        self.machine = Machine(model=self, states=STATES, transitions=TRANSITIONS, initial="idle",
                               queued=True, auto_transitions=False, send_event=True,
                               before_state_change="_leave", after_state_change="_arrive")
        self.behaviours["idle"].enter(bb)
        self.stop_watch = StopGestureWatch(bb.config.stop_gesture_hold_s, bb.config.stop_gesture_margin_px,
                                           bb.config.stop_gesture_gap_s, bb.config.stop_gesture_margin_m,
                                           abs(bb.tracker.rig.baseline_m))

    @property
    def needs(self) -> str:
        """The perception the current state wants: "full" or "track"."""
        return self.behaviours[self.state].needs

    def track_roi(self, rig, image_size: tuple[int, int]) -> TrackRegion | None:
        """Return where to look for the target in the next frame (rectified px), or None = everywhere.

        Only in tracking states with a target (lost_target: every other frame, the whole frame the others, as the
        prediction may have drifted; the box alone finds a faint far target, issue 11 session 58): a
        box around the predicted centre, ``behaviour.track_roi_margin_px`` plus the projected size of
        ``behaviour.track_roi_object_m`` on each side (the margin doubled after a miss, so the
        corridor's features, which only a box gets, still cover a drifting prediction); its left edge
        is widened by twice the predicted disparity so the right image's matches fall inside. A target
        predicted at least ``ZOOM_MIN_DEPTH_M`` away also gets a zoom box (``zoom_box``).
        """
        bb, tracker = self.bb, self.bb.tracker
        if self.needs != "track" or not tracker.active or (self.state == "lost_target" and tracker.misses % 2):
            return None
        xyz = tracker.predicted_xyz(bb.now_s, bb.command_in_force)
        if xyz is None or xyz[2] < 0.2:
            return None
        f = rig.focal_px
        u, v = project_px(xyz, rig)
        half = bb.config.track_roi_margin_px * (2.0 if tracker.misses else 1.0) + f * bb.config.track_roi_object_m / xyz[2]
        disparity = f * abs(rig.baseline_m) / xyz[2]
        w, h = image_size
        x0, x1 = int(max(0, u - half - 2 * disparity)), int(min(w, u + half))
        y0, y1 = int(max(0, v - half)), int(min(h, v + half))
        if x1 - x0 < 32 or y1 - y0 < 32:
            return None
        zoom, zoom_disparity = zoom_box(xyz, rig, image_size, bb.config.track_zoom_m, tracker.misses)
        return TrackRegion((x0, y0, x1, y1), zoom, zoom_disparity)

    def tick(self) -> str | None:
        """Run one tick of the current state; fire its trigger. Return the trigger fired, if any.

        When the link is not engaged (other than for stale perception) the mission is suspended
        (a target state and a ``SUSPEND_REASONS`` reason) or ended (``disengage`` to idle) before
        the state's own tick; ``suspended`` itself decides, in its tick, what a re-engage means.
        """
        bb = self.bb
        if self.state not in ("idle", "suspended") and not bb.engaged and bb.hold_reason not in HOLD_REASONS:
            if self.state in SUSPENDABLE and bb.hold_reason.startswith(SUSPEND_REASONS + (GCS_QUIET,)):
                bb.say(f"disengaged ({bb.hold_reason}): suspending the mission, keeping the target")
                self.trigger("suspend")
                return "suspend"
            bb.say(f"disengaged ({bb.hold_reason or 'link'}): stopping the mission")
            self.trigger("disengage")
            return "disengage"
        if self.stop_gesture_held():
            self.trigger("stop_gesture")
            return "stop_gesture"
        name = self.behaviours[self.state].tick(bb)
        if name:
            self.trigger(name)
        return name

    def stop_gesture_held(self) -> bool:
        """Feed this tick's new frame to the stop-gesture watch; True when it fires (not in idle / stopped)."""
        bb, obs = self.bb, self.bb.observation
        if obs is None or not bb.config.stop_gesture or self.state in ("idle", "stopped"):
            return False
        arm = obs.result.arm if obs.result is not None else obs.pose
        if not self.stop_watch.update(arm, obs.stamp_s):
            return False
        bb.say(f"stop gesture held {obs.stamp_s - self.stop_watch.since_s:.1f} s (both wrists above the head)")
        return True

    def _leave(self, event) -> None:
        """Exit the source state's behaviour."""
        self.behaviours[event.transition.source].exit(self.bb)

    def _arrive(self, event) -> None:
        """Enter the destination state's behaviour and record it."""
        dest = event.transition.dest
        self.history.append((self.bb.now_s, dest))
        self.bb.say(f"state {event.transition.source} -> {dest} ({event.event.name})")
        self.behaviours[dest].enter(self.bb)
