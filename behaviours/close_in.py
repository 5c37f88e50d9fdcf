"""Closing in on a far diver: a bounded advance toward the diver that keeps every candidate in view.

Past ~4 m the 12 cm stereo baseline does not measure the arm's tilt toward or away from the camera
(one pixel of disparity is ~0.2 m of depth at 5 m): a point at objects that lie one behind the other
along the arm's image line stays ambiguous however long the diver holds it. The arm's depth error
grows with the square of its range, so a step toward the diver helps, but only if everything the
diver may be pointing at stays in the image (an object that leaves the view can no longer be chosen,
and the arm would then seem to point at the ones still visible).

Pure geometry in the rectified left camera frame (x right, y down, z forward, metres), as
``second_look.py``: the vehicle keeps its heading and moves in the camera's x-z plane (surge along
z, sway along x; no heave), straight toward the diver's shoulder. The advance is the longest one
(in ``resolution_m`` steps) that ends no nearer the diver than ``target_range_m`` and
``standoff_m``, keeps the diver's joints and every kept point inside the image by ``margin_px``,
and passes no kept point (an object hypothesis) closer than ``clearance_m``; none when that is
shorter than ``min_step_m``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .second_look import _in_view

__all__ = ["CloseInStep", "horizontal_range_m", "path_clearance_m", "plan_close_in"]


@dataclass(frozen=True)
class CloseInStep:
    """A planned advance: camera-frame offset (metres), its length, the diver's range before / after (m)."""

    offset_m: tuple[float, float, float]
    distance_m: float
    range_before_m: float
    range_after_m: float


def horizontal_range_m(xyz) -> float:
    """Return a camera-frame point's range in the camera's x-z plane, metres.

    Examples:
        >>> horizontal_range_m([3.0, 1.0, 4.0])
        5.0
    """
    return math.hypot(float(xyz[0]), float(xyz[2]))


def path_clearance_m(points_xyz, end_xyz) -> float:
    """Return the least distance from any point to the straight path from the camera to ``end_xyz``, metres."""
    pts = np.asarray(points_xyz, float).reshape(-1, 3)
    if len(pts) == 0:
        return math.inf
    end = np.asarray(end_xyz, float)
    length2 = float(end @ end)
    t = np.clip(pts @ end / length2, 0.0, 1.0) if length2 > 0 else np.zeros(len(pts))
    return float(np.min(np.linalg.norm(pts - t[:, None] * end, axis=1)))


def plan_close_in(diver_xyz, keep_xyz, target_range_m: float, standoff_m: float, clearance_m: float,
                  focal_px: float, principal_px: tuple[float, float], margin_px: float = 80.0,
                  min_step_m: float = 0.3, resolution_m: float = 0.05) -> CloseInStep | None:
    """Return the longest safe advance toward the diver, or None when no useful one exists.

    Args:
        diver_xyz: the diver's joints (camera frame, metres), (N, 3); the first is the shoulder,
            which the advance aims at and whose horizontal range it measures.
        keep_xyz: points that must stay in view and off the path (the object hypotheses), (M, 3).
        target_range_m: stop when the shoulder is this far (the range to decide from).
        standoff_m: never end nearer the shoulder than this.
        clearance_m: the path passes no kept point closer than this.
        focal_px, principal_px: rectified intrinsics (the image is taken as 2 cx by 2 cy).
        margin_px: how far inside the image every point must stay.
        min_step_m: the shortest advance worth making.
        resolution_m: the advance is tried in steps of this, longest first.
    """
    diver = np.asarray(diver_xyz, float).reshape(-1, 3)
    keep = np.asarray(keep_xyz, float).reshape(-1, 3)
    shoulder = diver[0]
    rng = horizontal_range_m(shoulder)
    if rng <= 1e-6:
        return None
    u = np.array([shoulder[0], 0.0, shoulder[2]]) / rng
    longest = rng - max(target_range_m, standoff_m)
    points = np.vstack([diver, keep])
    n = int(math.floor(longest / resolution_m + 1e-9))
    for k in range(n, 0, -1):
        dist = k * resolution_m
        if dist < min_step_m:
            break
        c = dist * u
        if not _in_view(points - c, focal_px, principal_px, margin_px):
            continue
        if path_clearance_m(keep, c) < clearance_m:
            continue
        return CloseInStep(tuple(float(v) for v in c), dist, rng, horizontal_range_m(shoulder - c))
    return None
