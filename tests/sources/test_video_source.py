"""Video pairs, side-by-side streams, GStreamer availability, spec parsing."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from dip3d_vehicle.errors import SourceError
from dip3d_vehicle.sources import AnnotatedVideo, SideBySideSource, gstreamer_supported, open_source, parse_spec
from dip3d_vehicle.sources.video import split_side_by_side


def smooth_frames(n: int, width: int = 64, height: int = 48) -> list[np.ndarray]:
    """Smooth gradient images (survive lossy codecs closely), different per frame."""
    y, x = np.mgrid[0:height, 0:width]
    return [np.dstack([(x * 3 + i * 20) % 256, (y * 4 + i * 10) % 256, ((x + y) * 2) % 256]).astype(np.uint8)
            for i in range(n)]


def write_video(path: Path, images: list[np.ndarray], fps: float = 10.0) -> Path:
    height, width = images[0].shape[:2]
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), fps, (width, height))
    assert writer.isOpened()
    for image in images:
        writer.write(image)
    writer.release()
    return path


def close_to(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and np.abs(a.astype(int) - b).mean() < 4


def test_video_pair(tmp_path):
    lefts, rights = smooth_frames(6), [np.flipud(i).copy() for i in smooth_frames(6)]
    left = write_video(tmp_path / "l.avi", lefts)
    right = write_video(tmp_path / "r.avi", rights)
    with open_source(f"video:{left},{right}") as source:
        assert len(source) == 6
        got = list(source)
    assert len(got) == 6
    assert all(close_to(g.left, w) and close_to(g.right, r) for g, w, r in zip(got, lefts, rights))
    assert [round(g.stamp_s, 3) for g in got] == [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]


def test_video_pair_stops_at_the_shorter_file(tmp_path):
    left = write_video(tmp_path / "l.avi", smooth_frames(5))
    right = write_video(tmp_path / "r.avi", smooth_frames(3))
    with open_source(f"video:{left},{right}?max_frames=10") as source:
        assert len(list(source)) == 3
        assert source.stats["left_frame_count"] == 5 and source.stats["right_frame_count"] == 3


def test_side_by_side_split(tmp_path):
    lefts, rights = smooth_frames(4), [255 - i for i in smooth_frames(4)]
    sbs = write_video(tmp_path / "sbs.avi", [np.hstack([a, b]) for a, b in zip(lefts, rights)])
    with open_source(f"sbs:{sbs}") as source:
        assert isinstance(source, SideBySideSource)
        got = list(source)
    assert len(got) == 4
    assert all(g.left.shape == (48, 64, 3) for g in got)
    assert all(close_to(g.left, a) and close_to(g.right, b) for g, a, b in zip(got, lefts, rights))


def test_split_is_exact_and_rejects_odd_widths():
    image = np.arange(4 * 6 * 3, dtype=np.uint8).reshape(4, 6, 3)
    left, right = split_side_by_side(image, "x")
    assert np.array_equal(np.hstack([left, right]), image) and left.flags.c_contiguous
    with pytest.raises(SourceError, match="x: side-by-side frame width 5 is odd"):
        split_side_by_side(image[:, :5], "x")


def test_gstreamer_unsupported_is_said_clearly():
    if gstreamer_supported():
        pytest.skip("this OpenCV has GStreamer")
    with pytest.raises(SourceError, match=r"the installed OpenCV .* has no GStreamer support"):
        open_source("gst:videotestsrc ! videoconvert ! appsink")


def test_video_errors(tmp_path):
    with pytest.raises(SourceError, match="missing.avi: video file not found"):
        open_source(f"video:{tmp_path}/missing.avi,{tmp_path}/r.avi")
    with pytest.raises(SourceError, match="expected video:LEFT,RIGHT"):
        open_source(f"video:{tmp_path}/a.avi")
    (tmp_path / "junk.avi").write_bytes(b"junk")
    with pytest.raises(SourceError, match="junk.avi: OpenCV cannot open"):
        open_source(f"sbs:{tmp_path}/junk.avi")
    with pytest.raises(SourceError, match="no path, file or device"):
        open_source("bag:")


def test_parse_spec():
    assert parse_spec("bag:/d/x.bag?left=/a&right=/b&tolerance=0.01") == (
        "bag", "/d/x.bag", {"left": "/a", "right": "/b", "tolerance": "0.01"})
    assert parse_spec("gst:v4l2src ! video/x-raw,width=640 ! appsink") == (
        "gst", "v4l2src ! video/x-raw,width=640 ! appsink", {})
    assert parse_spec("v4l2:/dev/video0,/dev/video1?device_fps=30")[2] == {"device_fps": "30"}
    assert parse_spec("/data/dive.bag")[0] == "bag"
    assert parse_spec("/data/pairs")[0] == "folder"
    with pytest.raises(SourceError, match="key=value"):
        parse_spec("folder:/x?oops")


def test_annotated_video(tmp_path):
    frames = smooth_frames(3)
    with AnnotatedVideo(tmp_path / "a.mp4", fps=5) as video:
        for frame in frames:
            video.write(frame)
    cap = cv2.VideoCapture(str(tmp_path / "a.mp4"))
    assert int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) == 3
    cap.release()
