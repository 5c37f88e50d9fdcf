"""Image-based visual servoing of one point feature with its stereo depth.

Features: the target's normalised image point ``(x, y)`` against the desired point ``(x*, y*)``
and its depth ``Z`` against the stand-off ``Z*`` (``e_z = Z - Z*``, metres). Each feature is
paired with the vehicle axes that naturally drive it and is used only when one of them is enabled:
``x`` with yaw or sway, ``y`` with heave, the range with surge. The feature Jacobian in vehicle
axes is ``J = L @ M`` (``L``: point and depth interaction rows with the measured ``Z``;
``M``: the camera mount's map from vehicle velocities to the camera twist, which includes the
mount pitch and the lever arm of a camera ahead of the yaw axis). The law is ViSP's
``u = -lambda(|e|_inf) * pinv(J) @ e`` with ``vpAdaptiveGain``; ``e`` mixes normalised image units
and metres, so the adaptive gain's infinity norm sees whichever is larger (the range error, far
from the target). Then, per axis: a soft dead-band on the error (``|e|`` shrunk by the band, so the
command is continuous), saturation, and a rate (acceleration) limit.

Coasting: in ALT_HOLD the forward stick is thrust, not speed; the vehicle speeds up in ~0.4 s but
nothing brakes it except drag, so at the low speeds of the last few decimetres it coasts for seconds
(measured on the 4.7 SITL: asked 0, still 0.06 m/s 1 s later; paper_pool seed 0 swung +-0.1 m about
the stand-off for 30 s). With ``speed_gain`` > 0 the surge command also gets
``speed_gain * (surge - measured)``, the measured forward speed being minus the target's filtered
range rate (first-order filter ``speed_filter_s``): the vehicle is braked by reverse thrust when it
moves faster than asked, the way the autopilot's own velocity loop would in GUIDED.

Safety: when the target is lost (``target_px is None``) ``update`` returns ``NEUTRAL`` at once,
without ramping down, and forgets the previous command; the autopilot's own velocity loop does the
braking. When only the depth is missing the range feature and surge are dropped (surge ramps to
zero under its rate limit) and the interaction matrix uses the stand-off as depth.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np

from .command import NEUTRAL, VelocityCommand
from .gain import AdaptiveGain
from .interaction import depth_interaction, normalise, point_interaction
from .mount import VEHICLE_AXES, CameraMount

__all__ = ["PointServo", "ServoErrors"]

_FEATURE_AXES = {"x": ("yaw", "sway"), "y": ("heave",), "range": ("surge",)}


@dataclass(frozen=True)
class ServoErrors:
    """Current errors of the target against the goal, for the behaviour's arrive check.

    Attributes:
        du_px: target u minus desired u, rectified pixels (positive = target right of the goal).
        dv_px: target v minus desired v, pixels (positive = target below the goal).
        range_m: depth minus stand-off, m (positive = too far), or None without a depth.
    """

    du_px: float
    dv_px: float
    range_m: float | None

    @property
    def pixel_px(self) -> float:
        """Euclidean image error, pixels."""
        return math.hypot(self.du_px, self.dv_px)


def _valid_depth(depth_m: float | None) -> bool:
    """Return True for a usable depth (finite and positive)."""
    return depth_m is not None and math.isfinite(depth_m) and depth_m > 0.0


class PointServo:
    """IBVS of one point with stereo depth, producing body-frame velocity commands.

    Args:
        focal_px: rectified focal length, pixels.
        principal_point_px: rectified (cx, cy), pixels.
        desired_px: goal pixel (u*, v*).
        standoff_m: desired depth Z* of the target, m.
        gain: the adaptive gain.
        mount: the camera mount.
        axes: enabled vehicle axes, a subset of ``("surge", "sway", "heave", "yaw")``.
        max_speed: per axis limit (m/s, m/s, m/s, rad/s) in ``VEHICLE_AXES`` order or by name.
        max_accel: per axis rate limit (m/s^2 ..., rad/s^2), same layout.
        deadband_px: image error band (pixels) treated as zero.
        deadband_m: range error band (m) treated as zero.
        speed_gain: surge speed feedback on the measured approach speed (0 = none), 1.
        speed_filter_s: time constant of the range-rate filter for that feedback, s.
    """

    def __init__(self, focal_px: float, principal_point_px: tuple[float, float],
                 desired_px: tuple[float, float], standoff_m: float, gain: AdaptiveGain,
                 mount: CameraMount = CameraMount(), axes: Sequence[str] = ("surge", "heave", "yaw"),
                 max_speed: Sequence[float] | Mapping[str, float] = (0.4, 0.3, 0.3, 0.5),
                 max_accel: Sequence[float] | Mapping[str, float] = (0.4, 0.4, 0.4, 0.8),
                 deadband_px: float = 0.0, deadband_m: float = 0.0, speed_gain: float = 0.0,
                 speed_filter_s: float = 0.4) -> None:
        if not (focal_px > 0 and math.isfinite(focal_px)):
            raise ValueError(f"PointServo: focal_px = {focal_px!r}, expected > 0")
        if not standoff_m > 0:
            raise ValueError(f"PointServo: standoff_m = {standoff_m!r}, expected > 0")
        unknown = set(axes) - set(VEHICLE_AXES)
        if unknown:
            raise ValueError(f"PointServo: unknown axes {sorted(unknown)} (expected {VEHICLE_AXES})")
        self.focal_px = float(focal_px)
        self.principal_point_px = (float(principal_point_px[0]), float(principal_point_px[1]))
        self.desired_px = (float(desired_px[0]), float(desired_px[1]))
        self.standoff_m = float(standoff_m)
        self.gain = gain
        self.mount = mount
        self.axes = tuple(a for a in VEHICLE_AXES if a in axes)
        self.max_speed = _per_axis(max_speed, "max_speed")
        self.max_accel = _per_axis(max_accel, "max_accel")
        self.deadband_px = float(deadband_px)
        self.deadband_m = float(deadband_m)
        if not (speed_gain >= 0 and speed_filter_s > 0):
            raise ValueError(f"PointServo: speed_gain = {speed_gain!r} (>= 0), speed_filter_s = {speed_filter_s!r} (> 0)")
        self.speed_gain, self.speed_filter_s = float(speed_gain), float(speed_filter_s)
        self._last_depth: float | None = None
        self._range_rate: float | None = None  # filtered dZ/dt, m/s
        self._previous = np.zeros(4)
        self._last_errors: ServoErrors | None = None

    @classmethod
    def from_params(cls, params: Mapping, focal_px: float, principal_point_px: tuple[float, float],
                    image_size_px: tuple[int, int] | None = None) -> "PointServo":
        """Build the servo from the ``servo.*`` parameters and the rectified intrinsics.

        Args:
            params: effective parameters (``dip3d_vehicle.config.Params`` or a plain mapping).
            focal_px: rectified focal length (``StereoRig.focal_px``).
            principal_point_px: rectified (cx, cy) (``StereoRig.principal_point_px``).
            image_size_px: (width, height) for ``servo.desired_u_frac/_v_frac``; without it the
                image is taken as (2 cx, 2 cy), so 0.5 means the principal point.

        Returns:
            The configured servo.
        """
        p = {k[len("servo."):]: v for k, v in params.items() if k.startswith("servo.")}
        cx, cy = principal_point_px
        width, height = image_size_px if image_size_px is not None else (2.0 * cx, 2.0 * cy)
        return cls(
            focal_px, principal_point_px,
            desired_px=(p["desired_u_frac"] * width, p["desired_v_frac"] * height),
            standoff_m=p["standoff_m"],
            gain=AdaptiveGain(p["gain_l0"], p["gain_linf"], p["gain_slope"]),
            mount=CameraMount(p["mount_forward_m"], p["mount_right_m"], p["mount_down_m"], p["mount_pitch_rad"]),
            axes=[a for a in VEHICLE_AXES if p[a]],
            max_speed=[p["max_surge_m_s"], p["max_sway_m_s"], p["max_heave_m_s"], p["max_yaw_rate_rad_s"]],
            max_accel=[p["max_surge_accel_m_s2"], p["max_sway_accel_m_s2"], p["max_heave_accel_m_s2"],
                       p["max_yaw_accel_rad_s2"]],
            deadband_px=p["deadband_px"], deadband_m=p["deadband_m"],
            speed_gain=p["surge_speed_gain"], speed_filter_s=p["speed_filter_s"],
        )

    # -- errors and the law ----------------------------------------------------------------
    def errors(self, target_px: tuple[float, float] | None, depth_m: float | None) -> ServoErrors | None:
        """Return the pixel and range errors of a target (None when there is no target)."""
        if target_px is None:
            return None
        rng = depth_m - self.standoff_m if _valid_depth(depth_m) else None
        return ServoErrors(float(target_px[0]) - self.desired_px[0],
                           float(target_px[1]) - self.desired_px[1], rng)

    @property
    def last_errors(self) -> ServoErrors | None:
        """Errors seen by the last ``update`` (None after a lost target or ``reset``)."""
        return self._last_errors

    def jacobian(self, target_px: tuple[float, float], depth_m: float | None) -> tuple[np.ndarray, list[str], list[str]]:
        """Return (J, features, axes): the used feature rows' rates per unit vehicle velocity.

        ``J[i, j]`` is d(feature i)/dt per unit of vehicle axis j (features among
        ``x``, ``y`` (normalised) and ``range`` (m); axes among ``VEHICLE_AXES``).
        """
        has_depth = _valid_depth(depth_m)
        z = float(depth_m) if has_depth else self.standoff_m
        x, y = normalise(target_px, self.focal_px, self.principal_point_px)
        axes = [a for a in self.axes if a != "surge" or has_depth]
        features = [f for f, drivers in _FEATURE_AXES.items() if any(a in axes for a in drivers)]
        rows = {"x": point_interaction(x, y, z)[0], "y": point_interaction(x, y, z)[1],
                "range": depth_interaction(x, y, z)[0]}
        L = np.array([rows[f] for f in features]).reshape(len(features), 6)
        cols = [VEHICLE_AXES.index(a) for a in axes]
        return L @ self.mount.vehicle_jacobian()[:, cols], features, axes

    def law(self, target_px: tuple[float, float], depth_m: float | None) -> np.ndarray:
        """Return the raw command ``-lambda pinv(J) e`` (before saturation and rate limits).

        Returns:
            Array (surge m/s, sway m/s, heave m/s, yaw rate rad/s); disabled axes are 0.
        """
        J, features, axes = self.jacobian(target_px, depth_m)
        out = np.zeros(4)
        if not features:
            return out
        err = self.errors(target_px, depth_m)
        band = self.deadband_px / self.focal_px
        values = {"x": _shrink(err.du_px / self.focal_px, band), "y": _shrink(err.dv_px / self.focal_px, band),
                  "range": _shrink(err.range_m, self.deadband_m) if err.range_m is not None else 0.0}
        e = np.array([values[f] for f in features])
        u = -self.gain(e) * (np.linalg.pinv(J) @ e)
        out[[VEHICLE_AXES.index(a) for a in axes]] = u
        return out

    # -- the tick --------------------------------------------------------------------------
    def update(self, target_px: tuple[float, float] | None, depth_m: float | None, dt_s: float) -> VelocityCommand:
        """Return this tick's velocity command.

        Args:
            target_px: rectified left-image target (u, v), or None when it is not seen.
            depth_m: the target's stereo depth (camera z), or None / non-finite when unknown.
            dt_s: time since the previous update, s (for the rate limits).

        Returns:
            The command; ``NEUTRAL`` at once when the target is lost.

        Raises:
            ValueError: when ``dt_s`` is not a positive finite number.
        """
        if not (math.isfinite(dt_s) and dt_s > 0):
            raise ValueError(f"PointServo.update: dt_s = {dt_s!r}, expected a positive finite time step")
        if target_px is None or not all(math.isfinite(float(c)) for c in target_px):
            self.reset()
            return NEUTRAL
        self._last_errors = self.errors(target_px, depth_m)
        raw = self.law(target_px, depth_m)
        approach = self._approach_speed(depth_m, dt_s)
        i = VEHICLE_AXES.index("surge")
        if approach is not None and "surge" in self.axes and self.speed_gain > 0:
            raw[i] += self.speed_gain * (raw[i] - approach)
        sat = np.clip(raw, -self.max_speed, self.max_speed)
        step = self.max_accel * dt_s
        cmd = np.clip(sat, self._previous - step, self._previous + step)
        self._previous = cmd
        return VelocityCommand(*(float(v) for v in cmd))

    def _approach_speed(self, depth_m: float | None, dt_s: float) -> float | None:
        """Return the measured forward speed toward the target (-filtered dZ/dt), or None without two depths."""
        if not _valid_depth(depth_m):
            self._last_depth = self._range_rate = None
            return None
        last, self._last_depth = self._last_depth, float(depth_m)
        if last is None:
            return None
        rate = (float(depth_m) - last) / dt_s
        a = dt_s / (self.speed_filter_s + dt_s)
        self._range_rate = rate if self._range_rate is None else self._range_rate + a * (rate - self._range_rate)
        return -self._range_rate

    def reset(self) -> None:
        """Forget the previous command (rate limits restart from rest), the last errors and the range rate."""
        self._previous = np.zeros(4)
        self._last_errors = None
        self._last_depth = self._range_rate = None


def _shrink(value: float, band: float) -> float:
    """Return ``value`` moved towards 0 by ``band`` (0 inside the band): a continuous dead-band."""
    return math.copysign(max(abs(value) - band, 0.0), value)


def _per_axis(values: Sequence[float] | Mapping[str, float], name: str) -> np.ndarray:
    """Return a per-axis limit as an array in ``VEHICLE_AXES`` order; all must be > 0."""
    arr = np.array([values[a] for a in VEHICLE_AXES] if isinstance(values, Mapping) else values, dtype=float)
    if arr.shape != (4,) or not np.all(arr > 0):
        raise ValueError(f"PointServo: {name} = {values!r}, expected 4 positive limits {VEHICLE_AXES}")
    return arr
