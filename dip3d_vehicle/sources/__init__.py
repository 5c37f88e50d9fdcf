"""Stereo sources behind one interface: ``open_source(spec)`` -> StereoSource (iterable of StereoFrame).

Spec syntax (options after ``?`` as ``key=value&key=value``, except for ``gst:``):

=====================================================  ===========================================
``PATH`` (folder)                                      image pairs ``left_NNNNNN.png|jpg`` +
                                                       ``right_NNNNNN.png|jpg``, or ``left/`` +
                                                       ``right/`` with identical names; optional
                                                       ``stamps.csv`` (``frame,stamp_s``)
``folder:PATH``                                        the same, explicitly
``video:LEFT.mp4,RIGHT.mp4``                           two video files (or devices)
``sbs:FILE_OR_DEVICE``                                 one side-by-side stream, split in halves
``v4l2:/dev/video0,/dev/video1`` / ``v4l2:0``          two V4L2 devices / one side-by-side device
``gst:PIPELINE`` / ``gst:LEFT_PIPE || RIGHT_PIPE``     GStreamer (side-by-side / two pipelines);
                                                       needs an OpenCV built with GStreamer
``bag:PATH?left=/t&right=/t&tolerance=0.005``          ROS 1 ``.bag`` or ROS 2 bag folder
``PATH.bag`` or a folder holding ``metadata.yaml``     a bag, detected
``record:RUN.mcap`` or a ``.mcap`` run record          the stereo pairs a run record kept
=====================================================  ===========================================

Options (spec or keyword): ``max_frames``, ``folder_fps``, ``tolerance``/``bag_tolerance_s``,
``bag_max_pending``, ``device_width_px``, ``device_height_px``, ``device_fps``; unset ones come from
``params`` (``sources.*``) and then the schema defaults. Every failure is a SourceError naming the
spec or file.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping
from urllib.parse import parse_qsl

from ..errors import SourceError
from .bag import BagSource
from .record import RecordSource, is_run_record
from .base import StereoSource
from .folder import FolderSource
from .video import CapturePairSource, SideBySideSource, gstreamer_supported
from .video_writer import AnnotatedVideo
from .writer import FolderWriter, write_folder

__all__ = [
    "StereoSource", "open_source", "parse_spec", "FolderSource", "BagSource", "CapturePairSource",
    "SideBySideSource", "FolderWriter", "write_folder", "gstreamer_supported", "AnnotatedVideo",
]

_SCHEMES = ("folder", "video", "sbs", "v4l2", "gst", "bag", "record")


def parse_spec(spec: str) -> tuple[str, str, dict[str, str]]:
    """Split a source spec into (scheme, target, options); a bare path gets scheme folder or bag."""
    scheme, sep, rest = spec.partition(":")
    if not sep or scheme not in _SCHEMES:
        scheme, rest = "", spec
    if scheme == "gst":
        return scheme, rest.strip(), {}
    target, _, query = rest.partition("?")
    try:
        options = dict(parse_qsl(query, keep_blank_values=True, strict_parsing=bool(query)))
    except ValueError:
        raise SourceError(f"{spec}: options after '?' must be key=value&key=value") from None
    if not scheme:
        path = Path(target)
        is_bag = path.suffix in (".bag", ".db3", ".mcap") or (path / "metadata.yaml").is_file()
        scheme = "bag" if is_bag else "folder"
        if path.suffix == ".mcap" and is_run_record(path):
            scheme = "record"
    return scheme, target, options


def open_source(spec: str, params: Mapping[str, Any] | None = None, **options: Any) -> StereoSource:
    """Open the stereo source named by ``spec`` (see the module doc for the syntax).

    Args:
        spec: source spec, e.g. ``dive1/``, ``bag:dive1.bag?tolerance=0.01``, ``sbs:/dev/video0``.
        params: effective parameters (``config.Params``) for the ``sources.*`` defaults, or None.
        **options: options that override both the spec's ``?key=value`` options and ``params``.

    Returns:
        An open StereoSource; use it as a context manager or call ``close()``.

    Raises:
        SourceError: the spec is malformed or the source cannot be opened.
    """
    if not isinstance(spec, str) or not spec.strip():
        raise SourceError(f"source spec {spec!r} is empty")
    scheme, target, spec_options = parse_spec(spec.strip())
    opts = {**spec_options, **options}
    if not target:
        raise SourceError(f"{spec}: no path, file or device after '{scheme}:'")
    if scheme == "folder":
        return FolderSource(target, opts, params, spec=spec)
    if scheme == "record":
        return RecordSource(target, opts, params, spec=spec)
    if scheme == "bag":
        left, right = opts.pop("left", None), opts.pop("right", None)
        return BagSource(target, left or None, right or None, opts, params, spec=spec)
    if scheme == "gst":
        parts = [p.strip() for p in target.split("||")]
        if len(parts) == 2:
            return CapturePairSource(spec, parts[0], parts[1], "gst", opts, params)
        return SideBySideSource(spec, target, "gst", opts, params)
    parts = [p.strip() for p in target.split(",")]
    if scheme == "sbs" or (scheme == "v4l2" and len(parts) == 1):
        if len(parts) != 1:
            raise SourceError(f"{spec}: sbs: takes one file or device, got {len(parts)}")
        return SideBySideSource(spec, parts[0], "v4l2" if scheme == "v4l2" else "file", opts, params)
    if len(parts) != 2 or not all(parts):
        raise SourceError(f"{spec}: expected {scheme}:LEFT,RIGHT (two files or devices separated by a comma)")
    return CapturePairSource(spec, parts[0], parts[1], "v4l2" if scheme == "v4l2" else "file", opts, params)
