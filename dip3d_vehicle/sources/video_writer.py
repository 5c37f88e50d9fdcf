"""Optional annotated video of a run (mp4v), opened at the first frame so the size is known."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from ..errors import LogError

__all__ = ["AnnotatedVideo"]


class AnnotatedVideo:
    """Write BGR uint8 frames (all the same size) to an mp4 file with cv2.VideoWriter (mp4v).

    Args:
        path: output file (``.mp4``).
        fps: frame rate written into the file's header, Hz.

    Raises:
        LogError: the file cannot be opened, or a frame's size differs from the first one.
    """

    def __init__(self, path: str | Path, fps: float = 10.0) -> None:
        if not fps > 0:
            raise LogError(f"{path}: annotated video fps must be > 0, got {fps}")
        self.path, self.fps = Path(path), float(fps)
        self._writer: cv2.VideoWriter | None = None
        self._size: tuple[int, int] | None = None
        self.frames_written = 0

    def write(self, image: np.ndarray) -> None:
        """Append one BGR (or gray) uint8 frame."""
        if image.ndim == 2:
            image = cv2.cvtColor(image, cv2.COLOR_GRAY2BGR)
        size = (image.shape[1], image.shape[0])
        if self._writer is None:
            writer = cv2.VideoWriter(str(self.path), cv2.VideoWriter_fourcc(*"mp4v"), self.fps, size)
            if not writer.isOpened():
                raise LogError(f"{self.path}: cannot open an mp4v video writer ({size[0]}x{size[1]})")
            self._writer, self._size = writer, size
        elif size != self._size:
            raise LogError(f"{self.path}: frame size {size[0]}x{size[1]} differs from the first "
                           f"frame's {self._size[0]}x{self._size[1]}")
        self._writer.write(np.ascontiguousarray(image, dtype=np.uint8))
        self.frames_written += 1

    def close(self) -> None:
        """Finish the file; safe to call twice."""
        if self._writer is not None:
            self._writer.release()
            self._writer = None

    def __enter__(self) -> "AnnotatedVideo":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
