"""Fixtures for the simulator tests: an autopilot on a free loopback port, a pymavlink client, and a
lockstep loop that advances a SimClock so that timeouts of seconds cost no wall time."""

from __future__ import annotations

import os
from typing import Any, Callable, Iterator

import pytest
from pymavlink import mavutil

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.config import load_params
from sitl.autopilot import Autopilot

GCS_SYSID, GCS_COMPID = 255, 190


class Lockstep:
    """A SimClock, an Autopilot and pymavlink clients stepped together at ``dt_s``."""

    def __init__(self, ap: Autopilot, clock: SimClock, dt_s: float = 0.01) -> None:
        self.ap, self.clock, self.dt_s = ap, clock, dt_s
        self.clients: list[Any] = []
        self.received: dict[int, list[Any]] = {}

    def connect(self, url: str | None = None, sysid: int = GCS_SYSID, compid: int = GCS_COMPID) -> Any:
        """Open a pymavlink client to the autopilot (default: its first TCP address)."""
        url = url or self.ap.addresses[0]
        if url.startswith("udpin:"):
            url = "udpout:" + url[len("udpin:"):]
        old = os.environ.get("MAVLINK20")
        os.environ["MAVLINK20"] = "1"  # MAVLink 2 client (signing), as ArduSub speaks
        try:
            conn = mavutil.mavlink_connection(url, source_system=sysid, source_component=compid,
                                              dialect="ardupilotmega", autoreconnect=False)
        finally:
            if old is None:
                os.environ.pop("MAVLINK20", None)
            else:
                os.environ["MAVLINK20"] = old
        conn.mav.robust_parsing = True
        self.clients.append(conn)
        self.received[id(conn)] = []
        if url.startswith("udpout:"):  # the autopilot learns a UDP peer from its first packet
            conn.mav.heartbeat_send(mavutil.mavlink.MAV_TYPE_GCS, mavutil.mavlink.MAV_AUTOPILOT_INVALID, 0, 0, 0)
        self.step()
        return conn

    def step(self) -> None:
        """One lockstep tick: advance the clock, step the autopilot, drain every client."""
        self.clock.advance(self.dt_s)
        self.ap.step()
        for conn in self.clients:
            while True:
                m = conn.recv_match(blocking=False)
                if m is None:
                    break
                if m.get_type() != "BAD_DATA":
                    self.received[id(conn)].append(m)

    def run(self, seconds: float, every: Callable[[float], None] | None = None) -> None:
        """Run for ``seconds`` of simulated time, calling ``every(t)`` before each tick."""
        n = int(round(seconds / self.dt_s))
        for _ in range(n):
            if every is not None:
                every(self.clock.now())
            self.step()

    def run_until(self, cond: Callable[[], bool], timeout_s: float = 10.0) -> bool:
        """Step until ``cond()`` holds or ``timeout_s`` of simulated time passed."""
        end = self.clock.now() + timeout_s
        while self.clock.now() < end:
            if cond():
                return True
            self.step()
        return cond()

    def messages(self, conn: Any, kind: str | None = None) -> list[Any]:
        """Everything a client received so far (of one type)."""
        msgs = self.received[id(conn)]
        return [m for m in msgs if kind is None or m.get_type() == kind]

    def clear(self, conn: Any) -> None:
        """Forget what a client received so far."""
        self.received[id(conn)].clear()

    def close(self) -> None:
        for conn in self.clients:
            conn.close()
        self.ap.close()


def make_autopilot(overrides: dict | None = None, **kwargs: Any) -> tuple[Autopilot, SimClock]:
    """Return an Autopilot on a SimClock listening on free loopback ports (tcp, then udp)."""
    params = load_params(overrides=overrides or {})
    clock = SimClock(1000.0)
    kwargs.setdefault("listen", ["tcp:127.0.0.1:0", "udpin:127.0.0.1:0"])
    return Autopilot(params, clock, **kwargs), clock


@pytest.fixture
def lockstep_factory() -> Iterator[Callable[..., Lockstep]]:
    """Return a factory ``(overrides=None, **Autopilot kwargs) -> Lockstep``; closes everything after."""
    made: list[Lockstep] = []

    def factory(overrides: dict | None = None, dt_s: float = 0.01, **kwargs: Any) -> Lockstep:
        ap, clock = make_autopilot(overrides, **kwargs)
        ls = Lockstep(ap, clock, dt_s)
        made.append(ls)
        return ls
    yield factory
    for ls in made:
        ls.close()


@pytest.fixture
def sim(lockstep_factory: Callable[..., Lockstep]) -> Lockstep:
    """A pool vehicle without DVL, pilot-input failsafe off (SITL-like), at 3 m depth."""
    return lockstep_factory({"sim.pilot_input_failsafe": False, "sim.initial_depth_m": 3.0})

