"""Keypoints given from outside (a keypoints JSON file, an annotated dataset, simulator truth).

File format (DESIGN.md): ``{"left": {"shoulder": [x, y], "elbow": [x, y], "wrist": [x, y]},
"right": {...}}`` in original (unrectified) pixels, optionally ``"rectified": true``; each point
may carry a third value, its confidence in [0, 1] (default 1). Optional, for the stop gesture:
``"head"`` and ``"other_wrist"`` in ``"left"`` (same form); files without them stay valid.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import KeypointsError
from .calibration import StereoRig
from .pose import PoseEstimator
from .values import EXTRA_JOINTS, JOINTS, ArmKeypoints

__all__ = ["GivenKeypoints", "load_keypoints_file", "parse_keypoints", "parse_extra_joints"]


def load_keypoints_file(path: str | Path) -> dict:
    """Read a keypoints JSON file; raise KeypointsError naming the file on any problem."""
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise KeypointsError(f"{path}: keypoints file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise KeypointsError(f"{path}: cannot read keypoints file ({exc.__class__.__name__})") from None
    except json.JSONDecodeError as exc:
        raise KeypointsError(f"{path}:{exc.lineno}: not valid JSON ({exc.msg})") from None
    parse_keypoints(data, str(path))
    parse_extra_joints(data, str(path))
    return data


def _point(value: Any, where: str) -> tuple[float, float, float]:
    """Return (x, y, confidence) from [x, y] or [x, y, conf]; raise KeypointsError otherwise."""
    if not isinstance(value, (list, tuple)) or len(value) not in (2, 3):
        raise KeypointsError(f"{where}: expected [x, y] or [x, y, confidence], got {value!r}")
    try:
        x, y = float(value[0]), float(value[1])
        conf = float(value[2]) if len(value) == 3 else 1.0
    except (TypeError, ValueError):
        raise KeypointsError(f"{where}: expected numbers, got {value!r}") from None
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(conf)):
        raise KeypointsError(f"{where}: non-finite value {value!r}")
    if not 0.0 <= conf <= 1.0:
        raise KeypointsError(f"{where}: confidence {conf} is not in [0, 1]")
    return x, y, conf


def parse_keypoints(data: Any, where: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, bool]:
    """Validate keypoints data; return (left_px, right_px, left_conf, right_conf, rectified)."""
    if not isinstance(data, dict):
        raise KeypointsError(f"{where}: expected a JSON object with 'left' and 'right'")
    out = []
    for side in ("left", "right"):
        joints = data.get(side)
        if not isinstance(joints, dict):
            raise KeypointsError(f"{where}: missing or invalid '{side}' (an object of shoulder/elbow/wrist)")
        pts = []
        for name in JOINTS:
            if name not in joints:
                raise KeypointsError(f"{where}: missing key {side}.{name}")
            pts.append(_point(joints[name], f"{where}: {side}.{name}"))
        arr = np.array(pts, dtype=np.float64)
        out += [arr[:, :2], arr[:, 2]]
    rectified = data.get("rectified", False)
    if not isinstance(rectified, bool):
        raise KeypointsError(f"{where}: 'rectified' must be true or false, got {rectified!r}")
    return out[0], out[2], out[1], out[3], rectified


def parse_extra_joints(data: dict, where: str) -> dict[str, tuple[float, float]]:
    """Return the optional ``EXTRA_JOINTS`` of the left image as {name: (x, y)} (validated)."""
    left = data.get("left") if isinstance(data, dict) else None
    if not isinstance(left, dict):
        return {}
    out = {}
    for name in EXTRA_JOINTS:
        if name in left and left[name] is not None:
            x, y, _ = _point(left[name], f"{where}: left.{name}")
            out[name] = (x, y)
    return out


class GivenKeypoints(PoseEstimator):
    """A pose 'estimator' that returns keypoints provided before each frame (file or truth)."""

    name = "keypoints"

    def __init__(self, arm: str = "right", data: dict | None = None, where: str = "keypoints") -> None:
        self.arm = arm
        self._data: dict | None = None
        self._where = where
        if data is not None:
            self.provide(data, where)

    @classmethod
    def from_file(cls, path: str | Path, arm: str = "right") -> "GivenKeypoints":
        """Return an estimator that always yields the keypoints of one file."""
        return cls(arm, load_keypoints_file(path), str(path))

    def provide(self, data: dict | None, where: str = "keypoints") -> None:
        """Set the keypoints for the next frames (None = no person seen)."""
        if data is not None:
            parse_keypoints(data, where)
            parse_extra_joints(data, where)
        self._data, self._where = data, where

    def estimate(self, left_rect: np.ndarray, right_rect: np.ndarray, rig: StereoRig) -> ArmKeypoints | None:
        """Return the provided keypoints mapped to rectified pixels, or None if none were given."""
        if self._data is None:
            return None
        left, right, lconf, rconf, rectified = parse_keypoints(self._data, self._where)
        if not rectified:
            left, right = rig.to_rectified(left, "left"), rig.to_rectified(right, "right")
        source = str(self._data.get("source", "keypoints-file"))
        extra = parse_extra_joints(self._data, self._where)
        if extra and not rectified:
            names = list(extra)
            pts = rig.to_rectified(np.array([extra[n] for n in names], dtype=np.float64), "left")
            extra = {n: (float(p[0]), float(p[1])) for n, p in zip(names, pts)}
        return ArmKeypoints(self.arm, left, right, lconf, rconf, source, dict(extra))
