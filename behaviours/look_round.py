"""Look round an object that hides the target: a lost target whose line of sight a known object blocks, and the
sideways step of the camera that clears it (camera frame: x right, y down, z forward; metres).

A way round a near object can carry the line of sight to the target across that object: the target is then
hidden, the tracker loses it, and a vehicle that holds still stays hidden until it gives up (issue 11 session 58:
four of the five targets lost on ordinary layouts were hidden by another placard; ``variant_28_15`` seed 1 held
2.9 m from the target with a placard 1.4 m ahead 0.04 m off the line of sight). The step is horizontal, across
the line of sight; it is taken only when its straight path keeps every known object and the diver's points as
far as the way would (``clearance.distance_to_path_m``), so it never moves toward anything it may not.

Examples:
    >>> hider([0.0, 0.0, 3.0], [[0.05, 0.0, 1.5], [1.0, 0.0, 1.0]], 0.2)  # the first lies on the line of sight
    0
    >>> round(step_clear_m([0.0, 0.0, 3.0], [0.05, 0.0, 1.5], 0.25), 2)  # 0.2 m more off the line: 0.4 m left
    -0.4
"""

from __future__ import annotations

import math

import numpy as np

from .clearance import across_and_along, distance_to_path_m

__all__ = ["HIDE_RADIUS_M", "CLEAR_OF_HIDER_M", "hider", "step_clear_m", "safe_step_m", "look_round_m"]

HIDE_RADIUS_M = 0.2
"""An object whose centre lies this near the line of sight to the target, between the camera and it, hides it,
metres (a 0.3 m placard's half-diagonal is 0.21 m; the tracker needs the target's features, not a glimpse)."""


CLEAR_OF_HIDER_M = 0.3
"""The step ends when the line of sight passes this far from the hider's centre, metres (its half-size and 0.1 m)."""


def hider(target_xyz, objects_xyz, radius_m: float = HIDE_RADIUS_M) -> int | None:
    """Return the index of the nearest object lying between the camera and the target within ``radius_m`` of the
    line of sight (3D), or None."""
    t = np.asarray(target_xyz, float)
    rng = float(np.linalg.norm(t))
    objects = np.asarray(objects_xyz, float).reshape(-1, 3)
    if rng < 1e-9 or not len(objects):
        return None
    u = t / rng
    along = objects @ u
    off = np.linalg.norm(objects - along[:, None] * u[None], axis=1)
    between = (along > 0.0) & (along < rng - radius_m) & (off < radius_m)
    if not np.any(between):
        return None
    return int(np.flatnonzero(between)[np.argmin(along[between])])


def _offset_m(camera_x_m: float, target: np.ndarray, obj: np.ndarray) -> float:
    """Return ``obj``'s horizontal offset from the line of sight to ``target`` of a camera moved ``camera_x_m`` along
    x, metres (positive: right of the line)."""
    moved = np.array([camera_x_m, 0.0, 0.0])
    return across_and_along(target - moved, obj - moved)[0]


def step_clear_m(target_xyz, hider_xyz, clear_m: float, direction: float = 0.0) -> float:
    """Return the camera's sideways move (x, metres, positive: right) after which the horizontal line of sight to the
    target passes ``clear_m`` from the hider's centre: away from the side the hider leans to (``direction`` 0; right
    when it lies on the line itself), or toward ``direction``'s sign (past the hider: a longer move); 0 when it is
    clear already.

    Moving the camera by ``s`` moves the line at the hider by about ``s cos(bearing) (1 - a / L)`` across it (``a``:
    the hider's distance along the line, ``L``: the target's); a few Newton steps on the exact offset finish it.
    """
    t, h = np.asarray(target_xyz, float), np.asarray(hider_xyz, float)
    if math.hypot(float(t[0]), float(t[2])) < 1e-9:
        return 0.0
    off = _offset_m(0.0, t, h)
    move = (-1.0 if off > 0 else 1.0) if direction == 0 else math.copysign(1.0, direction)
    goal = -move * clear_m  # the camera moves one way, the hider ends on the line's other side
    if -move * off >= clear_m:
        return 0.0
    step = 0.0
    for _ in range(8):
        g = _offset_m(step, t, h)
        slope = (_offset_m(step + 1e-3, t, h) - g) / 1e-3
        if abs(slope) < 1e-6:
            return 0.0
        step += (goal - g) / slope
    return step if step * move > 0 and abs(_offset_m(step, t, h) - goal) < 0.01 else 0.0


def safe_step_m(step_m: float, objects_xyz, needed_m: np.ndarray, behind_m: float) -> bool:
    """Return True when the camera's sideways move ``step_m`` (x, metres) keeps every object at least as far from the
    hull as ``needed_m`` asks (or as it already is, when nearer): the hull's front and rear both sweep the move."""
    objects = np.asarray(objects_xyz, float).reshape(-1, 3)
    if not len(objects):
        return True
    end = np.array([step_m, 0.0, 0.0])
    for z in (0.0, -behind_m):
        start = np.array([0.0, 0.0, z])
        swept, _ = distance_to_path_m(objects, start, start + end)
        now = np.linalg.norm(objects - start, axis=1)
        if np.any(swept < np.minimum(needed_m, now) - 1e-9):
            return False
    return True


def look_round_m(target_xyz, objects_xyz, needed_m: np.ndarray, behind_m: float, max_m: float) -> float:
    """Return the sideways step (x, metres, positive: right; 0: none) that shows a target hidden by one of
    ``objects_xyz``: the shorter side first, the other when the shorter's path is not safe (``safe_step_m``, each
    object kept ``needed_m`` away), none longer than ``max_m``."""
    k = hider(target_xyz, objects_xyz)
    if k is None or max_m <= 0:
        return 0.0
    h = np.asarray(objects_xyz, float).reshape(-1, 3)[k]
    first = step_clear_m(target_xyz, h, CLEAR_OF_HIDER_M)
    for step in (first, step_clear_m(target_xyz, h, CLEAR_OF_HIDER_M, -first if first else -1.0)):
        if 0 < abs(step) <= max_m and safe_step_m(step, objects_xyz, needed_m, behind_m):
            return step
    return 0.0
