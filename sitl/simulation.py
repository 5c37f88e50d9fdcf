"""The whole mission closed-loop in simulated time: world, autopilot, router, pilot, controller.

Parties, all on one SimClock, stepped in lockstep every ``sitl.step_s``:

- ``Autopilot`` (sitl/autopilot.py): the ArduSub-like vehicle on a real loopback TCP socket.
- ``Router`` (sitl/router.py): forwards every MAVLink message between the autopilot and its clients, as BlueOS's
  mavlink-router does on a real vehicle (the autopilot itself routes nothing).
- ``SimPilot`` (sitl/sim_pilot.py): the ground station (system 255, a small pymavlink client on the router): 1 Hz GCS
  HEARTBEAT; at ``sitl.gcs_arm_at_s`` it arms, selects the engage mode (ALT_HOLD for
  manual_control, GUIDED for guided_velocity) and enables the controller with MAV_CMD_USER_1, as
  a pilot would; it can also take the vehicle back (mode change, disarm, disable) for the safety
  trials.
- the controller: ``VehicleLink`` (a client on the router) + the Mission (``behaviours.loop``).
- the camera: ``StereoRenderer`` frames at ``sitl.camera_rate_hz`` from the autopilot's TRUE
  vehicle state; perception runs synchronously and its result is delivered
  ``sitl.perception_latency_s`` later (deterministic).

Everything the autopilot receives is recorded on its side (``Simulation.received``: every
MANUAL_CONTROL / SET_POSITION_TARGET_LOCAL_NED with whether it asked for motion), by wrapping its
message handlers on the instance. Deterministic per (scenario, seed); runs as fast as it can, or
at ``speed`` x real time.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Mapping

from behaviours.loop import Controller, FrameProcessor, build_mission, observation_summary
from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.config import Params, load_params
from dip3d_vehicle.link import VehicleLink
from dip3d_vehicle.perception.pipeline import Perception
from dip3d_vehicle.perception.pointing_arm import AUTO

from .autopilot import Autopilot
from .clearance import closest_approach_m, closest_diver_m, closest_other_m
from .dynamics import VehicleState
from .pose_source import SimPose, pose_backend_for
from .render import StereoRenderer
from .router import Router
from .scenario import Scenario, load_scenario
from .sim_pilot import SimPilot
from .outcome import Sightings, mission_outcome, nearest_placard

__all__ = ["Router", "SimPilot", "Fault", "Received", "SimResult", "Simulation", "sim_params", "run_mission"]



# --------------------------------------------------------------------------------------- faults
@dataclass(frozen=True)
class Fault:
    """A failure injected during the run, ``after_s`` after the mission first enters ``state``.

    kinds: ``autopilot_silent`` (the autopilot's messages stop reaching the controller),
    ``mode_change`` (the pilot selects MANUAL), ``disarm`` (the pilot disarms), ``disable`` (the
    operator withdraws the enable), ``perception_stall`` (perception stops delivering results).
    """

    kind: str
    after_s: float = 1.0
    state: str = "servo"
    run_after_s: float = 4.0


@dataclass(frozen=True)
class Received:
    """A motion-capable message as the autopilot received it."""

    t_s: float
    kind: str
    motion: bool
    values: tuple


@dataclass
class SimResult:
    """The outcome of one simulated mission (``to_json`` gives the contract object)."""

    scenario: str
    seed: int
    diver_position: str
    target_id: int
    chosen_id: int | None
    arrived: bool
    reached: bool
    time_to_arrive_s: float | None
    final_range_m: float | None
    final_range_error_m: float | None
    final_pixel_error_px: float | None
    range_at_arrival_m: float | None
    range_error_at_arrival_m: float | None
    sim_time_s: float
    wall_time_s: float
    states: list[dict]
    story: list[str]
    outcome: str = ""
    outcome_reason: str = ""
    fault: dict | None = None
    safety: dict = field(default_factory=dict)
    counters: dict = field(default_factory=dict)
    pose_source: dict = field(default_factory=dict)
    decisions: list[dict] = field(default_factory=list)
    closest_m: dict = field(default_factory=dict)
    closest_diver_m: float | None = None
    held_short_m: float | None = None

    def to_json(self) -> dict:
        """Return the JSON object of ``dip3d-vehicle sitl --json`` (``outcome``: see sitl/outcome.py)."""
        out = {k: getattr(self, k) for k in (
            "outcome", "outcome_reason",
            "arrived", "target_id", "chosen_id", "final_range_m", "sim_time_s", "states", "scenario",
            "seed", "diver_position", "reached", "time_to_arrive_s", "final_range_error_m",
            "final_pixel_error_px", "range_at_arrival_m", "range_error_at_arrival_m", "wall_time_s", "counters")}
        out["pose_source"] = self.pose_source
        out["decisions"] = self.decisions
        out["closest_m"] = {str(k): v for k, v in self.closest_m.items()}
        out["closest_other_m"] = closest_other_m(self.closest_m, self.target_id)
        out["closest_diver_m"] = self.closest_diver_m
        out["held_short_m"] = self.held_short_m
        if self.fault is not None:
            out["fault"], out["safety"] = self.fault, self.safety
        return out


def sim_params(params: Params, scenario: Scenario, **overrides: Any) -> Params:
    """Return the parameters for a simulated run: the scenario's camera mount for the servo, the
    simulator's SIFT scale and, with the pose from BlazePose, ``pose.arm: auto`` wherever the user left
    the default, plus ``overrides``.

    ``auto`` because the simulated diver points with either hand and holds nothing in the other, and is
    often seen from behind, where BlazePose labels the arms as if the diver faced the camera: with
    ``right`` it reads the hanging arm (``far_placards``: no decision in 10 of 10 runs, issue 14).
    """
    cam = scenario.camera
    source = overrides.get("sitl.pose_source", params["sitl.pose_source"])
    derived = {"servo.mount_forward_m": cam.mount_frd_m[0], "servo.mount_right_m": cam.mount_frd_m[1],
               "servo.mount_down_m": cam.mount_frd_m[2], "servo.mount_pitch_rad": cam.mount_pitch_rad,
               "candidates.image_scale": params["sitl.image_scale"], "pose.backend": pose_backend_for(source)}
    if source == "blazepose":
        derived["pose.arm"] = AUTO
    over = {k: v for k, v in derived.items() if params.source(k) == "schema default" or k == "pose.backend"}
    over.update(overrides)
    return params.with_overrides(over, "sitl")


class Simulation:
    """One closed-loop mission run.

    Args:
        scenario: a resolved Scenario.
        params: effective parameters (already through ``sim_params``).
        fault: a failure to inject, or None.
        speed: simulated seconds per wall second (None = as fast as possible).
        stop_when_done: end the run ``sitl.after_done_s`` after the mission reaches ``done``.
    """

    def __init__(self, scenario: Scenario, params: Mapping[str, Any], fault: Fault | None = None,
                 speed: float | None = None, stop_when_done: bool = True, log: Any = None) -> None:
        self.scenario, self.params, self.fault, self.speed = scenario, params, fault, speed
        self.stop_when_done, self.log = stop_when_done, log
        self.clock = SimClock()
        if hasattr(log, "set_clock"):  # the run recorder (record/recorder.py): its timeline is the simulated one
            log.set_clock(self.clock)
        v = scenario.initial_vehicle_pose
        guided = params["link.output_mode"] == "guided_velocity"
        self.ap = Autopilot(params, self.clock, listen=["tcp:127.0.0.1:0"], has_position=guided or None,
                            initial_state=VehicleState(north_m=v.north_m, east_m=v.east_m, depth_m=v.depth_m,
                                                       yaw_rad=v.yaw_rad))
        self.received: list[Received] = []
        self._wrap_autopilot()
        self.router = Router(self.ap.addresses[0])
        self.router.step()
        self.link = VehicleLink(params.with_overrides({"link.url": self.router.address}, "sitl router"), self.clock,
                                recorder=log if hasattr(log, "mavlink_sent") else None)
        self.link.open()
        self.pilot = SimPilot(self.router.address, self.clock, self.link.config.engage_mode,
                              float(params["sitl.gcs_arm_at_s"]))
        self.router.step()
        self._build_controller(scenario, params)

    def _build_controller(self, scenario: Scenario, params: Mapping[str, Any]) -> None:
        """Build the camera, perception, mission and controller over ``self.link``, and the run's records."""
        self.rig = scenario.rig(params["calib.alpha"])
        self.renderer = StereoRenderer(scenario, params)
        self.pose = SimPose(params)
        self.perception = Perception(self.rig, params, self.pose, live=True)
        self.processor = FrameProcessor(self.perception, lambda f: self.pose.provide(f.meta["keypoints"]))
        self.mission = build_mission(params, self.rig, scenario.camera.image_size, perception=self.perception)
        self.controller = Controller(self.link, self.mission, self.clock)
        self.trajectory: list[tuple] = []
        self.servo_log: list[tuple] = []
        self.range_at_arrival: float | None = None
        self.held_short_m: float | None = None  # how much longer than the stand-off the arrival held off, m
        self.last_frame = None
        self.last_meta: dict = {}
        self.sightings = Sightings(self.rig.R1)
        self.fault_at_s: float | None = None
        self.ticks: list[tuple[float, str, bool, bool]] = []
        self.on_step: Any = None  # called with the sim time after every step (the live story printer)

    # -- autopilot-side counters ----------------------------------------------------------
    def _wrap_autopilot(self) -> None:
        ap = self.ap
        orig_mc, orig_sp = ap._on_manual_control, ap._on_set_position_target_local_ned

        def on_manual_control(link, msg, now):
            motion = not (msg.x == 0 and msg.y == 0 and msg.r == 0 and msg.z == 500)
            self.received.append(Received(now, "MANUAL_CONTROL", motion, (msg.x, msg.y, msg.z, msg.r)))
            orig_mc(link, msg, now)

        def on_setpoint(link, msg, now):
            motion = any(abs(v) > 0 for v in (msg.vx, msg.vy, msg.vz, msg.yaw_rate))
            self.received.append(Received(now, "SET_POSITION_TARGET_LOCAL_NED", motion,
                                          (msg.vx, msg.vy, msg.vz, msg.yaw_rate)))
            orig_sp(link, msg, now)

        ap._on_manual_control = on_manual_control
        ap._on_set_position_target_local_ned = on_setpoint

    # -- the loop ---------------------------------------------------------------------------
    def run(self) -> SimResult:
        """Run until done (+ ``sitl.after_done_s``), the fault's observation time, or ``sitl.max_sim_time_s``."""
        p = self.params
        dt = float(p["sitl.step_s"])
        period = 1.0 / float(p["sitl.camera_rate_hz"])
        latency = float(p["sitl.perception_latency_s"])
        max_t = float(p["sitl.max_sim_time_s"])
        next_frame, pending = period, []
        done_at: float | None = None
        wall0 = time.perf_counter()
        try:
            while self.clock.now() < max_t:
                now = self.clock.advance(self._step_dt(dt))
                self.ap.step()
                self.router.step()
                self.pilot.step()
                self._maybe_fault(now)
                if now + 1e-9 >= next_frame:
                    next_frame += period
                    obs = self._capture(now)
                    if obs is not None:
                        pending.append((now + latency, obs, self.last_frame.meta))
                observation, obs_meta = self._deliver(now, pending)
                if observation is not None:
                    self.sightings.frame(observation.stamp_s, obs_meta)
                rec = self.controller.tick(observation)
                self.sightings.note(self.mission.bb.tracker.last, self.last_meta)
                self.router.step()
                self.ticks.append((now, rec.state, rec.engaged, rec.command is not None and not rec.command.is_neutral()))
                self._record(now, rec, observation, obs_meta)
                if self.on_step is not None:
                    self.on_step(now)
                if self.mission.state == "done" and done_at is None:
                    done_at = now
                    self.range_at_arrival = self._true_range()
                    self.held_short_m = self.mission.bb.held_short_m
                if self.stop_when_done and done_at is not None and now - done_at >= float(p["sitl.after_done_s"]):
                    break
                if self.fault_at_s is not None and now - self.fault_at_s >= self.fault.run_after_s:
                    break
                if self.speed:
                    lag = now / self.speed - (time.perf_counter() - wall0)
                    if lag > 0:
                        time.sleep(lag)
        finally:
            self.link.close()
            self.router.step()
            self.ap.step()
        return self._with_outcome(self._result(time.perf_counter() - wall0))

    def _step_dt(self, dt: float) -> float:
        """The clock's advance this step (lockstep: ``dt``; the firmware world follows the wall clock)."""
        return dt

    def _deliver(self, now: float, pending: list) -> tuple[Any, dict | None]:
        """Return this step's (observation, frame meta): the newest whose modelled latency has passed."""
        observation, obs_meta = None, None
        while pending and pending[0][0] <= now + 1e-9:
            _, observation, obs_meta = pending.pop(0)
        return observation, obs_meta

    def _render_now(self, now: float):
        """Render the frame the camera sees now (kept and logged); None while perception is stalled."""
        s = self.ap.state
        frame = self.renderer.render(s.north_m, s.east_m, s.depth_m, s.yaw_rad, now)
        self.last_frame, self.last_meta = frame, frame.meta
        if self.log is not None:
            self.log.images(frame.index, frame.left, frame.right)
        if self.fault_at_s is not None and self.fault.kind == "perception_stall":
            return None
        return frame

    def _capture(self, now: float):
        """Render the frame the camera sees now and process it (None while perception is stalled)."""
        frame = self._render_now(now)
        if frame is None:
            return None
        need = self.mission.needs
        roi = self.mission.track_roi(self.rig, self.scenario.camera.image_size) if need == "track" else None
        return self.processor.process(frame, need, now, roi)

    def _maybe_fault(self, now: float) -> None:
        f = self.fault
        if f is None or self.fault_at_s is not None:
            return
        entered = next((t for t, s in self.mission.history if s == f.state), None)
        if entered is None or now < entered + f.after_s:
            return
        self.fault_at_s = now
        if f.kind == "autopilot_silent":
            self.router.mute_autopilot = True
        elif f.kind == "mode_change":
            self.pilot.set_mode("MANUAL" if self.link.config.engage_mode != "MANUAL" else "STABILIZE")
        elif f.kind == "disarm":
            self.pilot.disarm()
        elif f.kind == "disable":
            self.pilot.disable_controller()
        self.mission.bb.say(f"FAULT injected: {f.kind}")

    def _record(self, now: float, rec, observation, meta: dict | None) -> None:
        s = self.ap.state
        if not self.trajectory or now - self.trajectory[-1][0] >= 0.1 - 1e-9:
            self.trajectory.append((now, s.north_m, s.east_m, s.depth_m, s.yaw_rad, s.r_rad_s, rec.state))
            e = self.mission.bb.errors
            self.servo_log.append((round(now, 2), rec.state, None if e is None else round(e.pixel_px),
                                   None if e is None or e.range_m is None else round(e.range_m, 3),
                                   None if rec.command is None else tuple(round(v, 2) for v in (
                                       rec.command.surge_m_s, rec.command.heave_m_s, rec.command.yaw_rate_rad_s)),
                                   round(s.u_m_s, 2)))
            if self.log is not None:
                c = rec.command
                self.log.telemetry({"t_s": now, "north_m": s.north_m, "east_m": s.east_m, "depth_m": s.depth_m,
                                    "yaw_rad": s.yaw_rad, "state": rec.state, "engaged": rec.engaged,
                                    "command": None if c is None else [c.surge_m_s, c.sway_m_s, c.heave_m_s,
                                                                        c.yaw_rate_rad_s],
                                    "mode": self.ap.mode_name, "armed": self.ap.armed})
        if observation is not None and self.log is not None:
            rec_obs = observation_summary(observation)
            target = None
            r = observation.result
            if r is not None and r.target_rect_px is not None:
                target = {"left_px": [float(v) for v in self.rig.to_original(r.target_rect_px, "left")[0]]}
            rec_obs.update({"t_s": now, "state": rec.state, "status": r.status if r is not None else "tracking",
                            "target": target, "keypoints": (meta or {}).get("keypoints"),
                            "tracked_left_px": None if self.mission.bb.target is None else
                            [float(v) for v in self.mission.bb.target.left_px]})
            self.log.frame(rec_obs)
        if hasattr(self.log, "tick"):  # the run recorder: states, servo, story, overlays, live view
            self.log.tick(now, rec, self.mission, observation, self.link)

    # -- outcome ----------------------------------------------------------------------------
    def chosen_placard(self) -> int | None:
        """Return the id of the placard the tracker last saw as the target (``Sightings``; true positions), or None.

        Before any sighting, the placard nearest the tracker's position now."""
        bb = self.mission.bb
        if bb.target is None or not self.last_meta:
            return None
        if self.sightings.seen:
            return self.sightings.placard
        if bb.tracker.xyz_m is None:
            return None
        return nearest_placard(bb.tracker.xyz_m, self.last_meta["placards"], self.rig.R1)

    def _true_range(self) -> float | None:
        """Return the true range (left camera to placard centre) of the tracked placard now."""
        chosen = self.chosen_placard()
        if chosen is None or not self.last_meta:
            return None
        return float(self.last_meta["placards"][chosen]["range_m"])

    def _with_outcome(self, result: SimResult) -> SimResult:
        """Set the result's one outcome word and its reason (sitl/outcome.py); ``reached`` is that word."""
        outcome = mission_outcome(arrived=result.arrived, chosen_id=result.chosen_id, target_id=result.target_id,
                                  range_error_at_arrival_m=result.range_error_at_arrival_m,
                                  tolerance_m=self.mission.bb.config.arrive_tolerance_m,
                                  states=[s for _, s in self.mission.history], sim_time_s=result.sim_time_s)
        result.outcome, result.outcome_reason = outcome.word, outcome.reason
        result.reached = outcome.word == "reached"
        return result

    def _result(self, wall_s: float) -> SimResult:
        sc, bb = self.scenario, self.mission.bb
        meta = self.last_meta
        target = sc.target_id
        chosen = self.chosen_placard()
        done_t = next((t for t, s in self.mission.history if s == "done"), None)
        final_range = err_m = None
        standoff_m = bb.config.standoff_m + (self.held_short_m or 0.0)  # the stand-off in force at arrival
        if meta:
            info = meta["placards"][chosen if chosen is not None else target]
            final_range = float(info["range_m"])
            err_m = final_range - standoff_m
        px = bb.errors.pixel_px if bb.errors is not None else None
        at_arrival = self.range_at_arrival
        err_arrival = None if at_arrival is None else at_arrival - standoff_m
        reached = bool(bb.arrived and chosen == target and err_arrival is not None
                       and abs(err_arrival) <= bb.config.arrive_tolerance_m)
        story = sorted(self.link.events + bb.story + [f"t={t:.2f} pilot heard {s}" for t, s in self.pilot.statustexts],
                       key=_story_time)
        return SimResult(
            scenario=sc.name, seed=sc.seed, diver_position=sc.diver.position_name, target_id=target,
            chosen_id=chosen, arrived=bb.arrived, reached=reached, time_to_arrive_s=done_t,
            final_range_m=_round(final_range), final_range_error_m=_round(err_m), final_pixel_error_px=_round(px, 1),
            range_at_arrival_m=_round(at_arrival), range_error_at_arrival_m=_round(err_arrival),
            sim_time_s=round(self.clock.now(), 3), wall_time_s=round(wall_s, 2),
            states=[{"t_s": round(t, 3), "state": s} for t, s in self.mission.history], story=story,
            fault=None if self.fault is None else {"kind": self.fault.kind, "at_s": self.fault_at_s},
            safety=self.safety() if self.fault is not None else {},
            counters={"frames": dict(self.processor.processed), "ticks": len(self.ticks),
                      "statustext_sent": self.controller.sent["statustext"],
                      "received_commands": len(self.received),
                      "received_motion": sum(r.motion for r in self.received)},
            pose_source={k: v for k, v in self.pose.counts.items() if v},
            decisions=list(bb.decided),
            closest_m=closest_approach_m([row[1:4] for row in self.trajectory], sc.placards),
            closest_diver_m=closest_diver_m(self.trajectory, sc.diver, sc.placard(target).centre_ned_m),
            held_short_m=_round(self.held_short_m))

    def safety(self) -> dict:
        """Return the safety numbers of a fault run (times relative to the fault / its detection)."""
        f, t0 = self.fault, self.fault_at_s
        out: dict = {"fault_at_s": t0}
        if t0 is None:
            return out
        motion_after = [r for r in self.received if r.t_s > t0 and r.motion]
        out["motion_commands_after_fault"] = len(motion_after)
        out["last_motion_after_fault_s"] = round(max((r.t_s for r in motion_after), default=t0) - t0, 3)
        if f.kind in ("mode_change", "disarm"):
            changed = next((e.time_s for e in self.ap.events if e.time_s >= t0 and e.kind in ("mode", "armed")), None)
            out["autopilot_changed_at_s"] = changed
            told = _first_event(self.link.events, ("autopilot mode", "autopilot disarmed"), t0)
            out["controller_told_at_s"] = told
            if told is not None:
                out["motion_commands_after_told"] = sum(1 for r in motion_after if r.t_s > told + 1e-6)
        if f.kind in ("disable", "perception_stall", "autopilot_silent", "mode_change", "disarm"):
            dis = _first_event(self.link.events, ("disengaged",), t0)
            out["disengaged_at_s"] = dis
        if self.link.config.output_mode == "guided_velocity":
            dis = out.get("disengaged_at_s")
            after = [row for row in self.trajectory if dis is not None and row[0] >= dis + 1.0]
            out["max_abs_yaw_rate_1s_after_disengage"] = round(max((abs(r[5]) for r in after), default=math.nan), 4)
            zero_cmd = next((r.t_s for r in self.received if dis is not None and r.t_s >= dis and not r.motion
                             and r.kind == "SET_POSITION_TARGET_LOCAL_NED"), None)
            out["zero_yaw_rate_sent_after_s"] = None if zero_cmd is None else round(zero_cmd - dis, 3)
        if f.kind == "perception_stall":
            stale_from = None
            last_obs = self.controller.last_observation
            if last_obs is not None:
                stale_from = last_obs.stamp_s + min(self.mission.bb.config.perception_stale_s,
                                                    self.link.config.perception_timeout_s)
            out["stale_from_s"] = stale_from
            out["motion_commands_while_stale"] = sum(1 for r in motion_after if stale_from is not None
                                                     and r.t_s > stale_from + 1e-6)
        return out

    def close(self) -> None:
        """Release sockets and threads."""
        self.pilot.close()
        self.router.close()
        self.ap.close()
        self.renderer.close()


def _story_time(line: str) -> float:
    try:
        return float(line.split()[0][2:])
    except (ValueError, IndexError):
        return math.inf


def _first_event(events: list[str], needles: tuple[str, ...], after_s: float) -> float | None:
    for line in events:
        t = _story_time(line)
        if t >= after_s and any(n in line for n in needles):
            return t
    return None


def _round(v: float | None, nd: int = 3) -> float | None:
    return None if v is None or not math.isfinite(v) else round(float(v), nd)


def run_mission(scenario: str = "paper_pool", seed: int = 0, params: Params | None = None,
                fault: Fault | None = None, speed: float | None = None, log: Any = None,
                **overrides: Any) -> tuple[SimResult, Simulation]:
    """Load a scenario, run one mission, close the sockets; return (result, simulation)."""
    base = params if params is not None else load_params()
    sc = load_scenario(scenario, seed)
    sim = Simulation(sc, sim_params(base, sc, **overrides), fault=fault, speed=speed, log=log)
    try:
        result = sim.run()
    finally:
        sim.close()
    return result, sim
