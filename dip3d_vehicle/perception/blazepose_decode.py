"""BlazePose detector post-processing as MediaPipe does it: SSD anchors, decoding, weighted NMS.

Constants are those of MediaPipe's ``pose_detection_cpu.pbtxt`` (SsdAnchorsCalculator,
TensorsToDetectionsCalculator, NonMaxSuppressionCalculator with the WEIGHTED algorithm).
Coordinates here are normalised to the detector's 224x224 letterboxed input.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

__all__ = ["DETECTOR_SIZE", "RawDetection", "ssd_anchors", "decode", "weighted_nms"]

DETECTOR_SIZE = 224
"""Side of the detector's square input tensor, pixels."""

_STRIDES = (8, 16, 32, 32, 32)
_ANCHORS_PER_LAYER = 2          # aspect ratio 1.0 plus the interpolated scale
_SCORE_CLIP = 100.0             # score_clipping_thresh
_NMS_IOU = 0.3                  # min_suppression_threshold (intersection over union)
_NUM_KEYPOINTS = 4


@dataclass(frozen=True)
class RawDetection:
    """One merged detection in normalised letterbox coordinates (0..1 over the 224 tensor).

    Attributes:
        score: probability of the best box of the group.
        box: (4,) xmin, ymin, xmax, ymax.
        keypoints: (4, 2) x, y; 0 = hip centre, 1 = point giving body scale and rotation.
    """

    score: float
    box: np.ndarray
    keypoints: np.ndarray


@lru_cache(maxsize=None)
def ssd_anchors(size: int = DETECTOR_SIZE) -> np.ndarray:
    """Return the (2254, 2) anchor centres (x, y), normalised, in MediaPipe's order."""
    out = []
    i = 0
    while i < len(_STRIDES):
        j = i
        while j < len(_STRIDES) and _STRIDES[j] == _STRIDES[i]:
            j += 1                     # layers of equal stride share one grid
        cells = int(np.ceil(size / _STRIDES[i]))
        centres = (np.arange(cells) + 0.5) / cells
        xx, yy = np.meshgrid(centres, centres)
        grid = np.stack([xx.ravel(), yy.ravel()], 1)
        out.append(np.repeat(grid, _ANCHORS_PER_LAYER * (j - i), axis=0))
        i = j
    anchors = np.concatenate(out).astype(np.float64)
    anchors.setflags(write=False)
    return anchors


def decode(regressors: np.ndarray, logits: np.ndarray, min_score: float
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Decode raw detector outputs into (scores, boxes, keypoints) of anchors scoring >= min_score.

    Args:
        regressors: (2254, 12) raw box + keypoint offsets, pixels of the 224 tensor.
        logits: (2254,) raw score logits.
        min_score: minimum probability kept (MediaPipe: 0.5).

    Returns:
        scores (N,), boxes (N, 4) xmin, ymin, xmax, ymax and keypoints (N, 4, 2), normalised.
    """
    logits = np.clip(np.asarray(logits, np.float64), -_SCORE_CLIP, _SCORE_CLIP)
    scores = 1.0 / (1.0 + np.exp(-logits))
    keep = np.flatnonzero(scores >= min_score)
    anchors = ssd_anchors()[keep]
    raw = np.asarray(regressors, np.float64)[keep] / DETECTOR_SIZE
    centre = raw[:, 0:2] + anchors                 # reverse_output_order: x, y, w, h
    half = raw[:, 2:4] / 2.0
    boxes = np.concatenate([centre - half, centre + half], axis=1)
    keypoints = raw[:, 4:4 + 2 * _NUM_KEYPOINTS].reshape(-1, _NUM_KEYPOINTS, 2) + anchors[:, None, :]
    return scores[keep], boxes, keypoints


def _iou(boxes: np.ndarray, box: np.ndarray) -> np.ndarray:
    """Return the intersection over union of each row of ``boxes`` with ``box`` (0 if no union)."""
    inter_w = np.clip(np.minimum(boxes[:, 2], box[2]) - np.maximum(boxes[:, 0], box[0]), 0, None)
    inter_h = np.clip(np.minimum(boxes[:, 3], box[3]) - np.maximum(boxes[:, 1], box[1]), 0, None)
    inter = inter_w * inter_h
    union = ((boxes[:, 2] - boxes[:, 0]) * (boxes[:, 3] - boxes[:, 1])
             + (box[2] - box[0]) * (box[3] - box[1]) - inter)
    return np.where(union > 0, inter / np.where(union > 0, union, 1.0), 0.0)


def weighted_nms(scores: np.ndarray, boxes: np.ndarray, keypoints: np.ndarray,
                 max_detections: int = 1) -> list[RawDetection]:
    """Merge overlapping detections by score-weighted averaging (MediaPipe's WEIGHTED NMS).

    The best remaining box takes every box overlapping it with IoU > 0.3; box and keypoints
    become their score-weighted mean, the score stays the best one's. Best first.
    """
    order = np.argsort(-scores, kind="stable")
    out: list[RawDetection] = []
    while order.size and len(out) < max_detections:
        best = order[0]
        group = order[(_iou(boxes[order], boxes[best]) > _NMS_IOU) | (order == best)]
        weights = scores[group] / scores[group].sum()
        out.append(RawDetection(float(scores[best]), weights @ boxes[group],
                                np.tensordot(weights, keypoints[group], axes=1)))
        order = np.setdiff1d(order, group, assume_unique=True)
        order = order[np.argsort(-scores[order], kind="stable")]
    return out
