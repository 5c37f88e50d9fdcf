"""The arm of a held point: its keypoints averaged over the last frames, and a frame decided again with it.

A diver holds a point for seconds while the vehicle holds still. The keypoints' noise (pose jitter)
then averages down: the mean of ``n`` frames' keypoints has 1/sqrt(n) of one frame's noise, so the
arm's stereo depths, and with them its tilt toward or away from the camera (the open-set
selector's main doubt at 2 px), are known sqrt(n) times better. A systematic error (the diver's own
pointing error, a pose model's bias) does not average down, which is why the window is short
(``behaviour.fusion_arm_frames``) and the selector's pointing spread is unchanged.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from collections import deque
from functools import partial

import numpy as np

from .blobs import unexplained
from .corridor import merge_candidates
from .filters import pose_rejection
from .pipeline import Perception, PerceptionResult
from .selection import DefaultSelector
from .triangulation import triangulate
from .values import ArmKeypoints, Candidates

__all__ = ["HeldArm", "decide_held"]


class HeldArm:
    """The last ``window`` arms of one held point (rectified px, both images) and their mean."""

    def __init__(self, window: int) -> None:
        self.arms: deque[ArmKeypoints] = deque(maxlen=max(int(window), 1))

    def add(self, arm: ArmKeypoints) -> None:
        """Add one frame's arm (same side as the previous ones, or the window restarts)."""
        if self.arms and self.arms[-1].arm != arm.arm:
            self.arms.clear()
        self.arms.append(arm)

    def clear(self) -> None:
        """Forget every frame (a new point, or a new viewpoint)."""
        self.arms.clear()

    def __len__(self) -> int:
        return len(self.arms)

    @property
    def window(self) -> int:
        """How many frames' arms one mean holds (``behaviour.fusion_arm_frames``)."""
        return int(self.arms.maxlen or 1)

    def mean(self) -> ArmKeypoints | None:
        """Return the mean arm of the window (pixels; confidences: the lowest seen), or None if empty."""
        if not self.arms:
            return None
        a = list(self.arms)
        matched, sigma = None, a[-1].disparity_sigma_px
        if all(x.disparity_matched is not None for x in a):  # matched in every frame: the largest match sigma
            matched = np.all([x.disparity_matched for x in a], axis=0)
            sigma = np.max([x.disparity_sigma_px for x in a], axis=0)
        return dataclasses.replace(
            a[-1], left_px=np.mean([x.left_px for x in a], axis=0), right_px=np.mean([x.right_px for x in a], axis=0),
            left_conf=np.min([x.left_conf for x in a], axis=0), right_conf=np.min([x.right_conf for x in a], axis=0),
            source=f"{a[-1].source} (mean of {len(a)})", disparity_matched=matched, disparity_sigma_px=sigma)


def decide_held(perception: Perception, arm: ArmKeypoints, frames: int, result: PerceptionResult,
                recalled: Candidates | None = None) -> PerceptionResult:
    """Return ``result``'s candidates decided again with ``arm``, the mean of ``frames`` frames' arms.

    The keypoint noise (the prior ``selection.keypoint_sigma_px`` and the selector's own) is divided
    by sqrt(frames). ``recalled``: features of objects an earlier frame of the point saw and this one
    did not (``PointFusion.recall``). Those not within 3 px of one of this frame's join its candidates
    (``PerceptionResult.recalled`` counts them), so the objects are scored with this frame's arm: a
    missed detection is not evidence that the arm points elsewhere. ``result`` is returned unchanged
    when it has no decision to redo (its arm failed the checks, it found no object and nothing is
    recalled, one frame's arm and nothing recalled, or the selector is not the default one) or when
    the mean arm fails the pose filters.
    """
    selector = perception.selector
    cands, xyz = _with_recalled(perception, result, recalled)
    extra = len(cands) - len(result.candidates)
    redo = result.status in ("ok", "nothing_on_ray") or (extra and result.status == "no_candidates"
                                                          and result.arm3d is not None)
    if (frames < 2 and not extra) or not redo or not isinstance(selector, DefaultSelector):
        return result
    scale = 1.0 / math.sqrt(max(frames, 1))
    params = perception.params
    arm3d = perception.triangulate_arm(arm, params["selection.keypoint_sigma_px"] * scale)
    if pose_rejection(arm3d.xyz_m, params["filters.max_joint_dz_m"], params["filters.min_depth_m"],
                      arm3d.depth_sigma_m, params["filters.joint_dz_sigmas"]):
        return result
    held = copy.copy(selector)
    held.model = dataclasses.replace(selector.model, keypoint_sigma_px=selector.model.keypoint_sigma_px * scale)
    spots = result.unrecognised
    sel = held.select(arm, arm3d, cands, xyz, perception.rig, partial(unexplained, spots))
    if sel.nothing_on_ray:
        return PerceptionResult("nothing_on_ray", sel.reason, arm, arm3d, cands, xyz, sel, result.timings_ms,
                                unrecognised=spots, recalled=extra)
    if sel.index is None:
        return result
    return PerceptionResult("ok", "", arm, arm3d, cands, xyz, sel, result.timings_ms, unrecognised=spots,
                            recalled=extra)


def _with_recalled(perception: Perception, result: PerceptionResult, recalled: Candidates | None
                   ) -> tuple[Candidates, np.ndarray]:
    """Return ``result``'s candidates and 3D points (m) followed by the recalled features not already among them."""
    cands, xyz = result.candidates, result.candidates_xyz_m
    if recalled is None or not len(recalled):
        return cands, xyz
    merged = merge_candidates(cands, recalled, neighbourhood_px=0.0)
    extra = merged.subset(np.arange(len(cands), len(merged)))
    if not len(extra):
        return cands, xyz
    return merged, np.vstack([xyz.reshape(-1, 3), triangulate(perception.Q, extra.left_px, extra.disparity_px)])
