"""``mav.tlog``: every MAVLink message the controller sends and receives, in pymavlink's telemetry log
format (8-byte big-endian microseconds since the epoch, then the message's bytes as on the wire), so
MAVProxy, MAVExplorer and ``mavutil.mavlink_connection(path)`` replay the link.

Each message goes to the OS in one ``os.write`` on an ``O_APPEND`` descriptor: a killed process loses
nothing it recorded.
"""

from __future__ import annotations

import os
import struct
import threading
from pathlib import Path
from typing import Any

from ..errors import LogError

__all__ = ["TlogWriter"]


class TlogWriter:
    """Append MAVLink messages with their time to a new ``.tlog`` file.

    Args:
        path: file to create (replaced when ``overwrite``).

    Raises:
        LogError: the file cannot be created.
    """

    def __init__(self, path: str | Path, overwrite: bool = False) -> None:
        self.path = Path(path)
        flags = os.O_WRONLY | os.O_CREAT | os.O_APPEND | (os.O_TRUNC if overwrite else os.O_EXCL)
        try:
            self._fd: int | None = os.open(self.path, flags, 0o644)
        except FileExistsError:
            raise LogError(f"{self.path}: telemetry log already exists (refusing to overwrite it)") from None
        except OSError as exc:
            raise LogError(f"{self.path}: cannot create telemetry log ({exc.strerror})") from None
        self._lock = threading.Lock()
        self.counts = {"sent": {}, "received": {}}
        self.write_errors = 0

    def write(self, msg: Any, usec: int, direction: str) -> None:
        """Record one message (``direction`` "sent" or "received") at ``usec`` since the epoch."""
        buf = msg.get_msgbuf() if hasattr(msg, "get_msgbuf") else None
        if not buf or msg.get_type() == "BAD_DATA":
            return
        data = struct.pack(">Q", int(usec)) + bytes(buf)
        with self._lock:
            if self._fd is None:
                return
            try:
                os.write(self._fd, data)
            except OSError:
                self.write_errors += 1
                return
            kind = self.counts[direction]
            kind[msg.get_type()] = kind.get(msg.get_type(), 0) + 1

    def close(self) -> None:
        """Fsync and close; safe to call twice."""
        with self._lock:
            fd, self._fd = self._fd, None
        if fd is not None:
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
