"""Vehicle dynamics: a small ROV (BlueROV2 class) in 4 degrees of freedom (surge, sway, heave, yaw).

Each axis is a rigid body with added mass and linear + quadratic drag, driven by a thrust (or
torque) that is clamped to the axis' thrust limit:

    (m + m_a) dv/dt = F - d_lin v - d_quad v|v| (+ hull lift on heave from surge speed)

Body axes: x forward (surge u), y right (sway v), z down (heave w), yaw rate r clockwise from above.
The world frame is local NED: north_m, east_m, depth_m (down positive, never above the surface,
0). The constants are calibrated against a real ArduSub SITL (see
``/work/shared/reference/ardusub_sitl_response.md``) and live in ``params/schema/sim.yaml``.
Integration is semi-implicit Euler at a fixed step, so a run is bit-for-bit deterministic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Mapping

__all__ = ["AxisParams", "VehicleParams", "VehicleState", "Forces", "Dynamics", "wrap_pi"]


def wrap_pi(angle_rad: float) -> float:
    """Return the angle wrapped to [-pi, pi)."""
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


@dataclass(frozen=True)
class AxisParams:
    """One degree of freedom: effective inertia, drag and thrust limit (SI units).

    For yaw: inertia in kg m^2, drag in N m per rad/s (and per (rad/s)^2), limit in N m.
    """

    inertia: float
    linear_drag: float
    quadratic_drag: float
    max_thrust: float

    def drag(self, v: float) -> float:
        """Return the drag force (or torque) opposing speed ``v``."""
        return self.linear_drag * v + self.quadratic_drag * v * abs(v)

    def steady_force(self, v: float) -> float:
        """Return the thrust that holds speed ``v`` steady (the inverse model, unclamped)."""
        return self.drag(v)

    def max_speed(self) -> float:
        """Return the steady speed at full thrust."""
        a, b, c = self.quadratic_drag, self.linear_drag, -self.max_thrust
        if a <= 0.0:
            return self.max_thrust / self.linear_drag
        return (-b + math.sqrt(b * b - 4.0 * a * c)) / (2.0 * a)


@dataclass(frozen=True)
class VehicleParams:
    """All constants of the vehicle model."""

    surge: AxisParams
    sway: AxisParams
    heave: AxisParams
    yaw: AxisParams
    buoyancy_n: float = 0.0
    surge_lift_n_per_m2_s2: float = 0.0

    @classmethod
    def from_params(cls, params: Mapping[str, Any]) -> "VehicleParams":
        """Build from project parameters (keys ``sim.*``, see params/schema/sim.yaml)."""
        mass = float(params["sim.mass_kg"])

        def axis(name: str) -> AxisParams:
            p = f"sim.{name}."
            return AxisParams(mass + float(params[p + "added_mass_kg"]), float(params[p + "linear_drag"]),
                              float(params[p + "quadratic_drag"]), float(params[p + "max_thrust_n"]))

        yaw = AxisParams(float(params["sim.yaw.inertia_kg_m2"]), float(params["sim.yaw.linear_drag"]),
                         float(params["sim.yaw.quadratic_drag"]), float(params["sim.yaw.max_torque_nm"]))
        return cls(axis("surge"), axis("sway"), axis("heave"), yaw,
                   float(params["sim.buoyancy_n"]), float(params["sim.surge_lift_n_per_m2_s2"]))


@dataclass(frozen=True)
class VehicleState:
    """The vehicle's true state: pose in local NED and body-frame velocities."""

    north_m: float = 0.0
    east_m: float = 0.0
    depth_m: float = 0.0
    yaw_rad: float = 0.0
    u_m_s: float = 0.0
    v_m_s: float = 0.0
    w_m_s: float = 0.0
    r_rad_s: float = 0.0

    @property
    def vn_m_s(self) -> float:
        """North velocity, m/s."""
        return self.u_m_s * math.cos(self.yaw_rad) - self.v_m_s * math.sin(self.yaw_rad)

    @property
    def ve_m_s(self) -> float:
        """East velocity, m/s."""
        return self.u_m_s * math.sin(self.yaw_rad) + self.v_m_s * math.cos(self.yaw_rad)

    @property
    def yaw_rate_rad_s(self) -> float:
        """Yaw rate, rad/s (alias of r_rad_s)."""
        return self.r_rad_s


@dataclass(frozen=True)
class Forces:
    """Commanded body forces: surge, sway, heave (down +) in N, yaw torque in N m."""

    x_n: float = 0.0
    y_n: float = 0.0
    z_n: float = 0.0
    yaw_nm: float = 0.0


def _clamp(x: float, limit: float) -> float:
    return max(-limit, min(limit, x))


class Dynamics:
    """The 4-DOF vehicle: ``step(dt, forces)`` integrates one fixed step; ``state`` is the truth."""

    def __init__(self, params: VehicleParams, state: VehicleState | None = None) -> None:
        self.params = params
        self.state = state or VehicleState()

    def applied(self, forces: Forces) -> Forces:
        """Return the forces after the thrust limits."""
        p = self.params
        return Forces(_clamp(forces.x_n, p.surge.max_thrust), _clamp(forces.y_n, p.sway.max_thrust),
                      _clamp(forces.z_n, p.heave.max_thrust), _clamp(forces.yaw_nm, p.yaw.max_thrust))

    def step(self, dt_s: float, forces: Forces) -> VehicleState:
        """Advance the state by ``dt_s`` seconds under ``forces`` (clamped); return the new state."""
        p, s = self.params, self.state
        f = self.applied(forces)
        lift = -p.surge_lift_n_per_m2_s2 * s.u_m_s * abs(s.u_m_s)
        u = s.u_m_s + dt_s * (f.x_n - p.surge.drag(s.u_m_s)) / p.surge.inertia
        v = s.v_m_s + dt_s * (f.y_n - p.sway.drag(s.v_m_s)) / p.sway.inertia
        w = s.w_m_s + dt_s * (f.z_n - p.buoyancy_n + lift - p.heave.drag(s.w_m_s)) / p.heave.inertia
        r = s.r_rad_s + dt_s * (f.yaw_nm - p.yaw.drag(s.r_rad_s)) / p.yaw.inertia
        yaw = wrap_pi(s.yaw_rad + dt_s * r)
        c, sn = math.cos(yaw), math.sin(yaw)
        north = s.north_m + dt_s * (u * c - v * sn)
        east = s.east_m + dt_s * (u * sn + v * c)
        depth = s.depth_m + dt_s * w
        if depth <= 0.0:  # the surface: the hull cannot leave the water
            depth = 0.0
            w = max(w, 0.0)
        self.state = VehicleState(north, east, depth, yaw, u, v, w, r)
        return self.state

    def reset(self, **fields: float) -> None:
        """Replace some state fields (e.g. ``depth_m=3.0``)."""
        self.state = replace(self.state, **fields)
