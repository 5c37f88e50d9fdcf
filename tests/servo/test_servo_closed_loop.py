"""Closed loop: the servo drives a kinematic vehicle (first-order velocity lag, perception latency)."""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import pytest

from dip3d_vehicle.config import load_params
from dip3d_vehicle.servo.ibvs import PointServo

F, C, SIZE = 800.0, (640.0, 360.0), (1280, 720)


def _run(overrides: dict, target_body: tuple[float, float, float], duration_s: float = 25.0):
    """Simulate; return arrays of time, du px, dv px, range error m (measurements as the servo sees them)."""
    params = load_params().with_overrides(overrides)
    servo = PointServo.from_params(params, F, C, image_size_px=SIZE)
    tau = np.array([params[f"servo.tau_{a}_s"] for a in ("surge", "sway", "heave", "yaw")])
    latency, period, dt = params["servo.latency_s"], params["servo.sample_period_s"], 0.01
    pose = np.zeros(4)                               # north, east, down, yaw
    target = np.array(target_body, dtype=float)      # world = body at the start
    velocity, command = np.zeros(4), np.zeros(4)
    seen: deque = deque()
    log = []
    steps_per_period = int(round(period / dt))
    for k in range(int(duration_s / dt)):
        t = k * dt
        c, s = math.cos(pose[3]), math.sin(pose[3])
        body = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]]) @ (target - pose[:3])
        p_cam = servo.mount.camera_point(body)
        seen.append((t, (F * p_cam[0] / p_cam[2] + C[0], F * p_cam[1] / p_cam[2] + C[1]), p_cam[2]))
        if k % steps_per_period == 0:
            while len(seen) > 1 and seen[1][0] <= t - latency + 1e-9:
                seen.popleft()
            _, px, depth = seen[0]
            cmd = servo.update(px, depth, period)
            command = np.array([cmd.surge_m_s, cmd.sway_m_s, cmd.heave_m_s, cmd.yaw_rate_rad_s])
            err = servo.errors(px, depth)
            log.append((t, err.du_px, err.dv_px, err.range_m))
        velocity += (command - velocity) * dt / tau
        pose[0] += (velocity[0] * c - velocity[1] * s) * dt
        pose[1] += (velocity[0] * s + velocity[1] * c) * dt
        pose[2] += velocity[2] * dt
        pose[3] += velocity[3] * dt
    return np.array(log)


def _arrival_s(log: np.ndarray, px: float = 10.0, m: float = 0.05) -> float:
    """Return the first time after which the errors stay within (px, m)."""
    ok = (np.hypot(log[:, 1], log[:, 2]) <= px) & (np.abs(log[:, 3]) <= m)
    bad = np.nonzero(~ok)[0]
    return math.inf if bad.size and bad[-1] == len(ok) - 1 else log[bad[-1] + 1 if bad.size else 0, 0]


@pytest.mark.parametrize("overrides", [
    {},
    {"servo.mount_pitch_rad": -0.3, "servo.mount_down_m": 0.1, "servo.latency_s": 0.3},
    {"servo.sway": True},
], ids=["defaults", "pitched-mount-slow-perception", "with-sway"])
def test_converges_to_the_standoff(overrides):
    # target 3 m ahead of the camera, 0.8 m to the right and 0.4 m below: off-centre in the image
    log = _run(overrides, (3.2, 0.8, 0.4))
    pixel, rng = np.hypot(log[:, 1], log[:, 2]), log[:, 3]
    arrival = _arrival_s(log)
    print(f"\n{overrides or 'defaults'}: start {pixel[0]:.0f} px / {rng[0]:.2f} m, "
          f"final {pixel[-1]:.1f} px / {rng[-1]:+.3f} m, arrived (10 px, 5 cm) at {arrival:.1f} s")
    assert arrival < 15.0
    assert pixel[-1] < 5.0 and abs(rng[-1]) < 0.04
    # monotonic-ish: the range error never grows by more than 2 cm and never overshoots by 5 cm;
    # the image error never exceeds its start by more than 10 %
    assert np.all(np.diff(rng) < 0.02) and rng.min() > -0.05
    assert pixel.max() < 1.1 * pixel[0]
    assert np.all(np.abs(log[:, 1]) < SIZE[0] / 2) and np.all(np.abs(log[:, 2]) < SIZE[1] / 2)
