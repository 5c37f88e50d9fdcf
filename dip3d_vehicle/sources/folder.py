"""A folder of stereo image pairs.

Two layouts are read (``writer.FolderWriter`` writes the first):

- prefixed: ``left_NNNNNN.png`` + ``right_NNNNNN.png`` (``.png``, ``.jpg``, ``.jpeg``; any number
  of digits; pairs matched by the number, ordered by it);
- subfolders: ``left/NAME`` + ``right/NAME`` with identical file names, ordered by name.

Stamps come from an optional ``stamps.csv`` (header ``frame,stamp_s``; ``frame`` is the number
of a prefixed pair or the file name without extension in subfolders), else position / fps.
"""

from __future__ import annotations

import csv
import re
import time
from pathlib import Path
from typing import Any, Iterator, Mapping

import cv2
import numpy as np

from ..errors import SourceError
from .base import StereoSource, as_bgr, option

__all__ = ["FolderSource", "IMAGE_EXTENSIONS", "STAMPS_FILE"]

IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg")
STAMPS_FILE = "stamps.csv"
_PREFIXED = re.compile(r"^(left|right)_(\d+)\.(png|jpe?g)$", re.IGNORECASE)


class FolderSource(StereoSource):
    """Stereo pairs from a folder (prefixed names or ``left/`` + ``right/`` subfolders)."""

    def __init__(self, path: str | Path, options: Mapping[str, Any] | None = None,
                 params: Mapping[str, Any] | None = None, spec: str | None = None) -> None:
        options = dict(options or {})
        super().__init__(spec or str(path), option("max_frames", options, params))
        self.path = Path(path)
        if not self.path.is_dir():
            raise SourceError(f"{self.path}: image folder not found")
        self.fps = option("folder_fps", options, params)
        self.realtime = option("folder_realtime", options, params)
        self.pairs = _find_pairs(self.path)
        self.stamps = _read_stamps(self.path, [key for key, _, _ in self.pairs], self.fps)

    def __len__(self) -> int:
        n = len(self.pairs)
        return min(n, self.max_frames) if self.max_frames else n

    def describe(self) -> str:
        stamps = STAMPS_FILE if (self.path / STAMPS_FILE).is_file() else f"{self.fps:g} fps"
        pace = ", delivered at their pace" if self.realtime else ""
        return f"folder {self.path} ({len(self.pairs)} pairs, stamps from {stamps}{pace})"

    def _frames(self) -> Iterator[tuple[np.ndarray, np.ndarray, float, dict]]:
        start = None
        for (key, left_path, right_path), stamp_s in zip(self.pairs, self.stamps):
            if self.realtime:  # a camera's pace: pair k no earlier than its stamp after the first
                now = time.monotonic()
                start = start if start is not None else (now, stamp_s)
                delay = start[0] + (stamp_s - start[1]) - now
                if delay > 0:
                    time.sleep(delay)
            left = _read_image(left_path)
            right = _read_image(right_path)
            yield left, right, stamp_s, {"name": key, "left_path": str(left_path),
                                         "right_path": str(right_path)}


def _read_image(path: Path) -> np.ndarray:
    """Read one image as BGR uint8; raise SourceError naming the file when it cannot be read."""
    data = np.fromfile(str(path), dtype=np.uint8) if path.is_file() else None
    if data is None:
        raise SourceError(f"{path}: image file not found")
    image = cv2.imdecode(data, cv2.IMREAD_UNCHANGED) if data.size else None
    if image is None:
        raise SourceError(f"{path}: not a readable image")
    if image.dtype == np.uint16:
        image = (image >> 8).astype(np.uint8)
    return as_bgr(image, str(path))


def _find_pairs(folder: Path) -> list[tuple[str, Path, Path]]:
    """Return (key, left, right) for every pair in ``folder``; raise SourceError when none match."""
    if (folder / "left").is_dir() and (folder / "right").is_dir():
        return _subfolder_pairs(folder)
    sides: dict[str, dict[int, Path]] = {"left": {}, "right": {}}
    for entry in folder.iterdir():
        match = _PREFIXED.match(entry.name)
        if match and entry.is_file():
            side, number = match.group(1).lower(), int(match.group(2))
            if number in sides[side]:
                raise SourceError(f"{folder}: two {side} images numbered {number}: "
                                  f"{sides[side][number].name} and {entry.name}")
            sides[side][number] = entry
    if not sides["left"] and not sides["right"]:
        raise SourceError(f"{folder}: no stereo pairs found (expected left_NNNNNN.png|jpg + "
                          "right_NNNNNN.png|jpg, or subfolders left/ and right/)")
    _check_matched(folder, {k: v.name for k, v in sides["left"].items()},
                   {k: v.name for k, v in sides["right"].items()})
    return [(f"{n:06d}", sides["left"][n], sides["right"][n]) for n in sorted(sides["left"])]


def _subfolder_pairs(folder: Path) -> list[tuple[str, Path, Path]]:
    """Pairs from ``left/`` and ``right/`` holding images with identical names."""
    def images(side: str) -> dict[str, str]:
        return {p.name: p.name for p in (folder / side).iterdir()
                if p.is_file() and p.suffix.lower() in IMAGE_EXTENSIONS}
    left, right = images("left"), images("right")
    if not left and not right:
        raise SourceError(f"{folder}: subfolders left/ and right/ hold no .png/.jpg images")
    _check_matched(folder, left, right, "left/", "right/")
    return [(Path(name).stem, folder / "left" / name, folder / "right" / name) for name in sorted(left)]


def _check_matched(folder: Path, left: dict, right: dict, lname: str = "", rname: str = "") -> None:
    """Raise SourceError when the left and right images do not pair one to one."""
    only_left = sorted(set(left) - set(right))
    only_right = sorted(set(right) - set(left))
    if only_left or only_right:
        first = (f"{lname}{left[only_left[0]]} has no right image" if only_left
                 else f"{rname}{right[only_right[0]]} has no left image")
        raise SourceError(f"{folder}: mismatched pairs: {len(left)} left images, {len(right)} right "
                          f"images ({first})")


def _read_stamps(folder: Path, keys: list[str], fps: float) -> list[float]:
    """Return one stamp per pair from ``stamps.csv`` (header frame,stamp_s), else position / fps."""
    path = folder / STAMPS_FILE
    if not path.is_file():
        return [i / fps for i in range(len(keys))]
    table: dict[str, float] = {}
    try:
        with path.open(newline="") as handle:
            reader = csv.DictReader(handle)
            if not reader.fieldnames or not {"frame", "stamp_s"} <= set(reader.fieldnames):
                raise SourceError(f"{path}: expected a header line 'frame,stamp_s'")
            for line, row in enumerate(reader, start=2):
                try:
                    table[_norm_key(row["frame"])] = float(row["stamp_s"])
                except (TypeError, ValueError):
                    raise SourceError(f"{path}:{line}: bad row {row!r} (expected frame,stamp_s)") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise SourceError(f"{path}: cannot read ({exc.__class__.__name__})") from None
    missing = [k for k in keys if _norm_key(k) not in table]
    if missing:
        raise SourceError(f"{path}: no stamp for {len(missing)} pair(s), first frame {missing[0]}")
    return [table[_norm_key(k)] for k in keys]


def _norm_key(key: str) -> str:
    """Normalise a frame key: numbers compare as numbers (7 == 000007), names as text."""
    key = str(key).strip()
    return str(int(key)) if key.isdigit() else key
