"""The stereo source interface, and the parameter look-up every source shares."""

from __future__ import annotations

import abc
from typing import Any, Iterator, Mapping

import cv2
import numpy as np

from ..config import schema
from ..errors import SourceError
from ..frames import StereoFrame

__all__ = ["StereoSource", "option", "as_bgr"]


def option(name: str, options: Mapping[str, Any], params: Mapping[str, Any] | None = None) -> Any:
    """Return source option ``name``: the call's options first, then ``params``, then the schema.

    Args:
        name: the key without its ``sources.`` prefix (e.g. ``bag_tolerance_s``).
        options: keyword options of ``open_source`` and the spec's ``?key=value`` options.
        params: effective parameters (``config.Params``) or None.

    Returns:
        The value, converted and range-checked against the schema entry ``sources.<name>``.

    Raises:
        SourceError: the value does not fit the schema entry.
    """
    key = f"sources.{name}"
    entry = schema()[key]
    if name in options and options[name] is not None:
        try:
            return entry.coerce(options[name], f"source option {name}")
        except Exception as exc:  # ParamsError -> the source's own error kind
            raise SourceError(str(exc)) from None
    if params is not None and key in params:
        return params[key]
    return entry.default


def as_bgr(image: np.ndarray, where: str) -> np.ndarray:
    """Return ``image`` as HxWx3 uint8 BGR (gray and BGRA converted); raise SourceError otherwise."""
    if image is None or not isinstance(image, np.ndarray) or image.size == 0:
        raise SourceError(f"{where}: empty or unreadable image")
    if image.dtype != np.uint8:
        raise SourceError(f"{where}: image is {image.dtype}, expected 8-bit")
    if image.ndim == 2 or (image.ndim == 3 and image.shape[2] == 1):
        return cv2.cvtColor(image.reshape(image.shape[:2]), cv2.COLOR_GRAY2BGR)
    if image.ndim == 3 and image.shape[2] == 4:
        return cv2.cvtColor(image, cv2.COLOR_BGRA2BGR)
    if image.ndim == 3 and image.shape[2] == 3:
        return np.ascontiguousarray(image)
    raise SourceError(f"{where}: image shape {image.shape} is not gray, BGR or BGRA")


class StereoSource(abc.ABC):
    """An iterable of StereoFrame (original BGR uint8 images, source stamps), closed after use.

    Subclasses implement ``_frames()`` (yield left, right, stamp_s, meta) and ``describe()``;
    the base numbers the frames 0, 1, 2, ..., applies ``max_frames`` and is a context manager.
    ``stats`` holds counters a user should see (e.g. unpaired bag messages).
    """

    spec: str = ""

    def __init__(self, spec: str, max_frames: int = 0) -> None:
        self.spec = spec
        self.max_frames = int(max_frames)
        self.stats: dict[str, int] = {}
        self._closed = False

    @abc.abstractmethod
    def _frames(self) -> Iterator[tuple[np.ndarray, np.ndarray, float, dict]]:
        """Yield (left BGR, right BGR, stamp_s, meta) for each stereo pair."""

    @abc.abstractmethod
    def describe(self) -> str:
        """Return one line saying what this source reads (for logs and errors)."""

    def __iter__(self) -> Iterator[StereoFrame]:
        if self._closed:
            raise SourceError(f"{self.spec}: source is closed")
        for index, (left, right, stamp_s, meta) in enumerate(self._frames()):
            if self.max_frames and index >= self.max_frames:
                return
            if left.shape != right.shape:
                raise SourceError(f"{self.spec}: frame {index}: left image {left.shape[1]}x{left.shape[0]} "
                                  f"and right image {right.shape[1]}x{right.shape[0]} differ in size")
            yield StereoFrame(left=left, right=right, stamp_s=float(stamp_s), index=index, meta=meta)

    def close(self) -> None:
        """Release files and devices; safe to call twice."""
        self._closed = True

    def __enter__(self) -> "StereoSource":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.describe()}>"
