"""A tiny MAVLink 2 endpoint on a raw socket, for talking to the ArduSub SITL (probes, conformance).

Not the controller's link (that is ``dip3d_vehicle.link.VehicleLink``): a test-side client that can
speak as any system/component id and keeps everything it received, stamped with the vehicle's
``time_boot_ms`` where the message has one.
"""

from __future__ import annotations

import socket
import time
from typing import Any, Callable

from pymavlink.dialects.v20 import ardupilotmega as m2

__all__ = ["MavSocket"]


class MavSocket:
    """Send as (sysid, compid) on ``sock``; ``pump()`` reads everything waiting into ``received``."""

    def __init__(self, sock: socket.socket, sysid: int = 255, compid: int = 190) -> None:
        sock.setblocking(False)
        self.sock = sock
        self.parser = m2.MAVLink(None)
        self.parser.robust_parsing = True
        self.encoders: dict[tuple[int, int], Any] = {}
        self.sysid, self.compid = sysid, compid
        self.received: list[tuple[float, Any]] = []
        self.boot_ms = 0

    def encoder(self, sysid: int | None = None, compid: int | None = None) -> Any:
        """The MAVLink 2 encoder for (sysid, compid) (default: this endpoint's ids)."""
        key = (self.sysid if sysid is None else sysid, self.compid if compid is None else compid)
        if key not in self.encoders:
            self.encoders[key] = m2.MAVLink(None, srcSystem=key[0], srcComponent=key[1])
        return self.encoders[key]

    def send(self, msg: Any, sysid: int | None = None, compid: int | None = None) -> None:
        """Encode ``msg`` as (sysid, compid) and send it."""
        buf = msg.pack(self.encoder(sysid, compid))
        self.sock.sendall(buf)

    def pump(self) -> list[Any]:
        """Read and parse everything waiting; return the new messages."""
        new = []
        while True:
            try:
                data = self.sock.recv(65536)
            except (BlockingIOError, InterruptedError):
                break
            if not data:
                raise ConnectionError("the firmware closed the connection")
            for msg in self.parser.parse_buffer(data) or []:
                if msg.get_type() == "BAD_DATA":
                    continue
                boot = getattr(msg, "time_boot_ms", None)
                if boot is not None and msg.get_srcSystem() == 1:
                    self.boot_ms = max(self.boot_ms, int(boot))
                new.append(msg)
        now = time.monotonic()
        self.received += [(now, m) for m in new]
        return new

    def wait(self, pred: Callable[[Any], bool], timeout_s: float, tick: Callable[[], None] | None = None) -> Any:
        """Pump until a message satisfies ``pred`` (returned) or ``timeout_s`` passes (None)."""
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            for m in self.pump():
                if pred(m):
                    return m
            if tick is not None:
                tick()
            time.sleep(0.01)
        return None

    def command(self, command: int, *params: float, target: tuple[int, int] = (1, 1)) -> None:
        """COMMAND_LONG to ``target``."""
        p = list(params) + [0.0] * (7 - len(params))
        self.send(m2.MAVLink_command_long_message(target[0], target[1], command, 0, *p))

    def heartbeat(self) -> None:
        """A GCS HEARTBEAT from this endpoint's ids."""
        self.send(m2.MAVLink_heartbeat_message(m2.MAV_TYPE_GCS, m2.MAV_AUTOPILOT_INVALID, 0, 0, 4, 3))
