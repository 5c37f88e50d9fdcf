"""The run's recorder: ``run.mcap`` + ``mav.tlog`` (+ ``annotated.mp4``), the live view and the live
Foxglove server, fed from one place.

``run`` and ``sitl`` create one ``RunRecorder`` and hand it around as the run's log:

- the simulator / camera loop calls ``images()`` for every frame (kept every Nth in the MCAP; the
  newest left image feeds the live view and the video),
- the controller loop calls ``tick()`` after every controller tick (state changes, servo error and
  command, link status, story lines, and for each new observation its overlay: image annotations
  and the 3D scene; operator requests from the live page are applied here, on the loop's thread),
- the VehicleLink calls ``mavlink_sent`` / ``mavlink_received`` for every message (the tlog, the
  STATUSTEXT log and the autopilot's attitude, depth, mode and armed state as plottable channels),
- ``frame`` / ``telemetry`` / ``event`` keep the old run log's records (replay reads ``frame``).
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from .mcap_log import McapRunWriter
from .overlay import draw_overlay, image_annotations, overlay_of, scene_update
from .tlog import TlogWriter

__all__ = ["RunRecorder", "RecordingProcessor", "MCAP_NAME", "TLOG_NAME", "VIDEO_NAME"]

MCAP_NAME, TLOG_NAME, VIDEO_NAME = "run.mcap", "mav.tlog", "annotated.mp4"
_SERVO_PERIOD_S = 0.1  # /servo at 10 Hz
_LINK_PERIOD_S = 1.0  # /link/status at 1 Hz
_MAV_STATE_GCS = 6


class RunRecorder:
    """Record one run and serve it live.

    Args:
        mcap_path: the MCAP file to create (``run.mcap`` in the output folder).
        params: effective parameters (metadata; ``runlog.*`` configure the writer).
        meta: what the run is (command, scenario, seed, image size, calibration text or file names).
        rig: the StereoRig (overlays are computed in its original left pixels); may be set later.
        tlog_path: ``mav.tlog`` to create, or None for none.
        video_path: ``annotated.mp4`` to create, or None for none.
        view: a live-view server (``dip3d_vehicle.view.server.ViewServer``) or None.
        foxglove: a live Foxglove server (``dip3d_vehicle.view.foxglove_live.FoxgloveLive``) or None.
        clock: the run's clock; log times follow it (set later with ``set_clock``).
        writer_options: extra McapRunWriter keyword arguments (keep_images_every, overwrite, ...).
    """

    def __init__(self, mcap_path: str | Path, params: Mapping[str, Any] | None, meta: Mapping[str, Any] | None,
                 rig: Any = None, tlog_path: str | Path | None = None, video_path: str | Path | None = None,
                 view: Any = None, foxglove: Any = None, clock: Any = None, **writer_options: Any) -> None:
        self.mcap = McapRunWriter(mcap_path, params, meta, clock=clock, **writer_options)
        self.path = self.mcap.path
        self.settings = self.mcap.settings
        self.rig = rig
        self.tlog = TlogWriter(tlog_path, overwrite=writer_options.get("overwrite", False)) if tlog_path else None
        self.view, self.foxglove = view, foxglove
        self.video = None
        if video_path is not None:
            from ..sources.video_writer import AnnotatedVideo

            fps = float((params or {}).get("runlog.video_fps", 10.0)) if params is not None else 10.0
            self.video = AnnotatedVideo(video_path, fps)
        if foxglove is not None:
            self.mcap.mirror = foxglove.publish
        self._lock = threading.Lock()
        self._images: OrderedDict[int, np.ndarray] = OrderedDict()  # newest left images by frame index
        self._state: str | None = None
        self._next_servo_s = self._next_link_s = -1e18
        self._story_done = 0
        self._autopilot: tuple[int, int] | None = None
        self.last_overlay: dict | None = None
        self._chosen: tuple | None = None  # (probability, method, time) of the last full-perception choice
        self.counts = {"overlays": 0, "video_frames": 0, "operator_requests_applied": 0}

    # -- the old run log's interface (Simulation, run, fault_campaign call these) --------------
    @property
    def records_written(self) -> int:
        """Messages written to the MCAP so far."""
        return self.mcap.records_written

    def set_clock(self, clock: Any) -> None:
        """Follow ``clock`` for log times (the simulator's clock once the simulation exists)."""
        self.mcap.set_clock(clock)

    def frame(self, record: Mapping[str, Any]) -> None:
        """Log one frame record (what replay compares)."""
        self.mcap.frame(record)

    def telemetry(self, record: Mapping[str, Any]) -> None:
        """Log one telemetry record."""
        self.mcap.telemetry(record)

    def event(self, text: str, **fields: Any) -> None:
        """Log one event (a story line)."""
        self.mcap.event(text, **fields)

    def wants_images(self) -> bool:
        """True when the next pair will be kept in the MCAP."""
        return self.mcap.wants_images()

    def images(self, frame_index: int, left: np.ndarray, right: np.ndarray, force: bool = False,
               t_s: float | None = None) -> bool:
        """Take one camera frame: kept every Nth in the MCAP; the newest left image feeds view and video."""
        with self._lock:
            self._images[int(frame_index)] = left
            while len(self._images) > 8:
                self._images.popitem(last=False)
        kept = self.mcap.images(frame_index, left, right, force, t_s)
        if self.view is not None:
            self.view.set_frame(left, self.last_overlay, frame_index)
        return kept

    # -- the controller loop ----------------------------------------------------------------------
    def tick(self, now_s: float, rec: Any, mission: Any, observation: Any = None, link: Any = None) -> None:
        """Record what one controller tick did (call after ``Controller.tick``)."""
        bb = mission.bb
        if rec.state != self._state:
            self._on_state(now_s, rec, bb)
        if observation is not None:
            self._on_observation(now_s, observation, mission)
        if now_s + 1e-9 >= self._next_servo_s:
            self._next_servo_s = max(self._next_servo_s + _SERVO_PERIOD_S, now_s + _SERVO_PERIOD_S / 2)
            self._on_servo(now_s, rec, bb)
        if link is not None:
            self.story(link.events + bb.story)
            if now_s + 1e-9 >= self._next_link_s:
                self._next_link_s = max(self._next_link_s + _LINK_PERIOD_S, now_s + _LINK_PERIOD_S / 2)
                self._on_link(now_s, link)
            if self.view is not None:
                self._apply_operator(link)
        if self.view is not None:
            self.view.update(state=rec.state, engaged=bool(rec.engaged), t_s=round(now_s, 2),
                             hold_reason=bb.hold_reason, arrived=bool(bb.arrived),
                             link=None if link is None else _link_summary(now_s, link),
                             story=(link.events + bb.story if link is not None else bb.story)[-12:])

    def _on_state(self, now_s: float, rec: Any, bb: Any) -> None:
        previous, self._state = self._state, rec.state
        self.mcap.publish_json("/mission/state", {"t_s": now_s, "state": rec.state, "previous": previous,
                                                  "trigger": rec.trigger, "engaged": bool(rec.engaged),
                                                  "hold_reason": bb.hold_reason})
        self.mcap.log_line("/mission/log", f"t={now_s:.2f} state {previous} -> {rec.state}"
                           + (f" ({rec.trigger})" if rec.trigger else ""), "mission", 2, now_s)

    def _on_observation(self, now_s: float, obs: Any, mission: Any) -> None:
        if self.rig is None:
            return
        bb = mission.bb
        size = tuple(self.rig.image_size)
        try:
            region = mission.track_roi(self.rig, size)
            box = None if region is None else region.box
        except Exception:  # noqa: BLE001 - a box is a nicety, never a reason to stop recording
            box = None
        tracked = None if bb.target is None else bb.target.left_px
        ov = overlay_of(obs.result, self.rig, mission.state, tracked, box)
        if obs.track is not None:
            ov["features"] = len(obs.track.candidates)
        t = self.mcap.stamp_ns(obs.stamp_s)
        self.mcap.publish("/camera/left/annotations", image_annotations(ov, t), t)
        self.mcap.publish("/scene", scene_update(ov, t), t)
        self.counts["overlays"] += 1
        if ov["target"] is not None:
            self._chosen = (ov["target"].get("p"), ov["target"].get("method"), now_s)
        elif ov["tracked_px"] is not None and self._chosen is not None:  # view and video: the tracked target
            p, method, chosen_at = self._chosen
            ov = dict(ov, target={"px": ov["tracked_px"], "p": p, "method": f"{method}, tracked since t={chosen_at:.1f}"})
        self.last_overlay = ov
        with self._lock:
            image = self._images.get(int(obs.index))
        if image is None:
            return
        if self.video is not None:
            self.video.write(draw_overlay(image, ov, f"t={now_s:.1f}s {mission.state}: {ov['status']}"))
            self.counts["video_frames"] += 1
        if self.view is not None:
            self.view.set_frame(image, ov, int(obs.index))

    def _on_servo(self, now_s: float, rec: Any, bb: Any) -> None:
        e, c = bb.errors, rec.command
        self.mcap.publish_json("/servo", {
            "t_s": now_s, "state": rec.state, "engaged": bool(rec.engaged), "perception_fresh": bool(rec.fresh),
            "pixel_error_px": None if e is None else e.pixel_px,
            "range_error_m": None if e is None else e.range_m,
            "command": None if c is None else {"surge_m_s": c.surge_m_s, "sway_m_s": c.sway_m_s,
                                               "heave_m_s": c.heave_m_s, "yaw_rate_rad_s": c.yaw_rate_rad_s}})

    def story(self, lines: list[str]) -> None:
        """Log the story lines not logged yet (sorted by their t= time) on /story."""
        if len(lines) <= self._story_done:
            return
        for line in sorted(lines, key=_story_time)[self._story_done:]:
            t = _story_time(line)
            self.mcap.log_line("/story", line, "story", 3 if "disengaged" in line or "lost" in line else 2,
                               None if t == float("inf") else t)
        self._story_done = len(lines)

    def _on_link(self, now_s: float, link: Any) -> None:
        self.mcap.publish_json("/link/status", _link_summary(now_s, link))

    def _apply_operator(self, link: Any) -> None:
        for action in self.view.take_requests():
            if action == "enable":
                link.enable("live view")
            elif action == "stop":
                link.disable("live view")
            self.counts["operator_requests_applied"] += 1

    # -- the MAVLink link ---------------------------------------------------------------------------
    def attach_link(self, link: Any) -> None:
        """Know which system/component is the autopilot (its HEARTBEAT, ATTITUDE and VFR_HUD are plotted)."""
        c = link.config
        self._autopilot = (c.target_system, c.target_component)

    def mavlink_sent(self, msg: Any) -> None:
        """Record a message the controller sent (called by the VehicleLink)."""
        t = self.mcap.stamp_ns()
        if self.tlog is not None:
            self.tlog.write(msg, t // 1000, "sent")
        if msg.get_type() == "STATUSTEXT":
            self.mcap.log_line("/mavlink/statustext", _text(msg.text), "controller", _level(msg.severity))

    def mavlink_received(self, msg: Any) -> None:
        """Record a message the controller received (called by the VehicleLink)."""
        kind = msg.get_type()
        if kind == "BAD_DATA":
            return
        t = self.mcap.stamp_ns()
        if self.tlog is not None:
            self.tlog.write(msg, t // 1000, "received")
        src = (msg.get_srcSystem(), msg.get_srcComponent())
        if kind == "STATUSTEXT":
            self.mcap.log_line("/mavlink/statustext", _text(msg.text), f"{src[0]}/{src[1]}", _level(msg.severity))
        if self._autopilot is not None and src != self._autopilot:
            return
        if kind == "ATTITUDE":
            self.mcap.publish_json("/autopilot/attitude", {"roll_rad": msg.roll, "pitch_rad": msg.pitch,
                                                           "yaw_rad": msg.yaw, "yawspeed_rad_s": msg.yawspeed}, t)
        elif kind == "VFR_HUD":
            self.mcap.publish_json("/autopilot/depth", {"depth_m": -float(msg.alt), "climb_m_s": float(msg.climb)}, t)
        elif kind == "HEARTBEAT" and msg.type != _MAV_STATE_GCS:
            from ..link.state import mode_name

            self.mcap.publish_json("/autopilot/status", {
                "mode": mode_name(msg.custom_mode), "mode_number": int(msg.custom_mode),
                "armed": bool(msg.base_mode & 128), "system_status": int(msg.system_status)}, t)

    # -- end -------------------------------------------------------------------------------------------
    def close(self) -> None:
        """Finish the MCAP, the tlog and the video; safe to call twice."""
        self.mcap.close()
        if self.tlog is not None:
            self.tlog.close()
        if self.video is not None:
            self.video.close()

    def __enter__(self) -> "RunRecorder":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class RecordingProcessor:
    """Wraps a frame processor so every processed frame's images reach the recorder (``run``'s worker).

    The images are logged with the observation's capture stamp, so the annotations of that
    observation land on exactly that image in Foxglove.
    """

    def __init__(self, processor: Any, recorder: RunRecorder) -> None:
        self.processor, self.recorder = processor, recorder

    def process(self, frame: Any, need: str, stamp_s: float | None = None, roi: Any = None) -> Any:
        """Process one frame and hand its images to the recorder."""
        obs = self.processor.process(frame, need, stamp_s, roi)
        self.recorder.images(frame.index, frame.left, frame.right, t_s=obs.stamp_s)
        return obs

    def __getattr__(self, name: str) -> Any:
        return getattr(self.processor, name)


def _link_summary(now_s: float, link: Any) -> dict:
    ap, gcs = link.autopilot, link.gcs
    return {"engaged": bool(link.engaged), "operator_enabled": bool(link.operator_enabled),
            "not_engaged_reason": link.not_engaged_reason, "mode": ap.mode, "armed": bool(ap.armed),
            "autopilot_age_s": None if ap.last_message_s is None else round(now_s - ap.last_message_s, 2),
            "gcs_age_s": None if gcs.last_heartbeat_s is None else round(now_s - gcs.last_heartbeat_s, 2),
            "received": int(link.stats.received), "sent": int(sum(link.stats.sent.values()))}


def _story_time(line: str) -> float:
    try:
        return float(line.split()[0][2:])
    except (ValueError, IndexError):
        return float("inf")


def _text(raw: Any) -> str:
    return raw.decode(errors="replace").rstrip("\0") if isinstance(raw, (bytes, bytearray)) else str(raw)


def _level(severity: int) -> int:
    """MAV_SEVERITY (0 emergency .. 7 debug) -> foxglove log level (4 error .. 1 debug)."""
    return 4 if severity <= 3 else 3 if severity == 4 else 2 if severity <= 6 else 1

