"""The ``blazepose`` pose backend: ``BlazePoseEstimator``, BlazePose's arm in rectified stereo pairs.

``blazepose_model.BlazePose`` finds one image's 33 landmarks (MediaPipe Pose, BlazePose GHUM full, on
onnxruntime). ``BlazePoseEstimator`` is the ``PoseEstimator`` for rectified stereo pairs built on it, with
MediaPipe-style tracking (the next frame's ROI comes from the auxiliary landmarks while the pose flag stays
high) and a cheap right image: the left pose's ROI shifted along the same rows by a disparity found by template
matching, instead of a blind detection; with ``joint_disparity: stereo`` the arm's joints are matched along their
rows (``joint_stereo``) and the shoulder placed from the torso (``shoulder_model``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Mapping

import cv2
import numpy as np

from .blazepose_model import BlazePose, Contrast, Detection, PoseLandmarks, refine_from_heatmap
from .blazepose_roi import Roi
from .calibration import StereoRig
from .joint_stereo import (JOINT_FLOOR_FACTOR, LIMB_SLACK_M, JointDisparity, in_front_of_body, joint_disparities,
                           head_disparity, limb_spans_m, limb_switches, match_joint_disparity, on_background,
                           subpixel_peak as _subpixel, unmatched_sigma_px)
from .landmark_smoothing import LandmarkSmoother
from .pointing_arm import AUTO, pointing_arm
from .pose import ARM_INDICES, PoseEstimator
from .shoulder_model import ShoulderOrder, torso_shoulder_disparity
from .values import ArmKeypoints

__all__ = ["BlazePose", "BlazePoseEstimator", "Detection", "PoseLandmarks", "Contrast",
           "refine_from_heatmap", "body_disparity"]

_SEARCH_POINTS = (0, 11, 12, 13, 14, 15, 16, 23, 24)   # head, arms, hips: template for disparity
_TEMPLATE_WIDTH_PX = 96         # width of the downscaled template used to find the disparity
JOINT_DISPARITY = ("landmarks", "match", "stereo")
"""Ways of finding the arm joints' right-image x (``blazepose.joint_disparity``)."""
JOINT_PATCH_M = 0.12
"""Side of the patch matched around an elbow or wrist for ``stereo``, metres at the body's depth (wrist
disparity error on paper_pool's diver at 3 m: std 0.9 px at 0.12 m, 1.1 at 0.09, 2.2 at 0.06; issue 14)."""
_OTHER = {"right": "left", "left": "right"}
_BODY = (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 23, 24)   # head, shoulders, hips: what an arm in front hides


@dataclass
class _Track:
    """Tracking state of one camera: the ROI and contrast for its next frame."""

    roi: Roi | None = None
    contrast: Contrast | None = None

    def update(self, found: PoseLandmarks | None, enabled: bool) -> None:
        """Keep the next ROI from ``found`` (or forget it when nothing was found)."""
        self.roi = found.next_roi() if (found is not None and enabled) else None
        self.contrast = found.contrast if found is not None else None


@dataclass
class StereoStats:
    """How the right image's pose was found, frame counts."""

    searched: int = 0
    search_failed: int = 0
    tracked: int = 0
    detected: int = 0
    concurrent: int = 0
    matched: int = 0
    """frames whose right-image arm came from the stereo joint matches alone (no right landmark run)"""


class BlazePoseEstimator(PoseEstimator):
    """BlazePose on both rectified images, with tracking and a disparity-bounded right search."""

    name = "blazepose"

    def __init__(self, pose: BlazePose, arm: str = "right", tracking: bool = True,
                 stereo_search: str = "roi", max_disparity_px: float = 400.0,
                 joint_disparity: str = "landmarks", concurrent_eyes: bool = False,
                 disparity_floor_px: float = 1.5, keypoint_sigma_m: float | None = None,
                 limbs_m: tuple[tuple[float, float], tuple[float, float]] | None = None,
                 smoother: LandmarkSmoother | None = None) -> None:
        """Wrap a ``BlazePose``; ``stereo_search`` is "roi" (search along rows) or "detect".

        ``arm``: "right", "left", or "auto": in each frame the arm held away from the body
        (``pointing_arm.pointing_arm``; a diver points with either hand, and seen from behind the
        model may swap its left and right).

        ``joint_disparity``: "landmarks" = the right image's landmarks as BlazePose places them;
        "match" = each arm joint's right position found by patch matching along its rectified
        row around them (``joint_stereo.match_joint_disparity``); "stereo" = the elbow's and
        wrist's left patches matched along their rows within the depths an arm reaches from the
        body (``joint_stereo.joint_disparities``) and the shoulder placed from the torso (the body's
        disparity, half a shoulder width nearer or farther by the torso's turn,
        ``shoulder_model.torso_shoulder_disparity``, which doubts the pose model's shoulder order by how often it
        changed over the latest frames, ``shoulder_model.ShoulderOrder``, and checks
        the body's disparity against the head's match): the right landmarks are not used for depth, and the
        arm carries each joint's disparity sigma (its own, at least ``disparity_floor_px``), which
        the pipeline turns into the joints' depth sigma for the selector.

        ``concurrent_eyes``: while both eyes are tracked, the right landmark run starts with the
        left one, in a second thread (onnxruntime releases the GIL): its ROI is this frame's left
        ROI shifted by the body's disparity measured with the PREVIOUS frame's landmarks (the
        sequential search waits for this frame's); any failure falls back to the sequential path.

        ``keypoint_sigma_m``: the landmarks' own error at the body (metres), carried by every arm
        for the selector (``ArmKeypoints.keypoint_sigma_m``).

        ``limbs_m``: the plausible (shortest, longest) upper arm and forearm, metres; with "stereo", an
        elbow / wrist match that makes a limb impossible is dropped (``joint_stereo.limb_switches``).

        Keypoints are returned whatever their confidence: the pipeline applies
        ``pose.min_confidence`` (and reports ``pose_low_confidence`` rather than ``no_pose``).

        ``smoother``: smooths the left landmarks over the frames of one track (``landmark_smoothing``; a
        detected pose starts it again); everything read from the left pose (the arm, the stereo matches,
        the early arm) then uses the smoothed landmarks, the next ROI the raw ones. None = each frame as found.
        """
        if arm not in ARM_INDICES and arm != AUTO:
            raise ValueError(f"arm must be one of {sorted(ARM_INDICES)} or {AUTO!r}, not {arm!r}")
        if stereo_search not in ("roi", "detect"):
            raise ValueError(f"stereo_search must be 'roi' or 'detect', not {stereo_search!r}")
        self.pose = pose
        self.arm = arm
        self.tracking = bool(tracking)
        self.stereo_search = stereo_search
        self.max_disparity_px = float(max_disparity_px)
        if joint_disparity not in JOINT_DISPARITY:
            raise ValueError(f"joint_disparity must be one of {', '.join(JOINT_DISPARITY)}, not {joint_disparity!r}")
        self.joint_disparity = joint_disparity
        self.concurrent_eyes = bool(concurrent_eyes)
        self.disparity_floor_px = float(disparity_floor_px)
        self.keypoint_sigma_m = None if keypoint_sigma_m is None else float(keypoint_sigma_m)
        self.limbs_m = limbs_m
        self.smoother = smoother
        self._body_disparity_px: float | None = None
        self._side: tuple[PoseLandmarks, str] | None = None   # with "auto": the last left pose's arm
        self._order = ShoulderOrder()   # the shoulders' depth order over the latest frames
        self._order_of: tuple[PoseLandmarks, float] | None = None   # the last left pose's doubt of that order
        self.stats = StereoStats()
        self.last: tuple[PoseLandmarks | None, PoseLandmarks | None] = (None, None)
        self._left, self._right = _Track(), _Track()

    @classmethod
    def from_params(cls, params: Mapping[str, Any]) -> "BlazePoseEstimator":
        """Build from parameters ``pose.arm`` and ``blazepose.*``."""
        return cls(BlazePose.from_params(params), arm=params["pose.arm"], tracking=params["blazepose.tracking"],
                   stereo_search=params["blazepose.stereo_search"],
                   max_disparity_px=params["blazepose.max_disparity_px"],
                   joint_disparity=params.get("blazepose.joint_disparity", "landmarks"),
                   concurrent_eyes=params.get("blazepose.concurrent_eyes", False),
                   disparity_floor_px=params.get("blazepose.disparity_floor_px", 1.5),
                   keypoint_sigma_m=params.get("blazepose.keypoint_sigma_m"), limbs_m=limb_spans_m(params),
                   smoother=_smoother(params))

    def reset(self) -> None:
        """Forget both cameras' tracking state (and, with ``arm="auto"``, the last frame's arm)."""
        self._left, self._right = _Track(), _Track()
        self._side = None
        self._order.reset()
        self._order_of = None
        if self.smoother is not None:
            self.smoother.reset()

    def arm_of(self, left: PoseLandmarks) -> str:
        """Return the arm read from a left pose: ``arm``, or with "auto" the one pointing (``pointing_arm``)."""
        if self.arm != AUTO:
            return self.arm
        if self._side is None or self._side[0] is not left:
            self._side = (left, pointing_arm(left, None if self._side is None else self._side[1]))
        return self._side[1]

    def estimate(self, left_rect: np.ndarray, right_rect: np.ndarray, rig: StereoRig) -> ArmKeypoints | None:
        """Return the arm in rectified pixels of both images (confidence = visibility), or None."""
        self._body_disparity_px = None
        matched_eye = self.joint_disparity == "stereo" and not self.concurrent_eyes
        both = None if matched_eye else self._both_concurrently(left_rect, right_rect, rig.disparity_sign)
        if both is not None and both[0] is not None:
            left, right = both
            self._left.update(left, self.tracking)
        else:  # sequential; after a lost concurrent run the tracked ROI is not tried twice
            left = self.pose.process(left_rect) if both is not None else self._follow(left_rect, self._left)
            left = self._smoothed(left)
            self._left.update(left, self.tracking)
            right = None
            if left is not None and matched_eye:
                matched = self._matched(left_rect, right_rect, left, rig)
                if matched is not None:
                    return matched
            if left is not None:
                right = self._right_pose(left_rect, right_rect, left, rig.disparity_sign)
        self._right.update(right, self.tracking)
        self.last = (left, right)
        if left is None or right is None:
            return None
        side = self.arm_of(left)
        lxy, (rxy, rconf) = left.arm(side)[0], right.arm(side)
        sigma = None
        if self.joint_disparity == "match":
            rxy = match_joint_disparity(left_rect, right_rect, lxy, rxy, rig.disparity_sign)
        elif self.joint_disparity == "stereo":
            found = self.stereo_joints(left_rect, right_rect, left, rig)
            if found is not None:
                rxy, sigma = self._matched_right(lxy, found)
        return self._arm_keypoints(left, rxy, rconf, sigma)

    def _matched(self, left_rect: np.ndarray, right_rect: np.ndarray, left: PoseLandmarks,
                 rig: StereoRig) -> ArmKeypoints | None:
        """Return the arm from the left landmarks and the stereo joint matches, with no right landmark run.

        With ``joint_disparity="stereo"`` the right landmarks set no depth: the right eye's arm is
        the left one moved by each joint's matched disparity (right confidence = left), and the
        right landmark run is skipped. None when the body's disparity cannot be measured (the
        caller then runs the right landmarks, as "landmarks" does).
        """
        sign = rig.disparity_sign
        body = body_disparity(left_rect, right_rect, left, sign, self.max_disparity_px)
        if body is None:
            return None
        self._body_disparity_px = body
        self._tell_early(left, body, sign)
        found = self.stereo_joints(left_rect, right_rect, left, rig)
        self.stats.matched += 1
        self._right.update(None, self.tracking)
        self.last = (left, None)
        lxy, lconf = left.arm(self.arm_of(left))
        rxy, sigma = self._matched_right(lxy, found)
        return self._arm_keypoints(left, rxy, lconf.copy(), sigma)

    def _matched_right(self, lxy: np.ndarray, found: JointDisparity) -> tuple[np.ndarray, np.ndarray]:
        """Return the right-image joints at the matched disparities and their disparity sigma, pixels."""
        rxy = np.c_[lxy[:, 0] - found.disparity_px, lxy[:, 1]]
        return rxy, found.floored_sigma_px(self.disparity_floor_px)

    def _arm_keypoints(self, left: PoseLandmarks, rxy: np.ndarray, rconf: np.ndarray,
                       sigma: np.ndarray | None) -> ArmKeypoints:
        """Return the arm: the left landmarks' joints, ``rxy`` in the right image, the hand and the errors."""
        side = self.arm_of(left)
        lxy, lconf = left.arm(side)
        return ArmKeypoints(side, lxy, rxy, lconf, rconf, source="blazepose", extra_left_px=_extra(left, side),
                            disparity_sigma_px=sigma, keypoint_sigma_m=self.keypoint_sigma_m)

    def stereo_joints(self, left_rect: np.ndarray, right_rect: np.ndarray, left: PoseLandmarks,
                      rig: StereoRig) -> JointDisparity | None:
        """Return the arm joints' disparities: elbow and wrist matched, the shoulder from the torso (None: no body)."""
        sign = rig.disparity_sign
        body = self._body_disparity_px
        if body is None:
            body = body_disparity(left_rect, right_rect, left, sign, self.max_disparity_px)
        if body is None:
            return None
        side = self.arm_of(left)
        xy, _ = left.arm(side)
        found = joint_disparities(left_rect, right_rect, xy, sign * body, sign, rig.focal_px, rig.baseline_m,
                                  patch_m=JOINT_PATCH_M)
        near = left.z_px[ARM_INDICES[side][0]] <= left.z_px[ARM_INDICES[_OTHER[side]][0]]
        apart = float(np.linalg.norm(left.xy_px[11] - left.xy_px[12]))
        head = head_disparity(_extra(left, side).get("head"), left_rect, right_rect, sign * body, sign, rig.focal_px,
                              rig.baseline_m)
        d, sd = torso_shoulder_disparity(sign * body, apart, bool(near), rig.focal_px, rig.baseline_m, head,
                                         side_doubt=self._order_doubt(left, bool(near)))
        torso = float(np.linalg.norm(left.xy_px[[11, 12]].mean(axis=0) - left.xy_px[[23, 24]].mean(axis=0)))
        found = in_front_of_body(found, xy, left.xy_px[list(_BODY)], torso, sign * body, rig.focal_px, rig.baseline_m,
                                 JOINT_PATCH_M)
        found = on_background(found, left_rect, right_rect, xy, sign * body, sign, rig.focal_px, rig.baseline_m,
                              JOINT_PATCH_M)
        disp, sigma, matched = found.disparity_px.copy(), found.sigma_px.copy(), found.matched.copy()
        disp[0], sigma[0], matched[0] = d, sd, False
        if self.limbs_m is not None and matched.any():
            wide = unmatched_sigma_px(body, rig.focal_px * rig.baseline_m)
            slack = math.hypot(LIMB_SLACK_M, math.sqrt(2.0) * (self.keypoint_sigma_m or 0.0))
            dropped = limb_switches(xy, disp, np.maximum(sigma, self.disparity_floor_px * JOINT_FLOOR_FACTOR),
                                    sign * body, wide, matched, matched, rig.focal_px, rig.baseline_m,
                                    rig.principal_point_px, self.limbs_m, slack)
            disp[dropped], sigma[dropped], matched = sign * body, wide, matched & ~dropped
        return JointDisparity(disp, sigma, matched, found.score)

    def _order_doubt(self, left: PoseLandmarks, near: bool) -> float:
        """Return the doubt of the shoulders' order for a left pose, recorded once however often it is asked for."""
        if self._order_of is None or self._order_of[0] is not left:
            self._order_of = (left, self._order.doubt(near))
        return self._order_of[1]

    def _both_concurrently(self, left_img: np.ndarray, right_img: np.ndarray, sign: int
                           ) -> tuple[PoseLandmarks | None, PoseLandmarks | None] | None:
        """Return (left, right) from concurrent landmark runs in the tracked ROIs, or None to go sequential.

        None when not tracking both eyes or when the body's disparity cannot be measured with the
        previous landmarks; (None, None) when the left pose was lost in its tracked ROI (the caller
        re-detects). A right run that finds no pose is redone sequentially (``_right_pose``).
        """
        previous = self.last[0]
        if not (self.concurrent_eyes and self.tracking and self.stereo_search == "roi"
                and self._left.roi is not None and previous is not None):
            return None
        disparity = body_disparity(left_img, right_img, previous, sign, self.max_disparity_px)
        if disparity is None:
            return None
        roi, contrast = self._left.roi, self._left.contrast
        right_job = _eye_pool().submit(self.pose.process, right_img, roi.shifted(-sign * disparity), True, contrast)
        try:
            left = self.pose.process(left_img, roi, contrast=contrast)
        finally:
            right = right_job.result()
        if left is None:
            return None, None
        left = self._smoothed(left)
        self._tell_early(left, disparity, sign)
        if right is None:
            return left, self._right_pose(left_img, right_img, left, sign)
        self.stats.searched += 1
        self.stats.concurrent += 1
        return left, right

    def _smoothed(self, left: PoseLandmarks | None) -> PoseLandmarks | None:
        """Return the left pose with its landmarks smoothed over the track (unchanged without a smoother)."""
        if self.smoother is None or left is None:
            return left
        if left.detected:   # a new track: not the frames before it
            self.smoother.reset()
        return replace(left, xy_px=self.smoother.smooth(left.xy_px, left.roi.size_px))

    def _follow(self, image: np.ndarray, track: _Track) -> PoseLandmarks | None:
        """Return the pose in the tracked ROI, or from a fresh detection when there is none.

        MediaPipe's video graph re-detects on the frame after the pose flag drops; here the same
        frame is re-detected at once (one frame less without a pose, one landmark run more).
        """
        if track.roi is not None:
            found = self.pose.process(image, track.roi, contrast=track.contrast)
            if found is not None:
                return found
        return self.pose.process(image)

    def _right_pose(self, left_img: np.ndarray, right_img: np.ndarray, left: PoseLandmarks,
                    sign: int) -> PoseLandmarks | None:
        """Return the right image's pose.

        With ``stereo_search="roi"`` the right crop is the left one shifted along the rows by the
        body's disparity (every frame: the two crops then see the same content, which keeps the
        keypoints' disparities consistent); if that fails, or with "detect", the right image's
        own tracked ROI, else a full detection.
        """
        if self.stereo_search == "roi":
            found = self.search_right(left_img, right_img, left, sign)
            if found is not None:
                self.stats.searched += 1
                return found
            self.stats.search_failed += 1
        if self._right.roi is not None:
            found = self.pose.process(right_img, self._right.roi, contrast=self._right.contrast)
            if found is not None:
                self.stats.tracked += 1
                return found
        self.stats.detected += 1
        return self.pose.process(right_img)

    def search_right(self, left_img: np.ndarray, right_img: np.ndarray, left: PoseLandmarks,
                     sign: int) -> PoseLandmarks | None:
        """Return the right pose in the left ROI shifted by the body's disparity (None if not found)."""
        disparity = body_disparity(left_img, right_img, left, sign, self.max_disparity_px)
        self._body_disparity_px = disparity
        if disparity is None:
            return None
        self._tell_early(left, disparity, sign)
        return self.pose.process(right_img, left.roi.shifted(-sign * disparity), contrast=left.contrast)

    def _tell_early(self, left: PoseLandmarks, disparity_px: float, sign: int) -> None:
        """Give the early-arm listener the left arm and its right-image position at the body's disparity."""
        if self._early_listener is None:
            return
        side = self.arm_of(left)
        xy, conf = left.arm(side)
        right_xy = xy - np.array([sign * disparity_px, 0.0])
        self._early_listener(ArmKeypoints(side, xy, right_xy, conf, conf, source="blazepose (right predicted)",
                                          extra_left_px=_extra(left, side)))


_NOSE = 0
"""BlazePose's nose landmark (the head of the stop gesture)."""
_INDEX_FINGER = {"right": 20, "left": 19}
"""BlazePose's index-finger landmark per arm (the far end of the pointing hand)."""


def _smoother(params: Mapping[str, Any]) -> LandmarkSmoother | None:
    """Return the left landmarks' smoother from ``blazepose.smoothing*`` (None when off)."""
    if not params.get("blazepose.smoothing", False):
        return None
    return LandmarkSmoother(params["blazepose.smoothing_min_cutoff"], params["blazepose.smoothing_beta"],
                            params["blazepose.smoothing_jump"])


def _eye_pool():
    """Return the shared 1-thread pool of the right eye's concurrent landmark run."""
    from .threads import shared_pool
    return shared_pool("pose-right", 1)


EXTRA_MIN_VISIBILITY = {"head": 0.5, "other_wrist": 0.1, "hand": 0.5}
"""The visibility (BlazePose's own, 0-1) an extra joint needs to be reported. The other wrist serves only the stop
gesture, where it lies beside or behind the pointing hand above the head: BlazePose places it within ~12 px of the
body's wrist there but calls it hidden (visibility median 0.36 in clear water, 0.21 in murky water), so at 0.5 the
gesture was seen in 21 of 80 such frames in clear water and 0 of 56 in murky water; at 0.1, 70 and 49. In 376
ordinary frames of five scenarios no threshold made a stop gesture out of them (the pointing wrist is not above
the head; issue 14 session 72, ``docs/issue11/session72/scripts/stop_visibility.py``)."""


def _extra(pose: PoseLandmarks, arm: str) -> dict:
    """Return the head (nose), the other arm's wrist and the pointing hand's index finger, pixels, where visible
    (``EXTRA_MIN_VISIBILITY``)."""
    other = ARM_INDICES["left" if arm == "right" else "right"][2]
    out = {}
    for name, i in (("head", _NOSE), ("other_wrist", other), ("hand", _INDEX_FINGER[arm])):
        if pose.visibility[i] >= EXTRA_MIN_VISIBILITY[name]:
            out[name] = (float(pose.xy_px[i, 0]), float(pose.xy_px[i, 1]))
    return out


def _small_grey(patch: np.ndarray, scale: float) -> np.ndarray:
    """Return an image patch downscaled by ``scale`` as float32 grey (no full-frame copy)."""
    small = cv2.resize(patch, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
    if small.ndim == 3:
        small = cv2.cvtColor(small, cv2.COLOR_BGR2GRAY)
    return small.astype(np.float32)


def _body_box(pose: PoseLandmarks, width: int, height: int) -> tuple[int, int, int, int] | None:
    """Return the (x0, y0, x1, y1) pixel box around head, arms and hips, padded 10 %, in the image."""
    pts = pose.xy_px[list(_SEARCH_POINTS)]
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.1 * float((hi - lo).max())
    x0, y0 = (int(max(0, math.floor(v - pad))) for v in lo)
    x1, y1 = int(min(width, math.ceil(hi[0] + pad))), int(min(height, math.ceil(hi[1] + pad)))
    return (x0, y0, x1, y1) if x1 - x0 >= 8 and y1 - y0 >= 8 else None


def body_disparity(left_img: np.ndarray, right_img: np.ndarray, pose: PoseLandmarks, sign: int,
                   max_disparity_px: float) -> float | None:
    """Return the disparity of the person's body between rectified images, pixels (None if unknown).

    Normalised cross-correlation of the body box (downscaled to ~96 px wide) along the same rows
    of the right image, over disparities 0..max_disparity_px in the rig's direction (``sign`` +1:
    the right image's content lies to the left), with a few rows of slack and sub-pixel peak.
    """
    h, w = left_img.shape[:2]
    box = _body_box(pose, w, h)
    if box is None:
        return None
    x0, y0, x1, y1 = box
    scale = min(1.0, _TEMPLATE_WIDTH_PX / (x1 - x0))
    slack = int(math.ceil(2.0 / scale))
    reach = int(math.ceil(max_disparity_px))
    sx0, sx1 = (max(0, x0 - reach), x1) if sign > 0 else (x0, min(w, x1 + reach))
    sy0, sy1 = max(0, y0 - slack), min(h, y1 + slack)
    template = _small_grey(left_img[y0:y1, x0:x1], scale)
    strip = _small_grey(right_img[sy0:sy1, sx0:sx1], scale)
    if strip.shape[0] < template.shape[0] or strip.shape[1] < template.shape[1]:
        return None
    if float(template.std()) < 1e-3:
        return None
    scores = cv2.matchTemplate(strip, template, cv2.TM_CCOEFF_NORMED)
    row, col = np.unravel_index(int(np.argmax(scores)), scores.shape)
    x_match = sx0 + _subpixel(scores[row], int(col)) * (sx1 - sx0) / strip.shape[1]
    return float(sign * (x0 - x_match))

