"""The controller tick shared by ``run`` (real camera and autopilot) and ``sitl`` (lockstep simulator).

One tick, single-threaded, on the injected clock::

    link.poll()                      # telemetry, operator commands
    blackboard <- engaged, hold reason, operator enable, a new Observation if perception delivered one
    mission.tick()                   # the current state's behaviour; maybe a transition
    send the states' messages        # STATUSTEXT to the pilot, DO_SET_SERVO for the lights
    link.tick(command if perception is fresh else None, perception_fresh, capture stamp)

Perception never blocks the tick: in ``run`` the project's one ``PerceptionWorker``
(``dip3d_vehicle/worker.py``) processes the newest camera frame with ``FrameProcessor`` (older
frames are dropped and counted) and the tick picks up whatever result is new;
in the simulator, results are delivered after a modelled latency. While the newest result is
older than ``behaviour.perception_stale_s`` no motion is commanded (the link also refuses to engage
after ``link.perception_timeout_s``).
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

import numpy as np

from dip3d_vehicle.frames import StereoFrame
from dip3d_vehicle.perception.corridor import merge_candidates
from dip3d_vehicle.perception.held_arm import decide_held
from dip3d_vehicle.perception.pipeline import Perception
from dip3d_vehicle.perception.triangulation import triangulate
from dip3d_vehicle.perception.values import Candidates
from dip3d_vehicle.servo.command import VelocityCommand
from dip3d_vehicle.servo.ibvs import PointServo

from .blackboard import SEVERITY, BehaviourConfig, Blackboard, Observation, SetServo, StatusText, TrackFrame
from .machine import Mission
from .tracker import TargetTracker, TrackerConfig, TrackRegion

__all__ = ["build_mission", "FrameProcessor", "Controller", "MAV_CMD_DO_SET_SERVO"]

MAV_CMD_DO_SET_SERVO = 183


def build_mission(params: Mapping[str, Any], rig, image_size: tuple[int, int], now_s: float = 0.0,
                  perception: Perception | None = None) -> Mission:
    """Return a Mission (machine + blackboard + servo + tracker) for a rig and parameters.

    With ``perception`` (the core that makes the mission's results), the point's frames are decided
    again with the held arm (``behaviour.fusion_arm_frames``).
    """
    servo = PointServo.from_params(params, rig.focal_px, rig.principal_point_px, image_size)
    tracker = TargetTracker(TrackerConfig.from_params(params), rig)
    bb = Blackboard(BehaviourConfig.from_params(params), servo, tracker, now_s=now_s)
    if perception is not None:
        bb.decide_held = functools.partial(decide_held, perception)
    return Mission(bb)


class FrameProcessor:
    """Turns a camera frame into an Observation, doing only what the current state needs.

    ``full``: the perception core (pose, masked candidates, selection). ``track``: rectify and the
    full-frame matched features with their 3D points, for the tracker, plus the pose alone when
    ``behaviour.stop_gesture`` is on (the stop gesture is watched in every state).

    Args:
        perception: the perception core (its rig, detector and pose backend are used).
        before: called with each frame before processing (the simulator hands the pose source
            its keypoints here), or None.
    """

    def __init__(self, perception: Perception, before: Callable[[StereoFrame], None] | None = None,
                 pose_in_track: bool | None = None) -> None:
        self.perception = perception
        self.before = before
        self.pose_in_track = bool(perception.params.get("behaviour.stop_gesture", True)) \
            if pose_in_track is None else pose_in_track
        self.processed = {"full": 0, "track": 0}
        self.busy_s = 0.0

    def process(self, frame: StereoFrame, need: str, stamp_s: float | None = None,
                roi: TrackRegion | None = None) -> Observation:
        """Process one frame; ``stamp_s`` is its capture time on the loop clock (default its stamp).

        ``roi`` (``Mission.track_roi``) limits the ``track`` search to its box (x0, y0, x1, y1, rectified left
        px): both images are cropped to those rows and to the columns from ``x0`` minus the disparity
        allowance to ``x1``; its zoom box, when it has one, is scanned again closer.
        """
        t0 = time.perf_counter()
        stamp = frame.stamp_s if stamp_s is None else stamp_s
        if self.before is not None:
            self.before(frame)
        p = self.perception
        if need == "track":
            left, right = p.rig.rectify(frame.left, frame.right)
            cands = _detect_in(p, left, right, roi)
            xyz = triangulate(p.Q, cands.left_px, cands.disparity_px) if len(cands) else np.zeros((0, 3))
            keep = np.all(np.isfinite(xyz), axis=1) & (xyz[:, 2] > max(p.params["filters.min_depth_m"], 0.0)) \
                & (xyz[:, 2] <= p.params["filters.max_depth_m"])
            pose = p.pose.estimate(left, right, p.rig) if self.pose_in_track else None
            obs = Observation(stamp, frame.index, track=TrackFrame(cands.subset(keep), xyz[keep]), pose=pose)
        else:
            obs = Observation(stamp, frame.index, result=p.process(frame.left, frame.right))
        self.processed[need] = self.processed.get(need, 0) + 1
        self.busy_s += time.perf_counter() - t0
        return obs


def _detect_in(p: Perception, left: np.ndarray, right: np.ndarray, roi: TrackRegion | None) -> Candidates:
    """Full-frame (no arm mask) matched features, optionally only inside a region of interest.

    Inside a region of interest, the pointing corridor's detector (when on) adds its own matches:
    an object it found (small, far, faint) is followed with the same kind of features; and its zoom
    box, when it has one, is scanned again closer (``CorridorDetector.detect_zoom_box``).
    """
    if roi is None:
        return p.detector.detect(left, right, None, p.rig)
    cands = _detect_box(p, left, right, roi.box)
    if p.corridor is None or roi.zoom is None:
        return cands
    return merge_candidates(cands, p.corridor.detect_zoom_box(left, right, roi.zoom, roi.zoom_disparity_px, p.rig))


def _detect_box(p: Perception, left: np.ndarray, right: np.ndarray, box: tuple[int, int, int, int]) -> Candidates:
    """Matched features inside one search box (rectified left px), the corridor's added when on."""
    x0, y0, x1, y1 = box
    if x1 - x0 < 16 or y1 - y0 < 16:
        return p.detector.detect(left, right, None, p.rig)
    cands = p.detector.detect(left[y0:y1, x0:x1], right[y0:y1, x0:x1], None, p.rig)
    shift = np.array([x0, y0], float)
    cands = Candidates(cands.left_px + shift, cands.right_px + shift, cands.descriptors, cands.sizes_px)
    if p.corridor is None:
        return cands
    return merge_candidates(cands, p.corridor.detect_box(left, right, box, p.rig))


@dataclass
class TickRecord:
    """What one tick did (for logs and safety checks)."""

    t_s: float
    state: str
    engaged: bool
    command: VelocityCommand | None
    fresh: bool
    trigger: str | None = None


@dataclass
class Controller:
    """The controller: link + mission, one ``tick`` per loop iteration.

    Args:
        link: an opened VehicleLink.
        mission: the Mission (from ``build_mission``).
        clock: the loop's clock (the link's).
    """

    link: Any
    mission: Mission
    clock: Any
    sent: dict = field(default_factory=lambda: {"statustext": 0, "set_servo": 0})
    last_observation: Observation | None = None
    observations: int = 0
    _text_id: int = 0

    @property
    def bb(self) -> Blackboard:
        """The mission's blackboard."""
        return self.mission.bb

    def perception_fresh(self, now_s: float) -> bool:
        """True when the newest observation was captured within ``behaviour.perception_stale_s``."""
        obs = self.last_observation
        return obs is not None and now_s - obs.stamp_s <= self.bb.config.perception_stale_s

    def tick(self, observation: Observation | None = None) -> TickRecord:
        """Run one controller tick with this tick's new observation (or None)."""
        now = self.clock.now()
        link, bb = self.link, self.bb
        link.poll()
        if observation is not None:
            self.last_observation = observation
            self.observations += 1
        fresh = self.perception_fresh(now)
        bb.now_s, bb.observation, bb.perception_fresh = now, observation, fresh
        bb.engaged, bb.hold_reason, bb.operator_enabled = link.engaged, link.not_engaged_reason, link.operator_enabled
        trigger = self.mission.tick()
        if observation is not None:
            bb.last_observation = observation
        bb.observation = None
        self._send_outbox(bb.take_outbox())
        command = bb.command if fresh else None
        stamp = self.last_observation.stamp_s if self.last_observation is not None else None
        engaged = link.tick(command, perception_fresh=fresh, perception_stamp_s=stamp)
        return TickRecord(now, self.mission.state, engaged, command, fresh, trigger)

    def _send_outbox(self, items: list) -> None:
        """Send the states' STATUSTEXTs and servo commands through the link's connection."""
        for item in items:
            if isinstance(item, StatusText):
                self._text_id = self._text_id % 65535 + 1
                for msg in _statustext(item, self._text_id):  # chunks of 50 characters (id / chunk_seq)
                    self._raw_send("STATUSTEXT", msg)
                self.sent["statustext"] += 1
            elif isinstance(item, SetServo):
                c = self.link.config
                self._raw_send("COMMAND_LONG", _command_long(c.target_system, c.target_component, MAV_CMD_DO_SET_SERVO,
                                                             float(item.instance), float(item.pwm)))
                self.sent["set_servo"] += 1

    def _raw_send(self, name: str, msg: Any) -> None:
        """Send one non-motion message with the link's own identity (``name`` is for readers)."""
        self.link.send_message(msg)


def _statustext(item: StatusText, text_id: int) -> list[Any]:
    """Return the MAVLink STATUSTEXT message(s) of one text (chunked beyond 50 characters)."""
    from dip3d_vehicle.link.statustext import statustext_messages
    return statustext_messages(SEVERITY.get(item.severity, 6), item.text, text_id)


def _command_long(target_system: int, target_component: int, command: int, *params: float) -> Any:
    """Return a MAVLink COMMAND_LONG with up to 7 parameters."""
    from pymavlink.dialects.v20 import ardupilotmega as m2
    p = list(params) + [0.0] * (7 - len(params))
    return m2.MAVLink_command_long_message(target_system, target_component, command, 0, *p)


def observation_summary(obs: Observation | None) -> dict:
    """Return a small JSON-able summary of an observation for the run log."""
    if obs is None:
        return {}
    out: dict = {"stamp_s": obs.stamp_s, "index": obs.index}
    if obs.result is not None:
        r = obs.result
        out["status"] = r.status
        if getattr(r, "candidates_followed", False):  # decided on candidates followed from earlier frames
            out["candidates_followed"] = True
        if r.selection is not None and r.selection.none_probability > 0.0:
            out["none_probability"] = round(float(r.selection.none_probability), 3)
        if r.selection is not None and r.selection.target is not None:
            out["selection"] = {"xyz_m": [round(float(v), 3) for v in r.selection.target.xyz_m],
                                "confidence": round(float(r.selection.confidence), 3),
                                "ambiguous": bool(r.selection.ambiguous)}
    if obs.track is not None:
        out["features"] = len(obs.track.candidates)
    return out


def finite_or_none(value: float | None) -> float | None:
    """Return a finite float or None (JSON-safe)."""
    return None if value is None or not math.isfinite(float(value)) else float(value)
