"""Fault campaigns: every fault of ``sitl/faults.py`` over randomised trials, the lossy-link missions, a soak.

    python -m sitl.fault_campaign trials  [--trials 20] [--json FILE]     # fast tier, every fault
    python -m sitl.fault_campaign missions [--seeds 10] [--plan FILE] [--json FILE]  # full closed loop
    python -m sitl.fault_campaign soak    [--hours 1] [--json FILE]

Two tiers, because a closed-loop mission costs ~1 wall second per simulated second (SIFT on both
images of every frame), too slow for 20 trials x 13 faults on a shared machine:

- ``trials`` (``ControllerTrial``): the REAL simulated autopilot (sitl.Autopilot), the router and the
  simulated pilot/GCS of ``sitl.simulation``, the ``LossyRelay``, ``VehicleLink`` and the
  ``FrameGuard`` at the perception boundary, with a stand-in for perception + servo: small synthetic
  camera frames (through ``CameraFaults``), and a constant forward-and-turn command while the newest
  accepted frame is fresh (as ``behaviours.loop.Controller`` passes ``bb.command`` only when fresh).
  This measures what the issue asks per fault: the time from the fault's onset to the last motion
  command (sent by the controller, and received by the autopilot), crashes, log records written vs
  read back, and recovery (re-engaged and moving again after the fault clears and the pilot hands
  over again, per the link's enable-latch policy).
- ``missions`` (``FaultSimulation``): the whole mission (``sitl.simulation.Simulation``) with a fault
  plan: the relay sits between the controller and the router, camera faults act on the rendered
  frames before the ``FrameGuard``, timed events act on the autopilot / pilot.
- ``soak``: the fast tier, no faults, for simulated hours: memory (tracemalloc and RSS) and the gaps
  between heartbeats on both sides.
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import os
import resource
import statistics
import sys
import tempfile
import time
import tracemalloc
import traceback
from dataclasses import dataclass, field, replace
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
from .faults import (CAMERA_KINDS, CameraFaults, FaultEvent, FaultPlan, FrameGuard, LossyRelay, load_fault_plan,
                     parse_fault_plan)

__all__ = ["BOUNDS_S", "ControllerTrial", "FaultSimulation", "run_faulted_mission", "trial_campaign",
           "mission_campaign", "soak", "markdown_table", "make_simulation", "main"]

FAULT_DIR = Path(__file__).resolve().parent / "faults"
STEP_S = 0.02
FORWARD = VelocityCommand(surge_m_s=0.25, yaw_rate_rad_s=0.05)
FRAME_SIZE = (64, 48)

# The promised bound on "last motion command after the fault's onset", seconds, from the defaults:
# link.autopilot_timeout_s 0.6, link.gcs_timeout_s 2.5 (GCS HEARTBEAT 1 Hz), link.perception_timeout_s
# 0.5, the autopilot's 1 Hz HEARTBEAT, one 0.02 s tick, and (received) one relay / router hop.
BOUNDS_S: dict[str, float | None] = {
    "link_cut": 0.6 + 0.1,
    "autopilot_reboot": 0.6 + 0.1,
    "pilot_mode_change": 1.0 + 0.1,
    "pilot_disarm": 1.0 + 0.1,
    "gcs_loss": 2.5 + 0.1,
    "camera_stall": 0.5 + 0.1,
    "camera_black": 0.5 + 0.1,
    "camera_one_eye": 0.5 + 0.1,
    "camera_wrong_size": 0.5 + 0.1,
    "camera_time_backwards": 0.5 + 0.1,
    "camera_out_of_order": None,   # newer frames are still good: motion may continue (older ones dropped)
    "link_mess": None,              # degraded link: the controller keeps working
    "link_loss": None,              # 20 % loss, 100 +- 50 ms: the controller keeps working
}
EXPECTED = {
    "link_cut": "autopilot lost after 0.6 s: disengage ('autopilot lost'), neutral/zero stream (lost on the "
                "wire), enable latched off; link back: intervals + SYSID_MYGCS re-requested, re-engages "
                "after the operator's re-enable",
    "autopilot_reboot": "silence -> disengage as for a cut; reboot seen (time_boot_ms back / gap): streams and "
                        "SYSID_MYGCS re-requested; autopilot comes back disarmed in MANUAL: no command until "
                        "the pilot arms, selects the mode and re-enables",
    "pilot_mode_change": "hands off at the autopilot's next HEARTBEAT ('mode changed'), enable latched off; "
                         "re-engages only after the pilot selects the mode and re-enables",
    "pilot_disarm": "hands off at the next HEARTBEAT ('disarmed'), enable latched off; re-engages after re-arm "
                    "and re-enable",
    "gcs_loss": "ground station not heard for 2.5 s: disengage ('ground station lost'), enable latched off "
                "(ArduSub's own GCS failsafe may disarm); re-engages after the GCS is back and re-enables",
    "camera_stall": "no new frame: perception stale after 0.5 s -> hold (neutral), enable kept; resumes by itself",
    "camera_black": "black frames rejected at the perception boundary: stale -> hold; resumes by itself",
    "camera_one_eye": "frame with a missing eye rejected: no 3D decision, stale -> hold; resumes by itself",
    "camera_wrong_size": "frames of the wrong size rejected: stale -> hold; resumes by itself",
    "camera_out_of_order": "a frame older than the last one used is rejected; newer frames still used (here "
                           "every other frame: brief holds whenever the newest usable result is > 0.5 s old)",
    "camera_time_backwards": "frames whose stamp goes back rejected: stale -> hold; resumes by itself",
    "link_loss": "20 % loss, 100 +- 50 ms each way: keeps working (autopilot liveness from ~25 msg/s, "
                 "0.6 s timeout); GCS timeout 5 s for this link (see sitl/faults/link_loss.yaml)",
    "link_mess": "duplicates / reordered / corrupted packets: corrupted ones fail the CRC (counted as bad "
                 "data), the controller keeps working",
}
TRIAL_PLANS = {k: FAULT_DIR / f"{k}.yaml" for k in BOUNDS_S}


# ====================================================================================== helpers
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


def _max_gap(times: list[float], start: float | None = None) -> float:
    ts = [t for t in times if start is None or t >= start]
    return max((b - a for a, b in zip(ts, ts[1:])), default=math.nan)


class _Events:
    """Applies a plan's timed events to a run (autopilot, pilot, relay, camera) and re-hands over."""

    def __init__(self, plan: FaultPlan, ap, pilot, relay, camera) -> None:
        self.pending = list(plan.events)
        self.ap, self.pilot, self.relay, self.camera = ap, pilot, relay, camera
        self.applied: list[dict] = []
        self._actions: list[tuple[float, str]] = []

    def step(self, now: float, start_of: Any) -> None:
        """Fire due events; ``start_of(state)`` gives the first time a state was entered (or None)."""
        for ev in list(self.pending):
            if ev.at_s is not None:
                onset = ev.at_s
            else:
                t0 = start_of(ev.after_state)
                if t0 is None:
                    continue
                onset = t0 + ev.after_s
            if now + 1e-9 < onset:
                continue
            self.pending.remove(ev)
            self._fire(ev, now)
        for item in list(self._actions):
            t, what = item
            if now + 1e-9 >= t:
                self._actions.remove(item)
                if what == "gcs_back":
                    self.pilot.heartbeats = True
                elif what == "hand_over":
                    self.pilot.handed_over = self.pilot.enable_acked = False
                    self.pilot._next_try = now

    def _fire(self, ev: FaultEvent, now: float) -> None:
        clear = now + ev.lasting_s
        k = ev.kind
        if k == "link_cut":
            if self.relay is None:
                raise ValueError("link_cut needs the relay")
            self.relay.cut(now, clear)
        elif k == "autopilot_reboot":
            self.ap.reboot(ev.gap_s)
        elif k == "pilot_mode_change":
            self.pilot.set_mode(ev.mode)
        elif k == "pilot_disarm":
            self.pilot.disarm()
        elif k == "gcs_loss":
            self.pilot.heartbeats = False
            self._actions.append((clear, "gcs_back"))
        elif k in CAMERA_KINDS:
            self.camera.add(now, ev)
        handover = k not in CAMERA_KINDS and ev.reenable_s >= 0
        if handover:
            self._actions.append((clear + ev.reenable_s, "hand_over"))
        self.applied.append({"kind": k, "onset_s": round(now, 3), "clear_s": round(clear, 3),
                             "recover_from_s": round(clear + (ev.reenable_s if handover else 0.0), 3)})


# ====================================================================================== fast tier
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
        from .simulation import Router, SimPilot

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
        self.events = _Events(plan, self.ap, self.pilot, self.relay, self.camera)
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
                    "ap_heard_controller_hb_max_gap_s": round(_max_gap(trial.ap_heard_controller_hb), 3),
                    "ctrl_heard_ap_hb_max_gap_s": round(_max_gap(trial.ctrl_heard_ap_hb), 3)}
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
                                          for e in trial.link.events if _t(e) >= onset - 1e-6)
    res.counters["said_so"] = [e for e in trial.link.events if _t(e) >= onset - 1e-6 and (
        "disengaged" in e or "cleared" in e)][:2]
    dis = [e for e in trial.link.events if "disengaged" in e and _t(e) >= onset - 1e-6]
    res.disengage_reason = dis[0].split("disengaged: ", 1)[1] if dis else ""
    again = [t for t, eng, motion in trial.ticks if motion and t >= window_end]
    res.recovered = bool(again)
    res.reengaged_after_s = round(again[0] - window_end, 3) if again else None


def _t(line: str) -> float:
    try:
        return float(line.split()[0][2:])
    except (ValueError, IndexError):
        return math.inf


def trial_campaign(trials: int = 20, faults: list[str] | None = None, params: Mapping[str, Any] | None = None,
                   verbose: bool = True, jobs: int = 1, ray: str | None = None) -> dict:
    """Run ``trials`` seeded trials of every fault; return per-fault summaries and the raw trials.

    Runs here (``jobs`` 1), in ``jobs`` processes, or on Ray (``ray``: see sitl/parallel.py).
    """
    from .parallel import map_runs

    params = params if params is not None else load_params()
    out: dict[str, Any] = {"trials": {}, "summary": {}}
    names = faults or list(BOUNDS_S)
    items = [(fault, seed, params) for fault in names for seed in range(trials)]
    for (fault, seed, _), row in zip(items, map_runs(_trial_row, items, jobs, ray)):
        out["trials"].setdefault(fault, []).append(row)
        if verbose:
            print(f"{fault:22s} seed {seed:2d} sent {row['last_motion_sent_s']} recv {row['last_motion_received_s']} "
                  f"bound {row['bound_s']} ok {row['within_bound']} why '{row['disengage_reason']}' recovered "
                  f"{row['recovered']} ({row['reengaged_after_s']}) log {row['log_written']}/{row['log_read']} "
                  f"crash '{row['crashed'][:80]}'", flush=True)
    for fault in names:
        out["summary"][fault] = _summarise(fault, out["trials"].get(fault, []))
    return out


def _trial_row(args: tuple) -> dict:
    """One trial (in whatever process runs it) as a plain dict: (fault, seed, params)."""
    fault, seed, params = args
    return dict(run_trial(fault, seed, params).__dict__)


def _summarise(fault: str, rows: list[dict]) -> dict:
    sent = [r["last_motion_sent_s"] for r in rows if r["last_motion_sent_s"] is not None]
    recv = [r["last_motion_received_s"] for r in rows if r["last_motion_received_s"] is not None]
    reasons: dict[str, int] = {}
    for r in rows:
        key = r["disengage_reason"].split(" ->")[0] if r["disengage_reason"] else "(none)"
        reasons[key] = reasons.get(key, 0) + 1
    return {"trials": len(rows), "bound_s": BOUNDS_S.get(fault), "expected": EXPECTED.get(fault, ""),
            "max_last_motion_sent_s": max(sent, default=None), "max_last_motion_received_s": max(recv, default=None),
            "within_bound": sum(r["within_bound"] for r in rows),
            "crashes": sum(bool(r["crashed"]) for r in rows),
            "lost_log_records": sum(max(r["log_written"] - r["log_read"], 0) for r in rows),
            "log_records": sum(r["log_written"] for r in rows),
            "recovered": sum(bool(r["recovered"]) for r in rows),
            "reengaged_after_s_max": max((r["reengaged_after_s"] for r in rows if r["reengaged_after_s"] is not None),
                                         default=None),
            "disengage_reasons": reasons,
            "rechecked_state": sum(bool(r["counters"].get("rechecked_state")) for r in rows),
            "engaged_fraction_min": min((r["engaged_fraction"] for r in rows), default=None)}


# ====================================================================================== soak
def soak(hours: float = 1.0, params: Mapping[str, Any] | None = None, plan: FaultPlan | None = None,
         sample_every_s: float = 60.0, verbose: bool = True, trace: bool = False) -> dict:
    """Run the fast tier for ``hours`` simulated, engaged and streaming; measure memory and heartbeats.

    Memory: RSS and the number of live Python objects (gc) at every sample; with ``trace`` also
    tracemalloc (which slows the run 2-4x).
    """
    params = params if params is not None else load_params()
    plan = plan or FaultPlan()
    if trace:
        tracemalloc.start()
    trial = ControllerTrial(plan, params, 0, None)
    wall0 = time.perf_counter()
    samples = []
    try:
        trial.run_until(5.0)  # handed over, engaged
        warm = trial.clock.now() + 55.0
        trial.run_until(warm)
        # the trial keeps a tick/command history for scoring; trim it like a rolling buffer in the soak
        base = None
        end = warm + hours * 3600.0
        gaps = {"ap": 0.0, "ctrl": 0.0}
        n_hb = {"ap": 0, "ctrl": 0}
        del trial.ap_heard_controller_hb[:-1], trial.ctrl_heard_ap_hb[:-1]
        while trial.clock.now() < end - 1e-9:
            trial.run_until(min(trial.clock.now() + sample_every_s, end))
            del trial.ticks[:-100]
            del trial.received[:-100]
            for k, lst in (("ap", trial.ap_heard_controller_hb), ("ctrl", trial.ctrl_heard_ap_hb)):
                gaps[k] = max(gaps[k], _max_gap(lst) if len(lst) > 1 else 0.0)
                n_hb[k] += len(lst) - 1
                del lst[:-1]  # keep the last one for the next gap
            gc.collect()
            cur = tracemalloc.get_traced_memory()[0] if trace else len(gc.get_objects())
            rss = _rss_kib()
            if base is None:
                base = (cur, rss)
            samples.append((round(trial.clock.now(), 1), cur, rss))
            if verbose and len(samples) % 10 == 0:
                print(f"soak t={trial.clock.now():7.1f} s {'traced KiB' if trace else 'objects'} "
                      f"{cur / 1024 if trace else cur:.0f} rss {rss} KiB "
                      f"engaged {trial.link.engaged} wall {time.perf_counter() - wall0:.0f} s", flush=True)
        ap_gap, ctrl_gap = gaps["ap"], gaps["ctrl"]
        disengaged = [e for e in trial.link.events if "disengaged" in e and _t(e) >= warm]
        engaged_at_end = trial.link.engaged
    finally:
        trial.close()
        if trace:
            tracemalloc.stop()
    first, last = samples[0], samples[-1]
    what = "traced_kib" if trace else "python_objects"
    scale = 1024 if trace else 1
    return {"sim_hours": hours, "wall_s": round(time.perf_counter() - wall0, 1),
            f"{what}_first": round(first[1] / scale), f"{what}_last": round(last[1] / scale),
            f"{what}_growth_pct": round(100.0 * (last[1] - first[1]) / first[1], 2),
            "rss_first_kib": first[2], "rss_last_kib": last[2],
            "rss_growth_pct": round(100.0 * (last[2] - first[2]) / first[2], 2),
            "controller_heartbeats_heard_by_autopilot": n_hb["ap"],
            "max_gap_controller_hb_at_autopilot_s": round(ap_gap, 3),
            "autopilot_heartbeats_heard_by_controller": n_hb["ctrl"],
            "max_gap_autopilot_hb_at_controller_s": round(ctrl_gap, 3),
            "disengagements": disengaged, "engaged_at_end": engaged_at_end,
            "engaged_fraction_last_100_ticks": sum(e for _, e, _ in trial.ticks) / max(len(trial.ticks), 1),
            "autopilot_motion_commands_last_100": sum(m for _, m in trial.received),
            "samples": samples[:: max(1, len(samples) // 20)]}


def _rss_kib() -> int:
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss


# ====================================================================================== full loop
def _fault_simulation_class():
    """Build FaultSimulation lazily (sitl.simulation imports the whole perception stack)."""
    from behaviours.loop import Controller
    from .simulation import Simulation

    class FaultSimulation(Simulation):
        """The whole mission (``sitl.simulation.Simulation``) under a fault plan.

        The relay (when the plan needs one) sits between the controller's VehicleLink and the router;
        camera faults act on each rendered frame, then the FrameGuard decides whether perception
        may see it (a rejected frame gives no observation: no 3D decision, perception goes stale);
        timed events act on the autopilot and the simulated pilot.
        """

        def __init__(self, scenario, params, plan: FaultPlan, **kw: Any) -> None:
            super().__init__(scenario, params, **kw)
            self.plan = plan
            self.relay = None
            if plan.needs_relay:
                self.relay = LossyRelay(self.router.address, plan.link, self.clock, plan.seed)
                self.link.close()
                self.router.step()
                self.link = VehicleLink(params.with_overrides({"link.url": self.relay.controller_url},
                                                              "fault relay"), self.clock)
                self.link.open()
                self.controller = Controller(self.link, self.mission, self.clock)
                relay, orig = self.relay, self.router.step

                def router_step() -> None:
                    orig()
                    relay.step()
                self.router.step = router_step
            self.camera = CameraFaults(self._render_now)
            self.guard = FrameGuard(tuple(scenario.camera.image_size))
            self.fault_events = _Events(plan, self.ap, self.pilot, self.relay, self.camera)
            self.log_counts = {"frames": 0, "telemetry": 0}
            if self.log is not None:
                log, counts = self.log, self.log_counts
                orig_frame, orig_tel = log.frame, log.telemetry

                class _Counting:  # count what the simulation writes, to compare with what is read back
                    def frame(self, rec):
                        counts["frames"] += 1
                        orig_frame(rec)

                    def telemetry(self, rec):
                        counts["telemetry"] += 1
                        orig_tel(rec)

                    def __getattr__(self, name):
                        return getattr(log, name)
                self.log = _Counting()

        def _render_now(self, t_s: float):
            s = self.ap.state
            frame = self.renderer.render(s.north_m, s.east_m, s.depth_m, s.yaw_rad, t_s)
            self.last_frame, self.last_meta = frame, frame.meta
            return frame

        def _maybe_fault(self, now: float) -> None:
            super()._maybe_fault(now)
            self.fault_events.step(now, lambda st: next((t for t, s in self.mission.history if s == st), None))

        def _capture(self, now: float):
            frame = self.camera(now)
            if self.guard.check(frame):
                return None
            need = self.mission.needs
            roi = self.mission.track_roi(self.rig, self.scenario.camera.image_size) if need == "track" else None
            return self.processor.process(frame, need, now, roi)

        def close(self) -> None:
            super().close()
            if self.relay is not None:
                self.relay.close()

    return FaultSimulation


def __getattr__(name: str) -> Any:
    if name == "FaultSimulation":
        return _fault_simulation_class()
    raise AttributeError(name)


def run_faulted_mission(scenario: str = "paper_pool", seed: int = 0, plan: FaultPlan | str | Path | None = None,
                        params: Any = None, log: Any = None, **overrides: Any):
    """Run one whole mission under a fault plan (a FaultPlan or a plan file); return (result, simulation)."""
    from .scenario import load_scenario
    from .simulation import sim_params

    if plan is None or isinstance(plan, (str, Path)):
        plan = load_fault_plan(plan, seed=seed) if plan is not None else FaultPlan()
    base = params if params is not None else load_params()
    if plan.params:
        base = base.with_overrides(dict(plan.params), plan.source)
    sc = load_scenario(scenario, seed)
    sim = _fault_simulation_class()(sc, sim_params(base, sc, **overrides), plan, log=log)
    try:
        result = sim.run()
    finally:
        sim.close()
    return result, sim


def _mission_one(args: tuple) -> dict:
    seed, plan_path, overrides = args
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "run.mcap"
        params = load_params()
        wall0 = time.perf_counter()
        try:
            with McapRunWriter(path, None, {"command": "fault_campaign missions"}, overwrite=True) as log:
                result, sim = run_faulted_mission("paper_pool", seed, plan_path, params, log=log, **overrides)
        except Exception as exc:  # noqa: BLE001
            return {"seed": seed, "crashed": f"{exc.__class__.__name__}: {exc}", "traceback": traceback.format_exc()[-1500:]}
        with McapRunReader(path) as reader:
            read = {"frames": sum(1 for _ in reader.frames()), "telemetry": sum(1 for _ in reader.telemetry())}
        out = result.to_json()
        out.update({"crashed": "", "log_written": sim.log_counts, "log_read": read,
                    "relay": sim.relay.counts() if sim.relay else None, "guard_rejected": dict(sim.guard.rejected),
                    "fault_events": sim.fault_events.applied, "link_bad_data": sim.link.stats.bad_data,
                    "disengagements": [e for e in sim.link.events if "disengaged" in e],
                    "wall_s": round(time.perf_counter() - wall0, 1)})
        out.pop("states", None)
        safety = []
        for ev in sim.fault_events.applied:
            onset, end = ev["onset_s"], ev["recover_from_s"]
            if ev["kind"] == "camera_out_of_order":
                end = ev["clear_s"]
            recv = [r.t_s for r in sim.received if r.motion and onset <= r.t_s < end]
            sent = [t for t, _, eng, motion in sim.ticks if eng and motion and onset <= t < end]
            again = [r.t_s for r in sim.received if r.motion and r.t_s >= end]
            safety.append({**ev, "last_motion_received_s": round(max(recv) - onset, 3) if recv else 0.0,
                           "last_motion_sent_s": round(max(sent) - onset, 3) if sent else 0.0,
                           "bound_s": BOUNDS_S.get(ev["kind"]),
                           "moving_again_after_s": round(again[0] - end, 3) if again else None})
        out["fault_safety"] = safety
        return out


def mission_campaign(seeds: int = 10, plan: str | Path = FAULT_DIR / "link_loss.yaml", jobs: int = 1,
                     overrides: Mapping[str, Any] | None = None, verbose: bool = True, first_seed: int = 0,
                     ray: str | None = None) -> dict:
    """Whole missions (paper_pool seeds first_seed.. +seeds) under a plan; arrivals and safety counters.

    Runs here (``jobs`` 1), in ``jobs`` processes, or on Ray (``ray``: see sitl/parallel.py).
    """
    from .parallel import map_runs

    items = [(s, str(plan), dict(overrides or {})) for s in range(first_seed, first_seed + seeds)]
    runs = []
    for r in map_runs(_mission_one, items, jobs, ray):
        runs.append(r)
        if verbose:
            _print_mission(r)
    reached = sum(r.get("outcome") == "reached" for r in runs)
    outcomes: dict[str, int] = {}
    for r in runs:
        word = "crashed" if r.get("crashed") else r.get("outcome", "?")
        outcomes[word] = outcomes.get(word, 0) + 1
    return {"plan": str(plan), "seeds": seeds, "arrived": sum(bool(r.get("arrived")) for r in runs),
            "reached": reached, "outcomes": outcomes, "crashes": sum(bool(r.get("crashed")) for r in runs),
            "runs": runs}


def _print_mission(r: dict) -> None:
    print(f"seed {r['seed']} outcome {r.get('outcome')} t {r.get('time_to_arrive_s')} "
          f"sim {r.get('sim_time_s')} wall {r.get('wall_s')} log {r.get('log_written')} / {r.get('log_read')} "
          f"relay {r.get('relay')} dis {r.get('disengagements')} guard {r.get('guard_rejected')} "
          f"safety {r.get('fault_safety')} crash '{r.get('crashed', '')[:100]}'", flush=True)


def markdown_table(summary: Mapping[str, dict]) -> str:
    """The README table of a ``trials`` summary: fault, expected safe outcome, bound, measured numbers."""
    rows = ["| fault | expected safe outcome | bound on last motion command after onset | measured "
            "(max sent / max received by the autopilot) | within bound | recovered | crashes | log records "
            "lost / written | controller's reason |", "|---|---|---|---|---|---|---|---|---|"]
    for fault, s in summary.items():
        bound = "n/a (keeps working)" if s["bound_s"] is None else f"{s['bound_s']:.2f} s"
        meas = ("engaged fraction min {:.2f}".format(s["engaged_fraction_min"]) if s["max_last_motion_sent_s"] is None
                else f"{s['max_last_motion_sent_s']:.2f} s / {s['max_last_motion_received_s']:.2f} s")
        rec = "n/a" if s["max_last_motion_sent_s"] is None else (
            f"{s['recovered']}/{s['trials']} (moving again <= {s['reengaged_after_s_max']:.2f} s after the "
            f"clear / re-enable)")
        reasons = ", ".join(f"{k} x{v}" for k, v in s["disengage_reasons"].items())
        rows.append(f"| {fault} | {s['expected']} | {bound} | {meas} | {s['within_bound']}/{s['trials']} | {rec} | "
                    f"{s['crashes']} | {s['lost_log_records']} / {s['log_records']} | {reasons} |")
    return "\n".join(rows)


def make_simulation(scenario: Any, params: Any, faults: str | Path | None, seed: int = 0, **kw: Any):
    """For ``dip3d-vehicle sitl --faults FILE``: a Simulation, or a FaultSimulation when a plan file is given.

    Raises:
        ScenarioError: the plan file is bad (names the file and the field).
    """
    if not faults:
        from .simulation import Simulation
        return Simulation(scenario, params, **kw)
    plan = load_fault_plan(faults, seed=seed)
    if plan.params:
        params = params.with_overrides(dict(plan.params), plan.source)
    return _fault_simulation_class()(scenario, params, plan, **kw)


# ====================================================================================== cli
def main(argv: list[str] | None = None) -> int:
    """Command line: trials / missions / soak (see the module doc)."""
    from .parallel import add_executor_arguments

    ap = argparse.ArgumentParser(prog="python -m sitl.fault_campaign", description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="what", required=True)
    t = sub.add_parser("trials")
    t.add_argument("--trials", type=int, default=20)
    t.add_argument("--fault", action="append", choices=list(BOUNDS_S))
    add_executor_arguments(t)
    m = sub.add_parser("missions")
    m.add_argument("--seeds", type=int, default=10)
    m.add_argument("--plan", default=str(FAULT_DIR / "link_loss.yaml"))
    add_executor_arguments(m)
    m.add_argument("--first-seed", type=int, default=0)
    s = sub.add_parser("soak")
    s.add_argument("--hours", type=float, default=1.0)
    s.add_argument("--trace", action="store_true", help="also measure with tracemalloc (2-4x slower)")
    for p in (t, m, s):
        p.add_argument("--json", metavar="FILE")
    args = ap.parse_args(argv)
    if args.what == "trials":
        out = trial_campaign(args.trials, args.fault, jobs=args.jobs, ray=args.ray)
        for k, v in out["summary"].items():
            print(k, json.dumps(v))
        print(markdown_table(out["summary"]))
    elif args.what == "missions":
        out = mission_campaign(args.seeds, args.plan, args.jobs, first_seed=args.first_seed, ray=args.ray)
        print(f"reached the pointed placard {out['reached']} / {out['seeds']} (outcomes {out['outcomes']}; "
              f"arrived anywhere {out['arrived']}), crashes {out['crashes']}")
    else:
        out = soak(args.hours, trace=args.trace)
        print(json.dumps({k: v for k, v in out.items() if k != "samples"}))
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1, default=str))
    return 0


if __name__ == "__main__":
    sys.exit(main())
