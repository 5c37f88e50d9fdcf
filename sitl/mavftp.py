"""MAVLink FTP (FILE_TRANSFER_PROTOCOL) as ArduSub answers it, for what ground stations ask at connect.

MAVProxy (and Mission Planner) fetch the parameters at connect by MAVLink FTP: they open
``@PARAM/param.pck`` (``?withdefaults=1`` adds the defaults), read it with BurstReadFile and
terminate the session; without an answer MAVProxy prints "FTP: request timed out" and falls back to
PARAM_REQUEST_LIST. ArduPilot's server (``GCS_FTP.cpp`` + ``AP_Filesystem_Param``) serves that
virtual file; this one does the same for the simulated vehicle's parameters:

- OpenFileRO: Ack with the file size (uint32) for ``@PARAM/param.pck``; any other path is Nack
  FailErrno ENOENT (the simulated vehicle has no SD card).
- ReadFile / BurstReadFile: the bytes at the offset (239 per packet, or the size asked for; a
  burst runs to the end of the file, its last packet flagged ``burst_complete``); past the end,
  Nack EndOfFile.
- TerminateSession / ResetSessions: Ack; ListDirectory: Nack EndOfFile (no files to list);
  anything else (writing, removing, CRC): Nack UnknownCommand.

Every reply carries the request's session and opcode (``req_opcode``) and ``seq`` = request + 1;
a repeated request (same seq) gets the same reply again, as ArduPilot does for lost replies.

``param_pck`` writes ArduPilot's packed parameter format: a header ``<HHH`` (magic 0x671b, or
0x671c with defaults; parameter count; total count), then per parameter one type byte (low 4 bits:
4 = float; bit 4: a default follows), one byte ``(suffix length - 1) << 4 | common prefix length``
with the previous name, the name's suffix, the value and, if flagged, the default.
"""

from __future__ import annotations

import errno
import struct
from dataclasses import dataclass, field
from typing import Callable, Mapping

__all__ = ["FtpServer", "param_pck", "PARAM_FILE", "OP", "ERR"]

PARAM_FILE = "@PARAM/param.pck"
MAX_DATA = 239
_HDR = struct.Struct("<HBBBBBBI")


class OP:
    """MAVLink FTP opcodes."""

    NONE, TERMINATE_SESSION, RESET_SESSIONS, LIST_DIRECTORY, OPEN_FILE_RO, READ_FILE = 0, 1, 2, 3, 4, 5
    BURST_READ_FILE, LIST_DIRECTORY_WITH_TIME, ACK, NACK = 15, 16, 128, 129


class ERR:
    """MAVLink FTP error codes (first byte of a Nack's data)."""

    NONE, FAIL, FAIL_ERRNO, INVALID_DATA_SIZE, INVALID_SESSION, NO_SESSIONS, EOF, UNKNOWN_COMMAND = range(8)


def param_pck(values: Mapping[str, float], defaults: Mapping[str, float] | None = None) -> bytes:
    """Return the parameters in ArduPilot's ``param.pck`` format (all as float), sorted by name."""
    names = sorted(values)
    out = bytearray(struct.pack("<HHH", 0x671C if defaults is not None else 0x671B, len(names), len(names)))
    last = b""
    for name in names:
        raw = name.encode()[:16]
        common = 0
        while common < min(len(last), len(raw) - 1, 15) and last[common] == raw[common]:
            common += 1
        suffix = raw[common:]
        value = float(values[name])
        default = None if defaults is None else float(defaults.get(name, value))
        flagged = default is not None and default != value
        out += bytes([4 | (0x10 if flagged else 0), (len(suffix) - 1) << 4 | common]) + suffix
        out += struct.pack("<f", value) + (struct.pack("<f", default) if flagged else b"")
        last = raw
    return bytes(out)


@dataclass
class _Session:
    data: bytes


@dataclass
class FtpServer:
    """The vehicle's FTP server.

    Args:
        params: returns the current parameter values (read when the file is opened).
        defaults: the parameters' default values.
    """

    params: Callable[[], Mapping[str, float]]
    defaults: Mapping[str, float]
    sessions: dict[int, _Session] = field(default_factory=dict)
    _last: dict[tuple[int, int], tuple[int, list[bytes]]] = field(default_factory=dict)

    def handle(self, sender: tuple[int, int], payload: bytes) -> list[bytes]:
        """Return the reply payloads (251 bytes each) to one request payload from ``sender`` (sysid, compid)."""
        if len(payload) < _HDR.size:
            return []
        seq, session, opcode, size, _, _, _, offset = _HDR.unpack_from(payload)
        last = self._last.get(sender)
        if last is not None and last[0] == seq and opcode != OP.BURST_READ_FILE:
            return last[1]  # the client lost our reply and repeats the request
        data = bytes(payload[_HDR.size:_HDR.size + size])
        replies = [_pack(seq + 1, session, code, opcode, off, body, complete)
                   for code, off, body, complete in self._answer(session, opcode, size, offset, data)]
        self._last[sender] = (seq, replies)
        return replies

    def _answer(self, session: int, opcode: int, size: int, offset: int,
                data: bytes) -> list[tuple[int, int, bytes, int]]:
        """Return (ack/nack, offset, data, burst_complete) of every reply to one request."""
        if opcode == OP.TERMINATE_SESSION:
            self.sessions.pop(session, None)
            return [(OP.ACK, 0, b"", 0)]
        if opcode == OP.RESET_SESSIONS:
            self.sessions.clear()
            return [(OP.ACK, 0, b"", 0)]
        if opcode in (OP.LIST_DIRECTORY, OP.LIST_DIRECTORY_WITH_TIME):
            return [(OP.NACK, offset, bytes([ERR.EOF]), 0)]
        if opcode == OP.OPEN_FILE_RO:
            return [self._open(session, data)]
        if opcode in (OP.READ_FILE, OP.BURST_READ_FILE):
            s = self.sessions.get(session)
            if s is None:
                return [(OP.NACK, offset, bytes([ERR.INVALID_SESSION]), 1)]
            return self._read(s.data, offset, size or MAX_DATA, burst=opcode == OP.BURST_READ_FILE)
        return [(OP.NACK, offset, bytes([ERR.UNKNOWN_COMMAND]), 0)]

    def _open(self, session: int, data: bytes) -> tuple[int, int, bytes, int]:
        """Open ``@PARAM/param.pck`` (``?withdefaults=1``) read-only; any other path is not found."""
        path, _, query = data.split(b"\0")[0].decode(errors="replace").partition("?")
        if path != PARAM_FILE:
            return OP.NACK, 0, bytes([ERR.FAIL_ERRNO, errno.ENOENT]), 0
        body = param_pck(self.params(), self.defaults if "withdefaults=1" in query else None)
        self.sessions[session] = _Session(body)
        return OP.ACK, 0, struct.pack("<I", len(body)), 0

    @staticmethod
    def _read(body: bytes, offset: int, size: int, burst: bool) -> list[tuple[int, int, bytes, int]]:
        """Return one packet (ReadFile) or packets to the end (BurstReadFile) from ``offset``."""
        step = min(max(size, 1), MAX_DATA)
        if offset >= len(body):
            return [(OP.NACK, offset, bytes([ERR.EOF]), 1 if burst else 0)]
        if not burst:
            return [(OP.ACK, offset, body[offset:offset + step], 0)]
        out = []
        for ofs in range(offset, len(body), step):
            chunk = body[ofs:ofs + step]
            out.append((OP.ACK, ofs, chunk, 1 if ofs + step >= len(body) else 0))
        return out


def _pack(seq: int, session: int, opcode: int, req_opcode: int, offset: int, body: bytes, complete: int) -> bytes:
    """Return one 251-byte FTP payload."""
    hdr = _HDR.pack(seq & 0xFFFF, session, opcode, len(body), req_opcode, complete, 0, offset)
    return (hdr + body).ljust(251, b"\0")
