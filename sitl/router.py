"""The simulator's MAVLink router: forwards every message between the autopilot and its clients.

As BlueOS's mavlink-router does on a real vehicle (the autopilot itself routes nothing): the
autopilot is one TCP peer, the ground station (``sim_pilot.SimPilot``) and the controller's
``VehicleLink`` connect as clients on the router's loopback port.
"""

from __future__ import annotations

import socket

from pymavlink.dialects.v20 import ardupilotmega as m2

__all__ = ["Router"]


class _Peer:
    """One socket of the router with its own MAVLink parser."""

    def __init__(self, sock: socket.socket, name: str) -> None:
        sock.setblocking(False)
        self.sock, self.name = sock, name
        self.parser = m2.MAVLink(None)
        self.parser.robust_parsing = True
        self.alive = True

    def read(self) -> list[bytes]:
        """Return the raw bytes of every complete message waiting."""
        out = []
        while self.alive:
            try:
                data = self.sock.recv(65536)
            except (BlockingIOError, InterruptedError):
                break
            except OSError:
                self.alive = False
                break
            if not data:
                self.alive = False
                break
            for msg in self.parser.parse_buffer(data) or []:
                if msg.get_type() != "BAD_DATA":
                    out.append(bytes(msg.get_msgbuf()))
        return out

    def write(self, buf: bytes) -> None:
        """Send bytes (dropped if the peer is gone)."""
        if not self.alive:
            return
        try:
            self.sock.sendall(buf)
        except OSError:
            self.alive = False


class Router:
    """A MAVLink router: the autopilot's TCP port on one side, any number of TCP clients on the other.

    Every message from the autopilot goes to every client; every message from a client goes to the
    autopilot and to the other clients. ``mute_autopilot`` drops everything the autopilot sends
    (its telemetry and HEARTBEAT stop reaching the clients) while still delivering to it.

    Args:
        autopilot_address: ``tcp:HOST:PORT`` of the autopilot.
    """

    def __init__(self, autopilot_address: str) -> None:
        host, port = autopilot_address.split(":")[-2:]
        ap = socket.create_connection((host, int(port)))
        ap.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._serve(ap)

    def _serve(self, autopilot_sock: socket.socket) -> None:
        """Take a connected autopilot socket and open the clients' listening socket (loopback, any port)."""
        self.autopilot = _Peer(autopilot_sock, "autopilot")
        self.server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self.server.bind(("127.0.0.1", 0))
        self.server.listen(8)
        self.server.setblocking(False)
        self.clients: list[_Peer] = []
        self.mute_autopilot = False
        self.dropped_from_autopilot = 0

    @property
    def address(self) -> str:
        """The clients' URL (``tcp:127.0.0.1:PORT``)."""
        return f"tcp:127.0.0.1:{self.server.getsockname()[1]}"

    def accept(self) -> None:
        """Accept the clients waiting to connect."""
        while True:
            try:
                sock, _ = self.server.accept()
            except (BlockingIOError, InterruptedError):
                break
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self.clients.append(_Peer(sock, f"client{len(self.clients)}"))

    def step(self) -> None:
        """Accept new clients and forward everything waiting."""
        self.accept()
        for buf in self.autopilot.read():
            self.tap_autopilot(buf)
            if self.mute_autopilot:
                self.dropped_from_autopilot += 1
                continue
            for c in self.clients:
                c.write(buf)
        for src in self.clients:
            for buf in src.read():
                self.tap_client(buf)
                self.autopilot.write(buf)
                for c in self.clients:
                    if c is not src:
                        c.write(buf)

    def tap_autopilot(self, buf: bytes) -> None:
        """Hook: every buffer the autopilot sent, before it is forwarded (or dropped while muted)."""

    def tap_client(self, buf: bytes) -> None:
        """Hook: every buffer a client sent, before it is forwarded."""

    def close(self) -> None:
        """Close every socket."""
        for p in [self.autopilot, *self.clients]:
            try:
                p.sock.close()
            except OSError:
                pass
        self.server.close()
