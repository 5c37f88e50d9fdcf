"""Measure an ArduSub SITL's steady response to MANUAL_CONTROL steps in ALT_HOLD (yaw r, forward x, vertical z).

usage: .venv/bin/python tools/measure_ardusub_sticks.py [BINARY] [--axis r|x] [--values 100,171,250,500]
       [--speedup 1] [--instance 40]

Starts the binary on loopback (sitl/ardusub_sitl.py), speaks as the ground station (255/190), arms
in ALT_HOLD at 3 m, and for each value streams MANUAL_CONTROL at 20 Hz for ``--on-s`` seconds then
neutral; the steady state is the mean of the firmware's own truth (SIM_STATE zgyro for yaw, SIM_STATE
vn/ve rotated into the body for x, vd for z) over the last ``--mean-s`` seconds of each step. Prints one JSON
line per step and a table. Used for ``dip3d_vehicle/link/setpoints.py``'s per-firmware tables.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

from pymavlink.dialects.v20 import ardupilotmega as m2

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from sitl.ardusub_sitl import ArdusubSitl, SitlOptions, resolve_binary  # noqa: E402
from sitl.firmware_mav import MavSocket  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("binary", nargs="?", default=None)
    ap.add_argument("--axis", choices=["r", "x", "z"], default="r")
    ap.add_argument("--values", default="100,171,250,500")
    ap.add_argument("--speedup", type=float, default=1.0)
    ap.add_argument("--instance", type=int, default=40)
    ap.add_argument("--on-s", type=float, default=5.0)
    ap.add_argument("--mean-s", type=float, default=2.0)
    a = ap.parse_args()
    values = [int(v) for v in a.values.split(",")]
    sitl = ArdusubSitl(SitlOptions(resolve_binary(a.binary), instance=a.instance, speedup=a.speedup,
                                   home=(-27.563, -48.459, -8.0, 270.0)))
    m = MavSocket(sitl.start())
    rows = []
    try:
        clock = _Pacer(m, a.speedup)
        m.command(511, 108.0, 5e4)  # SIM_STATE 20 Hz
        clock.run_until(lambda: _armed_in_althold(m), 30.0, setup=True)
        clock.run_for(4.0, dict(x=0, y=0, z=500, r=0))  # settle after arming
        for v in values:
            sticks = {**dict(x=0, y=0, z=500, r=0), a.axis: v}
            t_on = clock.run_for(a.on_s, sticks)
            steady = _steady(m, a.axis, t_on + a.on_s / a.speedup - a.mean_s / a.speedup)
            rows.append({"axis": a.axis, "value": v, "steady": round(steady, 4),
                         "unit": {"r": "rad/s", "x": "m/s", "z": "m/s down"}[a.axis]})
            print(json.dumps(rows[-1]), flush=True)
            clock.run_for(3.0, dict(x=0, y=0, z=500, r=0))
    finally:
        status = sitl.stop()
    print(f"firmware exit status {status}")
    print(f"| {a.axis} | steady ({rows[0]['unit'] if rows else ''}) |\n|---|---|")
    for r in rows:
        print(f"| {r['value']} | {r['steady']:.3f} |")
    return 0


class _Pacer:
    """Keeps the GCS heartbeat (1 Hz) and MANUAL_CONTROL (20 Hz) going in wall-clock time."""

    def __init__(self, m: MavSocket, speedup: float) -> None:
        self.m, self.speedup = m, speedup
        self.next_hb = self.next_mc = 0.0

    def _tick(self, sticks: dict | None) -> None:
        now = time.monotonic()
        if now >= self.next_hb:
            self.m.heartbeat()
            self.next_hb = now + 1.0 / self.speedup
        if sticks is not None and now >= self.next_mc:
            self.m.send(m2.MAVLink_manual_control_message(1, sticks["x"], sticks["y"], sticks["z"], sticks["r"], 0))
            self.next_mc = now + 0.05 / self.speedup
        self.m.pump()
        time.sleep(0.005)

    def run_for(self, seconds: float, sticks: dict) -> float:
        t0 = time.monotonic()
        while time.monotonic() - t0 < seconds / self.speedup:
            self._tick(sticks)
        return t0

    def run_until(self, pred, timeout_s: float, setup: bool = False) -> None:
        t0, next_try = time.monotonic(), 0.0
        neutral = dict(x=0, y=0, z=500, r=0)
        while not pred():
            if time.monotonic() - t0 > timeout_s / self.speedup:
                raise SystemExit("the firmware did not arm in ALT_HOLD")
            if setup and time.monotonic() >= next_try:
                self.m.command(176, 1.0, 2.0)  # DO_SET_MODE ALT_HOLD
                self.m.command(400, 1.0)      # arm
                next_try = time.monotonic() + 1.0 / self.speedup
            self._tick(neutral)


def _armed_in_althold(m: MavSocket) -> bool:
    hb = [x for _, x in m.received if x.get_type() == "HEARTBEAT" and x.get_srcSystem() == 1]
    return bool(hb) and bool(hb[-1].base_mode & 128) and hb[-1].custom_mode == 2


def _steady(m: MavSocket, axis: str, since: float) -> float:
    xs = [x for t, x in m.received if t >= since and x.get_type() == "SIM_STATE"]
    if not xs:
        return math.nan
    if axis == "r":
        return sum(x.zgyro for x in xs) / len(xs)
    if axis == "z":
        return sum(x.vd for x in xs) / len(xs)  # down positive
    return sum(x.vn * math.cos(x.yaw) + x.ve * math.sin(x.yaw) for x in xs) / len(xs)


if __name__ == "__main__":
    raise SystemExit(main())
