"""BlazePose itself: one image in, 33 landmarks out, as MediaPipe Pose (BlazePose GHUM full) on onnxruntime.

``BlazePose.process`` reproduces MediaPipe's CPU graph: letterboxed detection with SSD decoding and weighted NMS
(``blazepose_decode``), a rotated square ROI from the detector's two keypoints (``blazepose_roi``), a 256x256 crop
with replicated border, the landmark model, heatmap refinement and projection back to image pixels. The stereo
estimator built on it is ``blazepose.BlazePoseEstimator``.
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
from .pose import ARM_INDICES

__all__ = ["BlazePose", "Detection", "PoseLandmarks", "Contrast", "refine_from_heatmap", "LANDMARK_SIZE",
           "NUM_LANDMARKS", "SQUARE_TILES"]

LANDMARK_SIZE = 256
"""Side of the landmark model's square input crop, pixels."""

NUM_LANDMARKS = 33
_ALL_LANDMARKS = 39             # 33 body + 2 auxiliary (ROI) + 4 unused
_AUX = (33, 34)                 # auxiliary landmarks: hip centre and scale point, for tracking
_HEATMAP_KERNEL = 7             # RefineLandmarksFromHeatmapCalculator kernel_size
_HEATMAP_MIN_CONF = 0.5         # ... min_confidence_to_refine
_STRETCH_PERCENT = (1.0, 99.0)  # contrast retry: per-channel percentile stretch
_STRETCH_MIN_SPAN = 16.0        # ... levels at least this far apart: a flat channel gains at most 255 / 16
_CLAHE = (2.0, (8, 8))          # local-contrast retry (detect_in_squares(local=True)): CLAHE clip limit, tile grid
_CROP_BORDER = 32               # crop stretch: levels read inside this margin of the 256 px crop (its replicated border)
SQUARE_TILES = 3
"""Square tiles of the frame's shorter side searched by the detector's last retry (``detect_in_squares``)."""
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
    if contrast is not None:  # the stretch as a per-channel table of the 256 grey levels (same values, ~5x faster)
        lo, hi = contrast
        levels = np.arange(256, dtype=np.float32)[:, None]
        table = np.clip((levels - lo) / np.maximum(hi - lo, 1.0), 0.0, 1.0).astype(np.float32)
        x = cv2.LUT(crop, table.reshape(256, 1, -1) if crop.ndim == 3 else table[:, :1])
    else:
        x = crop.astype(np.float32) * (1.0 / 255.0)
    if x.ndim == 2:
        x = np.repeat(x[:, :, None], 3, axis=2)
    elif bgr:
        x = x[:, :, ::-1]
    return np.ascontiguousarray(x[None])


def _crop_levels(crop: np.ndarray) -> Contrast:
    """Return per-channel 1-99 % levels of a landmark crop's inner part (a histogram per channel; uint8 crop)."""
    inner = crop[_CROP_BORDER:-_CROP_BORDER, _CROP_BORDER:-_CROP_BORDER]
    channels = inner.shape[2] if inner.ndim == 3 else 1
    lo, hi = np.empty(channels, np.float32), np.empty(channels, np.float32)
    for c in range(channels):
        cum = cv2.calcHist([inner], [c], None, [256], [0, 256]).ravel().cumsum()
        lo[c], hi[c] = np.searchsorted(cum, cum[-1] * np.asarray(_STRETCH_PERCENT) / 100.0)
    return lo, np.maximum(hi, lo + _STRETCH_MIN_SPAN)


def _local_contrast(image: np.ndarray, bgr: bool = True) -> np.ndarray:
    """Return a uint8 colour image with its lightness equalised locally (CLAHE, clip 2, 8 x 8 tiles; colour kept).

    A CLAHE object per call: the two eyes may run in two threads, and OpenCV's keeps buffers between calls.
    """
    clahe = cv2.createCLAHE(*_CLAHE)
    if image.ndim == 2:
        return clahe.apply(image)
    lab = cv2.cvtColor(image, cv2.COLOR_BGR2LAB if bgr else cv2.COLOR_RGB2LAB)
    lab[:, :, 0] = clahe.apply(lab[:, :, 0])
    return cv2.cvtColor(lab, cv2.COLOR_LAB2BGR if bgr else cv2.COLOR_LAB2RGB)


def _contrast_of(crop: np.ndarray, region: tuple[int, int, int, int]) -> Contrast:
    """Return per-channel percentile levels of ``crop[y0:y1, x0:x1]`` for a contrast stretch."""
    x0, y0, x1, y1 = region
    pixels = crop[y0:y1, x0:x1].reshape(-1, crop.shape[2] if crop.ndim == 3 else 1).astype(np.float32)
    lo, hi = np.percentile(pixels, _STRETCH_PERCENT, axis=0)
    return lo.astype(np.float32), np.maximum(hi, lo + _STRETCH_MIN_SPAN).astype(np.float32)


class BlazePose:
    """MediaPipe Pose (detector + full landmark model) on onnxruntime, one image at a time.

    Counters ``detector_calls`` and ``landmark_calls`` count model runs (for tests and timing).
    """

    def __init__(self, threads: int = 1, spin_wait: bool = False, min_detection_score: float = 0.5,
                 min_pose_flag: float = 0.5, contrast_retry: bool = True,
                 models_dir: str | Path | None = None, crop_stretch: bool = False,
                 local_retry: bool = False) -> None:
        """Load and verify both models; ``threads`` is onnxruntime's intra-op thread count."""
        self.min_detection_score = float(min_detection_score)
        self.min_pose_flag = float(min_pose_flag)
        self.contrast_retry = bool(contrast_retry)
        self.crop_stretch = bool(crop_stretch)
        self.local_retry = bool(local_retry)
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
                   contrast_retry=params["blazepose.contrast_retry"],
                   crop_stretch=params["blazepose.crop_stretch"], local_retry=params["blazepose.local_retry"])

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

    def detect_in_squares(self, image: np.ndarray, bgr: bool = True, local: bool = False) -> Detection | None:
        """Return the best contrast-stretched detection in square tiles of the image (image pixels), or None.

        The last retry of an empty frame: in murky water the whole frame, letterboxed and stretched,
        scores a diver at 3 m under 0.03, the same diver in a square tile of the frame's height
        0.8-0.9 (no letterbox bars, the stretch read from the tile). Tiles: ``SQUARE_TILES`` squares of
        the shorter side, spread evenly along the longer one. ``local``: each tile's lightness is first
        equalised locally (``_local_contrast``): a grey diver in green murky water at 3.4 m, seen in profile,
        scores 0.05-0.18 stretched and 0.8-0.94 so (issue 14 session 73, ``variant_44_17``).
        """
        h, w = image.shape[:2]
        side = min(h, w)
        if h == w:
            return None
        best: Detection | None = None
        for start in np.linspace(0, max(h, w) - side, SQUARE_TILES).round().astype(int):
            x0, y0 = (int(start), 0) if w > h else (0, int(start))
            tile = np.ascontiguousarray(image[y0:y0 + side, x0:x0 + side])
            det = self.detect(_local_contrast(tile, bgr) if local else tile, bgr, contrast=True)
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
        """Run the landmark model in ``roi`` and return its landmarks (whatever the pose flag).

        ``contrast``: the stretch to apply; without one, ``crop_stretch`` stretches the crop to its own levels.
        """
        to_image = crop_matrix(roi, LANDMARK_SIZE)
        crop = warp(image, to_image, LANDMARK_SIZE, cv2.BORDER_REPLICATE)
        levels = _crop_levels(crop) if contrast is None and self.crop_stretch else contrast
        self.landmark_calls += 1
        raw, flag, heat = self._landmarker.run(["Identity", "Identity_1", "Identity_3"],
                                               {"input_1": _to_unit_rgb(crop, bgr, levels)})
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
            roi: where to look (tracking); None runs the detector first (with contrast-stretched
                retries when it finds nothing and ``contrast_retry`` is on: the whole image, its square
                tiles, then with ``local_retry`` the tiles locally equalised).
            contrast: stretch to apply in ``roi`` (from a previous frame's result).
        """
        detected = roi is None
        if roi is None:
            det = self.detect(image, bgr)
            if det is None and self.contrast_retry:
                det = (self.detect(image, bgr, contrast=True) or self.detect_in_squares(image, bgr)
                       or (self.detect_in_squares(image, bgr, local=True) if self.local_retry else None))
            if det is None:
                return None
            roi, contrast = det.roi(), det.contrast
        if roi.size_px < 1.0:
            return None
        found = self.landmarks(image, roi, bgr, contrast, detected)
        return found if found.pose_flag >= self.min_pose_flag else None
