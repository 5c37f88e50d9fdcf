"""The run record as MCAP (``run.mcap``): crash-safe writer, tolerant reader.

Every ``run`` and ``sitl`` writes one; Foxglove opens it (images with overlays, a 3D scene, plots
and logs on one timeline), ``replay`` and ``fault_campaign`` read it back. Written with the ``mcap``
package (pure Python): chunked, zstd-compressed, indexed on close. Crash safety: the chunk in
progress is finished and handed to the OS at least every ``runlog.flush_every_s`` (a timer thread
flushes even when nothing new arrives), so a process killed with SIGKILL loses at most that much;
the file is fsynced at least every ``runlog.fsync_every_s`` (power loss). A file cut anywhere
(crash, full disk) is read up to its last complete chunk by ``McapRunReader``, which streams the
records instead of seeking to the (missing) summary, and checks every chunk's CRC.

Metadata records: ``run`` (what the old log header's ``meta`` held: command, scenario, seed,
image size, ...), ``params`` (every effective parameter, value as JSON text), ``calibration``
(``calib_opencv_yaml`` text when the rig is embedded, else the calibration file names) and
``record`` (format, version, writer settings).

The writer keeps the old run log's method names (``frame``, ``telemetry``, ``event``,
``images``, ``wants_images``, ``close``) so every caller of the old log works unchanged.
"""

from __future__ import annotations

import json
import os
import threading
import time
from pathlib import Path
from typing import Any, BinaryIO, Iterator, Mapping, NamedTuple

import cv2
import numpy as np

from ..errors import LogError
from .topics import Topic, encode_json, topic

__all__ = ["McapRunWriter", "McapRunReader", "Message", "FORMAT", "VERSION", "time_ns"]

FORMAT = "dip3d-vehicle-run"
VERSION = 2  # version 1 was the custom binary run.log
_META_KEYS = ("run", "params", "calibration", "record")


def time_ns(t_s: float) -> dict:
    """Return a Foxglove timestamp dict {sec, nsec} for seconds since the epoch."""
    ns = int(round(t_s * 1e9))
    return {"sec": ns // 1_000_000_000, "nsec": ns % 1_000_000_000}


class McapRunWriter:
    """Write a run record to a new MCAP file; everything logged reaches the OS within ``flush_every_s``.

    Args:
        path: file to create (an existing file is an error unless ``overwrite``).
        params: effective parameters (``runlog.*`` keys configure the writer), stored as metadata.
        meta: what the run was (command, source, calibration, image size, ...), stored as metadata.
        keep_images_every, image_format, jpeg_quality, png_compression, fsync_every_s, flush_every_s:
            override the ``runlog.*`` parameters.
        overwrite: replace an existing file.
        clock: the run's clock (``now()`` in seconds); log times are the wall time at creation plus
            the clock's elapsed time, so a simulated run has its own (accelerated) timeline.

    Raises:
        LogError: the file cannot be created or written, or a setting is out of range.
    """

    def __init__(self, path: str | Path, params: Mapping[str, Any] | None = None,
                 meta: Mapping[str, Any] | None = None, *, keep_images_every: int | None = None,
                 image_format: str | None = None, jpeg_quality: int | None = None,
                 png_compression: int | None = None, fsync_every_s: float | None = None,
                 flush_every_s: float | None = None, overwrite: bool = False, clock: Any = None,
                 **_ignored: Any) -> None:
        from mcap.writer import CompressionType, Writer

        self.path = Path(path)
        given = dict(keep_images_every=keep_images_every, image_format=image_format, jpeg_quality=jpeg_quality,
                     png_compression=png_compression, fsync_every_s=fsync_every_s, flush_every_s=flush_every_s)
        self.settings = _settings(params, given)
        try:
            self._file: BinaryIO | None = open(self.path, "wb" if overwrite else "xb")  # noqa: SIM115
        except FileExistsError:
            raise LogError(f"{self.path}: run record already exists (refusing to overwrite it)") from None
        except OSError as exc:
            raise LogError(f"{self.path}: cannot create run record ({exc.strerror})") from None
        self._lock = threading.RLock()
        self._mcap = Writer(self._file, chunk_size=4 << 20, compression=CompressionType.ZSTD)
        self._channels: dict[str, int] = {}
        self._schemas: dict[tuple[str, bytes], int] = {}
        self._images_calls = 0
        self.records_written = 0
        self.counts: dict[str, int] = {}
        self.mirror: Any = None  # called as mirror(topic, data, log_time_ns) after each write (live server)
        self._pending = 0
        self._last_flush = self._last_sync = time.monotonic()
        self.set_clock(clock)
        self._mcap.start(profile="", library="dip3d-vehicle")
        self._write_metadata(params, meta)
        self.flush(sync=True)
        self._stop = threading.Event()
        self._flusher = threading.Thread(target=self._flush_loop, name="dip3d-mcap-flush", daemon=True)
        self._flusher.start()

    # -- time ------------------------------------------------------------------------------
    def set_clock(self, clock: Any) -> None:
        """Use ``clock.now()`` (seconds) for log times from now on; None = wall time."""
        self._clock = clock
        self._t0_s = clock.now() if clock is not None else 0.0
        self._epoch0_s = time.time()

    def now_s(self) -> float:
        """Return the run clock's time now (seconds; wall time without a clock)."""
        return self._clock.now() if self._clock is not None else time.time()

    def stamp_ns(self, t_s: float | None = None) -> int:
        """Return the log time (ns since the epoch) of run-clock time ``t_s`` (default now)."""
        if self._clock is None:
            return int((time.time() if t_s is None else t_s) * 1e9)
        t = self._clock.now() if t_s is None else t_s
        return int(round((self._epoch0_s + (t - self._t0_s)) * 1e9))

    # -- generic ---------------------------------------------------------------------------
    def publish(self, name: str, data: bytes, log_time_ns: int | None = None) -> None:
        """Write one already-encoded message on topic ``name`` (see ``topics``) at ``log_time_ns``."""
        t = self.stamp_ns() if log_time_ns is None else int(log_time_ns)
        with self._lock:
            if self._file is None:
                raise LogError(f"{self.path}: run record is closed")
            try:
                channel = self._channels.get(name)
                if channel is None:
                    channel = self._register(topic(name))
                self._mcap.add_message(channel, log_time=t, data=data, publish_time=t)
                self.records_written += 1
                self.counts[name] = self.counts.get(name, 0) + 1
                self._pending += 1
                if time.monotonic() - self._last_flush >= self.settings["flush_every_s"]:
                    self.flush()
            except OSError as exc:
                raise LogError(f"{self.path}: cannot write run record ({exc.strerror})") from None
        if self.mirror is not None:
            self.mirror(name, data, t)

    def publish_json(self, name: str, obj: Any, log_time_ns: int | None = None) -> None:
        """Write one JSON message on topic ``name``."""
        self.publish(name, encode_json(obj), log_time_ns)

    def _register(self, t: Topic) -> int:
        key = (t.schema_name, t.schema_data)
        schema = self._schemas.get(key)
        if schema is None:
            schema = self._schemas[key] = self._mcap.register_schema(t.schema_name, t.schema_encoding, t.schema_data)
        self._channels[t.name] = self._mcap.register_channel(t.name, t.message_encoding, schema)
        return self._channels[t.name]

    def _write_metadata(self, params: Mapping[str, Any] | None, meta: Mapping[str, Any] | None) -> None:
        meta = dict(meta or {})
        calib = {k: _text(meta.pop(k)) for k in ("calib_opencv_yaml", "calib") if k in meta}
        record = {"format": FORMAT, "version": str(VERSION),
                  "created_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
                  "settings": json.dumps(self.settings)}
        self._mcap.add_metadata("record", record)
        self._mcap.add_metadata("run", {str(k): _text(v) for k, v in meta.items()})
        self._mcap.add_metadata("params", {str(k): _text(v) for k, v in dict(params or {}).items()})
        self._mcap.add_metadata("calibration", calib)

    # -- the old run log's records ---------------------------------------------------------
    def frame(self, record: Mapping[str, Any]) -> None:
        """Log one frame's record (index, stamp, status, target, keypoints, state, ...)."""
        self.publish_json("/dip3d/frame", _stamped(record))

    def telemetry(self, record: Mapping[str, Any]) -> None:
        """Log one telemetry record (simulator truth or the controller's view)."""
        self.publish_json("/dip3d/telemetry", _stamped(record))

    def event(self, text: str, **fields: Any) -> None:
        """Log an event: a story line on ``/story`` (foxglove.Log) and its fields on ``/dip3d/event``."""
        self.log_line("/story", str(text), "story")
        self.publish_json("/dip3d/event", _stamped({"text": str(text), **fields}))

    def log_line(self, name: str, text: str, source: str, level: int = 2, t_s: float | None = None) -> None:
        """Write one foxglove.Log line (level: 1 debug, 2 info, 3 warning, 4 error) on topic ``name``."""
        import foxglove.messages as fm

        t = self.stamp_ns(t_s)
        _LEVELS = {1: fm.LogLevel.Debug, 2: fm.LogLevel.Info, 3: fm.LogLevel.Warning, 4: fm.LogLevel.Error}
        msg = fm.Log(timestamp=fm.Timestamp(t // 1_000_000_000, t % 1_000_000_000), level=_LEVELS[level],
                     message=text, name=source)
        self.publish(name, msg.encode(), t)

    def wants_images(self) -> bool:
        """Return True when the next ``images()`` call will keep its pair (every Nth call)."""
        n = self.settings["keep_images_every"]
        return n > 0 and self._images_calls % n == 0

    def images(self, frame_index: int, left: np.ndarray, right: np.ndarray, force: bool = False,
               t_s: float | None = None) -> bool:
        """Keep a stereo pair as two foxglove.CompressedImage (every ``keep_images_every``-th call).

        Returns:
            True when the pair was written.
        """
        keep = force or self.wants_images()
        self._images_calls += 1
        if not keep:
            return False
        import foxglove.messages as fm

        fmt = self.settings["image_format"]
        t = self.stamp_ns(t_s)
        stamp = fm.Timestamp(t // 1_000_000_000, t % 1_000_000_000)
        for image, side in ((left, "left"), (right, "right")):
            data = encode_image(image, fmt, self.settings, f"{self.path}: {side} image")
            msg = fm.CompressedImage(timestamp=stamp, frame_id=f"camera_{side}", data=data,
                                     format="jpeg" if fmt == "jpg" else "png")
            self.publish(f"/camera/{side}/image", msg.encode(), t)
        self.publish_json("/dip3d/kept", {"frame_index": int(frame_index), "format": fmt}, t)
        return True

    # -- file ------------------------------------------------------------------------------
    def flush(self, sync: bool = False) -> None:
        """Finish the chunk in progress and hand it to the OS (fsync when due or ``sync``)."""
        with self._lock:
            if self._file is None:
                return
            try:
                self._mcap.flush()
                now = time.monotonic()
                self._pending, self._last_flush = 0, now
                if sync or now - self._last_sync >= self.settings["fsync_every_s"]:
                    os.fsync(self._file.fileno())
                    self._last_sync = now
            except OSError as exc:
                raise LogError(f"{self.path}: cannot write run record ({exc.strerror})") from None

    def _flush_loop(self) -> None:
        period = self.settings["flush_every_s"]
        while not self._stop.wait(period / 4):
            with self._lock:
                due = self._pending and time.monotonic() - self._last_flush >= period * 0.75
            if due:
                try:
                    self.flush()
                except LogError:
                    return

    def close(self) -> None:
        """Write the summary (indexes, statistics), fsync and close; safe to call twice."""
        if getattr(self, "_stop", None) is not None:
            self._stop.set()
        with self._lock:
            handle, self._file = self._file, None
            if handle is None:
                return
            try:
                self._mcap.finish()
                handle.flush()
                os.fsync(handle.fileno())
            except OSError as exc:
                raise LogError(f"{self.path}: cannot finish run record ({exc.strerror})") from None
            finally:
                handle.close()

    def __enter__(self) -> "McapRunWriter":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def encode_image(image: np.ndarray, fmt: str, settings: Mapping[str, Any], what: str) -> bytes:
    """Return ``image`` encoded as JPEG (``fmt`` "jpg") or PNG with the writer's settings."""
    if fmt == "png":
        args = [cv2.IMWRITE_PNG_COMPRESSION, int(settings["png_compression"])]
    else:
        args = [cv2.IMWRITE_JPEG_QUALITY, int(settings["jpeg_quality"])]
    ok, data = cv2.imencode("." + fmt, np.ascontiguousarray(image), args)
    if not ok:
        raise LogError(f"{what} ({getattr(image, 'shape', '?')}) cannot be encoded as {fmt}")
    return data.tobytes()


def _text(value: Any) -> str:
    """Return a metadata value as text: strings as they are, anything else as JSON."""
    return value if isinstance(value, str) else encode_json(value).decode()


def _stamped(record: Mapping[str, Any]) -> dict:
    if not isinstance(record, Mapping):
        raise LogError(f"a log record must be a mapping, got {type(record).__name__}")
    return {"wall_s": time.time(), **record}


def _settings(params: Mapping[str, Any] | None, given: Mapping[str, Any]) -> dict[str, Any]:
    """Return the writer's settings: explicit arguments, then ``params['runlog.*']``, then the schema."""
    from ..config import schema

    out = {}
    for name, value in given.items():
        entry = schema()[f"runlog.{name}"]
        if value is None:
            value = params[entry.key] if params is not None and entry.key in params else entry.default
        try:
            out[name] = entry.coerce(value, f"run record option {name}")
        except Exception as exc:  # ParamsError -> LogError, one line
            raise LogError(str(exc)) from None
    return out


# ============================================================================== reading
class Message(NamedTuple):
    """One message read back: topic, schema name, log time (ns) and the raw bytes."""

    topic: str
    schema_name: str
    log_time_ns: int
    data: bytes

    def json(self) -> Any:
        """Decode a JSON message."""
        return json.loads(self.data)


class McapRunReader:
    """Read a run record, also one cut anywhere (crash): every message of every complete chunk.

    After a full pass of ``messages()``, ``stats`` holds ``messages``, ``chunks``,
    ``truncated`` (True when the file ends without its footer) and ``error`` (what stopped the
    reading early, "" for a complete file).

    Raises:
        LogError: the file is missing, unreadable or not an MCAP run record.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        try:
            self._data = self.path.read_bytes()
        except FileNotFoundError:
            raise LogError(f"{self.path}: run record not found") from None
        except OSError as exc:
            raise LogError(f"{self.path}: cannot read run record ({exc.strerror})") from None
        from mcap.records import Metadata

        magic = b"\x89MCAP0\r\n"
        if not self._data.startswith(magic[:len(self._data)]) or (len(self._data) >= 8 and self._data[:8] != magic):
            raise LogError(f"{self.path}: not an MCAP file (bad magic bytes)")
        self.metadata: dict[str, dict[str, str]] = {}
        self.stats = {"messages": 0, "chunks": 0, "truncated": False, "error": ""}
        self._decoders: dict[str, Any] = {}
        for rec in self._records():
            if isinstance(rec, Metadata):
                self.metadata[rec.name] = dict(rec.metadata)
        record = self.metadata.get("record")
        if record is not None and record.get("format") != FORMAT:
            raise LogError(f"{self.path}: MCAP file is not a dip3d-vehicle run record "
                           f"(format {record.get('format')!r})")

    def _records(self) -> Iterator[Any]:
        """Yield records in file order until the end or the first damage (cut or CRC)."""
        import io

        from mcap.records import Chunk, Footer
        from mcap.stream_reader import StreamReader

        stats = {"messages": 0, "chunks": 0, "truncated": True, "error": ""}
        if len(self._data) < 8:
            stats["error"] = "cut inside the magic bytes"
            self.stats = stats
            return
        reader = StreamReader(io.BytesIO(self._data), skip_magic=False, emit_chunks=True, validate_crcs=True)
        it = reader.records
        while True:
            try:
                rec = next(it)
                if isinstance(rec, Chunk):
                    inner = _chunk_records(rec)
            except StopIteration:
                stats["error"] = stats["error"] or "ended without footer"
                break
            except Exception as exc:  # noqa: BLE001 - any damage (cut, CRC, zstd, bad record) ends the reading here
                stats["error"] = f"{type(exc).__name__}: {exc}"[:200]
                break
            if isinstance(rec, Chunk):
                stats["chunks"] += 1
                yield from inner
                continue
            if isinstance(rec, Footer):
                stats["truncated"], stats["error"] = False, ""
                break
            yield rec
        self.stats = stats

    def messages(self, topics: tuple[str, ...] | None = None) -> Iterator[Message]:
        """Yield messages (all, or of ``topics``) in file order (log time order within a chunk)."""
        from mcap.records import Channel, Message as McapMessage, Schema

        schemas: dict[int, str] = {}
        channels: dict[int, tuple[str, str]] = {}
        count = 0
        for rec in self._records():
            if isinstance(rec, Schema):
                schemas[rec.id] = rec.name
                self._decoders.setdefault(rec.name, (rec.encoding, rec.data))
            elif isinstance(rec, Channel):
                channels[rec.id] = (rec.topic, schemas.get(rec.schema_id, ""))
            elif isinstance(rec, McapMessage) and rec.channel_id in channels:
                count += 1
                name, schema = channels[rec.channel_id]
                if topics is None or name in topics:
                    yield Message(name, schema, rec.log_time, bytes(rec.data))
        self.stats["messages"] = count

    def decode(self, msg: Message) -> Any:
        """Decode a message: JSON to Python data, protobuf (Foxglove schemas) to a protobuf object."""
        encoding, data = self._decoders.get(msg.schema_name, ("jsonschema", b""))
        if encoding != "protobuf":
            return msg.json()
        return _protobuf_class(msg.schema_name, data).FromString(msg.data)

    # -- what replay and the campaigns read --------------------------------------------------
    @property
    def header(self) -> dict | None:
        """The old run log header's shape: {"format", "version", "params", "meta"} (None if cut before it)."""
        if "record" not in self.metadata:
            return None
        meta = {k: _untext(v) for k, v in self.metadata.get("run", {}).items()}
        meta.update({k: _untext(v) for k, v in self.metadata.get("calibration", {}).items()})
        return {"format": FORMAT, "version": int(self.metadata["record"].get("version", VERSION)),
                "params": self.params, "meta": meta,
                "runlog": json.loads(self.metadata["record"].get("settings", "{}"))}

    @property
    def params(self) -> dict:
        """The effective parameters of the run (from the ``params`` metadata)."""
        return {k: _untext(v) for k, v in self.metadata.get("params", {}).items()}

    def frames(self) -> Iterator[dict]:
        """Yield every frame record (dict) in order."""
        return (m.json() for m in self.messages(("/dip3d/frame",)))

    def telemetry(self) -> Iterator[dict]:
        """Yield every telemetry record (dict) in order."""
        return (m.json() for m in self.messages(("/dip3d/telemetry",)))

    def events(self) -> Iterator[dict]:
        """Yield every event record (dict with ``text``) in order."""
        return (m.json() for m in self.messages(("/dip3d/event",)))

    def image_pairs(self) -> Iterator[tuple[int, np.ndarray, np.ndarray]]:
        """Yield (frame_index, left BGR, right BGR) for every complete kept pair, in order.

        Raises:
            LogError: an intact image message cannot be decoded.
        """
        last: dict[str, Message] = {}
        wanted = ("/camera/left/image", "/camera/right/image", "/dip3d/kept")
        for msg in self.messages(wanted):  # one images() call writes left, right, kept in this order
            if msg.topic != "/dip3d/kept":
                last[msg.topic] = msg
                continue
            left, right = last.pop("/camera/left/image", None), last.pop("/camera/right/image", None)
            if left is None or right is None or not left.log_time_ns == right.log_time_ns == msg.log_time_ns:
                continue
            index = int(msg.json()["frame_index"])
            yield index, self._image(left), self._image(right)

    def _image(self, msg: Message) -> np.ndarray:
        data = self.decode(msg).data
        image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
        if image is None:
            raise LogError(f"{self.path}: {msg.topic} image at {msg.log_time_ns} ns cannot be decoded")
        return image

    def close(self) -> None:
        """Release the file's bytes."""
        self._data = b""

    def __enter__(self) -> "McapRunReader":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _chunk_records(chunk: Any) -> list:
    """Return the records inside a chunk (decompressed, its CRC checked)."""
    from mcap.stream_reader import breakup_chunk

    return breakup_chunk(chunk, validate_crc=True)


def _untext(value: str) -> Any:
    """Return a metadata value: JSON when it parses as JSON, else the text itself."""
    try:
        return json.loads(value)
    except ValueError:
        return value


_PB_CLASSES: dict[str, Any] = {}


def _protobuf_class(name: str, descriptor_set: bytes) -> Any:
    """Return the protobuf message class of ``name`` from its serialized FileDescriptorSet."""
    cls = _PB_CLASSES.get(name)
    if cls is None:
        from google.protobuf import descriptor_pb2, descriptor_pool, message_factory

        fds = descriptor_pb2.FileDescriptorSet.FromString(descriptor_set)
        pool = descriptor_pool.DescriptorPool()
        for fd in fds.file:
            try:
                pool.Add(fd)
            except Exception:  # noqa: BLE001 - already present (shared dependency files)
                pass
        cls = _PB_CLASSES[name] = message_factory.GetMessageClass(pool.FindMessageTypeByName(name))
    return cls
