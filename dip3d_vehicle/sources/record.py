"""``record:RUN.mcap``: the stereo pairs a run record kept, as a stereo source (``evaluate``, ``run``).

A bare path ending ``.mcap`` is read this way when the file is a dip3d-vehicle run record (its
``record`` metadata), and as a ROS 2 bag otherwise. Frames are numbered 0, 1, ... in the order
they were kept; ``meta["frame_index"]`` is the run's own frame index, ``stamp_s`` the log time.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Iterator, Mapping

import numpy as np

from ..errors import LogError, SourceError
from .base import StereoSource, option

__all__ = ["RecordSource", "is_run_record"]

_MARK = b"dip3d-vehicle-run"


def is_run_record(path: str | Path) -> bool:
    """True when ``path`` is an MCAP file written by this project's recorder."""
    try:
        with open(path, "rb") as f:
            head = f.read(4096)
    except OSError:
        return False
    return head.startswith(b"\x89MCAP0") and _MARK in head


class RecordSource(StereoSource):
    """The kept pairs of a run record (``run.mcap``)."""

    def __init__(self, path: str, options: Mapping[str, Any], params: Mapping[str, Any] | None = None,
                 spec: str = "") -> None:
        super().__init__(spec or f"record:{path}", int(option("max_frames", options, params) or 0))
        self.path = Path(path)
        if not self.path.is_file():
            raise SourceError(f"{self.spec}: run record {self.path} not found")

    def _frames(self) -> Iterator[tuple[np.ndarray, np.ndarray, float, dict]]:
        from ..record.mcap_log import McapRunReader

        try:
            with McapRunReader(self.path) as reader:
                for index, left, right in reader.image_pairs():
                    yield left, right, float(index), {"frame_index": index}
        except LogError as exc:
            raise SourceError(f"{self.spec}: {exc}") from None

    def describe(self) -> str:
        """One line: which record."""
        return f"run record {self.path} (kept pairs)"
