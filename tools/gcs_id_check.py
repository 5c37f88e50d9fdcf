"""After "ground station lost", count messages carrying the GCS id from the controller (issue 13).

usage: .venv/bin/python tools/gcs_id_check.py [--ardusub BINARY] [--runs 20]

Each run: the controller's real VehicleLink (manual_control, ALT_HOLD) behind the router, the simulated
pilot arms + enables, the controller drives (non-neutral sticks); then the pilot's GCS HEARTBEAT stops;
once the link says "ground station lost" the run ends, in turn, with the stop stream running out
(stop), ``close()`` (close) or a TCP reconnect of the link (reconnect). Counted at the router: every
message from the GCS system id that is not the pilot's own (255/190) after the loss; and (firmware)
any STATUSTEXT "GCS Failsafe Cleared" after the loss. Built-in autopilot (4.7 setting) in lockstep
simulated time; the firmware in wall-clock time.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
import time
from pathlib import Path

from pymavlink.dialects.v20 import ardupilotmega as m2

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from dip3d_vehicle.clock import SimClock  # noqa: E402
from dip3d_vehicle.config import load_params  # noqa: E402
from dip3d_vehicle.link import VehicleLink  # noqa: E402
from dip3d_vehicle.servo.command import VelocityCommand  # noqa: E402
from sitl.autopilot import Autopilot  # noqa: E402
from sitl.simulation import Router, SimPilot  # noqa: E402

MOVE = VelocityCommand(surge_m_s=0.2, yaw_rate_rad_s=0.1)
ENDINGS = ("stop", "close", "reconnect")


class _Tap:
    """Wraps a router's client->autopilot forwarding to record (t, src, type) of every message."""

    def __init__(self, router: Router, clock: SimClock) -> None:
        self.rows: list[tuple[float, tuple[int, int], str]] = []
        self.parser = m2.MAVLink(None)
        self.parser.robust_parsing = True
        write, self.clock = router.autopilot.write, clock

        def tapped(buf: bytes) -> None:
            for msg in self.parser.parse_buffer(buf) or []:
                if msg.get_type() != "BAD_DATA":
                    self.rows.append((clock.now(), (msg.get_srcSystem(), msg.get_srcComponent()), msg.get_type()))
            write(buf)
        router.autopilot.write = tapped


def one_run(ending: str, binary: Path | None, instance: int) -> dict:
    """One run; return its counts."""
    clock = SimClock()
    params = load_params()
    sitl = ap = None
    texts: list[tuple[float, str]] = []
    if binary is not None:
        from sitl.ardusub_sitl import ArdusubSitl, SitlOptions
        from sitl.dynamics import VehicleState
        from sitl.firmware_world import FirmwareRouter, FirmwareVehicle
        sitl = ArdusubSitl(SitlOptions(binary, instance=instance))
        sock = sitl.start()
        vehicle = FirmwareVehicle(sitl, VehicleState(), -27.563, -48.459, clock)
        router = FirmwareRouter(sock, vehicle, [])
        texts = vehicle.statustexts
    else:
        ap = Autopilot(params.with_overrides({"sim.firmware": "4.7"}), clock, listen=["tcp:127.0.0.1:0"])
        router = Router(ap.addresses[0])
    tap = _Tap(router, clock)
    router.step()
    link = VehicleLink(params.with_overrides({"link.url": router.address, "link.reconnect_s": 0.5}), clock)
    link.open()
    pilot = SimPilot(router.address, clock, "ALT_HOLD", 0.5)
    wall0 = time.perf_counter()
    sticks_at = 0.0

    def step() -> None:
        nonlocal sticks_at
        if binary is not None:
            time.sleep(0.01)
            clock.advance(max(0.0, time.perf_counter() - wall0 - clock.now()))
            if not link.engaged and not pilot.handed_over and clock.now() >= sticks_at:
                router.pilot_neutral_sticks()  # the pilot's joystick until the hand-over
                sticks_at = clock.now() + 0.1
        else:
            clock.advance(0.02)
            ap.step()
        router.step()
        pilot.step()
        link.poll()
        link.tick(MOVE, perception_fresh=True, perception_stamp_s=clock.now())
        router.step()

    def run_until(pred, timeout_s: float) -> bool:
        end = clock.now() + timeout_s
        while clock.now() < end:
            step()
            if pred():
                return True
        return False

    out = {"ending": ending, "autopilot": "firmware" if binary else "builtin-4.7"}
    try:
        out["engaged"] = run_until(lambda: link.engaged, 30.0)
        run_until(lambda: False, 1.0)
        pilot.heartbeats = False
        out["lost"] = run_until(lambda: link.disengage_reason == "ground station lost", 6.0)
        t_lost = clock.now()
        if ending == "close":
            link.close()
            run_until(lambda: False, 1.0)
        elif ending == "reconnect":
            for c in list(router.clients[:1]):  # the link's connection (the first client)
                c.sock.close()
                c.alive = False
            router.clients = router.clients[1:]
            run_until(lambda: False, 3.0)
            out["reconnected"] = any("tcp reconnected" in e for e in link.events)
        else:
            run_until(lambda: False, 3.0)
        link.close()
        run_until(lambda: False, 6.5 if binary else 3.0)  # the firmware's GCS failsafe acts after 5 s
        gcs_id = link.gcs.sysid
        out["gcs_id_messages_after_loss"] = sum(1 for t, src, _ in tap.rows if t > t_lost + 1e-6
                                                and src[0] == gcs_id and src != (255, 190))
        out["gcs_id_manual_control_before_loss"] = sum(1 for t, src, k in tap.rows if t <= t_lost
                                                       and src == (gcs_id, 191) and k == "MANUAL_CONTROL")
        out["failsafe_cleared"] = sum(1 for t, x in texts if t > t_lost and "Failsafe Cleared" in x)
        out["gcs_lost_statustext"] = sum(1 for t, x in texts if t > t_lost and "heartbeat lost" in x)
        out["firmware_said_after_loss"] = sorted({x for t, x in texts if t > t_lost and "EKF" not in x})
        if binary is not None:
            out["armed_at_end"] = vehicle.armed
        out["withheld"] = link.stats.gcs_id_withheld
    finally:
        link.close()
        pilot.close()
        router.close()
        if sitl is not None:
            sitl.stop()
        if ap is not None:
            ap.close()
    return out


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--ardusub", default=None)
    p.add_argument("--runs", type=int, default=20)
    p.add_argument("--out", default=None)
    a = p.parse_args()
    logging.getLogger("dip3d_vehicle.link").setLevel(logging.ERROR)
    binary = None
    if a.ardusub:
        from sitl.ardusub_sitl import resolve_binary
        binary = resolve_binary(a.ardusub)
    for i in range(a.runs):
        row = one_run(ENDINGS[i % 3], binary, 80 + i)
        print(json.dumps(row), flush=True)
        if a.out:
            with open(a.out, "a") as f:
                f.write(json.dumps(row) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
