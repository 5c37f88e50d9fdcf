"""Write stereo frames as ROS 1 / ROS 2 bags with rosbags (raw bgr8 or compressed png)."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_typestore

LEFT, RIGHT = "/stereo/left/image_raw", "/stereo/right/image_raw"
T0_NS = 1_700_000_000 * 10**9


def _message(ts, image: np.ndarray, encoding: str, ns: int, ros1: bool):
    Time, Header = ts.types["builtin_interfaces/msg/Time"], ts.types["std_msgs/msg/Header"]
    header = Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="cam",
                    **({"seq": 0} if ros1 else {}))
    if encoding == "png":
        data = cv2.imencode(".png", image)[1].reshape(-1)
        return ts.types["sensor_msgs/msg/CompressedImage"](header=header, format="png", data=data)
    h, w = image.shape[:2]
    return ts.types["sensor_msgs/msg/Image"](header=header, height=h, width=w, encoding="bgr8", is_bigendian=0,
                                             step=image.strides[0], data=np.ascontiguousarray(image).reshape(-1))


def write_stereo_bag(path: Path, version: str, pairs: list[tuple[np.ndarray, np.ndarray]], encoding: str) -> Path:
    """Write left/right pairs 100 ms apart (right stamped 1 ms later) to a .bag (ros1) or bag folder (ros2)."""
    ros1 = version == "ros1"
    ts = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    msgtype = "sensor_msgs/msg/" + ("CompressedImage" if encoding == "png" else "Image")
    writer = Ros1Writer(path) if ros1 else Ros2Writer(path, version=9)
    serialize = ts.serialize_ros1 if ros1 else ts.serialize_cdr
    with writer:
        conns = {t: writer.add_connection(t, msgtype, typestore=ts) for t in (LEFT, RIGHT)}
        for i, (left, right) in enumerate(pairs):
            ns = T0_NS + i * 100_000_000
            for topic, image, stamp in ((LEFT, left, ns), (RIGHT, right, ns + 1_000_000)):
                writer.write(conns[topic], stamp + 3_000_000,
                             serialize(_message(ts, image, encoding, stamp, ros1), msgtype))
    return path
