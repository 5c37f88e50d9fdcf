"""The arm joints' disparity by matching image patches along rectified rows.

BlazePose places a landmark independently in each image; on the simulated diver its left/right
x differ from the true disparity by 10-35 px at 2-3 m (issue 14), i.e. tens of centimetres of
depth, which turns the triangulated arm by tens of degrees. Here each joint's right-image position
is instead found by normalised cross-correlation: the left image's patch around the joint is
searched along the same rectified row of the right image, within ``reach_px`` of the pose
backend's own right-image estimate, with a sub-pixel parabola at the peak. A joint whose best
score stays below ``min_score`` keeps the backend's estimate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

__all__ = ["JOINT_FLOOR_FACTOR", "match_joint_disparity", "subpixel_peak",
           "joint_disparities", "JointDisparity", "reach_disparities",
           "ARM_REACH_M", "TORSO_DEPTH_M", "in_front_of_body", "match_point", "limb_excess_sigmas", "LIMB_SIGMAS",
           "limb_switches", "limb_spans_m", "unmatched_sigma_px", "head_disparity", "head_match", "head_stand_in",
           "on_background", "patch_half_px", "BACKGROUND_SIDE_M", "BACKGROUND_SAME_PX", "HEAD_SHOULDER_SIGMA_M",
           "matched_on_body"]


def _grey(patch: np.ndarray) -> np.ndarray:
    """Return a patch as float32 grey."""
    if patch.ndim == 3:
        patch = cv2.cvtColor(patch, cv2.COLOR_BGR2GRAY)
    return patch.astype(np.float32)


def subpixel_peak(scores: np.ndarray, k: int) -> float:
    """Return the parabola-refined position of peak ``k`` of a 1D score array."""
    if 0 < k < len(scores) - 1:
        a, b, c = scores[k - 1], scores[k], scores[k + 1]
        den = a - 2 * b + c
        if den < 0:
            return k + 0.5 * (a - c) / den
    return float(k)


def match_joint_disparity(left: np.ndarray, right: np.ndarray, left_xy: np.ndarray, right_xy: np.ndarray,
                          sign: int, half_px: int = 12, reach_px: float = 48.0,
                          min_score: float = 0.5) -> np.ndarray:
    """Return (N, 2) right-image joint positions matched from the left ones (rectified pixels).

    Args:
        left, right: rectified images.
        left_xy: (N, 2) joints in the left image.
        right_xy: (N, 2) the backend's estimates in the right image (the search is centred on them).
        sign: the rig's disparity sign (+1: the right image's content lies to the left).
        half_px: half side of the matched patch.
        reach_px: search +- this far around the backend's right x (disparity stays >= 0).
        min_score: lowest accepted normalised cross-correlation.
    """
    h, w = left.shape[:2]
    out = np.array(right_xy, dtype=np.float64, copy=True)
    for k, ((xl, yl), (xr, _)) in enumerate(zip(np.asarray(left_xy, float), np.asarray(right_xy, float))):
        x, y = int(round(xl)), int(round(yl))
        if not (half_px <= x < w - half_px and half_px <= y < h - half_px) or not math.isfinite(xr):
            continue
        lo, hi = xr - reach_px, xr + reach_px
        lo, hi = (lo, min(hi, xl)) if sign > 0 else (max(lo, xl), hi)  # disparity >= 0
        x0, x1 = int(math.floor(lo)) - half_px, int(math.ceil(hi)) + half_px + 1
        x0, x1 = max(0, x0), min(w, x1)
        if x1 - x0 < 2 * half_px + 3:
            continue
        template = _textured_patch(left, x, y, half_px, 1.0)
        if template is None:
            continue
        strip = _grey(right[y - half_px:y + half_px + 1, x0:x1])
        scores = cv2.matchTemplate(strip, template, cv2.TM_CCOEFF_NORMED)[0]
        best = int(np.argmax(scores))
        if scores[best] < min_score:
            continue
        out[k] = (x0 + half_px + subpixel_peak(scores, best) + (xl - x), yl)
    return out


ARM_REACH_M = 0.8
"""How far (depth, metres) an arm joint can lie in front of or behind the body's depth plane."""

JOINT_FLOOR_FACTOR = np.array([1.0, 2.5, 1.0])
"""Per joint (shoulder, elbow, wrist): the disparity sigma floor of ``stereo`` in units of
``blazepose.disparity_floor_px``. The elbow's landmark sits on the arm's edge and a level arm has
only row-parallel edges there: on the simulated diver its matched disparity erred by 2-3 px
(median) and 7-12 px (p90) against 0.5-1.5 / 1.3-2.9 px for the wrist (``sitl.arm_eval``, issue 14)."""

_FLAT_SCORE = 0.01
"""Disparities scoring within this of the best NCC are as good as the best (their span is the sigma; with
0.05 the wrist's sigma on the simulated diver was 3-10 times its error, issue 14)."""


@dataclass(frozen=True)
class JointDisparity:
    """Each joint's disparity x_left - x_right (pixels), its one-sigma error and whether it was matched.

    Attributes:
        disparity_px: (N,) disparities.
        sigma_px: (N,) one-sigma error: the half-span of the disparities whose score is within
            ``_FLAT_SCORE`` of the best (a flat or double peak gives a wide one: an arm held level
            has only row-parallel edges); for an unmatched joint the body's disparity with a
            quarter of the arm's reachable span.
        matched: (N,) True where the patch match passed its checks.
        score: (N,) the best normalised cross-correlation (NaN where none was computed).
    """

    disparity_px: np.ndarray
    sigma_px: np.ndarray
    matched: np.ndarray
    score: np.ndarray

    def floored_sigma_px(self, floor_px: float) -> np.ndarray:
        """Return each joint's sigma, at least ``floor_px`` times its ``JOINT_FLOOR_FACTOR`` (pixels)."""
        return np.maximum(self.sigma_px, floor_px * JOINT_FLOOR_FACTOR)


def reach_disparities(body_disparity_px: float, focal_baseline_px_m: float,
                      reach_m: float = ARM_REACH_M, min_depth_m: float = 0.3) -> tuple[float, float]:
    """Return the (smallest, largest) disparity magnitude of a point within ``reach_m`` of the body's depth."""
    depth = focal_baseline_px_m / max(abs(body_disparity_px), 1e-6)
    return focal_baseline_px_m / (depth + reach_m), focal_baseline_px_m / max(depth - reach_m, min_depth_m)


def unmatched_sigma_px(body_disparity_px: float, focal_baseline_px_m: float) -> float:
    """Return the disparity sigma of a joint placed at the body's disparity: a quarter of the arm's reach span, pixels."""
    d_lo, d_hi = reach_disparities(body_disparity_px, focal_baseline_px_m)
    return max(0.25 * (d_hi - d_lo), 0.5)


def _textured_patch(image: np.ndarray, x: int, y: int, half: int, min_std: float = 2.0) -> np.ndarray | None:
    """Return the grey patch of ``half`` pixels each side of (x, y), or None off the image or flatter than ``min_std``."""
    h, w = image.shape[:2]
    if not (half <= y < h - half and half <= x < w - half):
        return None
    patch = _grey(image[y - half:y + half + 1, x - half:x + half + 1])
    return patch if float(patch.std()) >= min_std else None


def _scores_along_row(template: np.ndarray, image: np.ndarray, y: int, x0: int, x1: int, half: int) -> np.ndarray:
    """Return NCC scores of ``template`` centred at columns x0..x1-1 of row ``y`` of ``image``."""
    strip = _grey(image[y - half:y + half + 1, x0 - half:x1 + half])
    return cv2.matchTemplate(strip, template, cv2.TM_CCOEFF_NORMED)[0]


def match_point(left: np.ndarray, right: np.ndarray, x: int, y: int, d_lo: float, d_hi: float, sign: int,
               half: int, min_score: float, lr_tolerance_px: float) -> tuple[float, float, float] | None:
    """Return (disparity magnitude, sigma, score) of one left pixel's match along its row, or None (pixels).

    The patch (``half`` pixels each side) is searched over disparities ``d_lo``..``d_hi``; the match counts
    when its score reaches ``min_score``, its peak is inside the span, and the right patch found back in
    the left image lands within ``lr_tolerance_px`` of x.
    """
    h, w = left.shape[:2]
    template = _textured_patch(left, x, y, half)
    if template is None:
        return None
    # right-image centres x - sign * d for d in [d_lo, d_hi]
    xa, xb = sorted((x - sign * int(math.ceil(d_hi)) - 1, x - sign * int(math.floor(d_lo)) + 1))
    xa, xb = max(xa, half), min(xb + 1, w - half)
    if xb - xa < 3:
        return None
    scores = _scores_along_row(template, right, y, xa, xb, half)
    k = int(np.argmax(scores))
    if scores[k] < min_score or k in (0, len(scores) - 1):
        return None  # too weak, or the best lies at the edge of the reachable span (outside it)
    xr = xa + subpixel_peak(scores, k)
    good = np.nonzero(scores >= scores[k] - _FLAT_SCORE)[0]
    sigma = max(0.5, 0.5 * float(good.max() - good.min()))
    # left-right check: the right patch found back in the left image near x
    back = _grey(right[y - half:y + half + 1, int(round(xr)) - half:int(round(xr)) + half + 1])
    if back.shape != template.shape or float(back.std()) < 2.0:
        return None
    span = int(math.ceil(lr_tolerance_px)) + 3
    la, lb = max(x - span, half), min(x + span + 1, w - half)
    back_scores = _scores_along_row(back, left, y, la, lb, half)
    kb = int(np.argmax(back_scores))
    if abs(la + kb - x) > lr_tolerance_px + 0.5:
        return None
    return float(sign * (x - xr)), sigma, float(scores[k])


def score_at(left: np.ndarray, right: np.ndarray, x: int, y: int, disparity_px: float, sign: int, half: int,
             spread_px: int = 1) -> float | None:
    """Return the best NCC of one left pixel's patch within ``spread_px`` of a given disparity magnitude (pixels).

    None when the patch or the right-image span falls off the image or the patch is flat.
    """
    xc = int(round(x - sign * disparity_px))
    xa, xb = xc - spread_px, xc + spread_px + 1
    template = _textured_patch(left, x, y, half)
    if template is None or xa < half or xb > left.shape[1] - half:
        return None
    return float(_scores_along_row(template, right, y, xa, xb, half).max())


MATCH_MIN_SCORE = 0.6
"""The least NCC score a joint's patch match counts with (``joint_disparities``, the wrist's background probes)."""

MATCH_LR_TOLERANCE_PX = 1.5
"""How far (pixels) the right patch found back in the left image may land from the joint for the match to count."""


def patch_half_px(body_disparity_px: float, baseline_m: float, patch_m: float) -> int:
    """Return the half side (pixels, 4-24) of a patch ``patch_m`` wide at the body's depth (disparity ``body_disparity_px``)."""
    return int(np.clip(round(0.5 * patch_m * abs(body_disparity_px) / baseline_m), 4, 24))


def joint_disparities(left: np.ndarray, right: np.ndarray, left_xy: np.ndarray, body_disparity_px: float,
                      sign: int, focal_px: float, baseline_m: float, patch_m: float = 0.12,
                      min_score: float = MATCH_MIN_SCORE, lr_tolerance_px: float = MATCH_LR_TOLERANCE_PX) -> JointDisparity:
    """Return the joints' disparities by matching each left joint's patch along its rectified row.

    The search covers the disparities of depths within ``ARM_REACH_M`` of the body's (from
    ``body_disparity_px``, x_left - x_right); the patch is about ``patch_m`` wide at the body's
    depth (9-49 px). A match counts when its score reaches ``min_score``, its peak is inside the
    searched span and the right patch found back in the left image lands within
    ``lr_tolerance_px`` of the joint. Otherwise the joint takes the body's disparity with a sigma
    of a quarter of the reachable span.

    Args:
        left, right: rectified images.
        left_xy: (N, 2) joints in the left image, pixels.
        body_disparity_px: the body's disparity x_left - x_right, pixels.
        sign: the rig's disparity sign (+1: the right image's content lies to the left).
        focal_px, baseline_m: the rectified rig's focal length (pixels) and baseline (metres).
    """
    d_lo, d_hi = reach_disparities(body_disparity_px, focal_px * baseline_m)
    half = patch_half_px(body_disparity_px, baseline_m, patch_m)
    n = len(left_xy)
    disp = np.full(n, float(body_disparity_px))
    sigma = np.full(n, unmatched_sigma_px(body_disparity_px, focal_px * baseline_m))
    matched = np.zeros(n, bool)
    score = np.full(n, np.nan)
    for k, (xl, yl) in enumerate(np.asarray(left_xy, float)):
        if not (math.isfinite(xl) and math.isfinite(yl)):
            continue
        found = match_point(left, right, int(round(xl)), int(round(yl)), d_lo, d_hi, sign, half, min_score,
                           lr_tolerance_px)
        if found is None:
            continue
        mag, sig, sc = found
        disp[k] = sign * mag
        sigma[k], matched[k], score[k] = sig, True, sc
    return JointDisparity(disp, sigma, matched, score)


TORSO_DEPTH_M = 0.15
"""How far (metres) a point matched on the body can lie from the body's depth (the chest's, back's and
head's surfaces around the body's plane)."""

FORESHORTENED = 0.7
"""An elbow / wrist seen nearer its shoulder than this share of its plausible distance
(``LIMB_PER_TORSO`` x the torso's image length) lies well out of the image plane."""

LIMB_PER_TORSO = (0.0, 0.5, 0.95)
"""Shortest plausible distance of shoulder, elbow and wrist from the shoulder joint, in units of the
torso's length (shoulders' to hips' midpoints, ~0.5 m for an adult: upper arm 0.28-0.33 m, shoulder to
wrist 0.55-0.6 m): the person's own scale in the image, whatever the stereo depth says."""


def _hull(points_px: np.ndarray) -> np.ndarray:
    """Return the convex hull of image points as OpenCV wants it, pixels."""
    return cv2.convexHull(np.asarray(points_px, np.float32).reshape(-1, 1, 2))


def _inside(point: np.ndarray, hull: np.ndarray, margin_px: float = 0.0) -> bool:
    """True when a pixel lies inside a convex hull (``_hull``) or within ``margin_px`` of it, pixels."""
    return cv2.pointPolygonTest(hull, (float(point[0]), float(point[1])), True) > -margin_px


def _on_body_px(body_px: float, focal_baseline_px_m: float) -> float:
    """Return how far (disparity, pixels) a point matched on the body can lie from the body's ``body_px``."""
    return reach_disparities(body_px, focal_baseline_px_m, TORSO_DEPTH_M, min_depth_m=0.1)[1] - body_px


def in_front_of_body(found: JointDisparity, left_xy: np.ndarray, body_px: np.ndarray, torso_px: float,
                     body_disparity_px: float, focal_px: float, baseline_m: float, patch_m: float = 0.12) -> JointDisparity:
    """Return ``found`` with every elbow / wrist seen over the body and matched at the body's depth put in front of it.

    When the arm points at the camera its elbow and wrist are seen in front of the body: their patch
    then holds more of the chest or the head behind them than of the limb, and the match lands on
    the body with a narrow, confident peak. From 4.5-5 m (far_diver, BlazePose) the wrist, seen over
    the head, was matched at the body's disparity (1.5 px sigma) 3-4 px (0.6-0.8 m) behind the fist
    in 17 of 38 frames, which turned the arm away from the camera (80-136 deg of error; issue 14,
    session 18). Such a joint hides the body, so it lies in front of it, by up to ``ARM_REACH_M``:
    its disparity becomes that of the middle of that span and its sigma half the span's (never
    narrower than its own), and it counts as unmatched. A joint is such when it is

    - seen over the body: its left pixel inside the hull of ``body_px`` (the head's, shoulders' and
      hips' landmarks) or within half its patch (``patch_m`` wide) of it;
    - foreshortened: nearer its shoulder than ``FORESHORTENED`` of its limb's plausible length,
      scaled by the torso's image length ``torso_px`` (so out of the image plane);
    - matched within ``TORSO_DEPTH_M`` of the body's depth.

    The shoulder (row 0) is the body's own and is left as it is.
    """
    fb = focal_px * baseline_m
    sign = 1.0 if body_disparity_px >= 0 else -1.0
    body = abs(body_disparity_px)
    tol = _on_body_px(body, fb)
    front = reach_disparities(body, fb)[1]
    middle = reach_disparities(body, fb, 0.5 * ARM_REACH_M)[1]
    margin = 0.5 * patch_m * body / baseline_m          # half the patch at the body's depth, pixels
    disp, sigma, matched = found.disparity_px.copy(), found.sigma_px.copy(), found.matched.copy()
    xy = np.asarray(left_xy, float)
    hull = None
    for k in range(1, len(xy)):
        short = float(np.linalg.norm(xy[k] - xy[0])) < FORESHORTENED * LIMB_PER_TORSO[k] * torso_px
        if not (matched[k] and short and abs(abs(disp[k]) - body) <= tol):
            continue
        hull = _hull(body_px) if hull is None else hull
        if _inside(xy[k], hull, margin):
            disp[k], sigma[k], matched[k] = sign * middle, max(sigma[k], 0.5 * (front - body)), False
    return JointDisparity(disp, sigma, matched, found.score.copy())


BACKGROUND_SIDE_M = 0.11
"""Where the wrist's background is probed: this far (metres at the body's depth) to both sides of the forearm, at
the wrist, clear of the forearm (the probe, ``JOINT_PATCH_M`` wide, spans 0.05-0.17 m from the forearm's axis).
Not past the hand: a probe there holds the pointing finger, at the wrist's depth (on session 18's seed-10
variants it set aside 28 of 530 right wrists, against 5 for the sides alone)."""

BACKGROUND_SAME_PX = 1.0
"""A background probe matched within this (disparity, pixels) of the wrist's match matches at the same depth."""


def _background_explains(left: np.ndarray, right: np.ndarray, left_xy: np.ndarray, k: int, found: JointDisparity,
                         sign: int, d_span: tuple[float, float], half: int, px_per_m: float) -> bool:
    """True when the background to either side of joint ``k`` matches at its disparity at least as well as it does (pixels)."""
    along = left_xy[k] - left_xy[k - 1]
    norm = float(np.linalg.norm(along))
    if not norm >= 1.0:             # the elbow on the wrist, or not seen (NaN): no forearm to look beside
        return False
    across = np.array([-along[1], along[0]]) / norm
    h, w = left.shape[:2]
    for side in (1.0, -1.0):
        x, y = (int(round(c)) for c in left_xy[k] + side * BACKGROUND_SIDE_M * px_per_m * across)
        if not (half <= x < w - half and half <= y < h - half):
            continue
        probe = match_point(left, right, x, y, d_span[0], d_span[1], sign, half, MATCH_MIN_SCORE,
                            MATCH_LR_TOLERANCE_PX)
        if (probe is not None and abs(probe[0] - abs(found.disparity_px[k])) <= BACKGROUND_SAME_PX
                and probe[2] >= found.score[k]):
            return True
    return False


def on_background(found: JointDisparity, left: np.ndarray, right: np.ndarray, left_xy: np.ndarray,
                  body_disparity_px: float, sign: int, focal_px: float, baseline_m: float,
                  patch_m: float = 0.12) -> JointDisparity:
    """Return ``found`` with a wrist whose match the background beside it explains as well set aside (unmatched).

    A wrist seen in front of a textured object: its patch (``patch_m`` wide at the body's depth) holds more of
    the object's edges than of the hand, and it matches the object, with a narrow, confident peak (issue 14
    session 31: ``variant_9_17`` seed 0, murky water, the hand over a placard 0.5 m behind it, the wrist 5-6 px
    too far at a 0.5 px sigma in every frame, the vehicle sent to that placard). Then the background to either
    side of the wrist (``BACKGROUND_SIDE_M`` across the forearm) matches at the same disparity (within
    ``BACKGROUND_SAME_PX``) at least as well: nothing in the match says it is the wrist, so the wrist takes the
    body's disparity with the unmatched sigma. Measured on BlazePose's wrists
    (``docs/issue14/session31/scripts/wrist_census.py``, frames whose joints lie within 25 px of the truth): of
    the matches more than 2.5 px off, 208 of 300 are set aside on the nine built-ins (seeds 0-9) and session 18's
    seed-9 variants (seeds 0-1), 14 of 34 on the seed-10 variants, never tuned on; of the rest, 2.7 % and 0.9 %.
    The same holds for a placard in front of the wrist, which a given (the simulator's truth) wrist does not hide
    behind: ``given_arm.match_arm`` probes too (issue 11 session 65, ``variant_35_07`` seed 2, the wrist matched
    0.5 m toward the camera on the placard's face, the vehicle sent to that placard).
    The elbow is not probed: beside it lies the torso, near its depth (the rule would set aside 15 % of its right
    matches, and 68 of 365 off).
    """
    k = len(left_xy) - 1
    if not found.matched[k]:
        return found
    fb = focal_px * baseline_m
    body = abs(body_disparity_px)
    half = patch_half_px(body, baseline_m, patch_m)
    if not _background_explains(left, right, np.asarray(left_xy, float), k, found, sign,
                                reach_disparities(body, fb), half, body / baseline_m):
        return found
    disp, sigma, matched = found.disparity_px.copy(), found.sigma_px.copy(), found.matched.copy()
    disp[k], sigma[k], matched[k] = body_disparity_px, unmatched_sigma_px(body, fb), False
    return JointDisparity(disp, sigma, matched, found.score.copy())


TORSO_LENGTH_M = 0.5
"""An adult's torso length (shoulders' to hips' midpoints), metres: the unit of ``LIMB_PER_TORSO``."""

HEAD_SHOULDER_SIGMA_M = 0.15
"""One-sigma depth distance (metres) between the head's matched surface and the pointing shoulder's joint:
half a shoulder width (0.19 m) times the torso's turn, with the face a few centimetres before the neck."""


HEAD_PATCHES_M = (0.12, 0.2)
"""Widths (metres at the body's depth) of the head's patch, tried in turn until one matches: a far diver's
head in murky water is a flat dark hood at 0.12 m, its outline against the water matches at 0.2 m (issue 11
session 24, the open-set families at 2 px, seed 500: of the far_diver draws whose shoulder patch is flat,
the head matched in 92 of 145 at 0.12 m, 130 at 0.12 then 0.2 m, the shoulder joint 0.13 m behind the
match in the median, |error| p90 0.16 m; the keypoints' own shoulder depth error there: median 0.35 m,
p90 0.90 m)."""


def head_disparity(head_px, left: np.ndarray, right: np.ndarray, body_px: float, sign: int,
                   focal_px: float, baseline_m: float) -> tuple[float, float] | None:
    """Return the head's matched disparity and its sigma as the shoulder's (pixels), or None.

    ``head_px``: the head's left-image point (the pose source's nose), or None. None also when no patch
    of ``HEAD_PATCHES_M`` matched. The head stands for the torso's depth: the shoulder's sigma is at
    least ``HEAD_SHOULDER_SIGMA_M``.
    """
    found = head_match(head_px, left, right, body_px, sign, focal_px, baseline_m)
    return None if found is None else head_stand_in(found, focal_px, baseline_m)


def head_stand_in(head: tuple[float, float], focal_px: float, baseline_m: float) -> tuple[float, float]:
    """Return the head's match (disparity, sigma, pixels) as the shoulder's: its sigma at least ``HEAD_SHOULDER_SIGMA_M``."""
    return head[0], max(head[1], head[0] ** 2 / (focal_px * baseline_m) * HEAD_SHOULDER_SIGMA_M)


def head_match(head_px, left: np.ndarray, right: np.ndarray, body_px: float, sign: int,
               focal_px: float, baseline_m: float) -> tuple[float, float] | None:
    """Return the head's own matched disparity and its sigma (pixels: the patch's surface), or None.

    The first of ``HEAD_PATCHES_M`` that matches; None without a head point or when none matched.
    """
    if head_px is None:
        return None
    for patch_m in HEAD_PATCHES_M:
        found = joint_disparities(left, right, np.array([head_px], float), body_px, sign, focal_px, baseline_m,
                                  patch_m=patch_m)
        if found.matched[0]:
            return float(found.disparity_px[0]), float(found.sigma_px[0])
    return None


def matched_on_body(left_xy: np.ndarray, disparity_px: np.ndarray, matched: np.ndarray, body_px: float,
                    focal_px: float, baseline_m: float) -> np.ndarray:
    """Return which elbow / wrist matches lie on the body behind a foreshortened limb (bool per joint).

    A joint nearer its shoulder in the image, along the arm (shoulder -> elbow -> wrist: a bent arm
    is not short), than ``FORESHORTENED`` of its limb's plausible length (``LIMB_PER_TORSO`` x
    ``TORSO_LENGTH_M`` at the body's depth, disparity ``body_px``) lies well out of the image
    plane, so it cannot be at the body's depth: a match within ``TORSO_DEPTH_M`` of
    it is the body seen behind the limb (far_diver at 4.7 m: the wrist's patch, mostly chest and
    head, matched 3 px behind the fist with a 0.5 px sigma; issue 11, session 21).
    """
    body = abs(body_px)
    px_per_m = body / baseline_m                      # image scale at the body's depth, pixels per metre
    tol = _on_body_px(body, focal_px * baseline_m)
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(left_xy, axis=0), axis=1))])
    out = np.zeros(len(left_xy), bool)
    for k in range(1, len(left_xy)):
        short = along[k] < FORESHORTENED * LIMB_PER_TORSO[k] * TORSO_LENGTH_M * px_per_m
        out[k] = bool(matched[k] and short and abs(abs(disparity_px[k]) - body) <= tol)
    return out


LIMB_SIGMAS = 3.0
"""A limb whose matched 3D length lies more than this many sigmas outside its plausible span is impossible."""

LIMB_SLACK_M = 0.02
"""Spread (metres) of a limb's length from where the keypoints sit on the joints, beyond the depths' own."""


def limb_excess_sigmas(left_px: np.ndarray, disparity_px: np.ndarray, sigma_px: np.ndarray, focal_px: float,
                       baseline_m: float, principal_px: tuple[float, float],
                       limbs_m: tuple[tuple[float, float], tuple[float, float]], slack_m: float = LIMB_SLACK_M
                       ) -> np.ndarray:
    """Return how many sigmas each limb's 3D length (upper arm, forearm) lies outside its span (0 inside).

    The joints (left pixels, disparities x_left - x_right with their sigmas, pixels) are placed at their
    stereo depths; a limb's length sigma is what its two joints' depth sigmas allow, and ``slack_m``.
    """
    fb = focal_px * baseline_m
    d = np.maximum(np.abs(np.asarray(disparity_px, float)), 1e-3)
    z, dz = fb / d, fb / d ** 2 * np.asarray(sigma_px, float)
    rays = np.c_[(left_px - np.asarray(principal_px)) / focal_px, np.ones(len(d))]
    out = np.zeros(2)
    for k, (lo, hi) in enumerate(limbs_m):
        a, b = rays[k] * z[k], rays[k + 1] * z[k + 1]
        length = float(np.linalg.norm(b - a))
        slope = [abs(float((a - b) @ rays[k])), abs(float((b - a) @ rays[k + 1]))]
        sigma = math.hypot(math.hypot(slope[0] * dz[k], slope[1] * dz[k + 1]) / max(length, 1e-6), slack_m)
        out[k] = max(lo - length, length - hi, 0.0) / sigma
    return out


def limb_switches(left_px: np.ndarray, disparity_px: np.ndarray, sigma_px: np.ndarray, other_px, other_sigma_px,
                  switchable: np.ndarray, is_match: np.ndarray, focal_px: float, baseline_m: float,
                  principal_px: tuple[float, float], limbs_m, slack_m: float = LIMB_SLACK_M) -> np.ndarray:
    """Return which elbow / wrist should take its other reading so that no limb is impossible (bool per joint).

    Each joint stands at ``disparity_px`` (sigma ``sigma_px``, pixels); a ``switchable`` elbow or wrist has a
    second reading, ``other_px`` (sigma ``other_sigma_px``): its patch match where it stands at the given
    keypoints' disparity, or the reverse, or the body's disparity for a pose model's match.

    A thin wrist seen in front of a textured object matches that object, not the wrist (a placard 0.3 m
    behind the wrist: issue 11 session 27, line_of_sight seed 900 scene 15, "nothing detected" at 0.8
    though the arm pointed 27 deg clear of every other placard). Such a match makes the forearm longer
    (or shorter) than any adult's by ``LIMB_SIGMAS`` and more (``limb_excess_sigmas``). Or the given
    keypoints' own disparity is the one far off (a 3-sigma draw of their noise) and its right match was
    set aside by the gross check. When some limb is impossible, the fewest switches that leave every limb
    plausible are made; among as few, those leaving the most joints at a patch match (``is_match``: whether a
    joint's reading where it stands is one; a switch turns it over), then the least excess. None when no
    switch helps. The shoulder never switches.
    """
    other = np.broadcast_to(np.asarray(other_px, float), switchable.shape)
    other_sigma = np.broadcast_to(np.asarray(other_sigma_px, float), switchable.shape)

    def excess(flip: tuple[int, ...]) -> np.ndarray:
        disp, sigma = np.array(disparity_px, float), np.array(sigma_px, float)
        disp[list(flip)], sigma[list(flip)] = other[list(flip)], other_sigma[list(flip)]
        return limb_excess_sigmas(left_px, disp, sigma, focal_px, baseline_m, principal_px, limbs_m, slack_m)

    out = np.zeros(switchable.shape, bool)
    if np.all(excess(()) <= LIMB_SIGMAS):
        return out
    match = np.asarray(is_match, bool)
    fine = []
    for flip in ((2,), (1,), (1, 2)):
        if not switchable[list(flip)].all():
            continue
        left = excess(flip)
        if np.all(left <= LIMB_SIGMAS):   # a switch turns a match into the other reading, or back
            matches = int(match.sum()) + len(flip) - 2 * int(match[list(flip)].sum())
            fine.append((len(flip), -matches, float(left.sum()), flip))
    if fine:
        out[list(min(fine)[-1])] = True
    return out


def limb_spans_m(params) -> tuple[tuple[float, float], tuple[float, float]] | None:
    """Return the plausible (shortest, longest) upper arm and forearm, metres, from ``selection.*``; None where not given."""
    keys = ("selection.upperarm_min_m", "selection.upperarm_max_m", "selection.forearm_min_m", "selection.forearm_max_m")
    if not all(k in params for k in keys):
        return None
    lo_u, hi_u, lo_f, hi_f = (float(params[k]) for k in keys)
    return (lo_u, hi_u), (lo_f, hi_f)
