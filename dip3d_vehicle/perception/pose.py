"""The PoseEstimator interface: both rectified images in, the pointing arm's keypoints out."""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Callable

import numpy as np

from .calibration import StereoRig
from .values import ArmKeypoints

__all__ = ["PoseEstimator", "ARM_INDICES"]

ARM_INDICES = {"right": (12, 14, 16), "left": (11, 13, 15)}
"""BlazePose landmark indices of (shoulder, elbow, wrist) for each arm."""


class PoseEstimator(ABC):
    """Estimates the pointing arm in both images of a rectified stereo pair.

    Lifecycle (as py_trees behaviours): construct with parameters, ``estimate`` once per frame,
    ``reset`` when the frame sequence is broken (tracking state is dropped).
    """

    name = "pose"
    _early_listener: Callable[[ArmKeypoints], None] | None = None

    @abstractmethod
    def estimate(self, left_rect: np.ndarray, right_rect: np.ndarray, rig: StereoRig) -> ArmKeypoints | None:
        """Return the arm's keypoints in RECTIFIED pixels of both images, or None if no person.

        Args:
            left_rect: rectified left image, HxWx3 uint8 BGR.
            right_rect: rectified right image, HxWx3 uint8 BGR.
            rig: the stereo rig (to map between original and rectified pixels if needed).
        """

    def reset(self) -> None:
        """Forget any tracking state (default: nothing to forget)."""

    def set_early_arm_listener(self, listener: Callable[[ArmKeypoints], None] | None) -> None:
        """Ask to be given a provisional arm (rectified px) before ``estimate`` returns (None: stop).

        A backend that finds the left pose before the right one calls ``listener`` once, with the
        left joints measured and the right ones predicted, so that work needing only the arm's
        rough position (the candidates' features) can start while the right pose runs. Backends
        that cannot tell earlier never call it.
        """
        self._early_listener = listener
