"""``--foxglove HOST:PORT``: the run record's channels, live, over Foxglove's WebSocket protocol.

Uses foxglove-sdk's server (Rust, in the wheel) with its own context, so nothing else in the process
logs to it. Every message written to ``run.mcap`` is mirrored here with the same topic, schema and
log time (``RunRecorder`` sets ``McapRunWriter.mirror``); a Foxglove app connects to
``ws://HOST:PORT``. The server offers no services and accepts no client publishing: read-only.
It binds to 127.0.0.1 unless an address is given.
"""

from __future__ import annotations

import threading
from typing import Any

from ..errors import Dip3dError
from ..record.topics import topic

__all__ = ["FoxgloveLive"]


class FoxgloveLive:
    """A Foxglove WebSocket server publishing the run record's topics.

    Args:
        host, port: where to listen (port 0 = any free port; see ``port``).
        name: the server name shown in Foxglove.
        topics: topics to advertise at start (others appear when first published).

    Raises:
        Dip3dError: the server cannot start (address in use, ...).
    """

    def __init__(self, host: str = "127.0.0.1", port: int = 8765, name: str = "dip3d-vehicle",
                 topics: tuple[str, ...] = ()) -> None:
        import foxglove

        self._foxglove = foxglove
        self._context = foxglove.Context()
        self._lock = threading.Lock()
        self._channels: dict[str, Any] = {}
        self.published = 0
        try:
            self._server = foxglove.start_server(name=name, host=host, port=port, context=self._context)
        except Exception as exc:  # noqa: BLE001 - the SDK raises its own error types
            raise Dip3dError(f"--foxglove {host}:{port}: cannot start the WebSocket server ({exc})") from None
        self.host, self.port = host, self._server.port
        for name_ in topics:
            self._channel(name_)

    @property
    def url(self) -> str:
        """The address a Foxglove app opens."""
        return f"ws://{self.host}:{self.port}"

    def _channel(self, name: str) -> Any:
        ch = self._channels.get(name)
        if ch is None:
            t = topic(name)
            schema = self._foxglove.Schema(name=t.schema_name, encoding=t.schema_encoding, data=t.schema_data)
            ch = self._channels[name] = self._foxglove.Channel(name, schema=schema, message_encoding=t.message_encoding,
                                                                context=self._context)
        return ch

    def publish(self, name: str, data: bytes, log_time_ns: int) -> None:
        """Send one encoded message on ``name`` to every subscribed client."""
        with self._lock:
            ch = self._channel(name)
        ch.log(bytes(data), log_time=int(log_time_ns))
        self.published += 1

    def close(self) -> None:
        """Stop the server."""
        self._server.stop()
