"""The approach states: acknowledge the decision, servo to the tracked target, look for it when lost,
and settle at the stand-off (arrive). All of them run on tracking frames (``needs = "track"``).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from dip3d_vehicle.servo import VelocityCommand

from .acknowledge import Acknowledgement
from .blackboard import Blackboard
from .clearance import DIRECT_BAND_M, HULL_HALF_LENGTH_M, Sidestep, sidestep
from .look_round import look_round_m
from .mission_state import MissionState, track_target
from .tracker import TrackedTarget

__all__ = ["Acknowledge", "Servo", "LostTarget", "Arrive", "within", "SETTLE_WINDOW_S"]

SETTLE_WINDOW_S = 1.0
"""Arrive judges the servo's errors over this long, s: their medians (a tracked centre that jumps on one frame, to
another part of the placard, neither drifts nor restarts the hold) and the range's rate (a coasting vehicle still
shows: ALT_HOLD's 0.06 m/s coast moves 6 cm in it, against a centimetre of stereo jitter)."""


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
        bb.ack_pending = True
        bb.say(f"acknowledging with {bb.config.ack_kind}")

    def tick(self, bb: Blackboard) -> str | None:
        track_target(bb)
        command, servos, finished = self.ack.tick(bb.now_s)
        bb.set_command(command)
        bb.outbox.extend(servos)
        if finished and self.start_xyz is not None:  # the nod ends at the heading it began at
            bb.tracker.rewind(self.start_xyz, bb.now_s)
        bb.ack_pending = not finished
        return "acked" if finished else None

    def exit(self, bb: Blackboard) -> None:
        bb.set_command(None)


def within(bb: Blackboard, factor: float) -> bool:
    """Return True when the last servo errors are inside the arrive tolerances times ``factor``."""
    e = bb.errors
    if e is None or e.range_m is None:
        return False
    return inside(bb, e.pixel_px, e.range_m, factor)


def inside(bb: Blackboard, pixel_px: float, range_m: float, factor: float) -> bool:
    """Return True when a pixel error (px) and a range error (m) are inside the arrive tolerances times ``factor``."""
    c = bb.config
    return pixel_px <= c.arrive_tolerance_px * factor and abs(range_m) <= c.arrive_tolerance_m * factor


class _Steering(MissionState):
    """A state that servos to the tracked target: each tracking frame goes to ``missed`` (target not
    found, the vehicle stopped) or ``seen``; gives up after ``behaviour.servo_timeout_s``."""

    needs = "track"
    timeout_text = "target not reached in"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        self.last_update_s: float | None = None
        self.sway_m_s = 0.0  # the sidestep's sway in force (keep_clear), m/s
        self.offset_m = 0.0  # the way's stand-off point's lateral offset from the camera, m
        self.side = 0.0  # the side of the way chosen last (its sign; 0: none yet)
        self.direct = False  # the last frame's way was the direct way (it keeps it within DIRECT_BAND_M)
        self.told: tuple | None = None  # (side, clear) last said

    def timed_out(self, bb: Blackboard) -> bool:
        """Return True (and warn the pilot) once the state ran longer than ``behaviour.servo_timeout_s``."""
        limit = bb.config.servo_timeout_s
        if self.elapsed(bb) > limit:
            bb.say(f"{self.timeout_text} {limit:g} s", "warning", pilot=True)
            return True
        return False

    def steer(self, bb: Blackboard, found: TrackedTarget) -> float:
        """Command the servo toward ``found`` on this frame; return the seconds since the previous frame."""
        stamp = bb.observation.stamp_s
        dt = max(stamp - self.last_update_s if self.last_update_s is not None else 0.2, 1e-3)
        self.last_update_s = stamp
        step = self.plan(bb, np.asarray(found.xyz_m, float))
        bb.servo.standoff_m = bb.standoff_m
        command = bb.servo.update(tuple(found.left_px), float(found.xyz_m[2]), dt)
        bb.errors = bb.servo.last_errors
        bb.set_command(self.keep_clear(bb, command, step, dt))
        return dt

    def plan(self, bb: Blackboard, target: np.ndarray) -> Sidestep | None:
        """Return the way round the known objects (clearance.py) from the stand-off held so far, or None when the
        direct way is clear; a way that holds short lengthens the stand-off held (``bb.held_short_m``)."""
        step = sidestep(target, target + self.kept_clear_m(bb), bb.standoff_m,
                        bb.config.servo_clearance_m, float(bb.servo.max_speed[1]),
                        bb.servo.mount.forward_m + HULL_HALF_LENGTH_M, self.side, bb.tracker.orbited_rad(target),
                        direct_band_m=DIRECT_BAND_M if self.direct else 0.0, extra_m=self.extra_m(bb))
        self.direct = step is None
        if step is not None:
            self.tell_way(bb, target, step)
            bb.held_short_m = max(bb.held_short_m, step.way.standoff_m - bb.config.standoff_m)
        return step

    def keep_clear(self, bb: Blackboard, command: VelocityCommand, step: Sidestep | None,
                   dt_s: float) -> VelocityCommand:
        """Return ``command`` following the way ``step`` (None: the direct way): a sway toward the way's stand-off
        point, ramped by the servo's sway acceleration limit, and no faster advance than keeps to it."""
        want = 0.0 if step is None else step.sway_m_s
        ramp = float(bb.servo.max_accel[1]) * dt_s
        self.sway_m_s = float(np.clip(want, self.sway_m_s - ramp, self.sway_m_s + ramp))
        self.offset_m = 0.0 if step is None else step.offset_m
        if step is None:
            return replace(command, sway_m_s=self.sway_m_s) if self.sway_m_s else command
        surge = command.surge_m_s
        if surge > 0:
            surge = min(surge, step.max_surge_m_s)
        return replace(command, sway_m_s=self.sway_m_s, surge_m_s=surge)

    @staticmethod
    def kept_clear_m(bb: Blackboard) -> np.ndarray:
        """Return what the way keeps clear of, as offsets from the target (camera frame, metres, (K, 3)): the
        decision's other objects, then the diver's body points (``pointing_states.diver_points_m``)."""
        return np.vstack([bb.tracker.neighbours_m, bb.tracker.diver_m])

    @staticmethod
    def extra_m(bb: Blackboard) -> np.ndarray:
        """Return how much further than ``behaviour.servo_clearance_m`` each of ``kept_clear_m``'s rows is kept, metres:
        half each object's span (its edge beyond its centre), ``behaviour.servo_diver_margin_m`` for the diver's
        points (the body beyond them)."""
        return np.r_[bb.tracker.neighbours_half_m,
                     np.full(len(bb.tracker.diver_m), bb.config.servo_diver_margin_m)]

    def tell_way(self, bb: Blackboard, target: np.ndarray, step: Sidestep) -> None:
        """Say the way taken when its side, whether it is clear or the stand-off it holds short at changes."""
        side = 1.0 if step.way.angle_rad > 0 else -1.0 if step.way.angle_rad < 0 else self.side
        held = round(step.way.standoff_m - bb.config.standoff_m, 1)
        told = (side, step.clear, held)
        self.side = side
        if told == self.told:
            return
        self.told = told
        where = ", ".join(f"{v:.2f}" for v in target + self.kept_clear_m(bb)[step.way.index])
        what = "an object" if step.way.index < len(bb.tracker.neighbours_m) else "the diver"
        turn = f"{abs(np.degrees(step.way.angle_rad)):.0f} deg {'right' if side > 0 else 'left'}"
        way = f"the stand-off turned {turn} about the target" if step.way.angle_rad else "straight"
        c = bb.config
        keeps = (f"{c.servo_clearance_m:.2f} m from every object and "
                 f"{c.servo_clearance_m + c.servo_diver_margin_m:.2f} m from the diver")
        if held <= 0:
            bb.say(f"{what} at ({where}) m is in the way to the target: going round, {way}", pilot=True)
        elif step.clear:
            bb.say(f"no way to the stand-off keeps {keeps}: holding short, {step.way.standoff_m:.1f} m from the "
                   f"target ({way}; nearest {what} at ({where}) m)", "warning", pilot=True)
        else:
            bb.say(f"no way keeps {keeps}: stopping here, {step.way.standoff_m:.1f} m from the target ({what} at "
                   f"({where}) m passes {step.way.clearance_m:.2f} m)", "warning", pilot=True)

    def tick(self, bb: Blackboard) -> str | None:
        if self.timed_out(bb):
            return "give_up"
        new, found = track_target(bb)
        if not new:
            return None
        if found is None:
            bb.stop()
            return self.missed(bb)
        return self.seen(bb, found)

    def missed(self, bb: Blackboard) -> str | None:
        """A tracking frame without the target (the vehicle already stopped); return a trigger or None."""
        return None

    def seen(self, bb: Blackboard, found: TrackedTarget) -> str | None:
        """A tracking frame with the target; steer toward it and return a trigger or None."""
        self.steer(bb, found)
        return None


class Servo(_Steering):
    """Visual servo to the tracked target; hold still through short losses."""

    name = "servo"
    triggers = ("centred", "lost", "give_up")

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.servo.reset()

    def missed(self, bb: Blackboard) -> str | None:
        """Hold through a short loss; ``lost`` once the target was unseen longer than ``behaviour.lost_grace_s``."""
        last = bb.tracker.last_seen_s
        if last is not None and bb.observation.stamp_s - last > bb.config.lost_grace_s:
            return "lost"
        return None

    def seen(self, bb: Blackboard, found: TrackedTarget) -> str | None:
        """Steer toward the target; ``centred`` once inside the arrive tolerances."""
        self.steer(bb, found)
        return "centred" if within(bb, 1.0) else None


class LostTarget(MissionState):
    """Target not seen for a while: look for it, first from beside an object that hides it (``look_round``), else
    holding still; give up ``behaviour.lost_timeout_s`` after the step (none: after the loss)."""

    name = "lost_target"
    triggers = ("reacquired", "give_up")
    needs = "track"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        bb.stop()
        self.step_m, self.moved_m, self.last_s = self.plan_step(bb), 0.0, None
        self.give_up_s = bb.config.lost_timeout_s + abs(self.step_m) / bb.config.look_round_speed_m_s
        if self.step_m:
            bb.say(f"target lost behind an object: stepping {abs(self.step_m):.2f} m "
                   f"{'right' if self.step_m > 0 else 'left'} to look round it", "warning", pilot=True)
        else:
            bb.say("target lost: holding and looking for it", "warning", pilot=True)

    @staticmethod
    def plan_step(bb: Blackboard) -> float:
        """Return the sideways step that shows the target round what hides it (metres, right +; 0: none)."""
        target = bb.tracker.xyz_m
        if target is None:
            return 0.0
        kept = target + _Steering.kept_clear_m(bb)
        needed = bb.config.servo_clearance_m + _Steering.extra_m(bb)
        return look_round_m(target, kept, needed, bb.servo.mount.forward_m + HULL_HALF_LENGTH_M,
                            bb.config.look_round_max_m)

    def tick(self, bb: Blackboard) -> str | None:
        if self.elapsed(bb) > self.give_up_s:
            return "give_up"
        _, found = track_target(bb)
        if found is not None:
            bb.say(f"target re-acquired ({found.matches} matches)")
            return "reacquired"
        self.sway(bb)
        return None

    def sway(self, bb: Blackboard) -> None:
        """Command the step's sway until the commanded distance covers it, then nothing."""
        now, command, moving = bb.now_s, bb.command, bb.command_in_force
        if self.last_s is not None and moving is not None:
            self.moved_m += abs(moving.sway_m_s) * max(now - self.last_s, 0.0)
        self.last_s = now
        if abs(self.step_m) - self.moved_m > 1e-6:
            bb.set_command(VelocityCommand(sway_m_s=math.copysign(bb.config.look_round_speed_m_s, self.step_m)))
        elif command is not None:
            bb.stop()

    def exit(self, bb: Blackboard) -> None:
        bb.set_command(None)


class Arrive(_Steering):
    """Centred and at the stand-off: keep correcting; done once inside tolerance and settled for the hold time.

    The servo's errors are judged by their medians over the last ``SETTLE_WINDOW_S``: the tracked centre of a
    placard can jump to another part of it for a frame (0.1 m, 60 px at 1.2 m: which of its features matched), and
    one such frame neither sends the vehicle back to servo nor restarts the hold (issue 11 session 55).
    Settled: the target's range changes by less than ``behaviour.arrive_max_range_rate_m_s`` between
    frames (in ALT_HOLD nothing brakes the vehicle horizontally: a coasting vehicle is not arrived), or, with
    the sidestep on (``behaviour.servo_clearance_m`` > 0), over the last ``SETTLE_WINDOW_S``: after a sidestep
    the target is seen at an angle, and its stereo range jitters by a centimetre from frame to frame while the
    vehicle stands (``clearance.py``). A way round objects must also have reached its end (its stand-off point
    turned about the target) within ``behaviour.arrive_tolerance_m`` sideways.
    Leaving tolerance x hysteresis goes back to servo; in between, the hold time restarts.
    """

    name = "arrive"
    triggers = ("held", "drifted", "lost", "give_up")
    timeout_text = "could not settle at the target in"

    def enter(self, bb: Blackboard) -> None:
        super().enter(bb)
        self.last_range_m: float | None = None
        self.inside_since: float | None = None
        self.window: list[tuple[float, float, float]] = []  # (stamp s, pixel px, range m) over SETTLE_WINDOW_S

    def missed(self, bb: Blackboard) -> str | None:
        """Restart the hold time; ``lost`` once the tracker gave the target up."""
        self.inside_since = None
        return "lost" if bb.tracker.lost else None

    def seen(self, bb: Blackboard, found: TrackedTarget) -> str | None:
        """Keep correcting; ``drifted`` outside tolerance x hysteresis, ``held`` once settled for the hold time."""
        c = bb.config
        dt = self.steer(bb, found)
        stamp, rng = bb.observation.stamp_s, bb.errors.range_m
        if rng is None:
            return "drifted"
        pixel_px, range_m = self.medians(stamp, bb.errors.pixel_px, rng)
        if not inside(bb, pixel_px, range_m, c.arrive_hysteresis):
            return "drifted"
        rate = abs(rng - self.last_range_m) / max(dt, 1e-3) if self.last_range_m is not None else float("inf")
        self.last_range_m = rng
        if c.servo_clearance_m > 0:  # a sidestep may leave the target seen at an angle
            rate = min(rate, self.window_rate())
        on_way_end = abs(self.offset_m) <= c.arrive_tolerance_m  # a way round objects ends turned about the target
        if inside(bb, pixel_px, range_m, 1.0) and rate <= c.arrive_max_range_rate_m_s and on_way_end:
            if self.inside_since is None:
                self.inside_since = stamp
            if stamp - self.inside_since >= c.arrive_hold_s:
                return "held"
        else:
            self.inside_since = None
        return None

    def medians(self, stamp_s: float, pixel_px: float, range_m: float) -> tuple[float, float]:
        """Add this frame's errors to the window; return the window's median pixel error (px) and range error (m)."""
        kept = [w for w in self.window if stamp_s - w[0] <= SETTLE_WINDOW_S + 1e-9]
        self.window = kept + [(stamp_s, pixel_px, range_m)]
        errors = np.array([w[1:] for w in self.window])
        return float(np.median(errors[:, 0])), float(np.median(errors[:, 1]))

    def window_rate(self) -> float:
        """Return the range's rate of change over the window (inf until it spans 80 % of ``SETTLE_WINDOW_S``), m/s."""
        (t0, _, r0), (t1, _, r1) = self.window[0], self.window[-1]
        span = t1 - t0
        return abs(r1 - r0) / span if span >= 0.8 * SETTLE_WINDOW_S else float("inf")
