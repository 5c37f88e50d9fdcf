"""Speed of the simulator: simulated seconds per wall second for dynamics + MAVLink in lockstep.

A SimClock advances by ``dt``; each tick the autopilot steps (sockets, 100 Hz physics, telemetry)
and a pymavlink client on loopback TCP streams MANUAL_CONTROL at 20 Hz, a GCS heartbeat at 1 Hz,
and reads all telemetry (ATTITUDE and VFR_HUD at 10 Hz, ...). Run ``python -m sitl.bench``.
"""

from __future__ import annotations

import json
import os
import sys
import time

__all__ = ["measure_speed"]


def measure_speed(sim_seconds: float = 60.0, dt_s: float = 0.01) -> dict:
    """Run the lockstep loop for ``sim_seconds``; return timings and the sim/real ratio."""
    os.environ["MAVLINK20"] = "1"  # a MAVLink 2 client, as against ArduSub
    from pymavlink import mavutil

    from dip3d_vehicle.clock import SimClock
    from dip3d_vehicle.config import load_params

    from .autopilot import Autopilot

    clock = SimClock()
    ap = Autopilot(load_params(overrides={"sim.initial_depth_m": 3.0}), clock, listen=["tcp:127.0.0.1:0"])
    conn = mavutil.mavlink_connection(ap.addresses[0], source_system=255, source_component=190,
                                      dialect="ardupilotmega", autoreconnect=False)
    received = 0
    try:
        ap.step()
        conn.mav.command_long_send(1, 1, 176, 0, 1, 2, 0, 0, 0, 0, 0)
        conn.mav.command_long_send(1, 1, 400, 0, 1, 0, 0, 0, 0, 0, 0)
        n = int(round(sim_seconds / dt_s))
        manual_every = max(1, int(round(0.05 / dt_s)))
        hb_every = max(1, int(round(1.0 / dt_s)))
        wall0 = time.perf_counter()
        for k in range(n):
            if k % manual_every == 0:
                conn.mav.manual_control_send(1, 300, 0, 500, 200 if (k // 500) % 2 else -200, 0)
            if k % hb_every == 0:
                conn.mav.heartbeat_send(6, 8, 0, 0, 0)
            clock.advance(dt_s)
            ap.step()
            while conn.recv_match(blocking=False) is not None:
                received += 1
        wall = time.perf_counter() - wall0
    finally:
        conn.close()
        ap.close()
    return {"sim_s": sim_seconds, "wall_s": round(wall, 3), "ratio": round(sim_seconds / wall, 1),
            "dt_s": dt_s, "physics_rate_hz": 1.0 / ap._dt, "messages_received": received,
            "armed_at_end": ap.armed}


def main(argv: list[str] | None = None) -> int:
    """Print the measurement as JSON; exit 1 if the ratio is below 20x."""
    args = argv if argv is not None else sys.argv[1:]
    sim_s = float(args[0]) if args else 60.0
    result = measure_speed(sim_s)
    print(json.dumps(result))
    return 0 if result["ratio"] >= 20.0 else 1


if __name__ == "__main__":
    sys.exit(main())
