"""Keeping clear of the other objects on the way to the target: a sidestep around them, and a slower approach.

The servo drives the camera straight at the target and stops ``standoff_m`` before it. Any object
the diver did not point at that lies near that straight path, or beside the stand-off point, is in
the vehicle's way: in the paper's own set-up (placards at 1, 2 and 3 m along a line) the stand-off
point before placard 2 lies 0.23 m from placard 1, and the simulator measured the vehicle's centre
passing 0.27 m from its face (``sitl --json``'s ``closest_other_m``).

The objects are the decision's other hypotheses (the tracker's known neighbours: offsets from the
target, turned by the commanded yaw), so they are remembered after they leave the image. Geometry
in the rectified left camera frame (x right, y down, z forward, metres), as ``close_in.py``: the
path is the straight segment from the hull's rear (``behind_m`` behind the camera: an object the
camera has passed still lies beside the hull) to the stand-off point. When an object lies nearer
that path than ``clearance_m``, the vehicle sways away from it (the yaw keeps the target centred, so
the vehicle turns about the target and the stand-off point moves off the object) at
``gain_per_s`` times the missing clearance; and while the object is nearer than half the clearance
and lies ahead of the camera by at most ``clearance_m`` along the path, the vehicle does not advance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["HULL_HALF_LENGTH_M", "Sidestep", "approach_end_m", "distance_to_path_m", "sidestep"]

GAIN_PER_S = 1.0
"""Sway speed per metre of missing clearance, 1/s (capped by the servo's sway limit)."""

HULL_HALF_LENGTH_M = 0.25
"""How far the hull reaches behind the vehicle's reference point, m (a BlueROV2 is 0.457 m long)."""


@dataclass(frozen=True)
class Sidestep:
    """How to keep clear of the nearest object in the way (camera frame, metres; body sway, m/s).

    Attributes:
        sway_m_s: the sway to add (positive = right), m/s.
        surge_factor: what the servo's forward surge is multiplied by (1 = unchanged, 0 = no advance).
        clearance_m: the nearest object's distance from the path, m.
        index: which object (row of the objects given) is in the way.
    """

    sway_m_s: float
    surge_factor: float
    clearance_m: float
    index: int


def approach_end_m(target_xyz, standoff_m: float) -> np.ndarray:
    """Return where the camera ends its approach: ``standoff_m`` before the target on its line of sight, metres."""
    t = np.asarray(target_xyz, float)
    rng = float(np.linalg.norm(t))
    return t * max(rng - standoff_m, 0.0) / rng if rng > 1e-9 else np.zeros(3)


def distance_to_path_m(points: np.ndarray, start: np.ndarray, end: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return each point's distance from the segment ``start`` -> ``end`` and its nearest point's distance along
    it from ``start``, metres."""
    d = end - start
    length = float(np.linalg.norm(d))
    if length < 1e-9:
        return np.linalg.norm(points - start, axis=1), np.zeros(len(points))
    along = np.clip((points - start) @ d / length, 0.0, length)
    return np.linalg.norm(points - start - along[:, None] * (d / length), axis=1), along


def sidestep(target_xyz, objects_xyz, standoff_m: float, clearance_m: float, max_sway_m_s: float,
             behind_m: float = 0.0, gain_per_s: float = GAIN_PER_S) -> Sidestep | None:
    """Return the sidestep around the object nearest the approach path, or None when every object is clear.

    Args:
        target_xyz: the target (camera frame, metres).
        objects_xyz: the other objects, (K, 3) (camera frame, metres).
        standoff_m: the servo's stand-off (the approach ends this far before the target).
        clearance_m: how far from the path every object must stay (0: never sidestep).
        max_sway_m_s: the sway limit, m/s.
        behind_m: how far the hull reaches behind the camera (the path starts there), m.
        gain_per_s: sway speed per metre of missing clearance, 1/s.

    Examples:
        >>> s = sidestep([0.0, 0.0, 2.0], [[0.2, 0.0, 1.0]], 1.0, 0.5, 0.3)  # right of the stand-off point
        >>> round(s.sway_m_s, 2), s.surge_factor, round(s.clearance_m, 2)  # sway left, still advancing
        (-0.3, 1.0, 0.2)
        >>> sidestep([0.0, 0.0, 2.0], [[0.2, 0.0, 0.3]], 1.0, 0.5, 0.3).surge_factor  # just ahead: no advance
        0.0
    """
    objects = np.asarray(objects_xyz, float).reshape(-1, 3)
    objects = objects[np.all(np.isfinite(objects), axis=1)]
    if clearance_m <= 0 or not len(objects):
        return None
    end = approach_end_m(target_xyz, standoff_m)
    start = np.array([0.0, 0.0, -behind_m])
    dist, along = distance_to_path_m(objects, start, end)
    k = int(np.argmin(dist))
    if dist[k] >= clearance_m:
        return None
    u = (end - start) / max(float(np.linalg.norm(end - start)), 1e-9)
    side = objects[k] - start - along[k] * u  # the object's offset from its nearest point on the path
    away = -1.0 if side[0] > 0 else 1.0  # on the path itself (x 0): to the left, away from the right-hand side
    sway = away * min(gain_per_s * (clearance_m - float(dist[k])), max_sway_m_s)
    ahead_m = float(objects[k] @ u)  # along the path from the camera (negative: beside the hull, already passed)
    close_ahead = 0.0 <= ahead_m <= clearance_m
    factor = 1.0 if not close_ahead else float(np.clip((dist[k] - clearance_m / 2) / (clearance_m / 2), 0.0, 1.0))
    return Sidestep(float(sway), factor, float(dist[k]), k)
