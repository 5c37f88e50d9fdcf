"""The mission against the real ArduSub SITL firmware: ``dip3d-vehicle sitl --ardusub PATH``.

The same parties as the built-in simulation (sitl/simulation.py) - the router, the simulated
pilot/GCS (SimPilot), the controller's real VehicleLink and Mission, the stereo renderer - but the
autopilot is the ArduSub SITL binary (sitl/ardusub_sitl.py, loopback only) and the camera is rendered
from the firmware's own simulated vehicle (SIM_STATE: the SITL physics' truth, asked for at 50 Hz).

World frame: the firmware's pose when the hand-over starts (after the dive below) is the scenario's
start pose; SIM_STATE maps into the scenario's world frame from there: the flat-earth displacement
(dlat * R, dlon * R cos(lat0)) rotated by (start yaw - firmware yaw at the reference), depth = start
depth + (firmware depth - its depth at the reference), yaw = firmware yaw + the same rotation. ArduSub measures
depth from its barometer as calibrated at boot, and will not rise above that "surface": started
below the surface it cannot climb (seen: z = 760 gave 0.00 m/s, z = 1000 stalled). So it boots at
the surface and the harness first dives it, as a pilot would, to the start depth (ALT_HOLD, armed
as the ground station, z = 250 until there), then disarms and returns to MANUAL; the simulated pilot
then hands over as in the built-in simulation. The dive costs ~8 s of wall time (arming is refused
for the first ~4 s after boot).

Position source: guided_velocity missions give the firmware's EKF the SITL's simulated external
navigation (``EXTERNAL_NAV_PARAMS``: what a BlueROV2 flying GUIDED has, a DVL or acoustic positioning)
instead of its simulated GPS, with which the EKF drove the vehicle around at up to 0.5 m/s under zero
velocity setpoints (sitl/ardusub_sitl.py). manual_control missions keep the SITL's defaults (ALT_HOLD
needs no position).

Time: the firmware runs its own physics in wall-clock time x ``--speedup``; the loop's SimClock
follows the wall clock x speedup (when the loop falls behind, the clock jumps to catch up, so the
controller's timeouts stay in the firmware's time). Use a speedup below 1 when the machine cannot
render and perceive in real time.

What the firmware received is recorded at the router (every MANUAL_CONTROL / SET_POSITION_TARGET_LOCAL_NED
forwarded to it), and its mode / armed changes come from its HEARTBEAT, for the same safety numbers
as the built-in autopilot.
"""

from __future__ import annotations

import math
import socket
import time
from typing import Any, Mapping

from pymavlink.dialects.v20 import ardupilotmega as m2

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.link import VehicleLink
from dip3d_vehicle.link.state import mode_name

from .ardusub_sitl import DEFAULT_HOME, EXTERNAL_NAV_ARGS, EXTERNAL_NAV_PARAMS, ArdusubSitl, SitlOptions
from .autopilot import Event
from .dynamics import VehicleState
from .scenario_model import Scenario
from .router import Router
from .sim_pilot import SimPilot
from .simulation import Received, Simulation
from .worker_perception import WorkerPerception

__all__ = ["FirmwareVehicle", "FirmwareRouter", "FirmwareSimulation", "make_firmware_simulation"]

EARTH_RADIUS_M = 6378137.0
HARNESS_SYSID, HARNESS_COMPID = 250, 190  # the simulation's own requests (SIM_STATE interval)
SIM_STATE_HZ = 50.0


class FirmwareVehicle:
    """What the simulation reads from the firmware: true state (SIM_STATE), mode, armed, events."""

    def __init__(self, sitl: ArdusubSitl, start: VehicleState, lat0_deg: float, lon0_deg: float,
                 clock: SimClock) -> None:
        self.sitl, self.start, self.clock = sitl, start, clock
        self.lat0, self.lon0 = lat0_deg, lon0_deg
        self.ref: Any = None  # the SIM_STATE that is the scenario's start pose (set by the first one)
        self.state = start
        self.armed = False
        self.mode = 19
        self.system_status = 0
        self.events: list[Event] = []
        self.sim_states = 0
        self.statustexts: list[tuple[float, str]] = []

    @property
    def mode_name(self) -> str:
        """The firmware's mode name."""
        return mode_name(self.mode)

    def step(self) -> None:
        """Nothing to do: the firmware runs by itself; the router feeds ``on_message``."""

    def on_message(self, msg: Any) -> None:
        """Update from one message of the firmware (1/1)."""
        kind, now = msg.get_type(), self.clock.now()
        if kind == "SIM_STATE":
            self.sim_states += 1
            self.state = self._map(msg)
        elif kind == "HEARTBEAT" and msg.type == m2.MAV_TYPE_SUBMARINE:
            armed = bool(msg.base_mode & m2.MAV_MODE_FLAG_SAFETY_ARMED)
            if armed != self.armed:
                self.events.append(Event(now, "armed", armed))
            if msg.custom_mode != self.mode:
                self.events.append(Event(now, "mode", mode_name(msg.custom_mode)))
            self.armed, self.mode, self.system_status = armed, int(msg.custom_mode), int(msg.system_status)
        elif kind == "STATUSTEXT":
            text = msg.text if isinstance(msg.text, str) else msg.text.decode(errors="replace")
            self.statustexts.append((now, text.rstrip("\x00")))
            self.events.append(Event(now, "statustext", text))

    def _map(self, msg: Any) -> VehicleState:
        """SIM_STATE (lat/lon deg, alt m, yaw rad, vn/ve/vd m/s, zgyro) -> the scenario's world frame."""
        if self.ref is None:
            self.ref = msg
        ref, st = self.ref, self.start
        dn = math.radians((msg.lat_int - ref.lat_int) * 1e-7) * EARTH_RADIUS_M
        de = math.radians((msg.lon_int - ref.lon_int) * 1e-7) * EARTH_RADIUS_M * math.cos(math.radians(self.lat0))
        turn = st.yaw_rad - float(ref.yaw)
        ct, sn = math.cos(turn), math.sin(turn)
        north, east = st.north_m + dn * ct - de * sn, st.east_m + dn * sn + de * ct
        depth = st.depth_m + (float(ref.alt) - float(msg.alt))
        yaw = math.remainder(float(msg.yaw) + turn, math.tau)
        c, s = math.cos(float(msg.yaw)), math.sin(float(msg.yaw))
        u = msg.vn * c + msg.ve * s
        v = -msg.vn * s + msg.ve * c
        return VehicleState(north_m=north, east_m=east, depth_m=depth, yaw_rad=yaw, u_m_s=u, v_m_s=v,
                            w_m_s=float(msg.vd), r_rad_s=float(msg.zgyro))

    def close(self) -> None:
        """Stop the firmware process."""
        self.sitl.stop()


class FirmwareRouter(Router):
    """The router with the firmware's connected socket as its autopilot side, tapping both directions."""

    def __init__(self, sock: socket.socket, vehicle: FirmwareVehicle, received: list[Received]) -> None:
        self._serve(sock)
        self.vehicle, self.received = vehicle, received
        self._tap = m2.MAVLink(None)
        self._tap.robust_parsing = True
        self._harness = m2.MAVLink(None, srcSystem=HARNESS_SYSID, srcComponent=HARNESS_COMPID)
        self._joystick = m2.MAVLink(None, srcSystem=255, srcComponent=190)

    def pilot_neutral_sticks(self) -> None:
        """One neutral MANUAL_CONTROL from the pilot's joystick (255/190), straight to the firmware."""
        self.autopilot.write(m2.MAVLink_manual_control_message(1, 0, 0, 500, 0, 0).pack(self._joystick))

    def request_sim_state(self, hz: float = SIM_STATE_HZ) -> None:
        """Ask the firmware for SIM_STATE (the simulator's truth) at ``hz``, as the harness."""
        msg = m2.MAVLink_command_long_message(1, 1, m2.MAV_CMD_SET_MESSAGE_INTERVAL, 0,
                                              float(m2.MAVLINK_MSG_ID_SIM_STATE), 1e6 / hz, 0, 0, 0, 0, 0)
        self.autopilot.write(msg.pack(self._harness))

    def step(self) -> None:
        """Accept clients, forward everything, and tap what passes."""
        if not self.autopilot.alive:
            raise ConnectionError("the ArduSub SITL closed its connection (did the process exit?)")
        super().step()

    def tap_autopilot(self, buf: bytes) -> None:
        """The firmware's own messages (1/1) update the vehicle's state."""
        for msg in self._parse(buf):
            if msg.get_srcSystem() == 1 and msg.get_srcComponent() == 1:
                self.vehicle.on_message(msg)

    def tap_client(self, buf: bytes) -> None:
        """What the clients send the firmware is recorded (``Received``)."""
        self._record(buf)

    def _parse(self, buf: bytes) -> list[Any]:
        return [m for m in (self._tap.parse_buffer(buf) or []) if m.get_type() != "BAD_DATA"]

    def _record(self, buf: bytes) -> None:
        """Record a motion-capable message on its way to the firmware."""
        for msg in self._parse(buf):
            kind, now = msg.get_type(), self.vehicle.clock.now()
            if kind == "MANUAL_CONTROL":
                motion = not (msg.x == 0 and msg.y == 0 and msg.r == 0 and msg.z == 500)
                self.received.append(Received(now, kind, motion, (msg.x, msg.y, msg.z, msg.r)))
            elif kind == "SET_POSITION_TARGET_LOCAL_NED":
                motion = any(abs(v) > 0 for v in (msg.vx, msg.vy, msg.vz, msg.yaw_rate))
                self.received.append(Received(now, kind, motion, (msg.vx, msg.vy, msg.vz, msg.yaw_rate)))
            elif msg.get_srcSystem() == 255 and kind in ("HEARTBEAT",):
                pass


class FirmwareSimulation(WorkerPerception, Simulation):
    """One mission against the ArduSub SITL binary (same outcome, story, plots and log as Simulation).

    The world follows the wall clock, so perception runs in the project's PerceptionWorker thread
    (``sitl/worker_perception.py``): real latency instead of the lockstep's modelled one.

    Args:
        scenario: a resolved Scenario.
        params: effective parameters (through ``sim_params``).
        binary: the ardusub executable (checked by ``resolve_binary``).
        speedup: the firmware's ``--speedup`` (simulated seconds per wall second).
        instance: ``-I`` (distinct per concurrent run).
        fault: a failure to inject, or None.
        external_nav: the EKF's position from the SITL's external navigation instead of its GPS
            (None: for guided_velocity only).
        log: the run recorder (record/recorder.py) or None.
    """

    def __init__(self, scenario: Scenario, params: Mapping[str, Any], binary, speedup: float = 1.0,
                 instance: int = 0, fault=None, stop_when_done: bool = True, log: Any = None,
                 external_nav: bool | None = None) -> None:
        self.scenario, self.params, self.fault, self.speed = scenario, params, fault, speedup
        self.stop_when_done, self.log = stop_when_done, log
        self.clock = SimClock()
        if hasattr(log, "set_clock"):  # the run recorder: its timeline is the simulated one
            log.set_clock(self.clock)
        v = scenario.initial_vehicle_pose
        start = VehicleState(north_m=v.north_m, east_m=v.east_m, depth_m=v.depth_m, yaw_rad=v.yaw_rad)
        lat0, lon0 = DEFAULT_HOME[0], DEFAULT_HOME[1]
        home = (lat0, lon0, 0.0, math.degrees(v.yaw_rad) % 360.0)
        guided = params["link.output_mode"] == "guided_velocity"
        nav = guided if external_nav is None else external_nav
        self.sitl = ArdusubSitl(SitlOptions(binary, instance=instance, speedup=speedup, home=home,
                                            extra_params=EXTERNAL_NAV_PARAMS if nav else (),
                                            extra_args=EXTERNAL_NAV_ARGS if nav else ()))
        self.received: list[Received] = []
        sock = self.sitl.start()
        try:
            self.dive_s = pre_dive(sock, v.depth_m, timeout_s=120.0 if guided else 60.0, guided=guided)
            self.ap = FirmwareVehicle(self.sitl, start, lat0, lon0, self.clock)
            self.router = FirmwareRouter(sock, self.ap, self.received)
            self.router.request_sim_state()  # (again: the dive asked too)
            self.router.step()
            self.link = VehicleLink(params.with_overrides({"link.url": self.router.address}, "sitl router"),
                                    self.clock, recorder=log if hasattr(log, "mavlink_sent") else None)
            self.link.open()
            self.pilot = SimPilot(self.router.address, self.clock, self.link.config.engage_mode,
                                  float(params["sitl.gcs_arm_at_s"]))
            self.router.step()
        except BaseException:
            self.sitl.stop()
            raise
        self._build_controller(scenario, params)
        self._wall0: float | None = None
        self._next_sticks_s = 0.0
        self._controller_had_sticks = False

    def _step_dt(self, dt: float) -> float:
        """Follow the wall clock x speedup: at least ``dt``, more when the loop fell behind.

        Until the controller first engages, the pilot's joystick streams neutral sticks (10 Hz), as
        QGroundControl does: the firmware's pilot-input failsafe ("Lost manual control", disarm) acts
        3 s after the last MANUAL_CONTROL, and the dive's ended before the hand-over.
        """
        now = self.clock.now()
        if not self._controller_had_sticks:
            self._controller_had_sticks = self.link.engaged
            if not self._controller_had_sticks and now >= self._next_sticks_s:
                self.router.pilot_neutral_sticks()
                self._next_sticks_s = now + 0.1
        if self._wall0 is None:
            self._wall0 = time.perf_counter() - self.clock.now() / self.speed
        behind = (time.perf_counter() - self._wall0) * self.speed - self.clock.now()
        return max(dt, behind)

    def close(self) -> None:
        """Stop the firmware first (on every path), then release sockets and threads."""
        try:
            self.sitl.stop()
        finally:
            super().close()


def make_firmware_simulation(scenario: Scenario, params: Mapping[str, Any], binary: str, fault=None,
                             log: Any = None) -> FirmwareSimulation:
    """For ``dip3d-vehicle sitl --ardusub PATH``: check the binary (one clear FirmwareError), then start it."""
    from .ardusub_sitl import resolve_binary
    path = resolve_binary(binary)
    return FirmwareSimulation(scenario, params, path, speedup=float(params["sitl.ardusub_speedup"]),
                              instance=int(params["sitl.ardusub_instance"]), fault=fault, log=log)


def pre_dive(sock: socket.socket, depth_m: float, timeout_s: float = 60.0, guided: bool = False) -> float:
    """As the pilot (255/190): arm in ALT_HOLD, dive to ``depth_m`` (SIM_STATE), hold, disarm, MANUAL.

    With ``guided``, instead of disarming it holds the depth in ALT_HOLD and asks for GUIDED every
    second until the firmware accepts it (the 4.7 SITL: ~41 s after boot when its EKF uses the simulated
    GPS; right after the dive with external navigation),
    and leaves the vehicle armed in GUIDED: disarmed in MANUAL meanwhile, it would sink ~1 m. Entering
    GUIDED from ALT_HOLD the firmware's depth controller first sinks the vehicle 0.3-1.5 m (seen: 0.9 ->
    1.58 -> 1.23 m; in one mission 2.5 m), so it then brings it back as the pilot would, with GUIDED
    vertical speed setpoints (0.8 /s x the depth error, at most 0.3 m/s) until it is within 0.05 m of
    ``depth_m`` and still (|vd| < 0.03 m/s) for 1 s.

    Returns:
        The wall time it took, s.

    Raises:
        FirmwareError: not there within ``timeout_s``.
    """
    from dip3d_vehicle.errors import FirmwareError
    from .firmware_mav import MavSocket
    m = MavSocket(sock)
    t0 = time.monotonic()
    m.command(m2.MAV_CMD_SET_MESSAGE_INTERVAL, float(m2.MAVLINK_MSG_ID_SIM_STATE), 1e6 / SIM_STATE_HZ)
    state = {"armed": False, "mode": 19, "depth": 0.0, "vd": 0.0}
    phase, next_hb, next_mc, next_try, hold_until = "arm", 0.0, 0.0, 0.0, 0.0
    still_since: float | None = None
    while phase != "done":
        now = time.monotonic()
        if now - t0 > timeout_s:
            raise FirmwareError(f"ArduSub SITL: could not dive to {depth_m:g} m in {timeout_s:g} s "
                                f"(phase {phase}, depth {state['depth']:.2f} m)")
        for msg in m.pump():
            if msg.get_type() == "HEARTBEAT" and msg.get_srcSystem() == 1 and msg.type == m2.MAV_TYPE_SUBMARINE:
                state["armed"], state["mode"] = bool(msg.base_mode & 128), msg.custom_mode
            elif msg.get_type() == "SIM_STATE":
                state["depth"], state["vd"] = -float(msg.alt), float(msg.vd)
        if now >= next_hb:
            m.heartbeat()
            next_hb = now + 1.0
        z = 250 if phase == "dive" else 500
        if now >= next_mc:
            m.send(m2.MAVLink_manual_control_message(1, 0, 0, z, 0, 0))
            if phase == "settle":
                vz = max(-0.3, min(0.3, 0.8 * (depth_m - state["depth"])))
                m.send(m2.MAVLink_set_position_target_local_ned_message(
                    0, 1, 1, m2.MAV_FRAME_BODY_NED, 1479, 0, 0, 0, 0, 0, vz, 0, 0, 0, 0, 0))
            next_mc = now + 0.05
        if phase == "arm":
            if state["armed"] and state["mode"] == 2:
                phase = "dive"
            elif now >= next_try:
                m.command(m2.MAV_CMD_DO_SET_MODE, 1.0, 2.0)
                m.command(m2.MAV_CMD_COMPONENT_ARM_DISARM, 1.0)
                next_try = now + 0.5
        elif phase == "dive" and state["depth"] >= depth_m - 0.1:
            phase, hold_until = "hold", now + 1.0
        elif phase == "hold" and now >= hold_until and not guided:
            m.command(m2.MAV_CMD_COMPONENT_ARM_DISARM, 0.0)
            m.command(m2.MAV_CMD_DO_SET_MODE, 1.0, 19.0)
            phase = "done"
        elif phase == "hold" and now >= hold_until:
            phase, next_try = "guided", now
        elif phase == "guided":
            if state["mode"] == 4 and state["armed"]:
                phase = "settle"
            elif now >= next_try:
                m.command(m2.MAV_CMD_DO_SET_MODE, 1.0, 4.0)
                next_try = now + 1.0
        elif phase == "settle":
            if abs(depth_m - state["depth"]) < 0.05 and abs(state["vd"]) < 0.03:
                still_since = now if still_since is None else still_since
                phase = "done" if now - still_since >= 1.0 else phase
            else:
                still_since = None
        time.sleep(0.005)
    return time.monotonic() - t0
