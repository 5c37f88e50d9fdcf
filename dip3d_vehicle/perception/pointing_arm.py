"""Which arm the diver points with: the one raised away from the body (``pose.arm: auto``).

A diver points with either hand, and a pose model seen from behind may swap its "left" and
"right" labels (BlazePose on the simulated diver, issue 14). With ``pose.arm: auto`` the arm read
in each frame is the one held farther from the body: the angle at the shoulder between the
shoulder-to-hip line (the torso, whatever the diver's attitude in the water) and the
shoulder-to-wrist line, in the landmarks' own 3D (image x and y, and the model's relative depth z
in the same pixel scale). A hanging arm lies along the torso (a few tens of degrees), a pointing
arm well away from it. An arm whose elbow or wrist the model does not see counts as hanging. The
previous frame's arm is kept unless the other one is raised ``AUTO_ARM_MARGIN_RAD`` more (no
flapping between two arms held alike).
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np

from .pose import ARM_INDICES

__all__ = ["AUTO", "ARMS", "AUTO_ARM_MARGIN_RAD", "arm_elevation_rad", "pointing_arm"]

AUTO = "auto"
"""The ``pose.arm`` value that picks the pointing arm in every frame."""

ARMS = ("right", "left", AUTO)
"""The values of ``pose.arm``."""

AUTO_ARM_MARGIN_RAD = math.radians(20.0)
"""How much more the other arm must be raised before the frame's arm changes, radians."""

MIN_VISIBILITY = 0.3
"""Below this visibility of its elbow or wrist an arm counts as hanging (not seen to point)."""

HIP_INDICES = {"right": 24, "left": 23}
"""BlazePose landmark index of each side's hip."""


class Landmarks(Protocol):
    """What the choice reads of a pose: 33 landmarks' pixels, relative depth and visibility."""

    xy_px: np.ndarray
    z_px: np.ndarray
    visibility: np.ndarray


def arm_elevation_rad(pose: Landmarks, arm: str) -> float:
    """Return the angle at the shoulder between the hip and the wrist of one arm, radians (0: hanging).

    0 when the elbow or wrist is not seen (visibility under ``MIN_VISIBILITY``) or the torso has no length.
    """
    shoulder, elbow, wrist = ARM_INDICES[arm]
    if min(float(pose.visibility[elbow]), float(pose.visibility[wrist])) < MIN_VISIBILITY:
        return 0.0
    xyz = np.c_[pose.xy_px, pose.z_px]
    down, out = xyz[HIP_INDICES[arm]] - xyz[shoulder], xyz[wrist] - xyz[shoulder]
    norms = float(np.linalg.norm(down)) * float(np.linalg.norm(out))
    if norms <= 0.0:
        return 0.0
    return math.acos(float(np.clip(down @ out / norms, -1.0, 1.0)))


def pointing_arm(pose: Landmarks, previous: str | None = None, margin_rad: float = AUTO_ARM_MARGIN_RAD) -> str:
    """Return "right" or "left": the arm raised farther from the body (``previous`` kept within ``margin_rad``)."""
    right, left = arm_elevation_rad(pose, "right"), arm_elevation_rad(pose, "left")
    if previous == "right":
        return "left" if left > right + margin_rad else "right"
    if previous == "left":
        return "right" if right > left + margin_rad else "left"
    return "left" if left > right else "right"
