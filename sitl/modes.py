"""ArduSub flight modes as the simulator runs them: pilot-input scaling and per-mode control laws.

What each mode does with its input (ArduSub 4.5, calibrated against the measured SITL responses in
``/work/shared/reference/ardusub_sitl_response.md``):

- forward / lateral sticks are open-loop thrust in every pilot mode (same speed in STABILIZE and
  ALT_HOLD);
- yaw stick is a rate command (STABILIZE, ALT_HOLD), open-loop torque in MANUAL;
- throttle is a climb-rate command with depth hold at neutral in ALT_HOLD, open-loop heave thrust in
  STABILIZE and MANUAL;
- GUIDED follows SET_POSITION_TARGET_LOCAL_NED (velocity loop without feed-forward, which is why the
  real SITL reached only ~0.36 m/s for 0.5 m/s asked), holds depth unless told otherwise, and keeps
  the last yaw / yaw-rate target forever.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

from .dynamics import Forces, VehicleParams, VehicleState, wrap_pi

__all__ = [
    "MODES", "MODE_NUMBERS", "POSITION_MODES", "PilotInput", "GuidedTarget", "ControlGains",
    "Controller", "joystick_to_pwm", "pilot_yaw_rate_rad_s", "pilot_climb_rate_m_s",
    "GUIDED_HEADING_BAND_RAD", "AUTO_YAW_SLEW_RAD_S",
]

#: HEARTBEAT.custom_mode numbers of ArduSub.
MODES: dict[int, str] = {0: "STABILIZE", 1: "ACRO", 2: "ALT_HOLD", 3: "AUTO", 4: "GUIDED", 7: "CIRCLE",
                         9: "SURFACE", 16: "POSHOLD", 19: "MANUAL", 20: "MOTOR_DETECT", 21: "SURFTRAK"}
MODE_NUMBERS: dict[str, int] = {name: num for num, name in MODES.items()}
#: Modes refused without a position estimate ("Mode change failed: GUIDED requires position").
POSITION_MODES = frozenset({3, 4, 7, 9, 16})

PWM_NEUTRAL = 1500
PWM_SPAN_US = 400.0  # 1100..1900

# Pilot command -> target, measured on the real SITL (ALT_HOLD steady states; PWM offsets from
# RC_CHANNELS): yaw ch4 offset (us) -> rate (rad/s); throttle ch3 offset -> climb (m/s, down +).
# Below 100 us both have dead zones, measured on the 4.7 SITL (issue 13; tools/measure_ardusub_sticks.py):
# yaw nothing up to 23 us (r = 115), then 0.044 / 0.097 / 0.154 rad/s at 26 / 34 / 42 us; throttle nothing
# up to 40 us (THR_DZ; z = 400), then 0.133 / 0.192 / 0.243 / 0.291 m/s down at 60 / 72 / 80 / 88 us
# (the up side mirrored: ArduSub will not climb above its boot depth, so it was not measured).
# Forward too (tools/measure_ardusub_sticks.py --axis x): nothing up to 24 us (x = 120), then 0.115 / 0.144 /
# 0.164 / 0.206 / 0.258 m/s at 26 / 28 / 32 / 40 / 50 us: the thrust starts at the dead zone's edge (no ramp).
FORWARD_DEAD_ZONE_US = 25
GUIDED_HEADING_BAND_RAD = math.radians(5.0)  # ArduSub's MAX_YAW_ERROR: nearer a GUIDED heading, it holds it
AUTO_YAW_SLEW_RAD_S = math.radians(60.0)  # AUTO_YAW_SLEW_RATE: the turn speed of a heading sent without a yaw rate
_YAW_TABLE_US = tuple([0.0, 23.0, 26.0, 34.2, 42.0, 50.0, 100.0, 200.0, 400.0])
_YAW_TABLE_RAD_S = tuple([0.0, 0.0, 0.0435, 0.097, 0.154, 0.214, 0.593, 1.319, 2.771])  # 400 us: extrapolated
_CLIMB_UP_US = tuple([0.0, 40.0, 60.0, 72.0, 80.0, 88.0, 100.0, 200.0, 400.0])
_CLIMB_UP_M_S = tuple([0.0, 0.0, 0.133, 0.192, 0.243, 0.291, 0.359, 0.898, 0.898])  # PILOT_SPEED_UP caps it
_CLIMB_DN_US = tuple([0.0, 40.0, 60.0, 72.0, 80.0, 88.0, 100.0, 200.0, 400.0])
_CLIMB_DN_M_S = tuple([0.0, 0.0, 0.133, 0.192, 0.243, 0.291, 0.356, 0.968, 0.968])


def _clamp(x: float, lo: float, hi: float) -> float:
    return max(lo, min(hi, x))


def _interp(x: float, xs: tuple[float, ...], ys: tuple[float, ...]) -> float:
    """Piecewise-linear interpolation, clamped at the ends (np.interp for one scalar, faster)."""
    if x <= xs[0]:
        return ys[0]
    for i in range(1, len(xs)):
        if x <= xs[i]:
            f = (x - xs[i - 1]) / (xs[i] - xs[i - 1])
            return ys[i - 1] + f * (ys[i] - ys[i - 1])
    return ys[-1]


def joystick_to_pwm(x: int, y: int, z: int, r: int, gain: float = 0.5, throttle_gain: float = 1.0
                    ) -> dict[str, int]:
    """Return ArduSub's RC PWM for a MANUAL_CONTROL (x, y, r in -1000..1000; z 0..1000, 500 neutral).

    PWM = 1500 + axis * 0.4 * gain (throttle: (z - 500) * 0.8 * gain * JS_THR_GAIN), clamped to
    1100..1900; with the default gain 0.5 a full stick is +-200 us.
    """
    def pwm(v: float) -> int:
        return int(_clamp(round(PWM_NEUTRAL + v), 1100, 1900))
    return {"forward": pwm(x * 0.4 * gain), "lateral": pwm(y * 0.4 * gain),
            "throttle": pwm((z - 500) * 0.8 * gain * throttle_gain), "yaw": pwm(r * 0.4 * gain)}


def pilot_yaw_rate_rad_s(yaw_pwm: int) -> float:
    """Return the yaw-rate target (rad/s, clockwise +) of a yaw-channel PWM."""
    off = yaw_pwm - PWM_NEUTRAL
    return math.copysign(float(_interp(abs(off), _YAW_TABLE_US, _YAW_TABLE_RAD_S)), off)


def pilot_climb_rate_m_s(throttle_pwm: int) -> float:
    """Return the ALT_HOLD vertical-speed target (m/s, down +) of a throttle PWM."""
    off = throttle_pwm - PWM_NEUTRAL
    if off > 0:
        return -float(_interp(off, _CLIMB_UP_US, _CLIMB_UP_M_S))
    return float(_interp(-off, _CLIMB_DN_US, _CLIMB_DN_M_S))


@dataclass
class PilotInput:
    """The RC channels the pilot (MANUAL_CONTROL) currently commands, PWM us."""

    forward: int = PWM_NEUTRAL
    lateral: int = PWM_NEUTRAL
    throttle: int = PWM_NEUTRAL
    yaw: int = PWM_NEUTRAL

    def effort(self, name: str) -> float:
        """Return one channel as a normalised effort in -1..1."""
        return _clamp((getattr(self, name) - PWM_NEUTRAL) / PWM_SPAN_US, -1.0, 1.0)

    def is_neutral(self, name: str, deadzone_us: int = 0) -> bool:
        """Return True when a channel is within ``deadzone_us`` of neutral."""
        return abs(getattr(self, name) - PWM_NEUTRAL) <= deadzone_us


@dataclass
class GuidedTarget:
    """The active GUIDED setpoint (local NED, SI units); None = not commanded."""

    position_ned: tuple[float, float, float] | None = None
    velocity_ned: tuple[float, float, float] | None = None  # vz None -> hold depth
    velocity_z_set: bool = False
    position_z_set: bool = False
    yaw_rad: float | None = None
    yaw_rate_rad_s: float | None = None
    yaw_slew_rad_s: float | None = None  # with yaw_rad: the turn speed toward it (None = AUTO_YAW_SLEW_RATE)
    last_update_s: float = -math.inf


@dataclass(frozen=True)
class ControlGains:
    """Gains of the simulated autopilot's inner loops."""

    yaw_rate_nm_per_rad_s: float = 3.45
    heave_n_per_m_s: float = 12.0
    depth_hold_1_s: float = 1.0
    guided_vel_n_per_m_s: float = 84.0
    guided_pos_1_s: float = 1.0
    guided_yaw_1_s: float = 1.5
    guided_max_speed_m_s: float = 1.0
    max_yaw_rate_rad_s: float = 3.0
    pilot_accel_z_m_s2: float = 2.0

    @classmethod
    def from_params(cls, params: Mapping[str, Any]) -> "ControlGains":
        """Build from project parameters ``sim.ctrl.*``."""
        sec = {k[len("sim.ctrl."):]: float(v) for k, v in params.items() if k.startswith("sim.ctrl.")}
        return cls(**{k: v for k, v in sec.items() if k in cls.__dataclass_fields__})


@dataclass
class Controller:
    """Turns (mode, pilot input, guided target, state) into body forces for the dynamics."""

    vehicle: VehicleParams
    gains: ControlGains = field(default_factory=ControlGains)
    depth_hold_m: float | None = None
    climb_target_m_s: float = 0.0  # ALT_HOLD climb-rate target after the PILOT_ACCEL_Z slew
    dt_s: float = 0.01

    def forces(self, mode: int, armed: bool, pilot: PilotInput, guided: GuidedTarget,
               state: VehicleState, now_s: float, velocity_timeout_s: float = 3.0) -> Forces:
        """Return the commanded forces for one control step (zero when disarmed)."""
        if not armed:
            self.depth_hold_m = None
            return Forces()
        if mode == MODE_NUMBERS["GUIDED"]:
            return self._guided(guided, state, now_s, velocity_timeout_s)
        forward = 0.0 if pilot.is_neutral("forward", FORWARD_DEAD_ZONE_US) else pilot.effort("forward")
        fx = self._open_loop(self.vehicle.surge.max_thrust, forward)
        fy = self._open_loop(self.vehicle.sway.max_thrust, pilot.effort("lateral"))
        if mode == MODE_NUMBERS["MANUAL"]:
            self.depth_hold_m = None
            return Forces(fx, fy, self._open_loop(self.vehicle.heave.max_thrust, -pilot.effort("throttle")),
                          self._open_loop(self.vehicle.yaw.max_thrust, pilot.effort("yaw")))
        tau = self._yaw_rate(pilot_yaw_rate_rad_s(pilot.yaw), state)
        if mode == MODE_NUMBERS["ALT_HOLD"] or mode == MODE_NUMBERS["SURFTRAK"]:
            fz = self._alt_hold(pilot, state)
        else:  # STABILIZE, ACRO: throttle is heave thrust, depth not held
            self.depth_hold_m = None
            fz = self._open_loop(self.vehicle.heave.max_thrust, -pilot.effort("throttle"))
        return Forces(fx, fy, fz, tau)

    @staticmethod
    def _open_loop(max_thrust: float, effort: float) -> float:
        """Thruster law: thrust grows with the square of the effort."""
        return max_thrust * effort * abs(effort)

    def _yaw_rate(self, target_rad_s: float, state: VehicleState) -> float:
        target = _clamp(target_rad_s, -self.gains.max_yaw_rate_rad_s, self.gains.max_yaw_rate_rad_s)
        return (self.vehicle.yaw.steady_force(target)
                + self.gains.yaw_rate_nm_per_rad_s * (target - state.r_rad_s))

    def _heave_rate(self, target_m_s: float, state: VehicleState) -> float:
        return (self.vehicle.heave.steady_force(target_m_s) + self.vehicle.buoyancy_n
                + self.gains.heave_n_per_m_s * (target_m_s - state.w_m_s))

    def _alt_hold(self, pilot: PilotInput, state: VehicleState) -> float:
        climb = pilot_climb_rate_m_s(pilot.throttle)
        if climb != 0.0:
            self.depth_hold_m = None
            step = self.gains.pilot_accel_z_m_s2 * self.dt_s
            self.climb_target_m_s += _clamp(climb - self.climb_target_m_s, -step, step)
            return self._heave_rate(self.climb_target_m_s, state)
        if self.depth_hold_m is None:
            self.depth_hold_m = state.depth_m
        self.climb_target_m_s = self._depth_rate(self.depth_hold_m, state)
        return self._heave_rate(self.climb_target_m_s, state)

    def _depth_rate(self, target_depth_m: float, state: VehicleState) -> float:
        err = max(target_depth_m, 0.0) - state.depth_m
        return _clamp(self.gains.depth_hold_1_s * err, -_CLIMB_UP_M_S[-1], _CLIMB_DN_M_S[-1])

    def _guided(self, g: GuidedTarget, state: VehicleState, now_s: float, timeout_s: float) -> Forces:
        vn = ve = 0.0
        vz: float | None = None
        if g.velocity_ned is not None and now_s - g.last_update_s <= timeout_s:
            vn, ve, vz_t = g.velocity_ned
            vz = vz_t if g.velocity_z_set else None
        if g.position_ned is not None:
            pn, pe, pd = g.position_ned
            k, vmax = self.gains.guided_pos_1_s, self.gains.guided_max_speed_m_s
            dn, de = k * (pn - state.north_m), k * (pe - state.east_m)
            norm = math.hypot(dn, de)
            scale = min(1.0, vmax / norm) if norm > 0 else 1.0
            vn, ve = vn + dn * scale, ve + de * scale
            if g.position_z_set:
                self.depth_hold_m = pd
        c, s = math.cos(state.yaw_rad), math.sin(state.yaw_rad)
        u_t, v_t = vn * c + ve * s, -vn * s + ve * c
        k = self.gains.guided_vel_n_per_m_s
        fx, fy = k * (u_t - state.u_m_s), k * (v_t - state.v_m_s)
        if vz is not None:
            self.depth_hold_m = None
            fz = self._heave_rate(vz, state)
        else:
            if self.depth_hold_m is None:
                self.depth_hold_m = state.depth_m
            fz = self._heave_rate(self._depth_rate(self.depth_hold_m, state), state)
        return Forces(fx, fy, fz, self._yaw_rate(self._guided_yaw_rate(g, state), state))

    def _guided_yaw_rate(self, g: GuidedTarget, state: VehicleState) -> float:
        """GUIDED's yaw: a rate kept forever; or a heading, turned toward at its slew speed while more than 5 deg
        away and then held (ArduSub's ``input_euler_angle_roll_pitch_slew_yaw``), rad/s."""
        if g.yaw_rate_rad_s is not None:
            return g.yaw_rate_rad_s
        if g.yaw_rad is None:
            return 0.0
        err = wrap_pi(g.yaw_rad - state.yaw_rad)
        if abs(err) > GUIDED_HEADING_BAND_RAD:
            slew = AUTO_YAW_SLEW_RAD_S if g.yaw_slew_rad_s is None else g.yaw_slew_rad_s
            return slew if err >= 0 else -slew
        return self.gains.guided_yaw_1_s * err
