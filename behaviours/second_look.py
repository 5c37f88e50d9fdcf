"""The active second look: a bounded sideways or vertical step that best separates two close candidates.

Pure geometry in the rectified left camera frame (x right, y down, z forward, metres). The vehicle's
sway is close to the camera's x and its heave to the camera's y (the camera looks forward, pitched a
few degrees), so a step of the camera along +-x / +-y is commanded as sway / heave.

Seen from the camera at c, two candidates a and b are apart by the angle between a - c and b - c:
candidates one behind the other (the "far placard behind the near one" case) are apart by little,
and a sideways step opens that angle most. The chosen step is the one of the four (right, left, up,
down) of ``step_m`` that opens it most while every point to keep (the diver's shoulder and wrist, the
two candidates) stays inside the image by ``margin_px``; none when no step opens it by ``min_gain_rad``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["LookStep", "separation_rad", "plan_second_look", "STEPS", "MIN_GAIN_RAD"]

STEPS: dict[str, tuple[float, float, float]] = {"right": (1.0, 0.0, 0.0), "left": (-1.0, 0.0, 0.0),
                                                 "down": (0.0, 1.0, 0.0), "up": (0.0, -1.0, 0.0)}
"""The candidate step directions (camera frame)."""

MIN_GAIN_RAD = 0.01
"""A step must open the angle it is chosen for by at least this much (radians) to be worth taking."""


@dataclass(frozen=True)
class LookStep:
    """A planned step: its name, camera-frame offset (metres) and the separation before / after (rad)."""

    direction: str
    offset_m: tuple[float, float, float]
    before_rad: float
    after_rad: float


def separation_rad(a_xyz, b_xyz, camera_xyz=(0.0, 0.0, 0.0)) -> float:
    """Return the angle between two points seen from ``camera_xyz``, radians.

    Examples:
        >>> round(separation_rad([0, 0, 2], [0, 0, 3]), 3), round(separation_rad([0, 0, 2], [0, 0, 3], [0.3, 0, 0]), 3)
        (0.0, 0.049)
    """
    c = np.asarray(camera_xyz, float)
    u, v = np.asarray(a_xyz, float) - c, np.asarray(b_xyz, float) - c
    nu, nv = float(np.linalg.norm(u)), float(np.linalg.norm(v))
    if nu < 1e-9 or nv < 1e-9:
        return 0.0
    return math.acos(float(np.clip(u @ v / (nu * nv), -1.0, 1.0)))


def _in_view(points: np.ndarray, focal_px: float, principal_px: tuple[float, float], margin_px: float) -> bool:
    """Return True when every point is in front of the camera and inside the image by ``margin_px``."""
    if np.any(points[:, 2] < 0.2):
        return False
    cx, cy = principal_px
    u = focal_px * points[:, 0] / points[:, 2] + cx
    v = focal_px * points[:, 1] / points[:, 2] + cy
    return bool(np.all((u >= margin_px) & (u <= 2 * cx - margin_px) & (v >= margin_px) & (v <= 2 * cy - margin_px)))


def plan_second_look(a_xyz, b_xyz, keep_xyz, step_m: float, focal_px: float, principal_px: tuple[float, float],
                     margin_px: float = 60.0, min_gain_rad: float = MIN_GAIN_RAD) -> LookStep | None:
    """Return the step that separates a and b most with everything kept in view, or None.

    Args:
        a_xyz, b_xyz: the two candidates (camera frame, metres).
        keep_xyz: other points that must stay in view (the diver's joints), (N, 3).
        step_m: the step's length.
        focal_px, principal_px: rectified intrinsics (the image is taken as 2 cx by 2 cy).
        margin_px: how far inside the image every point must stay.
        min_gain_rad: the least improvement in separation worth a step.
    """
    keep = np.vstack([np.asarray(a_xyz, float), np.asarray(b_xyz, float),
                      np.asarray(keep_xyz, float).reshape(-1, 3)])
    before = separation_rad(a_xyz, b_xyz)
    best: LookStep | None = None
    for name, d in STEPS.items():
        c = step_m * np.asarray(d)
        if not _in_view(keep - c, focal_px, principal_px, margin_px):
            continue
        after = separation_rad(a_xyz, b_xyz, c)
        if after - before >= min_gain_rad and (best is None or after > best.after_rad):
            best = LookStep(name, tuple(float(v) for v in c), before, after)
    return best
