"""The fault campaign's fast tier: one seeded trial of one fault (``ControllerTrial``, ``run_trial``).

The REAL simulated autopilot (sitl.Autopilot), the router and the simulated pilot/GCS of
``sitl.simulation``, the ``LossyRelay``, ``VehicleLink`` and the ``FrameGuard`` at the perception
boundary, with a stand-in for perception + servo: small synthetic camera frames (through
``CameraFaults``), and a constant forward-and-turn command while the newest accepted frame is fresh
(as ``behaviours.loop.Controller`` passes ``bb.command`` only when fresh). A trial measures the time
from the fault's onset to the last motion command (sent by the controller, and received by the
autopilot), crashes, log records written vs read back, and recovery (re-engaged and moving again
after the fault clears and the pilot hands over again, per the link's enable-latch policy).
"""

from __future__ import annotations

import math
import tempfile
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.config import load_params
from dip3d_vehicle.frames import StereoFrame
from dip3d_vehicle.link import VehicleLink
from dip3d_vehicle.record.mcap_log import McapRunReader, McapRunWriter
from dip3d_vehicle.servo.command import VelocityCommand

from .autopilot import Autopilot
from .fault_bounds import BOUNDS_S, TRIAL_PLANS
from .fault_events import FaultEvents
from .faults import CameraFaults, FaultPlan, FrameGuard, LossyRelay, load_fault_plan

__all__ = ["TrialResult", "ControllerTrial", "run_trial", "max_gap_s", "event_time_s"]

STEP_S = 0.02
FORWARD = VelocityCommand(surge_m_s=0.25, yaw_rate_rad_s=0.05)
FRAME_SIZE = (64, 48)


def _record_autopilot_commands(ap: Autopilot, received: list, heartbeats: list) -> None:
    """Record every MANUAL_CONTROL / SET_POSITION_TARGET_LOCAL_NED the autopilot gets (motion or not),
    and the times of the controller's HEARTBEATs (1/191) it hears."""
    orig_mc, orig_sp, orig_hb = ap._on_manual_control, ap._on_set_position_target_local_ned, ap._on_heartbeat

    def on_mc(link, msg, now):
        received.append((now, not (msg.x == 0 and msg.y == 0 and msg.r == 0 and msg.z == 500)))
        orig_mc(link, msg, now)

    def on_sp(link, msg, now):
        received.append((now, any(abs(v) > 0 for v in (msg.vx, msg.vy, msg.vz, msg.yaw_rate))))
        orig_sp(link, msg, now)

    def on_hb(link, msg, now):
        if (msg.get_srcSystem(), msg.get_srcComponent()) == (1, 191):
            heartbeats.append(now)
        orig_hb(link, msg, now)

    ap._on_manual_control, ap._on_set_position_target_local_ned, ap._on_heartbeat = on_mc, on_sp, on_hb


def max_gap_s(times: list[float], start: float | None = None) -> float:
    """Return the largest gap between consecutive ``times`` (from ``start`` on), or NaN with fewer than two."""
    ts = [t for t in times if start is None or t >= start]
    return max((b - a for a, b in zip(ts, ts[1:])), default=math.nan)


@dataclass
class TrialResult:
    """One fast-tier trial."""

    fault: str
    seed: int
    events: list
    last_motion_sent_s: float | None = None
    last_motion_received_s: float | None = None
    bound_s: float | None = None
    within_bound: bool = True
    disengage_reason: str = ""
    recovered: bool | None = None
    reengaged_after_s: float | None = None
    crashed: str = ""
    log_written: int = 0
    log_read: int = 0
    engaged_fraction: float = 0.0
    counters: dict = field(default_factory=dict)


class ControllerTrial:
    """The fast tier's closed loop: real autopilot, router, pilot/GCS, relay and VehicleLink; a stand-in
    for perception (synthetic frames through CameraFaults + FrameGuard) and the servo (a constant
    forward-and-turn command while fresh).

    Args:
        plan: the fault plan.
        params: parameters (link.*, sim.*, sitl.*).
        seed: drives the relay and the synthetic frames.
        log_path: run record (MCAP) to write (telemetry every 0.1 s, one frame record per accepted frame, events).
    """

    def __init__(self, plan: FaultPlan, params: Mapping[str, Any] | None = None, seed: int = 0,
                 log_path: str | Path | None = None) -> None:
        from .router import Router
        from .sim_pilot import SimPilot

        self.params = params if params is not None else load_params()
        if plan.params:
            self.params = self.params.with_overrides(dict(plan.params), plan.source)
        p = self.params
        self.plan, self.seed = plan, seed
        self.clock = SimClock()
        guided = p["link.output_mode"] == "guided_velocity"
        self.ap = Autopilot(p, self.clock, listen=["tcp:127.0.0.1:0"], has_position=guided or None)
        self.received: list[tuple[float, bool]] = []
        self.ap_heard_controller_hb: list[float] = []
        _record_autopilot_commands(self.ap, self.received, self.ap_heard_controller_hb)
        self.router = Router(self.ap.addresses[0])
        self.router.step()
        self.relay = LossyRelay(self.router.address, plan.link, self.clock, seed) if plan.needs_relay else None
        url = self.relay.controller_url if self.relay else self.router.address
        self.link = VehicleLink(p.with_overrides({"link.url": url}, "fault trial") if hasattr(p, "with_overrides")
                                else {**p, "link.url": url}, self.clock)
        self.link.open()
        self.pilot = SimPilot(self.router.address, self.clock, self.link.config.engage_mode,
                              float(p["sitl.gcs_arm_at_s"]))
        self.rng = np.random.default_rng(seed)
        self._texture = self.rng.integers(20, 235, size=(FRAME_SIZE[1], FRAME_SIZE[0], 3), dtype=np.uint8)
        self._frame_count = 0
        self.camera = CameraFaults(self._synthetic_frame)
        self.guard = FrameGuard(FRAME_SIZE)
        self.events = FaultEvents(plan, self.ap, self.pilot, self.relay, self.camera)
        self.ticks: list[tuple[float, bool, bool]] = []  # (t, engaged, motion sent)
        self.ctrl_heard_ap_hb: list[float] = []
        self._last_ap_hb: float | None = None
        self.log = McapRunWriter(log_path, None, {"command": "fault_campaign"}, overwrite=True) if log_path else None
        self.log_counts = {"frames": 0, "telemetry": 0, "events": 0}
        self._first_engaged: float | None = None
        self._latency = float(p["sitl.perception_latency_s"])
        self._period = 1.0 / float(p["sitl.camera_rate_hz"])
        self._pending: list[tuple[float, float]] = []
        self.last_stamp: float | None = None

    def _synthetic_frame(self, t_s: float) -> StereoFrame:
        i = self._frame_count
        self._frame_count += 1
        left = np.roll(self._texture, i, axis=1)
        return StereoFrame(left, np.roll(left, -3, axis=1), t_s, i, {"keypoints": {}})

    def _start_of(self, state: str) -> float | None:
        return self._first_engaged  # the stand-in's "servo": the first engagement

    def step(self) -> None:
        """One lockstep tick of every party."""
        now = self.clock.advance(STEP_S)
        self.ap.step()
        self.router.step()
        if self.relay:
            self.relay.step()
        self.pilot.step()
        self.events.step(now, self._start_of)
        if self._frame_count == 0 or now + 1e-9 >= self._next_frame:
            self._next_frame = now + self._period
            frame = self.camera(now)
            reason = self.guard.check(frame)
            if not reason:
                self._pending.append((now + self._latency, frame.stamp_s))
                if self.log:
                    self.log.frame({"t_s": now, "index": frame.index, "stamp_s": frame.stamp_s})
                    self.log_counts["frames"] += 1
            elif frame is not None and self._frame_count == 0:
                self._frame_count = 1
        while self._pending and self._pending[0][0] <= now + 1e-9:
            self.last_stamp = max(self.last_stamp or -math.inf, self._pending.pop(0)[1])
        fresh = self.last_stamp is not None and now - self.last_stamp <= float(self.params["behaviour.perception_stale_s"])
        self.link.poll()
        hb = self.link.autopilot.last_heartbeat_s
        if hb is not None and hb != self._last_ap_hb:
            self._last_ap_hb = hb
            self.ctrl_heard_ap_hb.append(hb)
        engaged = self.link.tick(FORWARD if fresh else None, perception_fresh=fresh, perception_stamp_s=self.last_stamp)
        self.router.step()
        if self.relay:
            self.relay.step()
        if engaged and self._first_engaged is None:
            self._first_engaged = now
        self.ticks.append((now, engaged, engaged and fresh))
        if self.log and len(self.ticks) % 5 == 0:
            self.log.telemetry({"t_s": now, "engaged": engaged, "armed": self.ap.armed, "mode": self.ap.mode_name,
                                "north_m": self.ap.state.north_m, "yaw_rad": self.ap.state.yaw_rad})
            self.log_counts["telemetry"] += 1

    def run_until(self, t_s: float) -> None:
        """Step until the clock reaches ``t_s``."""
        self._next_frame = getattr(self, "_next_frame", 0.0)
        while self.clock.now() < t_s - 1e-9:
            self.step()

    def close(self) -> None:
        """Close sockets (the link first: it sends its stop value) and the log."""
        try:
            self.link.close()
            if self.relay:
                self.relay.step()
                self.relay.close()
            self.router.step()
            self.ap.step()
        finally:
            self.pilot.close()
            self.router.close()
            self.ap.close()
            if self.log:
                for line in self.link.events:
                    self.log.event(line)
                    self.log_counts["events"] += 1
                self.log.close()


def run_trial(fault: str, seed: int, params: Mapping[str, Any] | None = None, tail_s: float = 6.0) -> TrialResult:
    """Run one fast-tier trial of ``fault`` (a plan in sitl/faults/) with ``seed``."""
    params = params if params is not None else load_params()
    plan = load_fault_plan(TRIAL_PLANS[fault], seed=seed)
    res = TrialResult(fault, seed, [], bound_s=BOUNDS_S.get(fault))
    with tempfile.TemporaryDirectory() as tmp:
        log_path = Path(tmp) / "trial.mcap"
        trial = None
        try:
            trial = ControllerTrial(plan, params, seed, log_path)
            lasting = max((e.lasting_s + max(e.reenable_s, 0) for e in plan.events), default=0.0)
            trial.run_until(3.0)
            deadline = 60.0
            while trial.clock.now() < deadline and (trial.events.pending or not trial.events.applied
                                                   ) and plan.events:
                trial.run_until(trial.clock.now() + 0.5)
            end = trial.clock.now() + lasting + tail_s + (10.0 if not plan.events else 0.0)
            trial.run_until(end)
        except Exception as exc:  # noqa: BLE001 - a crash is a result here
            res.crashed = f"{exc.__class__.__name__}: {exc}"
            res.counters["traceback"] = traceback.format_exc()[-2000:]
        finally:
            if trial is not None:
                try:
                    trial.close()
                except Exception as exc:  # noqa: BLE001
                    res.crashed = res.crashed or f"close: {exc.__class__.__name__}: {exc}"
        if trial is None:
            return res
        _score(res, trial)
        written = sum(trial.log_counts.values())
        try:
            with McapRunReader(log_path) as reader:
                read = sum(1 for _ in reader.frames()) + sum(1 for _ in reader.telemetry()) + sum(
                    1 for _ in reader.events())
        except Exception as exc:  # noqa: BLE001
            read = -1
            res.crashed = res.crashed or f"log read: {exc}"
        res.log_written, res.log_read = written, read
    return res


def _score(res: TrialResult, trial: ControllerTrial) -> None:
    res.events = trial.events.applied
    after_engaged = [t for t in trial.ticks if trial._first_engaged is not None and t[0] >= trial._first_engaged]
    res.engaged_fraction = round(sum(e for _, e, _ in after_engaged) / max(len(after_engaged), 1), 3)
    res.counters = {"relay": trial.relay.counts() if trial.relay else None,
                    "guard_rejected": dict(trial.guard.rejected), "link_bad_data": trial.link.stats.bad_data,
                    "autopilot_reboots": trial.ap.reboots,
                    "ap_heard_controller_hb_max_gap_s": round(max_gap_s(trial.ap_heard_controller_hb), 3),
                    "ctrl_heard_ap_hb_max_gap_s": round(max_gap_s(trial.ctrl_heard_ap_hb), 3)}
    if not res.events:
        if trial.plan.events:
            res.crashed = res.crashed or "fault never fired (controller never engaged)"
        return
    ev = res.events[0]
    onset, clear, recover_from = ev["onset_s"], ev["clear_s"], ev["recover_from_s"]
    window_end = recover_from if res.bound_s is not None else clear
    sent = [t for t, eng, motion in trial.ticks if motion and onset <= t < window_end]
    recv = [t for t, motion in trial.received if motion and onset <= t < window_end]
    res.last_motion_sent_s = round(max(sent) - onset, 3) if sent else 0.0
    res.last_motion_received_s = round(max(recv) - onset, 3) if recv else 0.0
    if res.bound_s is not None:
        res.within_bound = res.last_motion_sent_s <= res.bound_s + 1e-6 and res.last_motion_received_s <= res.bound_s + 1e-6
    res.counters["rechecked_state"] = any("requesting message intervals and SYSID_MYGCS" in e
                                          for e in trial.link.events if event_time_s(e) >= onset - 1e-6)
    res.counters["said_so"] = [e for e in trial.link.events if event_time_s(e) >= onset - 1e-6 and (
        "disengaged" in e or "cleared" in e)][:2]
    dis = [e for e in trial.link.events if "disengaged" in e and event_time_s(e) >= onset - 1e-6]
    res.disengage_reason = dis[0].split("disengaged: ", 1)[1] if dis else ""
    again = [t for t, eng, motion in trial.ticks if motion and t >= window_end]
    res.recovered = bool(again)
    res.reengaged_after_s = round(again[0] - window_end, 3) if again else None


def event_time_s(line: str) -> float:
    """Return the time of a link event line (``t=12.34 ...``), or infinity when it has none."""
    try:
        return float(line.split()[0][2:])
    except (ValueError, IndexError):
        return math.inf
