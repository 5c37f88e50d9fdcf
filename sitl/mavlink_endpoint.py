"""MAVLink 2 sockets of the simulated autopilot: loopback TCP and UDP listeners, one link per peer.

Every accepted TCP client and every UDP listen address is a ``Link`` with its own pymavlink parser,
sequence numbers, signing state and message intervals (as ArduPilot's serial ports are). Reading
never blocks: ``Endpoint.poll()`` accepts pending clients and drains each socket until EAGAIN, so a
lockstep loop sees a loopback packet sent in one step in the next one.

Signing: with a key, a link drops unsigned and wrongly signed messages (counted in
``Link.dropped_unsigned``), except the serial-0-like link (the first TCP listen address), which
accepts unsigned ones when ``serial0_accepts_unsigned``; a link signs what it sends once a correctly
signed message arrived on it (non-serial-0 links always sign).
"""

from __future__ import annotations

import errno
import socket
import time
from dataclasses import dataclass, field
from typing import Any, Callable

from pymavlink.dialects.v20 import ardupilotmega as mavlink2

from dip3d_vehicle.errors import LinkError

__all__ = ["Link", "Endpoint", "parse_listen_url", "signing_timestamp"]

_MAX_TX_BYTES = 1 << 20
_SIGNING_EPOCH_S = 1420070400  # 2015-01-01, MAVLink signing timestamps count 10 us from here


def signing_timestamp() -> int:
    """Return a MAVLink signing timestamp for now (10 us units since 2015; protocol metadata only)."""
    return int((time.time() - _SIGNING_EPOCH_S) * 100_000)


def parse_listen_url(url: str) -> tuple[str, str, int]:
    """Parse ``tcp:HOST:PORT`` / ``tcpin:`` / ``udp:`` / ``udpin:`` into (kind, host, port).

    Raises:
        LinkError: the URL is not one of these forms.
    """
    scheme, _, rest = url.partition(":")
    host, _, port = rest.rpartition(":")
    kinds = {"tcp": "tcp", "tcpin": "tcp", "udp": "udp", "udpin": "udp"}
    if scheme not in kinds or not host or not port.isdigit():
        raise LinkError(f"--listen {url!r}: expected tcp:HOST:PORT or udpin:HOST:PORT")
    return kinds[scheme], host, int(port)


class _Writer:
    """File-like object pymavlink writes packed messages to; the link flushes it to the socket."""

    def __init__(self, link: "Link") -> None:
        self.link = link

    def write(self, buf: bytes) -> None:
        self.link._queue(bytes(buf))


@dataclass(eq=False)
class Link:
    """One MAVLink peer connection (a TCP client, or a UDP listen address and its last sender)."""

    name: str
    kind: str
    sock: socket.socket
    sysid: int
    compid: int
    accepts_unsigned: bool = True
    udp_peer: tuple[str, int] | None = None
    closed: bool = False
    dropped_unsigned: int = 0
    intervals_s: dict[int, float | None] = field(default_factory=dict)
    next_due_s: dict[int, float] = field(default_factory=dict)
    _tx: bytearray = field(default_factory=bytearray)
    mav: Any = None

    def __post_init__(self) -> None:
        self.mav = mavlink2.MAVLink(_Writer(self), srcSystem=self.sysid, srcComponent=self.compid)
        self.mav.robust_parsing = True

    def set_signing(self, key: bytes | None, link_id: int, always_sign: bool) -> None:
        """Configure signing on this link (``key`` None or all zero turns it off)."""
        sig = self.mav.signing
        if key is None or not any(key):
            sig.secret_key, sig.sign_outgoing, sig.allow_unsigned_callback = None, False, None
            return
        sig.secret_key = bytes(key)
        sig.link_id = link_id & 0xFF
        sig.timestamp = max(sig.timestamp, signing_timestamp())
        sig.sign_outgoing = always_sign
        seen = {"bad": sig.badsig_count}

        def allow_unsigned(mav: Any, msg_id: int) -> bool:
            wrong_key = mav.signing.badsig_count != seen["bad"]
            seen["bad"] = mav.signing.badsig_count
            return self.accepts_unsigned and not wrong_key
        sig.allow_unsigned_callback = allow_unsigned

    def send(self, msg: Any) -> None:
        """Send one message (signed when the link signs); dropped silently when nobody listens."""
        if self.closed or (self.kind == "udp" and self.udp_peer is None):
            return
        self.mav.send(msg)
        self.flush()

    def _queue(self, buf: bytes) -> None:
        if len(self._tx) + len(buf) > _MAX_TX_BYTES:  # a peer that does not read: drop, as a UART would
            return
        self._tx.extend(buf)

    def flush(self) -> None:
        """Write queued bytes until the socket would block."""
        while self._tx and not self.closed:
            try:
                if self.kind == "udp":
                    self.sock.sendto(bytes(self._tx), self.udp_peer)
                    self._tx.clear()
                else:
                    n = self.sock.send(self._tx)
                    del self._tx[:n]
            except BlockingIOError:
                return
            except OSError:
                if self.kind == "tcp":
                    self.close()
                else:
                    self._tx.clear()
                return

    def receive(self) -> list[Any]:
        """Drain the socket (non-blocking) and return the decoded, accepted messages."""
        out: list[Any] = []
        while not self.closed:
            try:
                if self.kind == "udp":
                    data, addr = self.sock.recvfrom(65536)
                    self.udp_peer = addr
                else:
                    data = self.sock.recv(65536)
                    if not data:
                        self.close()
                        break
            except (BlockingIOError, InterruptedError):
                break
            except OSError as exc:
                if exc.errno in (errno.EAGAIN, errno.EWOULDBLOCK):
                    break
                if self.kind == "tcp":
                    self.close()
                break
            out.extend(self._parse(data))
        return out

    def _parse(self, data: bytes) -> list[Any]:
        msgs = self.mav.parse_buffer(data) or []
        good = []
        for m in msgs:
            if m.get_type() == "BAD_DATA":
                if "signature" in str(getattr(m, "reason", "")).lower():
                    self.dropped_unsigned += 1
                continue
            if m.get_signed() and self.mav.signing.secret_key is not None:
                self.mav.signing.sign_outgoing = True
            good.append(m)
        return good

    def close(self) -> None:
        """Close the link (TCP client sockets only; UDP listen sockets belong to the endpoint)."""
        if not self.closed:
            self.closed = True
            if self.kind == "tcp":
                try:
                    self.sock.close()
                except OSError:
                    pass


class Endpoint:
    """Listening sockets and their links; ``poll()`` returns (link, message) pairs in arrival order."""

    def __init__(self, listen: list[str], sysid: int = 1, compid: int = 1,
                 signing_key: bytes | None = None, serial0_accepts_unsigned: bool = True) -> None:
        self.sysid, self.compid = sysid, compid
        self.signing_key = signing_key
        self.serial0_accepts_unsigned = serial0_accepts_unsigned
        self.links: list[Link] = []
        self._listeners: list[tuple[socket.socket, str]] = []
        self.addresses: list[str] = []
        self._next_link_id = 0
        self._dropped_closed = 0
        self.on_new_link: Callable[[Link], None] | None = None
        try:
            for url in listen:
                self._open(url)
        except OSError as exc:
            self.close()
            raise LinkError(f"--listen {url!r}: cannot bind ({exc.strerror or exc})") from None

    def _open(self, url: str) -> None:
        kind, host, port = parse_listen_url(url)
        if kind == "tcp":
            s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            s.bind((host, port))
            s.listen(8)
            s.setblocking(False)
            serial0 = not any(k == "tcp" for _, k in self._listeners)
            self._listeners.append((s, "tcp0" if serial0 else "tcp"))
            self.addresses.append(f"tcp:{host}:{s.getsockname()[1]}")
        else:
            s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            s.bind((host, port))
            s.setblocking(False)
            self._listeners.append((s, "udp"))
            self.addresses.append(f"udpin:{host}:{s.getsockname()[1]}")
            self._add_link(Link(f"udp:{host}:{s.getsockname()[1]}", "udp", s, self.sysid, self.compid), False)

    def _add_link(self, link: Link, serial0: bool) -> None:
        link.accepts_unsigned = serial0 and self.serial0_accepts_unsigned
        link.set_signing(self.signing_key, self._next_link_id, always_sign=not link.accepts_unsigned)
        self._next_link_id += 1
        self.links.append(link)
        if self.on_new_link:
            self.on_new_link(link)

    def set_signing_key(self, key: bytes | None) -> None:
        """Set (or clear, with None / all zeros) the one signing key of every link."""
        self.signing_key = key if key and any(key) else None
        for i, link in enumerate(self.links):
            link.set_signing(self.signing_key, i, always_sign=not link.accepts_unsigned)

    def poll(self) -> list[tuple[Link, Any]]:
        """Accept new TCP clients and read every link without blocking."""
        for s, kind in self._listeners:
            if kind == "udp":
                continue
            while True:
                try:
                    conn, addr = s.accept()
                except (BlockingIOError, InterruptedError):
                    break
                except OSError:
                    break
                conn.setblocking(False)
                conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                self._add_link(Link(f"tcp:{addr[0]}:{addr[1]}", "tcp", conn, self.sysid, self.compid),
                               kind == "tcp0")
        out = []
        for link in list(self.links):
            for msg in link.receive():
                out.append((link, msg))
            link.flush()
        for lk in self.links:
            if lk.closed:
                self._dropped_closed += lk.dropped_unsigned
        self.links = [lk for lk in self.links if not lk.closed]
        return out

    def broadcast(self, msg: Any) -> None:
        """Send a message on every link."""
        for link in self.links:
            link.send(msg)

    @property
    def dropped_unsigned(self) -> int:
        """Messages dropped for a missing or wrong signature, over every link (closed ones too)."""
        return self._dropped_closed + sum(lk.dropped_unsigned for lk in self.links)

    def close(self) -> None:
        """Close every link and listening socket."""
        for link in self.links:
            link.close()
        for s, _ in self._listeners:
            try:
                s.close()
            except OSError:
                pass
        self.links, self._listeners = [], []
