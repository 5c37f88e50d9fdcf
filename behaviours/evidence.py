"""Evidence the mission states weigh: is an arm raised, is the pointing steady, who wins the vote.

Pure functions and one small accumulator; no clock, no link. Directions are unit vectors in the
rectified left camera frame (x right, y down, z forward).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from dip3d_vehicle.perception.pipeline import PerceptionResult
from dip3d_vehicle.perception.values import ArmKeypoints, Candidates, ObjectCandidate

__all__ = ["arm_direction", "image_direction", "is_raised", "is_folded_guess", "angular_spread_rad", "Vote", "VoteBox",
           "VoteDecision"]

_DOWN = np.array([0.0, 1.0, 0.0])


def arm_direction(result: PerceptionResult | None) -> np.ndarray | None:
    """Return the unit shoulder->wrist direction of a result's triangulated arm, or None.

    Args:
        result: a perception result (any status).

    Returns:
        (3,) unit vector in the camera frame, or None when the arm was not triangulated or the
        pose was rejected by the filters.
    """
    if result is None or result.arm3d is None or result.status == "pose_rejected":
        return None
    xyz = result.arm3d.xyz_m
    d = xyz[2] - xyz[0]
    n = float(np.linalg.norm(d))
    if not (math.isfinite(n) and n > 1e-6):
        return None
    return d / n


def image_direction(result: PerceptionResult | None) -> np.ndarray | None:
    """Return the unit shoulder->wrist direction in the rectified left image, or None.

    The 2D keypoints are precise (a pixel or two) where the triangulated depths are not (a few
    centimetres to decimetres at 3 m), so steadiness is judged on this direction.
    """
    if result is None or result.arm is None:
        return None
    d = np.asarray(result.arm.joint("wrist", "left"), float) - np.asarray(result.arm.joint("shoulder", "left"), float)
    n = float(np.linalg.norm(d))
    return d / n if math.isfinite(n) and n > 1e-6 else None


def is_raised(direction: np.ndarray | None, min_raise_rad: float) -> bool:
    """Return True when an arm direction is at least ``min_raise_rad`` away from straight down."""
    if direction is None:
        return False
    return math.acos(float(np.clip(direction @ _DOWN, -1.0, 1.0))) >= min_raise_rad


def is_folded_guess(arm: ArmKeypoints | None, direction_px: np.ndarray | None, min_confidence: float,
                    folded_rad: float) -> bool:
    """Return True for an arm the pose source is unsure of that it placed folded up over the shoulder.

    Unsure: some joint's confidence under ``min_confidence``. Folded up: the left-image shoulder-to-wrist
    direction ``direction_px`` within ``folded_rad`` of straight up. BlazePose guesses a hanging arm it
    cannot see (in profile, against the dark body) that way: on the simulated diver 36 % of the frames with
    both arms hanging passed the raised test, their wrist 170 deg from down in the image (median) and
    their joints' visibility 0.74 (a raised arm: 83 deg, 0.95; issue 14).
    """
    if arm is None or direction_px is None or arm.min_confidence() >= min_confidence:
        return False
    return math.acos(float(np.clip(-direction_px[1], -1.0, 1.0))) <= folded_rad


def angular_spread_rad(directions: list[np.ndarray]) -> float:
    """Return the largest angle between any direction and the mean direction, radians (0 for < 2).

    Examples:
        >>> round(angular_spread_rad([np.array([1.0, 0, 0]), np.array([0.0, 0, 1])]), 4)
        0.7854
    """
    if len(directions) < 2:
        return 0.0
    arr = np.asarray(directions, dtype=float)
    mean = arr.sum(axis=0)
    norm = float(np.linalg.norm(mean))
    if norm < 1e-9:
        return math.pi
    mean /= norm
    return float(np.max(np.arccos(np.clip(arr @ mean, -1.0, 1.0))))


@dataclass
class Vote:
    """One object's tally over frames: summed confidence, count, and its latest sighting.

    Attributes:
        xyz_m: latest 3D centre (camera frame, metres).
        weight: summed selection confidence.
        count: frames in which it was chosen (not ambiguous).
        obj: the latest ObjectCandidate.
        candidates: the Candidates of that frame (the object's members index into them).
        stamp_s: capture time of that frame.
        pool: its sightings, (object, its frame's candidates), newest first (the tracker's model for a small
            target).
    """

    xyz_m: np.ndarray
    weight: float
    count: int
    obj: ObjectCandidate
    candidates: Candidates
    stamp_s: float
    pool: list = field(default_factory=list)


@dataclass(frozen=True)
class VoteDecision:
    """The outcome of a vote: the winner (or None) and the numbers behind it."""

    winner: Vote | None
    share: float
    frames: int
    ambiguous_frames: int
    empty_frames: int
    reason: str


@dataclass
class VoteBox:
    """Aggregates per-frame selections into votes per object (matched by 3D position).

    Args:
        radius_m: two chosen centres within this distance are the same object.
    """

    radius_m: float
    votes: list[Vote] = field(default_factory=list)
    ambiguous_frames: int = 0
    empty_frames: int = 0

    @property
    def frames(self) -> int:
        """Frames counted so far (chosen, ambiguous or empty)."""
        return sum(v.count for v in self.votes) + self.ambiguous_frames + self.empty_frames

    def add(self, result: PerceptionResult, stamp_s: float) -> None:
        """Count one perception result with a raised arm: a vote, an ambiguous or an empty frame."""
        sel = result.selection
        if result.status != "ok" or sel is None or sel.target is None:
            self.empty_frames += 1
            return
        if sel.ambiguous:
            self.ambiguous_frames += 1
            return
        obj = sel.target
        xyz = np.asarray(obj.xyz_m, dtype=float)
        for vote in self.votes:
            if float(np.linalg.norm(vote.xyz_m - xyz)) <= self.radius_m:
                vote.weight += float(sel.confidence)
                vote.count += 1
                vote.xyz_m, vote.obj, vote.candidates, vote.stamp_s = xyz, obj, result.candidates, stamp_s
                return
        self.votes.append(Vote(xyz, float(sel.confidence), 1, obj, result.candidates, stamp_s))

    def summary(self) -> str:
        """Return the tally as text, e.g. ``(0.46,-0.21,2.96) x3 w2.71``."""
        parts = [f"({', '.join(f'{c:.2f}' for c in v.xyz_m)}) x{v.count} w{v.weight:.2f}" for v in self.votes]
        return "; ".join(parts) or "no votes"

    def decide(self, min_share: float, min_votes: int) -> VoteDecision:
        """Return the winner if it is clear: share >= ``min_share`` and chosen >= ``min_votes`` times.

        The best object is the one with the largest summed confidence; its share is the fraction of
        all counted frames that chose it, so ambiguous frames (the selector's confidence under its
        minimum) and empty frames count against it.
        """
        frames = self.frames
        if not self.votes or frames == 0:
            return VoteDecision(None, 0.0, frames, self.ambiguous_frames, self.empty_frames, "no object chosen")
        best = max(self.votes, key=lambda v: v.weight)
        share = best.count / frames
        if best.count < min_votes:
            why = f"best object chosen in {best.count} of {frames} frames (< {min_votes})"
            return VoteDecision(None, share, frames, self.ambiguous_frames, self.empty_frames, why)
        if share < min_share:
            why = f"best object's share {share:.2f} < {min_share:g}"
            return VoteDecision(None, share, frames, self.ambiguous_frames, self.empty_frames, why)
        return VoteDecision(best, share, frames, self.ambiguous_frames, self.empty_frames, "clear winner")
