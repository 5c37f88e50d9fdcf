"""Closing in on a far diver: a bounded advance toward the diver that keeps every candidate in view.

Past ~4 m the 12 cm stereo baseline does not measure the arm's tilt toward or away from the camera
(one pixel of disparity is ~0.2 m of depth at 5 m): a point at objects that lie one behind the other
along the arm's image line stays ambiguous however long the diver holds it. The arm's depth error
grows with the square of its range, so a step toward the diver helps, but only if everything the
diver may be pointing at stays in the image (an object that leaves the view can no longer be chosen,
and the arm would then seem to point at the ones still visible).

Pure geometry in the rectified left camera frame (x right, y down, z forward, metres), as
``second_look.py``: the vehicle keeps its heading and moves in the camera's x-z plane (surge along
z, sway along x), straight toward the diver's shoulder, and may also sink (heave along y, taken as
the camera's y as in ``second_look.py``) by up to ``max_descent_m``. The move ends no nearer the
diver than ``target_range_m`` and ``standoff_m``, keeps the diver's joints and every kept point
inside the image by ``margin_px`` along the whole straight path, and passes no kept point (an
object hypothesis) closer than ``clearance_m``; none when it is shorter than ``min_step_m``.

Why sink: seen from the arm's own height every horizontal pointing direction projects onto one
image line, so objects spread in azimuth around the diver (``far_diver``: placards between the
vehicle and the diver) differ only in the arm's tilt toward the camera, which the stereo depth does
not measure at 4-5 m. Seen from below, the arm's azimuth also shows in the image (its toward-camera
part becomes an image-vertical part, ~sin(elevation) of it), where BlazePose's 2D landmarks are
good: on ``far_diver`` the stereo arm's direction error fell from a median of ~11 deg to 6.5 deg
0.7 m lower at the start pose (``sitl.arm_eval``'s frames rendered from the lower pose; issue 14).
Of the moves that fit, the one that sees the diver's shoulder from the steepest angle below wins
(ties: the longer one); without descent it is the longest advance, as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .clearance import distance_to_path_m
from .second_look import _in_view

__all__ = ["CloseInStep", "horizontal_range_m", "path_clearance_m", "elevation_rad", "plan_close_in"]


@dataclass(frozen=True)
class CloseInStep:
    """A planned advance: camera-frame offset (metres), its length, the diver's range before / after (m)."""

    offset_m: tuple[float, float, float]
    distance_m: float
    range_before_m: float
    range_after_m: float
    descent_m: float = 0.0
    elevation_after_rad: float = 0.0


def horizontal_range_m(xyz) -> float:
    """Return a camera-frame point's range in the camera's x-z plane, metres.

    Examples:
        >>> horizontal_range_m([3.0, 1.0, 4.0])
        5.0
    """
    return math.hypot(float(xyz[0]), float(xyz[2]))


def elevation_rad(xyz, camera_xyz=(0.0, 0.0, 0.0)) -> float:
    """Return how far below a camera-frame point the camera is seen from it, as an angle (positive: camera below), rad.

    Examples:
        >>> round(elevation_rad([0.0, -1.0, 4.0]), 3), round(elevation_rad([0.0, 0.0, 4.0], [0.0, 1.0, 0.0]), 3)
        (0.245, 0.245)
    """
    d = np.asarray(xyz, float) - np.asarray(camera_xyz, float)
    return math.atan2(-float(d[1]), horizontal_range_m(d))


def path_clearance_m(points_xyz, end_xyz) -> float:
    """Return the least distance from any point to the straight path from the camera to ``end_xyz``, metres."""
    pts = np.asarray(points_xyz, float).reshape(-1, 3)
    if len(pts) == 0:
        return math.inf
    return float(np.min(distance_to_path_m(pts, np.zeros(3), np.asarray(end_xyz, float))[0]))


def _path_in_view(points: np.ndarray, end: np.ndarray, focal_px: float, principal_px: tuple[float, float],
                  margin_px: float, samples: int = 4) -> bool:
    """Return True when every point stays in view (``margin_px``) from the camera moved anywhere along 0 -> ``end``."""
    return all(_in_view(points - f * end, focal_px, principal_px, margin_px) for f in np.linspace(0.0, 1.0, samples + 1)[1:])


def plan_close_in(diver_xyz, keep_xyz, target_range_m: float, standoff_m: float, clearance_m: float,
                  focal_px: float, principal_px: tuple[float, float], margin_px: float = 80.0,
                  min_step_m: float = 0.3, resolution_m: float = 0.05, max_descent_m: float = 0.0) -> CloseInStep | None:
    """Return the safe move toward (and below) the diver that sees the arm from the steepest angle, or None.

    Args:
        diver_xyz: the diver's joints (camera frame, metres), (N, 3); the first is the shoulder,
            which the advance aims at and whose horizontal range it measures.
        keep_xyz: points that must stay in view and off the path (the object hypotheses), (M, 3).
        target_range_m: stop when the shoulder is this far (the range to decide from).
        standoff_m: never end nearer the shoulder than this.
        clearance_m: the path passes no kept point closer than this.
        focal_px, principal_px: rectified intrinsics (the image is taken as 2 cx by 2 cy).
        margin_px: how far inside the image every point must stay (all along the path).
        min_step_m: the shortest move worth making.
        resolution_m: advance and descent are tried in steps of this.
        max_descent_m: the most the vehicle may sink (0: level, the longest advance).
    """
    diver = np.asarray(diver_xyz, float).reshape(-1, 3)
    keep = np.asarray(keep_xyz, float).reshape(-1, 3)
    shoulder = diver[0]
    rng = horizontal_range_m(shoulder)
    if rng <= 1e-6:
        return None
    u = np.array([shoulder[0], 0.0, shoulder[2]]) / rng
    longest = max(rng - max(target_range_m, standoff_m), 0.0)
    points = np.vstack([diver, keep])
    n_adv = int(math.floor(longest / resolution_m + 1e-9))
    n_down = int(math.floor(max(max_descent_m, 0.0) / resolution_m + 1e-9))
    best: tuple[float, float] | None = None
    step: CloseInStep | None = None
    for j in range(n_down + 1):
        for k in range(n_adv, -1, -1):  # per descent, the longest advance that fits
            c = k * resolution_m * u + np.array([0.0, j * resolution_m, 0.0])
            dist = float(np.linalg.norm(c))
            if dist < min_step_m - 1e-9:
                break
            if not _path_in_view(points, c, focal_px, principal_px, margin_px):
                continue
            if path_clearance_m(keep, c) < clearance_m:
                continue
            elev = elevation_rad(shoulder, c)
            if best is None or (round(elev, 6), dist) > best:
                best = (round(elev, 6), dist)
                step = CloseInStep(tuple(float(v) for v in c), dist, rng, horizontal_range_m(shoulder - c),
                                   j * resolution_m, elev)
            break
    return step
