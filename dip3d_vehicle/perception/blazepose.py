"""The ``blazepose`` pose backend: MediaPipe Pose (BlazePose GHUM full) on onnxruntime.

Two layers:

- ``BlazePose``: one image in, 33 landmarks out (``process``), reproducing MediaPipe's CPU graph:
  letterboxed detection with SSD decoding and weighted NMS (``blazepose_decode``), a rotated
  square ROI from the detector's two keypoints (``blazepose_roi``), a 256x256 crop with replicated
  border, the landmark model, heatmap refinement and projection back to image pixels.
- ``BlazePoseEstimator``: the ``PoseEstimator`` for rectified stereo pairs, with MediaPipe-style
  tracking (the next frame's ROI comes from the auxiliary landmarks while the pose flag stays
  high) and a cheap right image: the left pose's ROI shifted along the same rows by a disparity
  found by template matching, instead of a blind detection.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Mapping

import cv2
import numpy as np

from ..errors import ModelError
from ..models import model_path
from .blazepose_decode import DETECTOR_SIZE, decode, weighted_nms
from .blazepose_roi import Roi, crop_matrix, letterbox_matrix, roi_from_points, warp
from .calibration import StereoRig
from .joint_stereo import (JOINT_FLOOR_FACTOR, LIMB_SLACK_M, JointDisparity, in_front_of_body, joint_disparities,
                           head_disparity, limb_spans_m, limb_switches, match_joint_disparity, on_background,
                           subpixel_peak as _subpixel, unmatched_sigma_px)
from .pointing_arm import AUTO, pointing_arm
from .pose import ARM_INDICES, PoseEstimator
from .shoulder_model import ShoulderOrder, torso_shoulder_disparity
from .values import ArmKeypoints

__all__ = ["BlazePose", "BlazePoseEstimator", "Detection", "PoseLandmarks", "Contrast",
           "refine_from_heatmap", "body_disparity"]

LANDMARK_SIZE = 256
"""Side of the landmark model's square input crop, pixels."""

NUM_LANDMARKS = 33
_ALL_LANDMARKS = 39             # 33 body + 2 auxiliary (ROI) + 4 unused
_AUX = (33, 34)                 # auxiliary landmarks: hip centre and scale point, for tracking
_HEATMAP_KERNEL = 7             # RefineLandmarksFromHeatmapCalculator kernel_size
_HEATMAP_MIN_CONF = 0.5         # ... min_confidence_to_refine
_SEARCH_POINTS = (0, 11, 12, 13, 14, 15, 16, 23, 24)   # head, arms, hips: template for disparity
_TEMPLATE_WIDTH_PX = 96         # width of the downscaled template used to find the disparity
_STRETCH_PERCENT = (1.0, 99.0)  # contrast retry: per-channel percentile stretch
SQUARE_TILES = 3
"""Square tiles of the frame's shorter side searched by the detector's last retry (``detect_in_squares``)."""
JOINT_DISPARITY = ("landmarks", "match", "stereo")
"""Ways of finding the arm joints' right-image x (``blazepose.joint_disparity``)."""
JOINT_PATCH_M = 0.12
"""Side of the patch matched around an elbow or wrist for ``stereo``, metres at the body's depth (wrist
disparity error on paper_pool's diver at 3 m: std 0.9 px at 0.12 m, 1.1 at 0.09, 2.2 at 0.06; issue 14)."""
_OTHER = {"right": "left", "left": "right"}
_BODY = (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 23, 24)   # head, shoulders, hips: what an arm in front hides
Contrast = tuple[np.ndarray, np.ndarray]
"""Per-channel (low, high) levels of a contrast stretch, in the image's channel order."""


def _sigmoid(x: np.ndarray) -> np.ndarray:
    """Return the logistic function of ``x`` (float64)."""
    return 1.0 / (1.0 + np.exp(-np.asarray(x, np.float64)))


@dataclass(frozen=True)
class Detection:
    """The detector's best person, in image pixels.

    Attributes:
        score: probability in [0, 1].
        box_px: (4,) xmin, ymin, xmax, ymax.
        keypoints_px: (4, 2); 0 = hip centre, 1 = scale/rotation point.
        contrast: the contrast stretch the detector saw (None = the image as is).
    """

    score: float
    box_px: np.ndarray
    keypoints_px: np.ndarray
    contrast: Contrast | None = None

    def roi(self) -> Roi:
        """Return the landmark ROI MediaPipe derives from this detection."""
        return roi_from_points(self.keypoints_px[0], self.keypoints_px[1])


@dataclass(frozen=True)
class PoseLandmarks:
    """One person's 33 BlazePose landmarks in image pixels.

    Attributes:
        xy_px: (33, 2) x, y, pixels.
        z_px: (33,) depth relative to the hips, pixels (same scale as x).
        visibility: (33,) probability that the landmark is visible, [0, 1].
        presence: (33,) probability that the landmark is in the image, [0, 1].
        pose_flag: probability that a person is in the ROI, [0, 1].
        roi: the ROI the landmarks were computed in.
        aux_px: (2, 2) auxiliary landmarks (hip centre, scale point) giving the next ROI.
        contrast: contrast stretch used (None = the image as is).
        detected: True when the ROI came from the detector (False: tracked or searched).
    """

    xy_px: np.ndarray
    z_px: np.ndarray
    visibility: np.ndarray
    presence: np.ndarray
    pose_flag: float
    roi: Roi
    aux_px: np.ndarray
    contrast: Contrast | None = None
    detected: bool = True

    def arm(self, arm: str) -> tuple[np.ndarray, np.ndarray]:
        """Return (shoulder, elbow, wrist) as ((3, 2) pixels, (3,) visibility) for ``arm``."""
        idx = list(ARM_INDICES[arm])
        return self.xy_px[idx], self.visibility[idx]

    def next_roi(self) -> Roi:
        """Return the ROI for the next frame (MediaPipe's pose_landmarks_to_roi)."""
        return roi_from_points(self.aux_px[0], self.aux_px[1])


def refine_from_heatmap(xy: np.ndarray, heatmap: np.ndarray) -> np.ndarray:
    """Return landmarks refined by the heatmap's weighted mean around each one (vectorised).

    Args:
        xy: (N, 2) landmark positions normalised to the crop (0..1).
        heatmap: (H, W, N) raw heatmap logits.

    Follows RefineLandmarksFromHeatmapCalculator: 7x7 window at int(x * W), int(y * H), refined
    only when the window's largest sigmoid reaches 0.5; the mean uses cell indices (no +0.5).
    """
    h, w, n = heatmap.shape
    half = _HEATMAP_KERNEL // 2
    col = np.trunc(xy[:, 0] * w).astype(np.int64)
    row = np.trunc(xy[:, 1] * h).astype(np.int64)
    inside = (col >= 0) & (col < w) & (row >= 0) & (row < h)
    offs = np.arange(-half, half + 1)
    rows = row[:, None] + offs                       # (N, 7)
    cols = col[:, None] + offs
    valid = ((rows >= 0) & (rows < h))[:, :, None] & ((cols >= 0) & (cols < w))[:, None, :]
    win = heatmap[np.clip(rows, 0, h - 1)[:, :, None], np.clip(cols, 0, w - 1)[:, None, :],
                  np.arange(n)[:, None, None]]
    conf = _sigmoid(win) * valid                     # (N, 7, 7)
    total = conf.sum(axis=(1, 2))
    refine = inside & (conf.max(axis=(1, 2)) >= _HEATMAP_MIN_CONF) & (total > 0)
    safe = np.where(total > 0, total, 1.0)
    mean_col = (conf * cols[:, None, :]).sum(axis=(1, 2)) / safe / w
    mean_row = (conf * rows[:, :, None]).sum(axis=(1, 2)) / safe / h
    out = np.array(xy, np.float64, copy=True)
    out[refine, 0] = mean_col[refine]
    out[refine, 1] = mean_row[refine]
    return out


def _session(path: Path, threads: int, spin_wait: bool) -> Any:
    """Return an onnxruntime CPU session for a verified model file; ModelError if it cannot load."""
    import onnxruntime as ort

    opts = ort.SessionOptions()
    opts.intra_op_num_threads = threads
    opts.inter_op_num_threads = 1
    opts.execution_mode = ort.ExecutionMode.ORT_SEQUENTIAL
    opts.add_session_config_entry("session.intra_op.allow_spinning", "1" if spin_wait else "0")
    opts.add_session_config_entry("session.inter_op.allow_spinning", "1" if spin_wait else "0")
    try:
        return ort.InferenceSession(str(path), opts, providers=["CPUExecutionProvider"])
    except Exception as exc:  # onnxruntime raises its own exception types
        raise ModelError(f"{path}: cannot load model ({exc.__class__.__name__}: {str(exc)[:120]})") from None


def _to_unit_rgb(crop: np.ndarray, bgr: bool, contrast: Contrast | None) -> np.ndarray:
    """Return a small uint8 crop as a (1, H, W, 3) float32 RGB tensor in 0..1 (optionally stretched)."""
    if contrast is None and crop.ndim == 3:  # channels swapped on uint8 (8x faster than on floats)
        x = (cv2.cvtColor(crop, cv2.COLOR_BGR2RGB) if bgr else crop).astype(np.float32)
        x *= 1.0 / 255.0
        return x[None]
    x = crop.astype(np.float32)
    if contrast is not None:
        lo, hi = contrast
        x = np.clip((x - lo) / np.maximum(hi - lo, 1.0), 0.0, 1.0)
    else:
        x *= 1.0 / 255.0
    if x.ndim == 2:
        x = np.repeat(x[:, :, None], 3, axis=2)
    elif bgr:
        x = x[:, :, ::-1]
    return np.ascontiguousarray(x[None])


def _contrast_of(crop: np.ndarray, region: tuple[int, int, int, int]) -> Contrast:
    """Return per-channel percentile levels of ``crop[y0:y1, x0:x1]`` for a contrast stretch."""
    x0, y0, x1, y1 = region
    pixels = crop[y0:y1, x0:x1].reshape(-1, crop.shape[2] if crop.ndim == 3 else 1).astype(np.float32)
    lo, hi = np.percentile(pixels, _STRETCH_PERCENT, axis=0)
    return lo.astype(np.float32), np.maximum(hi, lo + 16.0).astype(np.float32)


class BlazePose:
    """MediaPipe Pose (detector + full landmark model) on onnxruntime, one image at a time.

    Counters ``detector_calls`` and ``landmark_calls`` count model runs (for tests and timing).
    """

    def __init__(self, threads: int = 1, spin_wait: bool = False, min_detection_score: float = 0.5,
                 min_pose_flag: float = 0.5, contrast_retry: bool = True,
                 models_dir: str | Path | None = None) -> None:
        """Load and verify both models; ``threads`` is onnxruntime's intra-op thread count."""
        self.min_detection_score = float(min_detection_score)
        self.min_pose_flag = float(min_pose_flag)
        self.contrast_retry = bool(contrast_retry)
        self._detector = _session(model_path("pose_detection", models_dir), threads, spin_wait)
        self._landmarker = _session(model_path("pose_landmark_full", models_dir), threads, spin_wait)
        self.detector_calls = 0
        self.landmark_calls = 0

    @classmethod
    def from_params(cls, params: Mapping[str, Any]) -> "BlazePose":
        """Build from parameters ``blazepose.*``."""
        return cls(threads=params["blazepose.threads"], spin_wait=params["blazepose.spin_wait"],
                   min_detection_score=params["blazepose.min_detection_score"],
                   min_pose_flag=params["blazepose.min_pose_flag"],
                   contrast_retry=params["blazepose.contrast_retry"])

    # -- detector -------------------------------------------------------------------------
    def detect(self, image: np.ndarray, bgr: bool = True, contrast: Contrast | bool | None = None
               ) -> Detection | None:
        """Return the best person detection in image pixels, or None below the minimum score.

        ``contrast=True`` stretches each channel of the letterboxed image to its 1-99 % levels.
        """
        h, w = image.shape[:2]
        to_tensor = letterbox_matrix(w, h, DETECTOR_SIZE)
        small = cv2.warpAffine(image, to_tensor, (DETECTOR_SIZE, DETECTOR_SIZE), flags=cv2.INTER_LINEAR,
                               borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        if contrast is True:
            contrast = _contrast_of(small, self._letterbox_region(to_tensor, w, h))
        x = _to_unit_rgb(small, bgr, contrast or None) * 2.0 - 1.0
        self.detector_calls += 1
        regressors, logits = self._detector.run(["Identity", "Identity_1"], {"input_1": x})
        found = weighted_nms(*decode(regressors[0], logits[0, :, 0], self.min_detection_score))
        if not found:
            return None
        best = found[0]
        scale, offset = to_tensor[0, 0], to_tensor[:, 2]
        box = (best.box.reshape(2, 2) * DETECTOR_SIZE - offset) / scale
        kps = (best.keypoints * DETECTOR_SIZE - offset) / scale
        return Detection(best.score, box.ravel(), kps, contrast or None)

    def detect_in_squares(self, image: np.ndarray, bgr: bool = True) -> Detection | None:
        """Return the best contrast-stretched detection in square tiles of the image (image pixels), or None.

        The last retry of an empty frame: in murky water the whole frame, letterboxed and stretched,
        scores a diver at 3 m under 0.03, the same diver in a square tile of the frame's height
        0.8-0.9 (no letterbox bars, the stretch read from the tile). Tiles: ``SQUARE_TILES`` squares of
        the shorter side, spread evenly along the longer one.
        """
        h, w = image.shape[:2]
        side = min(h, w)
        if h == w:
            return None
        best: Detection | None = None
        for start in np.linspace(0, max(h, w) - side, SQUARE_TILES).round().astype(int):
            x0, y0 = (int(start), 0) if w > h else (0, int(start))
            det = self.detect(np.ascontiguousarray(image[y0:y0 + side, x0:x0 + side]), bgr, contrast=True)
            if det is not None and (best is None or det.score > best.score):
                shift = np.array([x0, y0], np.float64)
                best = replace(det, box_px=det.box_px + np.tile(shift, 2), keypoints_px=det.keypoints_px + shift)
        return best

    @staticmethod
    def _letterbox_region(to_tensor: np.ndarray, width: int, height: int) -> tuple[int, int, int, int]:
        """Return the (x0, y0, x1, y1) tensor pixels covered by the image inside a letterbox."""
        x0, y0 = to_tensor[:, 2]
        s = to_tensor[0, 0]
        return (int(math.ceil(x0)), int(math.ceil(y0)), int(x0 + width * s), int(y0 + height * s))

    # -- landmarks ------------------------------------------------------------------------
    def landmarks(self, image: np.ndarray, roi: Roi, bgr: bool = True,
                  contrast: Contrast | None = None, detected: bool = False) -> PoseLandmarks:
        """Run the landmark model in ``roi`` and return its landmarks (whatever the pose flag)."""
        to_image = crop_matrix(roi, LANDMARK_SIZE)
        crop = warp(image, to_image, LANDMARK_SIZE, cv2.BORDER_REPLICATE)
        self.landmark_calls += 1
        raw, flag, heat = self._landmarker.run(["Identity", "Identity_1", "Identity_3"],
                                               {"input_1": _to_unit_rgb(crop, bgr, contrast)})
        raw = raw.reshape(_ALL_LANDMARKS, 5).astype(np.float64)
        xy = refine_from_heatmap(raw[:, :2] / LANDMARK_SIZE, heat[0]) * LANDMARK_SIZE
        xy_px = xy @ to_image[:, :2].T + to_image[:, 2]
        n = NUM_LANDMARKS
        return PoseLandmarks(
            xy_px=xy_px[:n], z_px=raw[:n, 2] * roi.size_px / LANDMARK_SIZE,
            visibility=_sigmoid(raw[:n, 3]), presence=_sigmoid(raw[:n, 4]),
            pose_flag=float(flag.ravel()[0]), roi=roi, aux_px=xy_px[list(_AUX)],
            contrast=contrast, detected=detected)

    # -- whole image ------------------------------------------------------------------------
    def process(self, image: np.ndarray, roi: Roi | None = None, bgr: bool = True,
                contrast: Contrast | None = None) -> PoseLandmarks | None:
        """Return the person's landmarks in image pixels, or None if none is found.

        Args:
            image: HxWx3 uint8 (BGR unless ``bgr`` is False) or HxW grey.
            roi: where to look (tracking); None runs the detector first (with a contrast-stretched
                retry when it finds nothing and ``contrast_retry`` is on).
            contrast: stretch to apply in ``roi`` (from a previous frame's result).
        """
        detected = roi is None
        if roi is None:
            det = self.detect(image, bgr)
            if det is None and self.contrast_retry:
                det = self.detect(image, bgr, contrast=True) or self.detect_in_squares(image, bgr)
            if det is None:
                return None
            roi, contrast = det.roi(), det.contrast
        if roi.size_px < 1.0:
            return None
        found = self.landmarks(image, roi, bgr, contrast, detected)
        return found if found.pose_flag >= self.min_pose_flag else None


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
                 limbs_m: tuple[tuple[float, float], tuple[float, float]] | None = None) -> None:
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
        self._body_disparity_px: float | None = None
        self._side: tuple[PoseLandmarks, str] | None = None   # with "auto": the last left pose's arm
        self._order = ShoulderOrder()   # the shoulders' depth order over the latest frames
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
                   keypoint_sigma_m=params.get("blazepose.keypoint_sigma_m"), limbs_m=limb_spans_m(params))

    def reset(self) -> None:
        """Forget both cameras' tracking state (and, with ``arm="auto"``, the last frame's arm)."""
        self._left, self._right = _Track(), _Track()
        self._side = None
        self._order.reset()

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
                                         side_doubt=self._order.doubt(bool(near)))
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
        self._tell_early(left, disparity, sign)
        if right is None:
            return left, self._right_pose(left_img, right_img, left, sign)
        self.stats.searched += 1
        self.stats.concurrent += 1
        return left, right

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


def _eye_pool():
    """Return the shared 1-thread pool of the right eye's concurrent landmark run."""
    from .threads import shared_pool
    return shared_pool("pose-right", 1)


def _extra(pose: PoseLandmarks, arm: str, min_visibility: float = 0.5) -> dict:
    """Return the head (nose), the other arm's wrist and the pointing hand's index finger, pixels, where visible."""
    other = ARM_INDICES["left" if arm == "right" else "right"][2]
    out = {}
    for name, i in (("head", _NOSE), ("other_wrist", other), ("hand", _INDEX_FINGER[arm])):
        if pose.visibility[i] >= min_visibility:
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
