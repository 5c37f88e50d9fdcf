"""A clock-paced TCP reconnect: pymavlink's own one prints and blocks, which a tick-driven link cannot afford.

``VehicleLink`` watches a ``tcp:`` connection for the peer closing it, and from then on tries one reconnect every
``link.reconnect_s`` from its tick, moving the signing state over to the new connection.
"""

from __future__ import annotations

from typing import Any, Callable

from ..clock import Clock
from ..errors import LinkError
from .connection import open_connection
from .link_config import LinkConfig
from .signing import LinkSigning

__all__ = ["TcpReconnect"]


class TcpReconnect:
    """Notice a ``tcp:`` peer closing the connection, then reopen it every ``config.reconnect_s`` seconds."""

    def __init__(self, config: LinkConfig, clock: Clock, signing: LinkSigning, event: Callable[[str], None]) -> None:
        self.config = config
        self.clock = clock
        self._signing = signing
        self._event = event
        self.dead_since_s: float | None = None

    def watch(self, conn: Any) -> None:
        """Replace ``conn``'s print-and-block end-of-file handling by noting the time (clock seconds)."""
        def on_closed() -> None:
            if self.dead_since_s is None:
                self.dead_since_s = self.clock.now()
                self._event(f"tcp connection {self.config.url} closed by the peer")
        conn.handle_eof = on_closed
        conn.handle_disconnect = on_closed

    def reconnected(self, now_s: float, old: Any) -> Any:
        """Return a new connection replacing ``old`` once a reconnect is due and succeeds, else None."""
        if self.dead_since_s is None or now_s - self.dead_since_s < self.config.reconnect_s:
            return None
        c = self.config
        try:
            conn = open_connection(c.url, c.system_id, c.component_id, c.baud)
        except LinkError:
            self.dead_since_s = now_s
            return None
        self._signing.retire(old)
        try:
            old.close()
        except OSError:
            pass
        self.watch(conn)
        self._signing.setup(conn)
        self.dead_since_s = None
        self._event(f"tcp reconnected to {c.url}")
        return conn
