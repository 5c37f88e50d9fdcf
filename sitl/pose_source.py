"""Where the simulated mission's arm keypoints come from: BlazePose on the rendered frames, or truth.

``sitl.pose_source`` chooses:

- ``blazepose``: the same ``PoseEstimator`` the onboard ``run`` builds from the parameters
  (``pose.backend`` = blazepose, with its tracking, right-image search and early arm) runs on the
  rendered images; the simulator's truth is never used.
- ``truth``: the renderer's truth joints plus the scenario's noise and dropouts
  (``meta["keypoints"]``, the ``keypoints`` backend).

``SimPose`` counts the frames per source (``counts``): "blazepose" (an arm whose keypoints all reach
``pose.min_confidence``), "blazepose (low confidence)", "truth", "none" (no arm). ``sitl --json``
reports them as ``pose_source``.
"""

from __future__ import annotations

from typing import Any, Callable, Mapping

import numpy as np

from dip3d_vehicle.perception.calibration import StereoRig
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pose import PoseEstimator
from dip3d_vehicle.perception.values import ArmKeypoints

__all__ = ["SimPose", "POSE_SOURCES", "pose_backend_for"]

POSE_SOURCES = ("blazepose", "truth")
"""Values of ``sitl.pose_source``."""


def pose_backend_for(pose_source: str) -> str:
    """Return the ``pose.backend`` a ``sitl.pose_source`` runs (ValueError for an unknown one)."""
    if pose_source not in POSE_SOURCES:
        raise ValueError(f"sitl.pose_source {pose_source!r}: expected one of {', '.join(POSE_SOURCES)}")
    return "blazepose" if pose_source == "blazepose" else "keypoints"


class SimPose(PoseEstimator):
    """The simulated mission's pose: BlazePose on the frames, or the frames' truth keypoints.

    Args:
        params: effective parameters (``sitl.pose_source``, ``pose.arm``, ``pose.min_confidence``,
            ``blazepose.*``).
        backend: the pose backend to use for ``blazepose`` (default: built from ``params``).
    """

    name = "sim"

    def __init__(self, params: Mapping[str, Any], backend: PoseEstimator | None = None) -> None:
        self.source = str(params["sitl.pose_source"])
        pose_backend_for(self.source)
        self.given = GivenKeypoints(params["pose.arm"])
        self.min_confidence = float(params["pose.min_confidence"])
        self.backend: PoseEstimator | None = None
        if self.source == "blazepose":
            if backend is None:
                from dip3d_vehicle.perception.pipeline import make_pose_estimator
                backend = make_pose_estimator(params)
            self.backend = backend
        self.counts = {"blazepose": 0, "blazepose (low confidence)": 0, "truth": 0, "none": 0}

    def provide(self, keypoints: dict | None) -> None:
        """Give the next frame's truth keypoints (used only with ``truth``)."""
        self.given.provide(keypoints)

    def estimate(self, left_rect: np.ndarray, right_rect: np.ndarray, rig: StereoRig) -> ArmKeypoints | None:
        """Return the arm from the chosen source (rectified pixels) and count it."""
        if self.backend is None:
            arm = self.given.estimate(left_rect, right_rect, rig)
            self.counts["truth" if arm is not None else "none"] += 1
            return arm
        arm = self.backend.estimate(left_rect, right_rect, rig)
        if arm is None:
            self.counts["none"] += 1
        elif arm.min_confidence() >= self.min_confidence:
            self.counts["blazepose"] += 1
        else:
            self.counts["blazepose (low confidence)"] += 1
        return arm

    def reset(self) -> None:
        """Forget the backend's tracking state."""
        if self.backend is not None:
            self.backend.reset()

    def set_early_arm_listener(self, listener: Callable[[ArmKeypoints], None] | None) -> None:
        """Pass the early-arm listener to BlazePose (see ``PoseEstimator``)."""
        self._early_listener = listener
        if self.backend is not None:
            self.backend.set_early_arm_listener(listener)
