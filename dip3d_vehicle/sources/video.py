"""Stereo from OpenCV captures: two video files or devices, one side-by-side stream, GStreamer.

Stamps: a video file's own position (``CAP_PROP_POS_MSEC``, else index / its fps); a live device
or pipeline is stamped with the monotonic clock when both images have been grabbed.
"""

from __future__ import annotations

import os
import re
import time
from typing import Any, Iterator, Mapping

import cv2
import numpy as np

from ..errors import SourceError
from .base import StereoSource, as_bgr, option

__all__ = ["CapturePairSource", "SideBySideSource", "gstreamer_supported", "open_capture", "split_side_by_side"]


def gstreamer_supported() -> bool:
    """Return True when the installed OpenCV was built with GStreamer (``GStreamer: YES``)."""
    info = cv2.getBuildInformation()
    return re.search(r"^\s*GStreamer:\s*YES", info, re.MULTILINE) is not None


def _is_device(target: str) -> bool:
    """Return True for a camera index (``0``) or a device node (``/dev/video0``)."""
    return target.isdigit() or target.startswith("/dev/")


def open_capture(target: str, kind: str, options: Mapping[str, Any],
                 params: Mapping[str, Any] | None) -> cv2.VideoCapture:
    """Open one cv2.VideoCapture (``kind`` file, v4l2 or gst); raise SourceError when it fails."""
    if kind == "gst":
        if not gstreamer_supported():
            raise SourceError(f"gst:{target}: the installed OpenCV {cv2.__version__} has no GStreamer "
                              "support (cv2.getBuildInformation() says 'GStreamer: NO'); use a build "
                              "with GStreamer, or video:/sbs:/v4l2: sources")
        cap = cv2.VideoCapture(target, cv2.CAP_GSTREAMER)
    elif kind == "v4l2" or _is_device(target):
        device: int | str = int(target) if target.isdigit() else target
        cap = cv2.VideoCapture(device, cv2.CAP_V4L2)
        _configure_device(cap, options, params)
    else:
        if not os.path.isfile(target):
            raise SourceError(f"{target}: video file not found")
        cap = cv2.VideoCapture(target)
    if not cap.isOpened():
        raise SourceError(f"{target}: OpenCV cannot open this {kind if kind != 'file' else 'video file'}")
    return cap


def _configure_device(cap: cv2.VideoCapture, options: Mapping[str, Any],
                      params: Mapping[str, Any] | None) -> None:
    """Request the configured size and frame rate from a camera device (0 = leave as is)."""
    for name, prop in (("device_width_px", cv2.CAP_PROP_FRAME_WIDTH),
                       ("device_height_px", cv2.CAP_PROP_FRAME_HEIGHT),
                       ("device_fps", cv2.CAP_PROP_FPS)):
        value = option(name, options, params)
        if value:
            cap.set(prop, float(value))


class _Captures(StereoSource):
    """Shared reading loop: grab every capture first (closest in time), then retrieve."""

    def __init__(self, spec: str, targets: list[str], kind: str, options: Mapping[str, Any],
                 params: Mapping[str, Any] | None) -> None:
        super().__init__(spec, option("max_frames", options, params))
        self.targets, self.kind = targets, kind
        self.live = kind in ("v4l2", "gst") or any(_is_device(t) for t in targets)
        self.caps: list[cv2.VideoCapture] = []
        try:
            for target in targets:
                self.caps.append(open_capture(target, kind, options, params))
        except SourceError:
            self.close()
            raise
        self.stats = {"frames_read": 0}

    def _read_all(self) -> list[np.ndarray] | None:
        """Grab from every capture, then retrieve; None at the end of any stream."""
        if not all(cap.grab() for cap in self.caps):
            return None
        images = []
        for cap, target in zip(self.caps, self.targets):
            ok, image = cap.retrieve()
            if not ok:
                return None
            images.append(as_bgr(image, target))
        return images

    def _stamp(self, index: int) -> float:
        """Stamp of the frame just read: the file's position, else index / fps, else the clock."""
        if self.live:
            return time.monotonic()
        msec = self.caps[0].get(cv2.CAP_PROP_POS_MSEC)
        fps = self.caps[0].get(cv2.CAP_PROP_FPS)
        if index > 0 and msec > 0:
            return msec / 1000.0
        return index / fps if fps and fps > 0 else float(index)

    def _file_length(self) -> int:
        """Frames in the shortest file as the container reports it (0 if unknown or live)."""
        if self.live:
            return 0
        counts = [int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) for cap in self.caps]
        return min(counts) if counts and min(counts) > 0 else 0

    def __len__(self) -> int:
        n = self._file_length()
        return min(n, self.max_frames) if self.max_frames else n

    def _pair(self, images: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Return (left, right) from the images read from every capture (two captures here)."""
        return images[0], images[1]

    def _frames(self) -> Iterator[tuple[np.ndarray, np.ndarray, float, dict]]:
        index = 0
        while self.caps:
            images = self._read_all()
            if images is None:
                return
            left, right = self._pair(images)
            self.stats["frames_read"] += 1
            yield left, right, self._stamp(index), {}
            index += 1

    def close(self) -> None:
        for cap in self.caps:
            cap.release()
        self.caps = []
        super().close()


class CapturePairSource(_Captures):
    """Left and right from two captures: ``video:L.mp4,R.mp4`` or ``v4l2:/dev/video0,/dev/video1``."""

    def __init__(self, spec: str, left: str, right: str, kind: str = "file",
                 options: Mapping[str, Any] | None = None, params: Mapping[str, Any] | None = None) -> None:
        super().__init__(spec, [left, right], kind, dict(options or {}), params)
        self._check_counts()

    def _check_counts(self) -> None:
        """Record (not reject) files whose frame counts differ: reading stops at the shorter."""
        if not self.live:
            counts = [int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) for cap in self.caps]
            self.stats["left_frame_count"], self.stats["right_frame_count"] = counts

    def describe(self) -> str:
        return f"{self.kind} pair left={self.targets[0]} right={self.targets[1]}"


class SideBySideSource(_Captures):
    """One stream whose frames hold left | right side by side (``sbs:FILE|DEVICE``, ``gst:``)."""

    def __init__(self, spec: str, target: str, kind: str = "file",
                 options: Mapping[str, Any] | None = None, params: Mapping[str, Any] | None = None) -> None:
        super().__init__(spec, [target], kind, dict(options or {}), params)

    def describe(self) -> str:
        return f"side-by-side {self.kind} {self.targets[0]}"

    def _pair(self, images: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Split the one side-by-side image into (left, right)."""
        return split_side_by_side(images[0], self.targets[0])


def split_side_by_side(image: np.ndarray, where: str) -> tuple[np.ndarray, np.ndarray]:
    """Split a left | right frame in two halves; raise SourceError when the width is odd."""
    width = image.shape[1]
    if width % 2:
        raise SourceError(f"{where}: side-by-side frame width {width} is odd, cannot split in two halves")
    half = width // 2
    return np.ascontiguousarray(image[:, :half]), np.ascontiguousarray(image[:, half:])
