"""The one shared context of the mission: what the states read and write, nothing global.

The loop fills in the inputs each tick (time, engaged, a new observation if one arrived); the
states read them and write the outputs (the velocity command, messages for the pilot and the
lights, the chosen target). Values that cross into the loop are small frozen dataclasses.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field, fields
from typing import Any, Callable, Mapping

import numpy as np

from dip3d_vehicle.perception.pipeline import PerceptionResult
from dip3d_vehicle.perception.values import ArmKeypoints, Candidates
from dip3d_vehicle.servo.command import VelocityCommand
from dip3d_vehicle.servo.ibvs import PointServo, ServoErrors

from .evidence import Vote
from .fusion import FusedDecision, PointFusion
from .close_in import CloseInStep
from .second_look import LookStep
from .tracker import TargetTracker, TrackedTarget
from .weak_lean import WeakLean

__all__ = ["BehaviourConfig", "TrackFrame", "Observation", "StatusText", "SetServo", "Blackboard"]

DECIDED_KEPT = 64
"""Decisions the blackboard keeps a record of (``Blackboard.decided``): bounded for a long onboard run."""

SEVERITY = {"critical": 2, "warning": 4, "notice": 5, "info": 6}
"""MAV_SEVERITY numbers for StatusText."""


@dataclass(frozen=True)
class BehaviourConfig:
    """The ``behaviour.*`` parameters (see params/schema/behaviour.yaml) plus the servo stand-off."""

    tick_rate_hz: float = 50.0
    perception_stale_s: float = 0.5
    arm_seen_n: int = 3
    arm_seen_m: int = 5
    min_raise_rad: float = 0.9
    min_arm_confidence: float = 0.85
    folded_arm_rad: float = 0.785
    arm_lost_frames: int = 3
    steady_angle_rad: float = 0.1
    steady_hold_s: float = 1.0
    confirm_timeout_s: float = 10.0
    vote_frames: int = 4
    vote_radius_m: float = 0.3
    min_vote_share: float = 0.6
    min_votes: int = 3
    select_timeout_s: float = 6.0
    ack_kind: str = "nod"
    ack_nod_yaw_rate_rad_s: float = 0.35
    ack_nod_swing_s: float = 0.5
    ack_nod_cycles: int = 1
    ack_settle_s: float = 1.0
    ack_lights_servo: int = 9
    ack_lights_on_pwm: int = 1900
    ack_lights_off_pwm: int = 1100
    ack_flashes: int = 2
    ack_flash_period_s: float = 0.6
    track_ratio: float = 0.8
    track_min_matches: int = 4
    track_gate_m: float = 0.5
    track_gate_growth_m_s: float = 0.4
    track_gate_max_m: float = 0.75
    track_near_m: float = 0.25
    track_model_size: int = 600
    track_lost_frames: int = 3
    track_roi_margin_px: float = 200.0
    track_roi_object_m: float = 0.4
    track_zoom_m: float = 0.3
    track_pool_below: int = 50
    track_neighbours: bool = True
    track_surface_slope: float = 2.0
    track_reckoning: str = "vehicle"
    track_coast_m: float = 0.23
    lost_grace_s: float = 1.0
    lost_timeout_s: float = 6.0
    look_round_max_m: float = 0.8
    look_round_speed_m_s: float = 0.15
    servo_timeout_s: float = 90.0
    servo_clearance_m: float = 0.6
    servo_diver_margin_m: float = 0.4
    arrive_tolerance_px: float = 40.0
    arrive_tolerance_m: float = 0.10
    arrive_hysteresis: float = 1.5
    arrive_hold_s: float = 1.5
    arrive_max_range_rate_m_s: float = 0.03
    release_frames: int = 3
    abort_hold_s: float = 3.0
    resume_within_s: float = 30.0
    fusion_temper: float = 0.5
    fusion_floor_p: float = 0.02
    fusion_min_posterior: float = 0.9
    fusion_no_objects_none_p: float = 0.8
    fusion_max_effective_frames: float = 4.0
    fusion_arm_frames: int = 4
    fusion_recall_s: float = 0.0
    fusion_spot_support: bool = False
    fusion_min_shared_posterior: float = 0.5
    fusion_shared_rule: str = "always"
    fusion_min_pose_shared_posterior: float = 0.5
    target_max_extent_m: float = 0.6
    second_look_max_tries: int = 1
    second_look_step_m: float = 0.4
    second_look_speed_m_s: float = 0.15
    second_look_settle_s: float = 1.0
    second_look_min_p: float = 0.15
    second_look_margin_px: float = 80.0
    decide_max_range_m: float = 2.5
    close_in_max_tries: int = 1
    close_in_speed_m_s: float = 0.15
    close_in_standoff_m: float = 2.0
    close_in_clearance_m: float = 0.5
    close_in_min_step_m: float = 0.3
    close_in_max_descent_m: float = 0.0
    close_in_weak_one_look: float = 0.6
    close_in_one_look: float = 0.7
    close_in_weak_min_error_cut: float = 0.25
    weak_look_again: bool = True
    nothing_there_relook_s: float = 0.0
    nothing_there_relook_one_look: float = 0.7
    shake_yaw_rate_rad_s: float = 0.35
    shake_swing_s: float = 0.4
    stop_gesture: bool = True
    stop_gesture_hold_s: float = 1.0
    stop_gesture_margin_px: float = 5.0
    stop_gesture_margin_m: float = 0.1
    stop_gesture_gap_s: float = 0.5
    standoff_m: float = 1.0
    statustext: bool = True

    @classmethod
    def from_params(cls, params: Mapping[str, Any]) -> "BehaviourConfig":
        """Build from effective parameters (``behaviour.*``, ``servo.standoff_m``, ``mission.statustext``,
        ``selection.target_max_extent_m``)."""
        out, known = {}, set(params)
        for f in fields(cls):
            for key in (f"behaviour.{f.name}", f"servo.{f.name}", f"mission.{f.name}", f"selection.{f.name}"):
                if key in known:
                    out[f.name] = params[key]
                    break
        return cls(**out)


@dataclass(frozen=True)
class TrackFrame:
    """Full-frame matched features of one frame (no arm mask), for the tracker."""

    candidates: Candidates
    xyz_m: np.ndarray


@dataclass(frozen=True)
class Observation:
    """What perception made of one camera frame.

    Attributes:
        stamp_s: capture time on the loop's clock.
        index: frame number.
        result: the full perception core's result (diver, pointing, selection), or None.
        track: full-frame features for the tracker, or None.
        pose: the pose of a ``track`` frame (for the stop gesture), or None (full frames: ``result.arm``).
    """

    stamp_s: float
    index: int
    result: PerceptionResult | None = None
    track: TrackFrame | None = None
    pose: ArmKeypoints | None = None


@dataclass(frozen=True)
class StatusText:
    """A STATUSTEXT for the pilot."""

    severity: str
    text: str


@dataclass(frozen=True)
class SetServo:
    """A MAV_CMD_DO_SET_SERVO (e.g. lights) for the autopilot."""

    instance: int
    pwm: int


@dataclass
class Blackboard:
    """Shared mission context.

    Inputs (written by the loop each tick): ``now_s``, ``engaged``, ``hold_reason``,
    ``operator_enabled`` (the link's enable latch), ``observation`` (a new one this tick, else None),
    ``perception_fresh``. Set once: ``decide_held`` (perception's ``decide_held`` bound to the
    perception core: a frame decided again with the point's held arm; None: frames as perceived).
    Outputs (written by the states): ``command`` (None = no motion), ``outbox``, ``chosen``,
    ``target``, ``errors``, ``arrived``; ``fusion`` (the current point's fused evidence) and
    ``decision`` (its latest fused decision), ``decided`` (a small record, ``FusedDecision.record``,
    of each decision the mission acted on: a target chosen or "nothing there", in order; the last
    ``DECIDED_KEPT``); ``look_step`` / ``second_looks`` (the planned second
    look and how many this point has had); ``close_in_step`` / ``close_ins`` (the planned advance
    toward a far diver and how many this point has had); ``relooks`` (fresh looks this point had after a "nothing
    there" the diver kept pointing through); ``weak_lean`` (a weak decision's winner
    carried across the move made before acting on it, ``weak_lean.py``; None: none); ``held_short_m`` (how much
    longer than ``standoff_m`` the approach to the chosen target holds off, m: the way round the other objects and the
    diver held short, ``clearance.py``; 0 until then); ``ack_pending`` (an acknowledgement began and has not played to
    its end: a suspension cut it short, and resuming acknowledges again).
    """

    config: BehaviourConfig
    servo: PointServo
    tracker: TargetTracker
    now_s: float = 0.0
    engaged: bool = False
    hold_reason: str = ""
    operator_enabled: bool = False
    perception_fresh: bool = False
    observation: Observation | None = None
    last_observation: Observation | None = None
    command: VelocityCommand | None = None
    command_since_s: float = 0.0
    chosen: Vote | None = None
    fusion: PointFusion | None = None
    decision: FusedDecision | None = None
    decided: deque = field(default_factory=lambda: deque(maxlen=DECIDED_KEPT))
    decide_held: Callable | None = None
    look_step: LookStep | None = None
    second_looks: int = 0
    close_in_step: CloseInStep | None = None
    close_ins: int = 0
    relooks: int = 0
    weak_lean: WeakLean | None = None
    target: TrackedTarget | None = None
    errors: ServoErrors | None = None
    held_short_m: float = 0.0
    ack_pending: bool = False
    arrived: bool = False
    arrivals: int = 0
    outbox: list = field(default_factory=list)
    story: list[str] = field(default_factory=list)

    @property
    def command_in_force(self) -> VelocityCommand | None:
        """The command the vehicle acts on: ``command`` while the link is engaged and perception fresh, else None (the
        link sends its stop value, or nothing). The tracker's dead reckoning uses it: a perception hold keeps the
        states' ``command`` but stops the vehicle (issue 11 session 61: ``camera_black`` seed 5 predicted 1.4 m of
        approach through a 3.3 s blackout, 0.6 m happened, and the tracker took the placard in front)."""
        return self.command if self.engaged and self.perception_fresh else None

    @property
    def standoff_m(self) -> float:
        """The approach's stand-off in force: ``servo.standoff_m``, longer by ``held_short_m`` where the way held
        short, m."""
        return self.config.standoff_m + self.held_short_m

    def say(self, text: str, severity: str = "info", pilot: bool = False) -> None:
        """Add a line to the story; with ``pilot`` also queue it as a STATUSTEXT."""
        self.story.append(f"t={self.now_s:.2f} {text}")
        if pilot and self.config.statustext:
            self.outbox.append(StatusText(severity, "DIP3D: " + text))  # sent in 50-character chunks

    def set_command(self, command: VelocityCommand | None) -> None:
        """Set the command the link streams until the next change (None = no motion)."""
        if command != self.command:
            self.command_since_s = self.now_s
        self.command = command

    def stop(self) -> None:
        """Command no motion and reset the servo (its rate limiter restarts from rest)."""
        self.set_command(None)
        self.servo.reset()

    def take_outbox(self) -> list:
        """Return and clear the queued messages."""
        out, self.outbox = self.outbox, []
        return out
