"""Test helpers for the link: a small fake ArduSub (plus ground station) on real loopback sockets, driven in lockstep with a SimClock.

The fake follows the ArduSub facts the link relies on (reference/ardusub_mavlink.md): 1 Hz
HEARTBEAT (type 12, autopilot 3, base_mode 0x80 when armed, custom_mode = mode number), ATTITUDE
at the requested rate with time_boot_ms, PARAM_VALUE for SYSID_MYGCS (no reply for MAV_GCS_SYSID,
as 4.5) and COMMAND_ACK for SET_MESSAGE_INTERVAL; it records everything it receives with the sender ids
so the tests can check who sent what. It is not the project's simulator (sitl/); it exists to test the link alone.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from pymavlink import mavutil

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.link import VehicleLink
from dip3d_vehicle.link.connection import gcs_encoder, mavlink2, use_mavlink2
from dip3d_vehicle.servo.command import VelocityCommand

MODES = {"STABILIZE": 0, "ALT_HOLD": 2, "GUIDED": 4, "MANUAL": 19}


@dataclass
class Received:
    """One message the fake received: sim time, type, source ids, and the message itself."""

    t: float
    kind: str
    src: tuple[int, int]
    msg: Any


@dataclass
class FakeAutopilot:
    """Fake ArduSub at (1, 1) with a fake ground station (255, 190) on the same socket."""

    conn: Any
    clock: SimClock
    sysid_mygcs: int = 255
    armed: bool = False
    mode: str = "MANUAL"
    alive: bool = True
    gcs_alive: bool = True
    answer_params: bool = True
    attitude_hz: float = 4.0
    attitude_yaw_rad: float = 0.0
    boot_origin_s: float = 0.0
    received: list[Received] = field(default_factory=list)
    gcs_heartbeats_s: list[float] = field(default_factory=list)
    last_sent_s: float | None = None
    _next_hb: float = 0.0
    _next_att: float = 0.0
    _next_gcs: float = 0.0

    @classmethod
    def udp(cls, clock: SimClock, link_port: int, **kw: Any) -> "FakeAutopilot":
        conn = mavutil.mavlink_connection(f"udpout:127.0.0.1:{link_port}", source_system=1, source_component=1)
        use_mavlink2(conn)
        return cls(conn=conn, clock=clock, **kw)

    @classmethod
    def tcp_server(cls, clock: SimClock, **kw: Any) -> tuple["FakeAutopilot", int]:
        conn = mavutil.mavlink_connection("tcpin:127.0.0.1:0", source_system=1, source_component=1)
        use_mavlink2(conn)
        return cls(conn=conn, clock=clock, **kw), conn.listen.getsockname()[1]

    def sign(self, key: bytes) -> None:
        """Sign what we send and reject unsigned / wrong-key input (as an ArduSub non-serial-0 link)."""
        self.conn.setup_signing(key, sign_outgoing=True)

    @property
    def gcs_mav(self) -> Any:
        enc = getattr(self, "_gcs", None)
        if enc is None:
            enc = self._gcs = gcs_encoder(self.conn, self.sysid_mygcs, 190)
        return enc

    def reboot(self) -> None:
        """Restart: time_boot_ms from zero, disarmed in MANUAL, intervals forgotten."""
        self.boot_origin_s = self.clock.now()
        self.armed, self.mode, self.attitude_hz = False, "MANUAL", 4.0

    def send(self, msg: Any, as_gcs: bool = False) -> None:
        (self.gcs_mav if as_gcs else self.conn.mav).send(msg)
        if not as_gcs:
            self.last_sent_s = self.clock.now()

    def heartbeat(self) -> None:
        base = 81 | (0x80 if self.armed else 0)
        self.send(mavlink2.MAVLink_heartbeat_message(12, 3, base, MODES[self.mode], 4 if self.armed else 3, 3))

    def gcs_heartbeat(self) -> None:
        self.send(mavlink2.MAVLink_heartbeat_message(6, 8, 0, 0, 4, 3), as_gcs=True)
        self.gcs_heartbeats_s.append(self.clock.now())

    def operator(self, enable: bool, as_gcs: bool = True) -> None:
        """MAV_CMD_USER_1 to the controller (1, 191), from the ground station (or from the autopilot's id)."""
        msg = mavlink2.MAVLink_command_long_message(1, 191, 31010, 0, 1.0 if enable else 0.0, 0, 0, 0, 0, 0, 0)
        self.send(msg, as_gcs=as_gcs)

    def update(self) -> None:
        """Send whatever is due at the current sim time."""
        now = self.clock.now()
        if self.alive and now >= self._next_hb:
            self.heartbeat()
            self._next_hb = now + 1.0
        if self.alive and now >= self._next_att:
            boot_ms = int((now - self.boot_origin_s) * 1000)
            self.send(mavlink2.MAVLink_attitude_message(boot_ms, 0, 0, self.attitude_yaw_rad, 0, 0, 0))
            self._next_att = now + 1.0 / self.attitude_hz
        if self.gcs_alive and now >= self._next_gcs:
            self.gcs_heartbeat()
            self._next_gcs = now + 1.0

    def poll(self) -> None:
        """Read everything the link sent; answer params and interval requests like ArduSub."""
        now = self.clock.now()
        while True:
            msg = self.conn.recv_msg()
            if msg is None:
                break
            kind = msg.get_type()
            if kind == "BAD_DATA":
                continue
            self.received.append(Received(now, kind, (msg.get_srcSystem(), msg.get_srcComponent()), msg))
            if not self.alive:
                continue
            if kind == "PARAM_REQUEST_READ" and msg.param_id == "SYSID_MYGCS" and self.answer_params:
                self.send(mavlink2.MAVLink_param_value_message(b"SYSID_MYGCS", float(self.sysid_mygcs), 2, 1, 0))
            elif kind == "COMMAND_LONG" and msg.command == 511:
                if int(msg.param1) == 30:
                    self.attitude_hz = 1e6 / msg.param2
                self.send(mavlink2.MAVLink_command_ack_message(511, 0, 0, 0, msg.get_srcSystem(),
                                                               msg.get_srcComponent()))

    def of(self, kind: str, since: float = -1e9) -> list[Received]:
        return [r for r in self.received if r.kind == kind and r.t >= since]

    def close(self) -> None:
        self.conn.close()


class Harness:
    """The link and the fake in lockstep: each step advances the SimClock by dt, then both sides run."""

    def __init__(self, link: VehicleLink, fake: FakeAutopilot, clock: SimClock) -> None:
        self.link, self.fake, self.clock = link, fake, clock

    def step(self, command: VelocityCommand | None = None, fresh: bool = True, dt: float = 0.01) -> None:
        self.clock.advance(dt)
        self.fake.update()
        self.link.poll()
        self.link.tick(command, fresh)
        self.fake.poll()

    def run(self, seconds: float, command: VelocityCommand | None = None, fresh: bool = True,
            dt: float = 0.01) -> None:
        for _ in range(int(round(seconds / dt))):
            self.step(command, fresh, dt)

    def engage(self, mode: str = "ALT_HOLD", command: VelocityCommand | None = None) -> None:
        """Arm in ``mode``, enable from the ground station, run until engaged (or fail)."""
        self.fake.armed, self.fake.mode = True, mode
        self.fake.heartbeat()
        self.fake.operator(True)
        for _ in range(300):
            self.step(command)
            if self.link.engaged:
                return
        raise AssertionError(f"did not engage: {self.link.not_engaged_reason}; events {self.link.events}")


MOVE = VelocityCommand(surge_m_s=0.3, sway_m_s=0.1, heave_m_s=0.0, yaw_rate_rad_s=0.2)
"""A command that is clearly non-neutral on every horizontal axis."""


def link_params(**over: Any) -> dict[str, Any]:
    """link.* parameters for a loopback test (udpin on an ephemeral port by default)."""
    p: dict[str, Any] = {"link.url": "udpin:127.0.0.1:0"}
    p.update({f"link.{k.replace('__', '.')}": v for k, v in over.items()})
    return p
