"""Write stereo frames as an image folder that ``FolderSource`` reads back (datasets, tests)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Iterable

import cv2
import numpy as np

from ..errors import SourceError
from ..frames import StereoFrame
from .folder import STAMPS_FILE

__all__ = ["FolderWriter", "write_folder"]


class FolderWriter:
    """Write ``left_NNNNNN.EXT`` + ``right_NNNNNN.EXT`` (NNNNNN = frame.index) and ``stamps.csv``.

    Each image is written to a ``.part`` file and renamed, so a reader never sees half an image;
    ``stamps.csv`` is flushed after every frame.

    Args:
        path: folder to write (created; must not already hold pairs unless ``overwrite``).
        fmt: ``png`` (exact) or ``jpg``.
        jpeg_quality: JPEG quality 1..100 when ``fmt`` is ``jpg``.
        layout: ``prefixed`` (left_/right_ names) or ``subfolders`` (left/ and right/).
    """

    def __init__(self, path: str | Path, fmt: str = "png", jpeg_quality: int = 95,
                 layout: str = "prefixed", overwrite: bool = False) -> None:
        if fmt not in ("png", "jpg"):
            raise SourceError(f"{path}: image format {fmt!r} is not png or jpg")
        if layout not in ("prefixed", "subfolders"):
            raise SourceError(f"{path}: layout {layout!r} is not prefixed or subfolders")
        self.path = Path(path)
        self.fmt, self.layout = fmt, layout
        self._params = [cv2.IMWRITE_JPEG_QUALITY, int(jpeg_quality)] if fmt == "jpg" else []
        self._seen: set[int] = set()
        self.path.mkdir(parents=True, exist_ok=True)
        stamps = self.path / STAMPS_FILE
        if stamps.exists() and not overwrite:
            raise SourceError(f"{self.path}: already holds {STAMPS_FILE} (a written dataset); "
                              "pass overwrite=True to replace it")
        if layout == "subfolders":
            (self.path / "left").mkdir(exist_ok=True)
            (self.path / "right").mkdir(exist_ok=True)
        self._stamps = stamps.open("w", newline="")
        self._stamps.write("frame,stamp_s\n")
        self._stamps.flush()

    def _names(self, index: int) -> tuple[Path, Path]:
        name = f"{index:06d}.{self.fmt}"
        if self.layout == "subfolders":
            return self.path / "left" / name, self.path / "right" / name
        return self.path / f"left_{name}", self.path / f"right_{name}"

    def write(self, frame: StereoFrame) -> tuple[Path, Path]:
        """Write one frame's images and its stamp; return the two image paths."""
        if frame.index in self._seen:
            raise SourceError(f"{self.path}: frame index {frame.index} written twice")
        self._seen.add(frame.index)
        paths = self._names(frame.index)
        for image, path in zip((frame.left, frame.right), paths):
            ok, data = cv2.imencode(f".{self.fmt}", np.ascontiguousarray(image), self._params)
            if not ok:
                raise SourceError(f"{path}: cannot encode image of shape {image.shape}")
            tmp = path.with_name(path.name + ".part")
            tmp.write_bytes(data.tobytes())
            os.replace(tmp, path)
        self._stamps.write(f"{frame.index:06d},{frame.stamp_s!r}\n")
        self._stamps.flush()
        return paths

    def close(self) -> None:
        """Close ``stamps.csv``; safe to call twice."""
        if not self._stamps.closed:
            self._stamps.close()

    def __enter__(self) -> "FolderWriter":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def write_folder(path: str | Path, frames: Iterable[StereoFrame], fmt: str = "png",
                 jpeg_quality: int = 95, layout: str = "prefixed", overwrite: bool = False) -> int:
    """Write every frame of ``frames`` to ``path`` (see FolderWriter); return how many."""
    count = 0
    with FolderWriter(path, fmt, jpeg_quality, layout, overwrite) as writer:
        for frame in frames:
            writer.write(frame)
            count += 1
    return count
