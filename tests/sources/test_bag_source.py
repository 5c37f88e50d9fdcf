"""ROS 1 / ROS 2 bags written here with rosbags replay exactly the frames of the same folder."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin, Writer as Ros2Writer
from rosbags.typesys import Stores, get_typestore

from dip3d_vehicle.errors import SourceError
from dip3d_vehicle.frames import StereoFrame
from dip3d_vehicle.sources import BagSource, open_source, write_folder
from dip3d_vehicle.sources.bag import pair_by_stamp

LEFT, RIGHT = "/stereo/left/image_raw", "/stereo/right/image_raw"
T0_NS = 1_700_000_000 * 10**9


def _stamp_s(ns: int) -> float:
    return ns // 10**9 + (ns % 10**9) * 1e-9


def _image_msg(ts, image: np.ndarray, encoding: str, ns: int, ros1: bool):
    """A sensor_msgs Image or CompressedImage (encoding 'jpeg'/'png') holding a BGR image."""
    Time, Header = ts.types["builtin_interfaces/msg/Time"], ts.types["std_msgs/msg/Header"]
    extra = {"seq": 0} if ros1 else {}
    header = Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="cam", **extra)
    if encoding in ("jpeg", "png"):
        ext = ".jpg" if encoding == "jpeg" else ".png"
        data = cv2.imencode(ext, image)[1].reshape(-1)
        return ts.types["sensor_msgs/msg/CompressedImage"](header=header, format=encoding, data=data)
    convert = {"bgr8": None, "rgb8": cv2.COLOR_BGR2RGB, "mono8": cv2.COLOR_BGR2GRAY,
               "bgra8": cv2.COLOR_BGR2BGRA, "rgba8": cv2.COLOR_BGR2RGBA}[encoding]
    pixels = image if convert is None else cv2.cvtColor(image, convert)
    height, width = pixels.shape[:2]
    step = pixels.strides[0]
    return ts.types["sensor_msgs/msg/Image"](header=header, height=height, width=width, encoding=encoding,
                                             is_bigendian=0, step=step, data=pixels.reshape(-1))


def write_bag(path: Path, version: str, messages: list[tuple[str, np.ndarray, int]], encoding: str,
              storage: str = "sqlite3") -> Path:
    """Write (topic, BGR image, header stamp ns) messages to a ROS 1 .bag or ROS 2 bag folder."""
    ros1 = version == "ros1"
    ts = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    msgtype = "sensor_msgs/msg/" + ("CompressedImage" if encoding in ("jpeg", "png") else "Image")
    if ros1:
        writer = Ros1Writer(path)
    else:
        plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
        writer = Ros2Writer(path, version=9, storage_plugin=plugin)
    serialize = ts.serialize_ros1 if ros1 else ts.serialize_cdr
    with writer:
        conns = {t: writer.add_connection(t, msgtype, typestore=ts) for t in sorted({m[0] for m in messages})}
        for topic, image, ns in messages:
            # bag (receive) time a little after the header stamp, as on a real vehicle
            writer.write(conns[topic], ns + 3_000_000, serialize(_image_msg(ts, image, encoding, ns, ros1), msgtype))
    return path


def stereo_messages(frames: list[StereoFrame], right_offsets_ns=(0, 1_000_000, -2_000_000, 4_000_000, 500_000)):
    """Interleaved left/right messages for ``frames``; right stamps offset by a few ms."""
    out, stamps = [], []
    for i, frame in enumerate(frames):
        ns = T0_NS + i * 100_000_000
        stamps.append(ns)
        out.append((LEFT, frame.left, ns))
        out.append((RIGHT, frame.right, ns + right_offsets_ns[i % len(right_offsets_ns)]))
    return out, stamps


def folder_twin(tmp_path: Path, frames: list[StereoFrame], stamps_ns: list[int], encoding: str) -> list[StereoFrame]:
    """The same frames through a folder: PNG for raw/png, the very JPEG bytes for jpeg."""
    folder = tmp_path / "folder"
    stamped = [StereoFrame(f.left, f.right, _stamp_s(ns), f.index) for f, ns in zip(frames, stamps_ns)]
    if encoding == "jpeg":
        folder.mkdir()
        lines = ["frame,stamp_s"]
        for f in stamped:
            for side, image in (("left", f.left), ("right", f.right)):
                (folder / f"{side}_{f.index:06d}.jpg").write_bytes(cv2.imencode(".jpg", image)[1].tobytes())
            lines.append(f"{f.index},{f.stamp_s!r}")
        (folder / "stamps.csv").write_text("\n".join(lines) + "\n")
    else:
        write_folder(folder, stamped)
    with open_source(str(folder)) as source:
        return list(source)


CASES = [(v, e) for v in ("ros1", "ros2") for e in ("bgr8", "rgb8", "mono8", "rgba8", "jpeg", "png")]


@pytest.mark.parametrize("version, encoding", CASES)
def test_bag_replays_the_same_frames_as_a_folder(tmp_path, make_frames, version, encoding):
    frames = make_frames(5, gray=encoding == "mono8")
    messages, stamps = stereo_messages(frames)
    bag = write_bag(tmp_path / ("dive.bag" if version == "ros1" else "dive"), version, messages, encoding)
    want = folder_twin(tmp_path, frames, stamps, encoding)
    with open_source(f"bag:{bag}") as source:  # topics found by their names
        got = list(source)
        stats = dict(source.stats)
    assert len(got) == len(want) == 5
    for g, w in zip(got, want):
        assert g.left.dtype == np.uint8 and g.left.shape == w.left.shape == (32, 40, 3)
        assert np.array_equal(g.left, w.left) and np.array_equal(g.right, w.right)
        assert g.stamp_s == w.stamp_s and g.index == w.index
    assert stats == {"pairs": 5, "left_unpaired": 0, "right_unpaired": 0}


def test_ros2_mcap_and_db3_file_path(tmp_path, make_frames):
    frames = make_frames(3)
    messages, stamps = stereo_messages(frames)
    bag = write_bag(tmp_path / "m", "ros2", messages, "bgr8", storage="mcap")
    mcap = next(bag.glob("*.mcap"))
    got = list(open_source(str(mcap)))  # detected as a bag from the suffix
    assert [g.stamp_s for g in got] == [_stamp_s(ns) for ns in stamps]
    assert all(np.array_equal(g.left, f.left) for g, f in zip(got, frames))


@pytest.mark.parametrize("version", ["ros1", "ros2"])
def test_unpaired_messages_are_skipped_and_counted(tmp_path, make_frames, version):
    frames = make_frames(6)
    messages, stamps = stereo_messages(frames)
    # frame 2 lost its right image, frame 4 its left; a stray right message far from any left
    messages = [m for m in messages if not (m[0] == RIGHT and abs(m[2] - stamps[2]) < 10**7)]
    messages = [m for m in messages if not (m[0] == LEFT and m[2] == stamps[4])]
    messages.append((RIGHT, frames[0].right, stamps[5] + 50_000_000))
    bag = write_bag(tmp_path / ("u.bag" if version == "ros1" else "u"), version, messages, "bgr8")
    with open_source(f"bag:{bag}?left={LEFT}&right={RIGHT}&tolerance=0.005") as source:
        got = list(source)
        assert source.stats == {"pairs": 4, "left_unpaired": 1, "right_unpaired": 2}
    assert [g.stamp_s for g in got] == [_stamp_s(stamps[i]) for i in (0, 1, 3, 5)]
    assert np.array_equal(got[2].left, frames[3].left) and np.array_equal(got[2].right, frames[3].right)
    # a tolerance below the 4 ms offset of frame 3 drops that pair too
    with open_source(f"bag:{bag}", tolerance=0.003) as source:
        assert [g.stamp_s for g in source] == [_stamp_s(stamps[i]) for i in (0, 1, 5)]


def test_pairing_prefers_the_closer_next_message():
    class M:
        def __init__(self, t):
            self.stamp_s = t

        def __repr__(self):
            return f"M({self.stamp_s})"
    stream = [("left", M(0.000)), ("right", M(0.004)), ("left", M(0.005)), ("right", M(0.100)),
              ("left", M(0.101))]
    stats: dict = {}
    pairs = [(a.stamp_s, b.stamp_s) for a, b in pair_by_stamp(iter(stream), 0.005, 64, stats)]
    assert pairs == [(0.005, 0.004), (0.101, 0.100)]
    assert stats == {"left_unpaired": 1, "right_unpaired": 0}


def test_bag_errors_list_topics(tmp_path, make_frames):
    frames = make_frames(2)
    messages, _ = stereo_messages(frames)
    bag = write_bag(tmp_path / "e.bag", "ros1", messages + [("/cam/left/image_rect", frames[0].left, T0_NS)], "bgr8")
    with pytest.raises(SourceError, match=r"left topic /nope is not an image topic of this bag \(image topics: "
                                          r"/cam/left/image_rect \(Image\), /stereo/left/image_raw"):
        BagSource(bag, left="/nope", right=RIGHT)
    source = BagSource(bag)  # image_rect is not preferred over image_raw for the left side
    assert (source.left_topic, source.right_topic) == (LEFT, RIGHT)
    source.close()
    with pytest.raises(SourceError, match="bag not found"):
        open_source(f"bag:{tmp_path}/missing.bag")
    (tmp_path / "junk.bag").write_bytes(b"#ROSBAG V2.0\nnot really")
    with pytest.raises(SourceError, match="junk.bag: cannot open as a ROS 1 or ROS 2 bag"):
        open_source(str(tmp_path / "junk.bag"))
    with pytest.raises(SourceError, match="not a ROS 2 bag folder"):
        open_source(f"bag:{tmp_path}")
    only_left = write_bag(tmp_path / "l.bag", "ros1", [m for m in messages if m[0] == LEFT], "bgr8")
    with pytest.raises(SourceError, match="no image topics name 'right'"):
        open_source(str(only_left))
