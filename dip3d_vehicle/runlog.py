"""The run log: an append-only, crash-safe binary file of what a run saw and did.

Every ``run`` and ``sitl`` writes one. The file is a sequence of records::

    offset  size  field
    0       4     sync     b"\\x89DLG"
    4       1     type     b"H" header, b"F" frame, b"T" telemetry, b"E" event, b"I" images
    5       4     length   payload bytes, uint32 little-endian
    9       4     crc32    zlib.crc32 of bytes 4..8 (type + length) followed by the payload
    13      n     payload  UTF-8 JSON (H, F, T, E) or an image pair (I, below)

An image-pair payload is ``uint32 LE json_len`` + JSON ``{"frame_index", "format", "left_bytes",
"right_bytes"}`` + the left then the right encoded image (JPEG or PNG from cv2.imencode).

The first record is the header: ``{"format": "dip3d-vehicle-runlog", "version": 1,
"created_utc", "params", "meta"}``. Each record goes to the OS in one ``os.write`` on an
``O_APPEND`` descriptor (a crashed process loses nothing it logged) and the file is fsynced every
``runlog.fsync_every_records`` records or ``runlog.fsync_every_s`` seconds (power loss loses at most
that). The reader stops cleanly at a partially written tail and resynchronises on the sync bytes
after a corrupt record in the middle, counting what it skipped.

Recommended frame record keys (the writer takes any JSON-able dict): ``index``, ``stamp_s``,
``status``, ``arm``, ``candidates``, ``target``, ``selection``, ``state``, ``setpoint``,
``timings_ms``. The writer adds ``wall_s`` (time.time()) to frame, telemetry and event records.
"""

from __future__ import annotations

import dataclasses
import enum
import json
import math
import mmap
import os
import struct
import threading
import time
import zlib
from pathlib import Path
from typing import Any, Iterator, Mapping, NamedTuple

import cv2
import numpy as np

from .errors import LogError

__all__ = ["RunLogWriter", "RunLogReader", "Record", "to_jsonable", "SYNC", "FORMAT", "VERSION"]

SYNC = b"\x89DLG"
FORMAT = "dip3d-vehicle-runlog"
VERSION = 1
_HEAD = struct.Struct("<4scI I")  # sync, type, length, crc
_HEAD_SIZE = _HEAD.size  # 13
_MAX_PAYLOAD = 1 << 30
_TYPES = {b"H": "header", b"F": "frame", b"T": "telemetry", b"E": "event", b"I": "images"}


def to_jsonable(value: Any) -> Any:
    """Return ``value`` as plain JSON data: numpy to lists/numbers, NaN/inf to None, tuples to lists.

    Dataclasses become dicts, enums their value, paths strings; anything else unknown is its str().
    """
    if value is None or isinstance(value, (bool, str, int)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Mapping):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return to_jsonable(value.tolist())
    if isinstance(value, np.generic):
        return to_jsonable(value.item())
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: to_jsonable(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, enum.Enum):
        return to_jsonable(value.value)
    if isinstance(value, (set, frozenset)):
        return [to_jsonable(v) for v in sorted(value, key=str)]
    return str(value)


def _pack(kind: bytes, payload: bytes) -> bytes:
    """Return one whole record (header + payload) of type ``kind``."""
    type_len = kind + struct.pack("<I", len(payload))
    crc = zlib.crc32(payload, zlib.crc32(type_len))
    return SYNC + type_len + struct.pack("<I", crc) + payload


def _json_bytes(obj: Any) -> bytes:
    return json.dumps(to_jsonable(obj), separators=(",", ":"), allow_nan=False).encode("utf-8")


class RunLogWriter:
    """Append records to a new run log; every record reaches the OS before the call returns.

    Args:
        path: log file to create (an existing file is an error unless ``overwrite``).
        params: effective parameters (a mapping; ``runlog.*`` keys configure the writer) stored
            whole in the header record, or None for the schema defaults.
        meta: extras for the header (command line, source spec, calibration file, software version).
        keep_images_every, image_format, jpeg_quality, png_compression, fsync_every_s,
        fsync_every_records: override the ``runlog.*`` parameters.
        overwrite: replace an existing file.

    Raises:
        LogError: the file cannot be created or written.
    """

    def __init__(self, path: str | Path, params: Mapping[str, Any] | None = None,
                 meta: Mapping[str, Any] | None = None, *, keep_images_every: int | None = None,
                 image_format: str | None = None, jpeg_quality: int | None = None,
                 png_compression: int | None = None, fsync_every_s: float | None = None,
                 fsync_every_records: int | None = None, overwrite: bool = False) -> None:
        self.path = Path(path)
        given = dict(keep_images_every=keep_images_every, image_format=image_format,
                     jpeg_quality=jpeg_quality, png_compression=png_compression,
                     fsync_every_s=fsync_every_s, fsync_every_records=fsync_every_records)
        self.settings = _runlog_settings(params, given)
        self._lock = threading.Lock()
        self._images_calls = 0
        self._since_sync = 0
        self._last_sync = time.monotonic()
        self.records_written = 0
        flags = os.O_WRONLY | os.O_CREAT | os.O_APPEND | (os.O_TRUNC if overwrite else os.O_EXCL)
        try:
            self._fd: int | None = os.open(self.path, flags, 0o644)
        except FileExistsError:
            raise LogError(f"{self.path}: run log already exists (refusing to overwrite it)") from None
        except OSError as exc:
            raise LogError(f"{self.path}: cannot create run log ({exc.strerror})") from None
        header = {"format": FORMAT, "version": VERSION,
                  "created_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
                  "runlog": self.settings, "params": dict(params) if params is not None else {},
                  "meta": dict(meta or {})}
        self._write(b"H", _json_bytes(header), sync=True)

    # -- records ---------------------------------------------------------------------------
    def frame(self, record: Mapping[str, Any]) -> None:
        """Log one frame's record (timestamps, arm keypoints, candidates, selection, state, setpoint)."""
        self._write(b"F", _json_bytes(_stamped(record)))

    def telemetry(self, record: Mapping[str, Any]) -> None:
        """Log one telemetry sample from the autopilot (mode, armed, attitude, depth, ...)."""
        self._write(b"T", _json_bytes(_stamped(record)))

    def event(self, text: str, **fields: Any) -> None:
        """Log an event (state change, mode change, error, ...) with optional fields."""
        self._write(b"E", _json_bytes(_stamped({"text": str(text), **fields})))

    def wants_images(self) -> bool:
        """Return True when the next ``images()`` call will keep its pair (every Nth call)."""
        n = self.settings["keep_images_every"]
        return n > 0 and self._images_calls % n == 0

    def images(self, frame_index: int, left: np.ndarray, right: np.ndarray, force: bool = False) -> bool:
        """Keep a stereo pair (every ``keep_images_every``-th call, or always with ``force``).

        Returns:
            True when the pair was written.
        """
        keep = force or self.wants_images()
        self._images_calls += 1
        if not keep:
            return False
        fmt = self.settings["image_format"]
        encoded = [self._encode(image, fmt, side) for image, side in ((left, "left"), (right, "right"))]
        head = _json_bytes({"frame_index": int(frame_index), "format": fmt,
                            "left_bytes": len(encoded[0]), "right_bytes": len(encoded[1])})
        self._write(b"I", struct.pack("<I", len(head)) + head + encoded[0] + encoded[1])
        return True

    def _encode(self, image: np.ndarray, fmt: str, side: str) -> bytes:
        if fmt == "png":
            args = [cv2.IMWRITE_PNG_COMPRESSION, int(self.settings["png_compression"])]
        else:
            args = [cv2.IMWRITE_JPEG_QUALITY, int(self.settings["jpeg_quality"])]
        ok, data = cv2.imencode("." + fmt, np.ascontiguousarray(image), args)
        if not ok:
            raise LogError(f"{self.path}: cannot encode the {side} image ({getattr(image, 'shape', '?')}) as {fmt}")
        return data.tobytes()

    # -- file ------------------------------------------------------------------------------
    def _write(self, kind: bytes, payload: bytes, sync: bool = False) -> None:
        if len(payload) > _MAX_PAYLOAD:
            raise LogError(f"{self.path}: record of {len(payload)} bytes is larger than the 1 GiB limit")
        data = memoryview(_pack(kind, payload))
        with self._lock:
            if self._fd is None:
                raise LogError(f"{self.path}: run log is closed")
            try:
                while data:
                    data = data[os.write(self._fd, data):]
                self.records_written += 1
                self._since_sync += 1
                now = time.monotonic()
                if (sync or self._since_sync >= self.settings["fsync_every_records"]
                        or now - self._last_sync >= self.settings["fsync_every_s"]):
                    os.fsync(self._fd)
                    self._since_sync, self._last_sync = 0, now
            except OSError as exc:
                raise LogError(f"{self.path}: cannot write run log ({exc.strerror})") from None

    def close(self) -> None:
        """Fsync and close the log; safe to call twice."""
        with self._lock:
            fd, self._fd = self._fd, None
        if fd is not None:
            try:
                os.fsync(fd)
            finally:
                os.close(fd)

    def __enter__(self) -> "RunLogWriter":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _stamped(record: Mapping[str, Any]) -> dict:
    if not isinstance(record, Mapping):
        raise LogError(f"a log record must be a mapping, got {type(record).__name__}")
    return {"wall_s": time.time(), **record}


def _runlog_settings(params: Mapping[str, Any] | None, given: Mapping[str, Any]) -> dict[str, Any]:
    """Return the writer's settings: explicit arguments, then ``params['runlog.*']``, then the schema."""
    from .config import schema

    out = {}
    for name, value in given.items():
        entry = schema()[f"runlog.{name}"]
        if value is None:
            value = params[entry.key] if params is not None and entry.key in params else entry.default
        try:
            out[name] = entry.coerce(value, f"run log option {name}")
        except Exception as exc:  # ParamsError -> LogError, one line
            raise LogError(str(exc)) from None
    return out


class Record(NamedTuple):
    """One record read back: its kind (header/frame/telemetry/event/images), place and payload."""

    kind: str
    offset: int
    end: int
    payload: bytes

    def json(self) -> Any:
        """Decode a JSON payload (not for ``images`` records)."""
        return json.loads(self.payload)


class RunLogReader:
    """Read a run log, tolerating a cut tail and corrupt records (see the module doc).

    After a full pass (any of the iterators run to the end), ``stats`` holds ``records``,
    ``bytes_skipped`` (corrupt regions in the middle), ``corrupt_regions`` and
    ``truncated_tail_bytes`` (an incomplete last record, e.g. after a crash).

    Raises:
        LogError: the file is missing, unreadable, or does not start with a run-log header.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        try:
            with self.path.open("rb") as handle:
                size = os.fstat(handle.fileno()).st_size
                self._data: bytes | mmap.mmap = (
                    mmap.mmap(handle.fileno(), 0, access=mmap.ACCESS_READ) if size else b"")
        except FileNotFoundError:
            raise LogError(f"{self.path}: run log not found") from None
        except (OSError, ValueError) as exc:
            raise LogError(f"{self.path}: cannot read run log ({exc})") from None
        self.stats = {"records": 0, "bytes_skipped": 0, "corrupt_regions": 0, "truncated_tail_bytes": 0}
        self.header = self._read_header()

    def _read_header(self) -> dict | None:
        """Return the header record's JSON; None for a log cut inside its header (crash at start)."""
        data = self._data
        if len(data) < _HEAD_SIZE or data[:4] != SYNC:
            if SYNC.startswith(bytes(data[:4])) and len(data) < _HEAD_SIZE:
                return None
            raise LogError(f"{self.path}: not a dip3d-vehicle run log (bad header bytes)")
        record = self._record_at(0)
        if record is None:
            _, kind, length, _ = _HEAD.unpack_from(data, 0)
            if kind == b"H" and _HEAD_SIZE + length > len(data):
                return None  # cut inside the header record
            raise LogError(f"{self.path}: not a dip3d-vehicle run log (corrupt header record)")
        try:
            header = record.json()
        except ValueError:
            header = None
        if record.kind != "header" or not isinstance(header, dict) or header.get("format") != FORMAT:
            raise LogError(f"{self.path}: not a dip3d-vehicle run log (first record is not its header)")
        if header.get("version", 0) > VERSION:
            raise LogError(f"{self.path}: run log version {header.get('version')} is newer than this "
                           f"reader (version {VERSION})")
        return header

    @property
    def params(self) -> dict:
        """The effective parameters of the run that wrote this log (from the header)."""
        return dict((self.header or {}).get("params", {}))

    def _record_at(self, pos: int) -> Record | None:
        """Return the valid record starting at ``pos``, or None (incomplete, corrupt, not a record)."""
        data = self._data
        if pos + _HEAD_SIZE > len(data) or data[pos:pos + 4] != SYNC:
            return None
        _, kind, length, crc = _HEAD.unpack_from(data, pos)
        end = pos + _HEAD_SIZE + length
        if kind not in _TYPES or length > _MAX_PAYLOAD or end > len(data):
            return None
        payload = bytes(data[pos + _HEAD_SIZE:end])
        if zlib.crc32(payload, zlib.crc32(data[pos + 4:pos + 9])) != crc:
            return None
        return Record(_TYPES[kind], pos, end, payload)

    def records(self) -> Iterator[Record]:
        """Yield every valid record in file order (the header first), resynchronising past damage."""
        stats = {"records": 0, "bytes_skipped": 0, "corrupt_regions": 0, "truncated_tail_bytes": 0}
        data, pos = self._data, 0
        while pos < len(data):
            record = self._record_at(pos)
            if record is not None:
                stats["records"] += 1
                yield record
                pos = record.end
                continue
            nxt = self._next_record(pos + 1)
            if nxt is None:
                stats["truncated_tail_bytes"] = len(data) - pos
                break
            stats["bytes_skipped"] += nxt - pos
            stats["corrupt_regions"] += 1
            pos = nxt
        self.stats = stats

    def _next_record(self, start: int) -> int | None:
        """Return the offset of the next valid record at or after ``start``, or None."""
        data = self._data
        while True:
            pos = data.find(SYNC, start)
            if pos < 0:
                return None
            if self._record_at(pos) is not None:
                return pos
            start = pos + 1

    def _json_of(self, kind: str) -> Iterator[dict]:
        for record in self.records():
            if record.kind == kind:
                yield record.json()

    def frames(self) -> Iterator[dict]:
        """Yield every frame record (dict) in order."""
        return self._json_of("frame")

    def telemetry(self) -> Iterator[dict]:
        """Yield every telemetry record (dict) in order."""
        return self._json_of("telemetry")

    def events(self) -> Iterator[dict]:
        """Yield every event record (dict with ``text``) in order."""
        return self._json_of("event")

    def image_pairs(self) -> Iterator[tuple[int, np.ndarray, np.ndarray]]:
        """Yield (frame_index, left BGR, right BGR) for every kept image pair, in order.

        Raises:
            LogError: a pair whose record is intact (CRC ok) cannot be decoded.
        """
        for record in self.records():
            if record.kind == "images":
                yield self._decode_images(record)

    def _decode_images(self, record: Record) -> tuple[int, np.ndarray, np.ndarray]:
        payload = record.payload
        try:
            (head_len,) = struct.unpack_from("<I", payload, 0)
            head = json.loads(payload[4:4 + head_len])
            start = 4 + head_len
            split = start + int(head["left_bytes"])
            parts = (payload[start:split], payload[split:split + int(head["right_bytes"])])
            images = [cv2.imdecode(np.frombuffer(p, np.uint8), cv2.IMREAD_COLOR) for p in parts]
        except (struct.error, ValueError, KeyError, TypeError, cv2.error):
            images = [None]
        if any(image is None for image in images):
            raise LogError(f"{self.path}: image record at byte {record.offset} cannot be decoded")
        return int(head["frame_index"]), images[0], images[1]

    def close(self) -> None:
        """Release the file mapping."""
        if isinstance(self._data, mmap.mmap):
            self._data.close()
        self._data = b""

    def __enter__(self) -> "RunLogReader":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
