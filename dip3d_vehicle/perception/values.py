"""Frozen values that cross module boundaries in the perception core.

Pixel coordinates are ``(x, y)`` with ``x`` to the right and ``y`` down. Unless a name says
otherwise, pixel arrays are in RECTIFIED image coordinates (what triangulation needs); the
pipeline maps them back to original pixels for output. 3D points are in the rectified left
camera frame: x right, y down, z forward, metres.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["JOINTS", "EXTRA_JOINTS", "ArmKeypoints", "Candidates", "Arm3D", "ObjectCandidate", "Selection"]

JOINTS = ("shoulder", "elbow", "wrist")
"""Joint order used in every (3, ...) array."""

EXTRA_JOINTS = ("head", "other_wrist", "hand")
"""Optional joints beyond the pointing arm: for the stop gesture the head (BlazePose: the nose) and the
wrist of the other arm; "hand" = the pointing hand's far end (BlazePose: its index finger), beyond
which the candidates' region starts (the diver's own fingers are no target)."""


@dataclass(frozen=True)
class ArmKeypoints:
    """The pointing arm's shoulder, elbow and wrist in both rectified images.

    Attributes:
        arm: "right" or "left" ("auto": given keypoints of the pointing arm, its side not known).
        left_px: (3, 2) float array, rows in JOINTS order, rectified left-image pixels.
        right_px: (3, 2) float array, rectified right-image pixels.
        left_conf: (3,) per-keypoint confidence in [0, 1] for the left image.
        right_conf: (3,) per-keypoint confidence in [0, 1] for the right image.
        source: which estimator produced them (e.g. "keypoints-file", "blazepose", "sim-truth").
        extra_left_px: optional ``EXTRA_JOINTS`` seen in the rectified left image, by name (x, y);
            absent names were not given or not seen.
        disparity_sigma_px: optional (3,) one-sigma error of each joint's disparity (x_left -
            x_right) as the estimator measured it, pixels; None = unknown (the pipeline then uses
            the keypoints' epipolar residuals and ``selection.keypoint_sigma_px``).
        keypoint_sigma_m: optional one-sigma distance (metres, at the body, per image axis) between
            where the estimator places a joint and the joint's centre: a pose model's landmark
            definition and bias, systematic over the frames of one pose (it does not average);
            None = none beyond ``selection.keypoint_sigma_px`` (truth + noise, keypoints files).
        disparity_matched: optional (3,) bool: joints whose disparity was measured by matching the
            left joint's image patch along its rectified row (``given_arm.match_arm``); their
            ``disparity_sigma_px`` is the match's own and is used as it is, not raised to the
            keypoints' noise (the match does not inherit the keypoints' left/right disagreement).
    """

    arm: str
    left_px: np.ndarray
    right_px: np.ndarray
    left_conf: np.ndarray
    right_conf: np.ndarray
    source: str = ""
    extra_left_px: dict = field(default_factory=dict)
    disparity_sigma_px: np.ndarray | None = None
    keypoint_sigma_m: float | None = None
    disparity_matched: np.ndarray | None = None

    def joint(self, name: str, side: str = "left") -> np.ndarray:
        """Return one joint's (x, y) in the rectified ``side`` image, pixels."""
        arr = self.left_px if side == "left" else self.right_px
        return arr[JOINTS.index(name)]

    def min_confidence(self) -> float:
        """Return the lowest confidence over the three joints in both images."""
        return float(min(self.left_conf.min(), self.right_conf.min()))


@dataclass(frozen=True)
class Candidates:
    """Matched features across the pair: each row is one candidate point.

    Attributes:
        left_px: (N, 2) rectified left-image pixels.
        right_px: (N, 2) rectified right-image pixels.
        descriptors: (N, D) float32 descriptors of the left features (may be empty (N, 0)).
        sizes_px: (N,) feature sizes (diameters) in pixels, or zeros.
    """

    left_px: np.ndarray
    right_px: np.ndarray
    descriptors: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), np.float32))
    sizes_px: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __len__(self) -> int:
        return int(self.left_px.shape[0])

    @property
    def disparity_px(self) -> np.ndarray:
        """Return the disparities x_left - x_right, pixels."""
        return self.left_px[:, 0] - self.right_px[:, 0]

    def subset(self, keep: np.ndarray) -> "Candidates":
        """Return the candidates selected by a boolean mask or index array."""
        desc = self.descriptors[keep] if len(self.descriptors) == len(self) else self.descriptors
        sizes = self.sizes_px[keep] if len(self.sizes_px) == len(self) else self.sizes_px
        return Candidates(self.left_px[keep], self.right_px[keep], desc, sizes)

    def stacked(self, other: "Candidates") -> "Candidates":
        """Return these candidates followed by ``other``'s (descriptors and sizes kept where both have them)."""
        same = (self.descriptors.shape[1:] == other.descriptors.shape[1:] and len(self.descriptors) == len(self)
                and len(other.descriptors) == len(other))
        desc = np.vstack([self.descriptors, other.descriptors]) if same else np.zeros((0, 0), np.float32)
        full = len(self.sizes_px) == len(self) and len(other.sizes_px) == len(other)
        sizes = np.r_[self.sizes_px, other.sizes_px] if full else np.zeros(0)
        return Candidates(np.vstack([self.left_px, other.left_px]), np.vstack([self.right_px, other.right_px]),
                          desc, sizes)

    @staticmethod
    def empty() -> "Candidates":
        """Return a candidate set with no rows."""
        return Candidates(np.zeros((0, 2)), np.zeros((0, 2)), np.zeros((0, 128), np.float32), np.zeros(0))


@dataclass(frozen=True)
class Arm3D:
    """Triangulated joints (rectified left camera frame, metres) with their stereo depth sigma.

    Attributes:
        xyz_m: (3, 3) rows shoulder, elbow, wrist.
        depth_sigma_m: (3,) one-sigma depth uncertainty of each joint, metres.
    """

    xyz_m: np.ndarray
    depth_sigma_m: np.ndarray

    def joint(self, name: str) -> np.ndarray:
        """Return one joint's xyz in metres."""
        return self.xyz_m[JOINTS.index(name)]


@dataclass(frozen=True)
class ObjectCandidate:
    """One candidate object: a group of matched features and its robust 3D centre.

    Attributes:
        left_px: (2,) representative rectified left-image point, pixels.
        xyz_m: (3,) robust centre in the rectified left camera frame, metres.
        depth_sigma_m: one-sigma uncertainty of the centre's depth, metres.
        members: indices of the candidate rows (in the filtered Candidates) that form it.
    """

    left_px: np.ndarray
    xyz_m: np.ndarray
    depth_sigma_m: float
    members: tuple[int, ...]


@dataclass(frozen=True)
class Selection:
    """What the selector chose and how sure it is.

    Attributes:
        index: index of the chosen object in ``objects`` (None if nothing was chosen).
        objects: the scored objects (single features for the paper selector).
        scores: (len(objects),) score per object; lower is better for ``paper`` (distance, m),
            higher is better for ``default`` (posterior probability).
        confidence: in [0, 1]; posterior of the chosen object (1.0 for ``paper``, which has none);
            for ``default`` the absolute probability of the chosen object and its fragments (objects
            touching it within one target's extent, ``selection.same_target_gap_m``), or of "nothing
            detected" when that won.
        ambiguity_margin: best minus second-best in the selector's own units (inf if one object).
        method: "paper" or "default".
        ambiguous: True when the confidence is under the configured minimum.
        none_probability: probability that the arm points at nothing that was detected (the
            open-set hypothesis of the ``default`` selector; 0 for ``paper``). ``scores`` and
            ``confidence`` are then absolute: they and ``none_probability`` sum to 1.
        reason: one line saying why nothing was chosen (empty when an object was).
        spots: the unrecognised spots along the arm that were scored (``default``), as
            ``(xyz_m, probability)`` pairs (camera frame, metres; absolute probability). Their
            probabilities are part of ``none_probability``: never a target in this frame.
    """

    index: int | None
    objects: tuple[ObjectCandidate, ...]
    scores: np.ndarray
    confidence: float
    ambiguity_margin: float
    method: str
    ambiguous: bool = False
    none_probability: float = 0.0
    reason: str = ""
    spots: tuple = ()

    @property
    def nothing_on_ray(self) -> bool:
        """Return True when "the arm points at nothing detected" won over every object."""
        return self.index is None and len(self.objects) > 0 and self.none_probability > 0.0

    @property
    def target(self) -> ObjectCandidate | None:
        """Return the chosen object, or None."""
        return None if self.index is None else self.objects[self.index]

    def spot_probability(self, xyz_m) -> float | None:
        """Return the probability the selector gave the unrecognised spot at ``xyz_m`` (metres), or None when it
        did not score it (outside the arm's image direction, or hidden from the diver by a recognised object)."""
        return next((p for xyz, p in self.spots if np.allclose(xyz, xyz_m, atol=1e-9)), None)
