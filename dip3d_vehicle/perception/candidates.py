"""Candidate objects: the CandidateDetector interface and the paper's SIFT detector.

The paper's detector masks away the diver (everything on the far side of the wrist), computes SIFT
in both rectified images, matches them with brute-force k-NN (k = 2) and Lowe's ratio test, and
keeps matches on the same rectified row with positive disparity. ``row_band`` matching gives the
same kind of matches without the quadratic cost: each left feature is compared only with right
features whose row is within the tolerance (epipolar constraint) and whose disparity is plausible.
"""

from __future__ import annotations

import time
from abc import ABC, abstractmethod
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import Mapping

import cv2
import numpy as np

from .calibration import StereoRig
from .threads import shared_pool
from .values import ArmKeypoints, Candidates

__all__ = ["CandidateDetector", "SiftDetector", "match_bruteforce", "match_row_band", "kept_columns"]

# A lone row-band neighbour (no second one for the ratio test) is accepted only if it is this close
# (SIFT descriptors are L2-normalised to 512; good matches are typically well under 200).
_LONE_MATCH_MAX_DIST = 180.0
_BAND_ROWS = 24.0
"""Height of the row blocks matched together, pixels (a speed trade-off only: results do not depend on it)."""

# Up to this many left x right feature pairs, row-band matching is one vectorised distance matrix.
_ONE_SHOT_PAIRS = 1_000_000

def _pool() -> ThreadPoolExecutor:
    """Return the shared pool for the left and right features (2 threads)."""
    return shared_pool("sift", 2)


class CandidateDetector(ABC):
    """Finds candidate object points matched across a rectified stereo pair."""

    name = "candidates"

    @abstractmethod
    def detect(self, left_rect: np.ndarray, right_rect: np.ndarray, arm: ArmKeypoints | None,
               rig: StereoRig) -> Candidates:
        """Return matched candidates in rectified pixels (the diver's side masked away)."""


def kept_columns(arm: ArmKeypoints | None, side: str, width: int, mask_side: str,
                 offset_px: float, hand_px: float = 0.0) -> tuple[int, int]:
    """Return the [x0, x1) column range kept for candidates in one image, pixels.

    ``mask_side``: "right" keeps x > wrist + offset (paper), "left" keeps x < wrist - offset,
    "pointing" picks the side the forearm points to in the left image. The offset is at least
    ``hand_px`` (``hand_extent_px``).
    """
    if arm is None:
        return 0, width
    wrist = arm.joint("wrist", side)
    if mask_side == "pointing":
        elbow = arm.joint("elbow", "left")
        mask_side = "right" if arm.joint("wrist", "left")[0] >= elbow[0] else "left"
    offset_px = max(offset_px, hand_px)
    if mask_side == "right":
        return int(np.clip(np.ceil(wrist[0] + offset_px), 0, width)), width
    return 0, int(np.clip(np.floor(wrist[0] - offset_px), 0, width))


HAND_LENGTH_M = 0.2
"""Wrist joint to fingertips of an adult hand, metres (with a glove)."""


def hand_extent_px(arm: ArmKeypoints | None, baseline_m: float) -> float:
    """Return how far (image x, pixels) the pointing hand reaches beyond the wrist, for a neural pose.

    A pose backend that reports the hand (``extra_left_px["hand"]``, BlazePose) places the wrist
    landmark on the visible wrist, often short of the joint (on the simulated diver by 10-60 px,
    issue 14): the hand's own features then fall inside the candidates' region and form an object
    a hand's length beyond the wrist. The extent is ``HAND_LENGTH_M`` at the wrist's depth
    (focal / depth = disparity / baseline) along the forearm's image direction. 0 without a hand.
    """
    if arm is None or "hand" not in (arm.extra_left_px or {}):
        return 0.0
    disparity = abs(float(arm.joint("wrist", "left")[0] - arm.joint("wrist", "right")[0]))
    forearm = arm.joint("wrist", "left") - arm.joint("elbow", "left")
    across = abs(float(forearm[0])) / max(float(np.linalg.norm(forearm)), 1e-6)
    return HAND_LENGTH_M * disparity / max(baseline_m, 1e-6) * across


def _ratio_keep(pairs, ratio: float) -> tuple[np.ndarray, np.ndarray]:
    """Apply Lowe's ratio test to cv2 knn results; return (query idx, train idx)."""
    q, t = [], []
    for m in pairs:
        if len(m) == 2 and m[0].distance < ratio * m[1].distance:
            q.append(m[0].queryIdx)
            t.append(m[0].trainIdx)
    return np.asarray(q, dtype=np.int64), np.asarray(t, dtype=np.int64)


def match_bruteforce(desc_l: np.ndarray, desc_r: np.ndarray, ratio: float) -> tuple[np.ndarray, np.ndarray]:
    """Brute-force 2-NN matching with Lowe's ratio test (the paper's); return index pairs."""
    if len(desc_l) == 0 or len(desc_r) < 2:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    pairs = cv2.BFMatcher(cv2.NORM_L2).knnMatch(desc_l, desc_r, k=2)
    return _ratio_keep(pairs, ratio)


def match_row_band(pts_l: np.ndarray, desc_l: np.ndarray, pts_r: np.ndarray, desc_r: np.ndarray,
                   ratio: float, row_tol_px: float, disp_range: tuple[float, float],
                   disparity_sign: int) -> tuple[np.ndarray, np.ndarray]:
    """2-NN matching restricted to the epipolar band: |y_l - y_r| <= tol and disparity in range.

    Args:
        pts_l, pts_r: (N, 2) / (M, 2) feature positions, rectified pixels.
        desc_l, desc_r: float32 descriptors.
        ratio: Lowe ratio among the candidates that satisfy the geometric constraint.
        row_tol_px: row tolerance, pixels.
        disp_range: (min, max) disparity magnitude, pixels.
        disparity_sign: +1 if x_l > x_r for points in front of the rig.
    Returns:
        (left indices, right indices) of accepted matches.
    """
    if len(pts_l) == 0 or len(pts_r) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    if len(pts_l) * len(pts_r) <= _ONE_SHOT_PAIRS:
        # Few features: one masked distance matrix (the same constraint as the bands, no Python loop).
        q, t = _band_matches(pts_l, desc_l, pts_r, desc_r, ratio, row_tol_px, disp_range, disparity_sign)
        return _unique_right(q, t)
    band = max(2.0 * row_tol_px, _BAND_ROWS)  # tall bands: few numpy calls; the exact row test is inside
    order_r = np.argsort(pts_r[:, 1], kind="stable")
    yr = pts_r[order_r, 1]
    keys_l = np.floor(pts_l[:, 1] / band).astype(np.int64)
    q_out, t_out = [], []
    for key in np.unique(keys_l):
        rows_l = np.nonzero(keys_l == key)[0]
        lo = np.searchsorted(yr, key * band - row_tol_px, "left")
        hi = np.searchsorted(yr, (key + 1) * band + row_tol_px, "right")
        if hi <= lo:
            continue
        cand = order_r[lo:hi]
        q, t = _band_matches(pts_l[rows_l], desc_l[rows_l], pts_r[cand], desc_r[cand], ratio,
                             row_tol_px, disp_range, disparity_sign)
        q_out.append(rows_l[q])
        t_out.append(cand[t])
    if not q_out:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    return _unique_right(np.concatenate(q_out), np.concatenate(t_out))


def _unique_right(q: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drop matches whose right feature was claimed by several left features (ambiguous).

    Edges that run along the image rows give several left features that all match one right
    feature at different disparities; none of them can be trusted.
    """
    _, inverse, counts = np.unique(t, return_inverse=True, return_counts=True)
    keep = counts[inverse] == 1
    return q[keep], t[keep]


def _band_matches(pl, dl, pr, dr, ratio, row_tol_px, disp_range, sign) -> tuple[np.ndarray, np.ndarray]:
    """Match one band of left features against right features allowed by geometry."""
    d2 = (np.sum(dl * dl, 1)[:, None] + np.sum(dr * dr, 1)[None, :] - 2.0 * dl @ dr.T)
    disp = sign * (pl[:, None, 0] - pr[None, :, 0])
    ok = (np.abs(pl[:, None, 1] - pr[None, :, 1]) <= row_tol_px) & (disp >= disp_range[0]) & (disp <= disp_range[1])
    d2 = np.where(ok, np.maximum(d2, 0.0), np.inf)
    if d2.shape[1] == 1:
        best = np.zeros(len(pl), np.int64)
        second = np.full(len(pl), np.inf)
    else:
        two = np.argpartition(d2, 1, axis=1)[:, :2]
        a, b = np.take_along_axis(d2, two, 1).T
        swap = b < a
        best = np.where(swap, two[:, 1], two[:, 0])
        second = np.where(swap, a, b)
    first = d2[np.arange(len(pl)), best]
    dist1, dist2 = np.sqrt(first), np.sqrt(second)
    keep = np.isfinite(dist1) & ((dist1 < ratio * dist2) | (~np.isfinite(dist2) & (dist1 < _LONE_MATCH_MAX_DIST)))
    return np.nonzero(keep)[0], best[keep]


@dataclass
class _Prefetch:
    """Features being computed ahead of ``detect`` (see ``SiftDetector.prefetch``)."""

    left: np.ndarray
    right: np.ndarray
    cols_l: tuple[int, int] | None          # None: only the right image's features started (``prefetch_right``)
    cols_r: tuple[int, int]
    jobs: tuple[Future | None, Future]


class SiftDetector(CandidateDetector):
    """The paper's detector: SIFT on the masked region, k-NN matching, ratio test, row filter."""

    name = "sift"

    def __init__(self, mask_side: str = "right", mask_offset_px: float = 40.0, matcher: str = "bruteforce",
                 lowe_ratio: float = 0.3, row_tolerance_px: float = 1.5, min_disparity_px: float = 0.5,
                 max_features: int = 0, image_scale: float = 1.0, contrast_threshold: float = 0.04,
                 min_depth_m: float = 0.2) -> None:
        self.mask_side, self.mask_offset_px = mask_side, mask_offset_px
        self.matcher, self.lowe_ratio = matcher, lowe_ratio
        self.row_tolerance_px, self.min_disparity_px = row_tolerance_px, min_disparity_px
        self.image_scale, self.min_depth_m = image_scale, min_depth_m
        # One SIFT object per image: the two images are processed concurrently (cv2 releases the GIL).
        self._sifts = tuple(cv2.SIFT_create(nfeatures=max_features, contrastThreshold=contrast_threshold)
                            for _ in range(2))
        self._sift = self._sifts[0]
        self.concurrent = True
        self.last_counts: dict[str, int] = {}
        self.last_timings_ms: dict[str, float] = {}
        self._prefetched: _Prefetch | None = None

    @classmethod
    def from_params(cls, params: Mapping) -> "SiftDetector":
        """Build the detector from effective parameters (``candidates.*``)."""
        return cls(params["candidates.mask_side"], params["candidates.mask_offset_px"],
                   params["candidates.matcher"], params["candidates.lowe_ratio"],
                   params["candidates.row_tolerance_px"], params["candidates.min_disparity_px"],
                   params["candidates.max_features"], params["candidates.image_scale"],
                   params["candidates.sift_contrast_threshold"], max(params["filters.min_depth_m"], 0.2))

    def features(self, image: np.ndarray, cols: tuple[int, int], which: int = 0
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Return (points px, descriptors, sizes px) of SIFT features in a column range.

        ``which`` (0 or 1) picks the SIFT instance, so that two images may run in parallel threads.
        """
        x0, x1 = cols
        if x1 - x0 < 8:
            return np.zeros((0, 2)), np.zeros((0, 128), np.float32), np.zeros(0)
        crop = image[:, x0:x1]
        gray = crop if crop.ndim == 2 else cv2.cvtColor(crop, cv2.COLOR_BGR2GRAY)
        s = self.image_scale
        if s != 1.0:
            gray = cv2.resize(gray, None, fx=s, fy=s, interpolation=cv2.INTER_AREA)
        kps, desc = self._sifts[which].detectAndCompute(gray, None)
        if not kps:
            return np.zeros((0, 2)), np.zeros((0, 128), np.float32), np.zeros(0)
        pts = np.array([k.pt for k in kps], np.float64)
        pts = (pts + 0.5) / s - 0.5 if s != 1.0 else pts
        pts[:, 0] += x0
        sizes = np.array([k.size for k in kps], np.float64) / s
        return pts, desc.astype(np.float32), sizes

    def prefetch(self, left_rect: np.ndarray, right_rect: np.ndarray, arm_hint: ArmKeypoints,
                 margin_px: float = 80.0) -> None:
        """Start computing this pair's features in the background, in columns predicted by ``arm_hint``.

        For frame sequences: the previous frame's arm (or, on a first frame, the pose's early arm)
        predicts the kept columns (widened by ``margin_px``), so the features are computed while
        the pose runs. ``detect`` on the same
        two arrays uses them when the real kept columns lie inside the predicted ones (features
        outside the real columns are dropped), and computes afresh otherwise.
        """
        pending = self._prefetched
        right_started = (pending is not None and pending.cols_l is None and pending.left is left_rect
                         and pending.right is right_rect)
        if not right_started:
            self.cancel_prefetch()
        width = left_rect.shape[1]
        cols = []
        for side in ("left", "right"):
            x0, x1 = kept_columns(arm_hint, side, width, self.mask_side, self.mask_offset_px)
            cols.append((int(max(0, x0 - margin_px if x0 > 0 else 0)),
                         int(min(width, x1 + margin_px if x1 < width else width))))
        left_job = _pool().submit(self.features, left_rect, cols[0], 0)
        if right_started:
            self._prefetched = _Prefetch(left_rect, right_rect, cols[0], pending.cols_r, (left_job, pending.jobs[1]))
            return
        right_job = _pool().submit(self.features, right_rect, cols[1], 1)
        self._prefetched = _Prefetch(left_rect, right_rect, cols[0], cols[1], (left_job, right_job))

    def prefetch_right(self, left_rect: np.ndarray, right_rect: np.ndarray) -> None:
        """Start the right image's features over its whole width, before any arm is known (px).

        A sequence's first frame: while the pose runs on one core, the other computes the right
        features that any arm's kept columns will need; ``prefetch`` (from the pose's early arm) then
        adds the left image's in its exact columns.
        """
        self.cancel_prefetch()
        width = right_rect.shape[1]
        job = _pool().submit(self.features, right_rect, (0, width), 1)
        self._prefetched = _Prefetch(left_rect, right_rect, None, (0, width), (None, job))

    def cancel_prefetch(self) -> None:
        """Forget a prefetch (waits for its jobs: they hold the SIFT objects)."""
        pending, self._prefetched = self._prefetched, None
        if pending is not None:
            for job in pending.jobs:
                if job is not None:
                    job.result()

    def _take_prefetch(self, left_rect: np.ndarray, right_rect: np.ndarray, cols_l: tuple[int, int],
                       cols_r: tuple[int, int]):
        """Return prefetched ((pl, dl, sl), (pr, dr, sr)) cut to the kept columns, or None."""
        pending, self._prefetched = self._prefetched, None
        if pending is None:
            return None
        results = [None if job is None else job.result() for job in pending.jobs]
        if pending.left is not left_rect or pending.right is not right_rect:
            return None
        if pending.cols_l is None:     # only the right image's were started (no early arm came): the left's now
            pending.cols_l, results[0] = cols_l, self.features(left_rect, cols_l, 0)
        out = []
        for (x0, x1), (px0, px1), (pts, desc, sizes) in zip((cols_l, cols_r), (pending.cols_l, pending.cols_r), results):
            if x1 - x0 < 8:
                out.append((np.zeros((0, 2)), np.zeros((0, 128), np.float32), np.zeros(0)))
                continue
            if x0 < px0 or x1 > px1:
                return None
            keep = (pts[:, 0] >= x0) & (pts[:, 0] < x1) if len(pts) else np.zeros(0, bool)
            out.append((pts[keep], desc[keep], sizes[keep]))
        return out

    def detect(self, left_rect: np.ndarray, right_rect: np.ndarray, arm: ArmKeypoints | None,
               rig: StereoRig) -> Candidates:
        """Return matched candidates in rectified pixels.

        Timings of the last call are in ``last_timings_ms``: "features" (both images, concurrently
        unless ``concurrent`` is False; only the wait when they were prefetched) and "match"
        (matching and the row/disparity filter).
        """
        t0 = time.perf_counter()
        width = left_rect.shape[1]
        hand = hand_extent_px(arm, rig.baseline_m)
        cols_l = kept_columns(arm, "left", width, self.mask_side, self.mask_offset_px, hand)
        cols_r = kept_columns(arm, "right", width, self.mask_side, self.mask_offset_px, hand)
        ready = self._take_prefetch(left_rect, right_rect, cols_l, cols_r)
        if ready is not None:
            (pl, dl, sl), (pr, dr, _) = ready
        elif self.concurrent:
            right_job = _pool().submit(self.features, right_rect, cols_r, 1)
            pl, dl, sl = self.features(left_rect, cols_l, 0)
            pr, dr, _ = right_job.result()
        else:
            pl, dl, sl = self.features(left_rect, cols_l, 0)
            pr, dr, _ = self.features(right_rect, cols_r, 1)
        t1 = time.perf_counter()
        cands = self._match(pl, dl, sl, pr, dr, rig)
        self.last_counts["prefetched"] = int(ready is not None)
        self.last_timings_ms = {"features": (t1 - t0) * 1e3, "match": (time.perf_counter() - t1) * 1e3}
        return cands

    def match_features(self, left: tuple[np.ndarray, np.ndarray, np.ndarray],
                       right: tuple[np.ndarray, np.ndarray, np.ndarray], rig: StereoRig) -> Candidates:
        """Return matched candidates from two images' ``features`` (points, descriptors, sizes)."""
        (pl, dl, sl), (pr, dr, _) = left, right
        return self._match(pl, dl, sl, pr, dr, rig)

    def _match(self, pl: np.ndarray, dl: np.ndarray, sl: np.ndarray, pr: np.ndarray, dr: np.ndarray,
               rig: StereoRig) -> Candidates:
        """Match left and right features; keep same-row pairs with positive disparity."""
        sign = rig.disparity_sign
        max_disp = rig.focal_px * rig.baseline_m / self.min_depth_m
        if self.matcher == "row_band":
            qi, ti = match_row_band(pl, dl, pr, dr, self.lowe_ratio, self.row_tolerance_px,
                                    (self.min_disparity_px, max_disp), sign)
        else:
            qi, ti = match_bruteforce(dl, dr, self.lowe_ratio)
        self.last_counts = {"features_left": len(pl), "features_right": len(pr), "matches": len(qi)}
        if len(qi) == 0:
            return Candidates.empty()
        left, right = pl[qi], pr[ti]
        disp = sign * (left[:, 0] - right[:, 0])
        keep = (np.abs(left[:, 1] - right[:, 1]) <= self.row_tolerance_px) & (disp >= self.min_disparity_px)
        self.last_counts["kept"] = int(keep.sum())
        return Candidates(left[keep], right[keep], dl[qi][keep], sl[qi][keep])
