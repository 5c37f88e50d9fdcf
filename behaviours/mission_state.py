"""The base of every mission state and the helpers the states share.

The machine (``machine.py``) decides which state runs; a state only looks at the blackboard,
sets the command and returns a trigger name (or None to stay). ``needs`` tells the loop which
perception the state wants: ``full`` (the perception core: diver, pointing, selection) or
``track`` (full-frame features for the tracker; no pose needed while the vehicle moves).
Time is ``bb.now_s`` (the loop's clock); nothing here sleeps or starts a timer.
"""

from __future__ import annotations

from .blackboard import Blackboard
from .evidence import arm_direction, image_direction, is_folded_guess, is_raised
from .tracker import TrackedTarget

__all__ = ["MissionState", "new_result", "arm_raised", "track_target"]


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


def new_result(bb: Blackboard):
    """Return this tick's new perception-core result, or None."""
    obs = bb.observation
    return None if obs is None else obs.result


def arm_raised(bb: Blackboard, result) -> bool:
    """Return True when a result shows a raised pointing arm, and not an arm the pose source folded up.

    Raised: the triangulated shoulder-to-wrist direction at least ``behaviour.min_raise_rad`` from
    straight down. Folded: BlazePose puts a hanging arm it cannot see (in profile, against the dark
    body) up over the shoulder, at a lower confidence (``evidence.is_folded_guess``).
    """
    c = bb.config
    if result is None or not is_raised(arm_direction(result), c.min_raise_rad):
        return False
    return not is_folded_guess(result.arm, image_direction(result), c.min_arm_confidence, c.folded_arm_rad)


def track_target(bb: Blackboard) -> tuple[bool, TrackedTarget | None]:
    """Feed a new tracking frame to the tracker: (was there a new frame, the target or None)."""
    obs = bb.observation
    if obs is None or obs.track is None:
        return False, None
    found = bb.tracker.update(obs.track.candidates, obs.track.xyz_m, obs.stamp_s, bb.command_in_force)
    if found is not None:
        bb.target = found
    return True, found
