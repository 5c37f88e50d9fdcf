"""Stereo pairs from a ROS 1 bag file or a ROS 2 bag folder (sqlite3 .db3 or .mcap), via ``rosbags``.

Two image topics (``sensor_msgs/Image`` in bgr8, rgb8, mono8, bgra8, rgba8, or
``sensor_msgs/CompressedImage`` in jpeg/png) are paired by header stamp: a left and a right
message form a pair when their stamps differ by at most ``tolerance`` seconds and neither has a
closer partner next in line; messages left without a partner are skipped and counted
(``stats['left_unpaired']``, ``stats['right_unpaired']``). The frame stamp is the left header stamp.
Images are decoded only once paired, in one streaming pass (a bag may be many GB).
"""

from __future__ import annotations

from collections import deque
from pathlib import Path
from typing import Any, Iterator, Mapping, NamedTuple

import cv2
import numpy as np

from ..errors import SourceError
from .base import StereoSource, as_bgr, option

__all__ = ["BagSource", "IMAGE_TYPES", "decode_image_message", "resolve_bag_path"]

IMAGE_TYPES = ("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage")
_CHANNELS = {"bgr8": 3, "rgb8": 3, "mono8": 1, "8uc1": 1, "8uc3": 3, "bgra8": 4, "rgba8": 4, "8uc4": 4}
_TO_BGR = {"rgb8": cv2.COLOR_RGB2BGR, "bgra8": cv2.COLOR_BGRA2BGR, "rgba8": cv2.COLOR_RGBA2BGR,
           "8uc4": cv2.COLOR_BGRA2BGR, "mono8": cv2.COLOR_GRAY2BGR, "8uc1": cv2.COLOR_GRAY2BGR}


class _Pending(NamedTuple):
    stamp_s: float
    connection: Any
    msg: Any


def resolve_bag_path(path: str | Path) -> Path:
    """Return what AnyReader opens: a ROS 1 ``.bag`` file or a ROS 2 bag folder.

    A ROS 2 ``.db3`` / ``.mcap`` file is accepted and replaced by its folder (which must hold the
    bag's ``metadata.yaml``).
    """
    path = Path(path)
    if not path.exists():
        raise SourceError(f"{path}: bag not found")
    if path.is_file() and path.suffix in (".db3", ".mcap"):
        if not (path.parent / "metadata.yaml").is_file():
            raise SourceError(f"{path}: a ROS 2 bag file needs its folder's metadata.yaml "
                              f"(not found in {path.parent})")
        return path.parent
    if path.is_dir() and not (path / "metadata.yaml").is_file():
        raise SourceError(f"{path}: not a ROS 2 bag folder (no metadata.yaml)")
    return path


def decode_image_message(msg: Any, msgtype: str, where: str) -> np.ndarray:
    """Return a sensor_msgs Image or CompressedImage as HxWx3 uint8 BGR; SourceError otherwise."""
    if msgtype.endswith("CompressedImage"):
        data = np.asarray(msg.data, dtype=np.uint8)
        image = cv2.imdecode(data, cv2.IMREAD_COLOR) if data.size else None
        if image is None:
            raise SourceError(f"{where}: compressed image (format {msg.format!r}) cannot be decoded")
        return image
    encoding = msg.encoding.lower()
    channels = _CHANNELS.get(encoding)
    if channels is None:
        raise SourceError(f"{where}: image encoding {msg.encoding!r} is not supported "
                          f"(expected one of {', '.join(sorted(k for k in _CHANNELS if not k[0].isdigit()))})")
    height, width, step = int(msg.height), int(msg.width), int(msg.step)
    data = np.asarray(msg.data, dtype=np.uint8)
    if step < width * channels or data.size < step * height:
        raise SourceError(f"{where}: image data of {data.size} bytes does not fit "
                          f"{width}x{height} {msg.encoding} with step {step}")
    rows = data[: step * height].reshape(height, step)[:, : width * channels]
    image = rows.reshape(height, width, channels) if channels > 1 else rows.reshape(height, width)
    code = _TO_BGR.get(encoding)
    return cv2.cvtColor(image, code) if code is not None else np.ascontiguousarray(image)


class BagSource(StereoSource):
    """Stereo pairs from two image topics of a ROS 1 / ROS 2 bag, paired by header stamp.

    Args:
        path: ``.bag`` file, ROS 2 bag folder, or a ``.db3``/``.mcap`` file inside one.
        left, right: topic names; when None, the two image topics whose names contain
            ``left`` and ``right``.
        options: ``tolerance`` (alias of ``bag_tolerance_s``), ``bag_max_pending``, ``max_frames``.
        params: effective parameters (``sources.*``) or None.
    """

    def __init__(self, path: str | Path, left: str | None = None, right: str | None = None,
                 options: Mapping[str, Any] | None = None, params: Mapping[str, Any] | None = None,
                 spec: str | None = None) -> None:
        options = dict(options or {})
        if "tolerance" in options:
            options["bag_tolerance_s"] = options.pop("tolerance")
        super().__init__(spec or f"bag:{path}", option("max_frames", options, params))
        self.tolerance_s = option("bag_tolerance_s", options, params)
        self.max_pending = option("bag_max_pending", options, params)
        self.path = resolve_bag_path(path)
        self._reader = _open_reader(self.path)
        try:
            self.topics = _image_topics(self._reader)
            self.left_topic, self.right_topic = _choose_topics(self.path, self.topics, left, right)
        except SourceError:
            self.close()
            raise
        self.stats = {"pairs": 0, "left_unpaired": 0, "right_unpaired": 0}

    def __len__(self) -> int:
        """Upper bound: the smaller message count of the two topics (unpaired ones are skipped)."""
        n = min(self.topics[self.left_topic][1], self.topics[self.right_topic][1])
        return min(n, self.max_frames) if self.max_frames else n

    def describe(self) -> str:
        return (f"bag {self.path} left={self.left_topic} right={self.right_topic} "
                f"tolerance={self.tolerance_s:g} s")

    def close(self) -> None:
        reader, self._reader = getattr(self, "_reader", None), None
        if reader is not None:
            reader.close()
        super().close()

    def _messages(self) -> Iterator[tuple[str, _Pending]]:
        """Yield ('left'|'right', pending message) in bag order, reading only the two topics."""
        if self._reader is None:
            raise SourceError(f"{self.path}: bag is closed")
        wanted = {self.left_topic: "left", self.right_topic: "right"}
        conns = [c for c in self._reader.connections if c.topic in wanted]
        for conn, _, raw in self._reader.messages(connections=conns):
            msg = self._deserialize(conn, raw)
            stamp = msg.header.stamp
            yield wanted[conn.topic], _Pending(stamp.sec + stamp.nanosec * 1e-9, conn, msg)

    def _deserialize(self, conn: Any, raw: bytes) -> Any:
        try:
            return self._reader.deserialize(raw, conn.msgtype)
        except Exception as exc:  # rosbags raises several kinds on a corrupt message
            raise SourceError(f"{self.path}: {conn.topic}: cannot deserialise {conn.msgtype} "
                              f"({exc.__class__.__name__}: {exc})") from None

    def _decode(self, item: _Pending) -> np.ndarray:
        msg = item.msg
        where = f"{self.path}: {item.connection.topic} at {item.stamp_s:.6f} s"
        return as_bgr(decode_image_message(msg, item.connection.msgtype, where), where)

    def _frames(self) -> Iterator[tuple[np.ndarray, np.ndarray, float, dict]]:
        for left, right in pair_by_stamp(self._messages(), self.tolerance_s, self.max_pending, self.stats):
            self.stats["pairs"] += 1
            meta = {"left_stamp_s": left.stamp_s, "right_stamp_s": right.stamp_s,
                    "left_topic": self.left_topic, "right_topic": self.right_topic}
            yield self._decode(left), self._decode(right), left.stamp_s, meta


def pair_by_stamp(stream: Iterator[tuple[str, Any]], tolerance_s: float, max_pending: int,
                  stats: dict[str, int]) -> Iterator[tuple[Any, Any]]:
    """Pair ('left'|'right', item with .stamp_s) messages whose stamps differ by <= tolerance_s.

    Greedy on the oldest message of each side, with one message of look-ahead: a head is paired
    with the other head unless the next message on either side is a strictly closer partner.
    A head older than the other head by more than the tolerance can never be paired and is
    dropped (counted in ``stats['<side>_unpaired']``). Assumes stamps rise within each topic.
    """
    queues: dict[str, deque] = {"left": deque(), "right": deque()}
    ended = False
    stream = iter(stream)
    while True:
        while queues["left"] and queues["right"]:
            left, right = queues["left"][0], queues["right"][0]
            if left.stamp_s < right.stamp_s - tolerance_s:
                _drop(queues, "left", stats)
                continue
            if right.stamp_s < left.stamp_s - tolerance_s:
                _drop(queues, "right", stats)
                continue
            # The later side's partner is fixed; the earlier side's next message may be closer.
            early = "left" if left.stamp_s < right.stamp_s else "right"
            other = "right" if early == "left" else "left"
            waiting = len(queues[early]) < 2 and not ended and len(queues[other]) < max_pending
            if waiting:
                break
            gap = abs(left.stamp_s - right.stamp_s)
            if len(queues[early]) > 1 and abs(queues[early][1].stamp_s - queues[other][0].stamp_s) < gap:
                _drop(queues, early, stats)
                continue
            yield queues["left"].popleft(), queues["right"].popleft()
        if ended:
            break
        try:
            side, item = next(stream)
        except StopIteration:
            ended = True
            continue
        queues[side].append(item)
    for side in ("left", "right"):
        stats[f"{side}_unpaired"] = stats.get(f"{side}_unpaired", 0) + len(queues[side])


def _drop(queues: dict[str, deque], side: str, stats: dict[str, int]) -> None:
    queues[side].popleft()
    stats[f"{side}_unpaired"] = stats.get(f"{side}_unpaired", 0) + 1


def _open_reader(path: Path) -> Any:
    """Open a rosbags AnyReader on ``path`` (ROS 1 or ROS 2); SourceError when it cannot."""
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    try:
        reader = AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
        reader.open()
    except Exception as exc:  # rosbags: AnyReaderError, ReaderError, ... on a bad bag
        raise SourceError(f"{path}: cannot open as a ROS 1 or ROS 2 bag ({exc.__class__.__name__}: {exc})") from None
    return reader


def _image_topics(reader: Any) -> dict[str, tuple[str, int]]:
    """Return {topic: (msgtype, message count)} of every image topic in the bag."""
    topics: dict[str, tuple[str, int]] = {}
    for conn in reader.connections:
        if conn.msgtype in IMAGE_TYPES:
            _, count = topics.get(conn.topic, (conn.msgtype, 0))
            topics[conn.topic] = (conn.msgtype, count + conn.msgcount)
    return topics


def _choose_topics(path: Path, topics: dict[str, tuple[str, int]], left: str | None,
                   right: str | None) -> tuple[str, str]:
    """Check the given topics, or pick the image topics naming left and right; SourceError otherwise."""
    listing = ", ".join(f"{t} ({m.split('/')[-1]})" for t, (m, _) in sorted(topics.items())) or "none"
    for side, topic in (("left", left), ("right", right)):
        if topic is not None and topic not in topics:
            raise SourceError(f"{path}: {side} topic {topic} is not an image topic of this bag "
                              f"(image topics: {listing})")
    if left is None:
        left = _guess(path, topics, "left", listing, exclude=right)
    if right is None:
        right = _guess(path, topics, "right", listing, exclude=left)
    if left == right:
        raise SourceError(f"{path}: left and right topic are the same ({left})")
    return left, right


def _guess(path: Path, topics: dict, side: str, listing: str, exclude: str | None) -> str:
    """Return the one image topic whose name contains ``side``; prefer raw-looking names on ties."""
    found = [t for t in sorted(topics) if side in t.lower() and t != exclude]
    if len(found) > 1:
        found = [t for t in found if "rect" not in t.lower()] or found
    if len(found) != 1:
        what = "no" if not found else f"{len(found)}"
        raise SourceError(f"{path}: {what} image topics name '{side}'; give bag:PATH?left=TOPIC&right=TOPIC "
                          f"(image topics: {listing})")
    return found[0]
