"""Candidates along the pointing corridor: where the diver points, look harder.

One SIFT pass over the half-resolution image loses small, faint, distant objects (about 50 px in
attenuated water). This stage looks only where the arm points: the image region around the
projected pointing ray (the 2D half-line from the wrist along the shoulder-to-wrist direction,
widened by the pointing spread), with local contrast normalisation (CLAHE) and a low SIFT
contrast threshold, in both rectified images, matched along the same rows. Its matches join the
ordinary candidates (those already found nearby are not added twice).
"""

from __future__ import annotations

import math
import time
from typing import Mapping

import cv2
import numpy as np
from scipy.spatial import cKDTree

from .calibration import StereoRig
from .candidates import hand_extent_px, match_row_band
from .threads import shared_pool
from .values import ArmKeypoints, Candidates

__all__ = ["CorridorDetector", "corridor_polygon", "merge_candidates", "zoom_boxes"]


def corridor_polygon(arm: ArmKeypoints, width: int, height: int, half_angle_rad: float,
                     start_px: float, min_half_width_px: float) -> np.ndarray | None:
    """Return the corridor (a wedge from the wrist to the image border) as a (4, 2) polygon, left px.

    The wedge starts ``start_px`` beyond the wrist along the shoulder-to-wrist direction, is at
    least ``min_half_width_px`` wide on each side there, and opens by ``half_angle_rad`` each side.
    None when the arm has no direction in the image.
    """
    s, w = arm.joint("shoulder"), arm.joint("wrist")
    axis = w - s
    norm = float(np.linalg.norm(axis))
    if norm < 1.0:
        return None
    u = axis / norm
    n = np.array([-u[1], u[0]])
    reach = float(np.hypot(width, height))
    start = w + start_px * u
    end = w + reach * u
    near = min_half_width_px
    far = near + reach * math.tan(half_angle_rad)
    return np.array([start + near * n, end + far * n, end - far * n, start - near * n])


def merge_candidates(base: Candidates, extra: Candidates, radius_px: float = 3.0, neighbourhood_px: float = 25.0,
                     disparity_tol_px: float = 2.0) -> Candidates:
    """Return ``base`` plus the ``extra`` candidates that are new and consistent with it (left px).

    An extra candidate within ``radius_px`` of a base one is the same feature (not added twice);
    one among base features (within ``neighbourhood_px``) whose disparity agrees with none of
    theirs (within ``disparity_tol_px`` or 10 %) is a false match of the low-threshold pass, e.g.
    across an occlusion boundary, and is dropped: the corridor adds objects, not outliers.
    """
    if len(extra) == 0:
        return base
    if len(base):
        tree = cKDTree(base.left_px)
        dist, _ = tree.query(extra.left_px, k=1)
        keep = dist > radius_px
        disp_base, disp_extra = base.disparity_px, extra.disparity_px
        for i, near in enumerate(tree.query_ball_point(extra.left_px, neighbourhood_px)):
            if keep[i] and near:
                gap = np.abs(disp_base[near] - disp_extra[i])
                keep[i] = bool(np.any(gap <= np.maximum(disparity_tol_px, 0.1 * np.abs(disp_base[near]))))
        extra = extra.subset(keep)
    if len(extra) == 0:
        return base
    return base.stacked(extra)


class CorridorDetector:
    """SIFT with CLAHE and a low contrast threshold inside the pointing corridor of both images."""

    name = "corridor"

    def __init__(self, half_angle_rad: float = 0.2, start_px: float = 40.0, min_half_width_px: float = 40.0,
                 image_scale: float = 0.5, contrast_threshold: float = 0.01, clahe_clip: float = 3.0,
                 lowe_ratio: float = 0.6, row_tolerance_px: float = 1.5, min_disparity_px: float = 0.5,
                 min_depth_m: float = 1.0, max_area_px: float = 300_000.0, tiles: int = 4, zoom_boxes: int = 0,
                 zoom_scale: float = 1.0, object_features: int = 3, object_radius_m: float = 0.15) -> None:
        self.half_angle_rad, self.start_px, self.min_half_width_px = half_angle_rad, start_px, min_half_width_px
        self.zoom_boxes, self.zoom_scale = int(zoom_boxes), zoom_scale
        self.object_features, self.object_radius_m = int(object_features), object_radius_m
        self.image_scale, self.lowe_ratio = image_scale, lowe_ratio
        self.row_tolerance_px, self.min_disparity_px, self.min_depth_m = row_tolerance_px, min_disparity_px, min_depth_m
        self.max_area_px, self.tiles = max_area_px, tiles
        # one CLAHE and one SIFT per image and per use (0/1: the corridor, 2/3: the tracker's box): the two
        # images are scanned concurrently and neither object is thread-safe
        self._clahes = tuple(cv2.createCLAHE(clipLimit=clahe_clip, tileGridSize=(8, 8)) for _ in range(4))
        self._sifts = tuple(cv2.SIFT_create(contrastThreshold=contrast_threshold) for _ in range(4))
        self.last_polygon: np.ndarray | None = None
        self.last_timings_ms: dict[str, float] = {}
        self.concurrent = True  # the right image in the shared "sift" pool (False: in the calling thread)

    @classmethod
    def from_params(cls, params: Mapping) -> "CorridorDetector":
        """Build the detector from effective parameters (``corridor.*``)."""
        return cls(params["corridor.half_angle_rad"], params["candidates.mask_offset_px"],
                   params["corridor.min_half_width_px"], params["corridor.image_scale"],
                   params["corridor.sift_contrast_threshold"], params["corridor.clahe_clip"],
                   params["candidates.lowe_ratio"], params["candidates.row_tolerance_px"],
                   params["candidates.min_disparity_px"], params["corridor.min_depth_m"],
                   params["corridor.max_area_px"], zoom_boxes=params["corridor.zoom_boxes"],
                   zoom_scale=params["corridor.zoom_scale"], object_features=params["selection.min_object_features"],
                   object_radius_m=params["selection.object_radius_m"])

    def detect(self, left_rect: np.ndarray, right_rect: np.ndarray, arm: ArmKeypoints, rig: StereoRig) -> Candidates:
        """Return the matches found inside the corridor (rectified px), with SIFT descriptors.

        The wedge is cut into ``tiles`` pieces along its axis, each scanned in its own tight box
        (a diagonal wedge's bounding box would be several times its area); a piece's right-image
        box is the left one widened by the disparity range.
        """
        t0 = time.perf_counter()
        poly, boxes = self._wedge_boxes(arm, left_rect.shape, rig)
        if not boxes:
            return Candidates.empty()
        out = self._match_boxes(left_rect, right_rect, boxes, [_polygon_mask(poly, box) for box in boxes], rig, poly=poly)
        out = self._zoomed(left_rect, right_rect, out, poly, rig)
        self.last_timings_ms = {"corridor": (time.perf_counter() - t0) * 1e3}
        return out

    def _zoomed(self, left_rect: np.ndarray, right_rect: np.ndarray, found: Candidates, poly: np.ndarray,
                rig: StereoRig) -> Candidates:
        """Return ``found`` plus the matches of a closer look (``zoom_scale``) around its lone matches.

        A small, faint, distant object gives the wedge's scan one or two matches, too few for an
        object; a box around each such match (``zoom_boxes`` of them, nearest the wedge's axis first,
        ``ZOOM_HALF_M`` each side at the match's depth, inside the wedge) is scanned again at
        ``zoom_scale`` (coarser past ``ZOOM_MAX_AREA_PX``), its right box only within ``ZOOM_DEPTH_M`` of the
        match's depth.
        """
        if self.zoom_boxes <= 0 or len(found) == 0:
            return found
        height, width = left_rect.shape[:2]
        chosen = zoom_boxes(found, poly, rig.focal_px, rig.baseline_m, width, height, self.zoom_boxes,
                            self.object_features, self.object_radius_m)
        if not chosen:
            return found
        boxes = [box for box, _ in chosen]
        fb = rig.focal_px * rig.baseline_m
        right_boxes = [_zoom_right_box(box, d, fb, width, rig.disparity_sign) for box, d in chosen]
        scale = self._scale(boxes, self.zoom_scale, ZOOM_MAX_AREA_PX)
        masks = [_polygon_mask(poly, box) for box in boxes]
        zoom = self._match_boxes(left_rect, right_rect, boxes, masks, rig, scale=scale, right_masks=[None] * len(boxes),
                                 right_boxes=right_boxes)
        return merge_candidates(found, zoom)

    def detect_beyond(self, left_rect: np.ndarray, right_rect: np.ndarray, arm: ArmKeypoints, rig: StereoRig,
                      scanned: np.ndarray) -> Candidates:
        """Return the matches in the part of ``arm``'s corridor outside ``scanned`` (a wedge scanned before, left px).

        For a followed sequence whose arm moved: only the new part of the wedge is looked at, at the
        scale ``detect`` would scan the whole wedge at, each piece's box cut to that part. Features up
        to ``BEYOND_OVERLAP_PX`` inside the old wedge may be found again (the caller keeps one of each).
        """
        t0 = time.perf_counter()
        poly, boxes = self._wedge_boxes(arm, left_rect.shape, rig)
        if not boxes:
            return Candidates.empty()
        width = left_rect.shape[1]
        scale = self._scale(boxes)
        new_boxes, masks = [], []
        for box in boxes:
            cut = _beyond(poly, scanned, box)
            if cut is not None:
                new_boxes.append(cut[0])
                masks.append(cut[1])
        if not new_boxes:
            return Candidates.empty()
        sign, max_disp = rig.disparity_sign, rig.focal_px * rig.baseline_m / self.min_depth_m
        right_boxes = self._right_boxes(new_boxes, width, max_disp, sign)
        right_masks = [_swept_mask(m, b, rb, max_disp, sign) for m, b, rb in zip(masks, new_boxes, right_boxes)]
        out = self._match_boxes(left_rect, right_rect, new_boxes, masks, rig, scale=scale, right_masks=right_masks)
        self.last_timings_ms = {"corridor": (time.perf_counter() - t0) * 1e3}
        return out

    def _wedge_boxes(self, arm: ArmKeypoints, shape: tuple[int, ...], rig: StereoRig
                     ) -> tuple[np.ndarray | None, list[tuple[int, int, int, int]]]:
        """Return ``arm``'s wedge (kept as ``last_polygon``) and its pieces' boxes inside an image of ``shape``, px."""
        height, width = shape[:2]
        poly = self.wedge(arm, width, height, rig)
        self.last_polygon = poly
        if poly is None:
            return None, []
        return poly, [b for b in (_clip_box(piece, width, height) for piece in _pieces(poly, self.tiles)) if b is not None]

    def wedge(self, arm: ArmKeypoints, width: int, height: int, rig: StereoRig) -> np.ndarray | None:
        """Return the corridor's wedge for ``arm`` (``corridor_polygon``, starting beyond a neural pose's hand)."""
        start_px = max(self.start_px, hand_extent_px(arm, rig.baseline_m))
        return corridor_polygon(arm, width, height, self.half_angle_rad, start_px, self.min_half_width_px)

    def detect_box(self, left_rect: np.ndarray, right_rect: np.ndarray, box: tuple[int, int, int, int],
                   rig: StereoRig) -> Candidates:
        """Return the matches found with the corridor's settings inside one left-image box (x0, y0, x1, y1, px).

        The tracker searches here for an object the corridor found: its features carry CLAHE-normalised
        descriptors that the ordinary detector's would not match.
        """
        box = _in_image(box, left_rect.shape[1], left_rect.shape[0])
        if box is None:
            return Candidates.empty()
        return self._match_boxes(left_rect, right_rect, [box], [None], rig, first=2)

    def detect_zoom_box(self, left_rect: np.ndarray, right_rect: np.ndarray, box: tuple[int, int, int, int],
                        disparity_px: float, rig: StereoRig) -> Candidates:
        """Return the matches of a closer look (``zoom_scale``) inside one left-image box (x0, y0, x1, y1, px)
        around a point of disparity ``disparity_px``: its right box only within ``ZOOM_DEPTH_M`` of that depth.

        The tracker looks here where it predicts a far target: the search box's own scan is as coarse as
        its area makes it, and a small far placard gives it a few features or none.
        """
        width = left_rect.shape[1]
        left_box = _in_image(box, width, left_rect.shape[0])
        if left_box is None or disparity_px <= 0.0:
            return Candidates.empty()
        right_box = _zoom_right_box(left_box, disparity_px, rig.focal_px * rig.baseline_m, width, rig.disparity_sign)
        scale = self._scale([left_box], self.zoom_scale, ZOOM_MAX_AREA_PX)
        return self._match_boxes(left_rect, right_rect, [left_box], [None], rig, first=2, scale=scale,
                                 right_masks=[None], right_boxes=[right_box])

    def _scale(self, boxes: list, image_scale: float | None = None, max_area_px: float | None = None) -> float:
        """Return the scale boxes are scanned at: ``image_scale`` (the corridor's by default), coarser past
        ``max_area_px`` SIFT pixels (after its doubling; the corridor's cap by default)."""
        image_scale = self.image_scale if image_scale is None else image_scale
        max_area_px = self.max_area_px if max_area_px is None else max_area_px
        area = sum((x1 - x0) * (y1 - y0) for x0, y0, x1, y1 in boxes) * image_scale ** 2 * 4.0
        return image_scale * min(1.0, math.sqrt(max_area_px / max(area, 1.0)))

    @staticmethod
    def _right_boxes(boxes: list, width: int, max_disp: float, sign: int) -> list:
        """Return the right image's boxes: the left ones widened by the disparity range, px."""
        return [(int(max(0, x0 - max_disp)), y0, x1, y1) if sign > 0 else (x0, y0, int(min(width, x1 + max_disp)), y1)
                for x0, y0, x1, y1 in boxes]

    def _match_boxes(self, left_rect: np.ndarray, right_rect: np.ndarray, boxes: list, masks: list,
                     rig: StereoRig, first: int = 0, poly: np.ndarray | None = None, scale: float | None = None,
                     right_masks: list | None = None, right_boxes: list | None = None) -> Candidates:
        """Scan left boxes (with masks) and their right boxes widened by the disparity range; match along rows.

        ``first``: the left image's CLAHE / SIFT pair index (the right's is the next). ``poly``: the
        corridor's wedge (the right image is then scanned only where its matches can lie), or
        ``right_masks`` given. ``scale``: by default from the boxes' area (``_scale``). ``right_boxes``: by
        default the left ones widened by the disparity range.
        """
        width = left_rect.shape[1]
        max_disp = rig.focal_px * rig.baseline_m / self.min_depth_m
        sign = rig.disparity_sign
        scale = self._scale(boxes) if scale is None else scale
        if right_boxes is None:
            right_boxes = self._right_boxes(boxes, width, max_disp, sign)
        # right image: only where a left corridor feature's match can lie (the wedge swept over the
        # disparity range, widened): SIFT finds the same keypoints with a mask, and describes fewer
        if right_masks is None:
            right_masks = [None] * len(boxes)
        if poly is not None:
            swept = _swept_polygon(poly, -sign * max_disp)
            right_masks = [_polygon_mask(swept, box, grow_px=_RIGHT_MASK_GROW_PX) for box in right_boxes]
        if self.concurrent:
            right_job = shared_pool("sift", 2).submit(self._scan, right_rect, right_boxes, right_masks, scale, first + 1)
            pl, dl = self._scan(left_rect, boxes, masks, scale, first)
            pr, dr = right_job.result()
        else:
            pl, dl = self._scan(left_rect, boxes, masks, scale, first)
            pr, dr = self._scan(right_rect, right_boxes, right_masks, scale, first + 1)
        qi, ti = match_row_band(pl, dl, pr, dr, self.lowe_ratio, self.row_tolerance_px,
                                (self.min_disparity_px, max_disp), sign)
        if len(qi) == 0:
            return Candidates.empty()
        return Candidates(pl[qi], pr[ti], dl[qi], np.zeros(len(qi)))

    def _scan(self, image: np.ndarray, boxes: list, masks: list, scale: float, which: int
              ) -> tuple[np.ndarray, np.ndarray]:
        """Return the features of every box, duplicates from overlapping boxes removed."""
        pts, descs = [], []
        for box, mask in zip(boxes, masks):
            p, d = self._features(image, box, mask, scale, which)
            if len(p) and pts:
                prev = np.vstack(pts)
                dist, _ = cKDTree(prev).query(p, k=1)
                p, d = p[dist > 1.0], d[dist > 1.0]
            pts.append(p)
            descs.append(d)
        return np.vstack(pts), np.vstack(descs)

    def _features(self, image: np.ndarray, box: tuple[int, int, int, int], mask: np.ndarray | None,
                  scale: float, which: int) -> tuple[np.ndarray, np.ndarray]:
        """Return (points px, descriptors) of SIFT features on the CLAHE-normalised box (and mask)."""
        x0, y0, x1, y1 = box
        crop = image[y0:y1, x0:x1]
        gray = crop if crop.ndim == 2 else cv2.cvtColor(crop, cv2.COLOR_BGR2GRAY)
        if scale != 1.0:
            gray = cv2.resize(gray, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
            if mask is not None:
                mask = cv2.resize(mask, (gray.shape[1], gray.shape[0]), interpolation=cv2.INTER_NEAREST)
        if min(gray.shape[:2]) < 16:
            return np.zeros((0, 2)), np.zeros((0, 128), np.float32)
        kps, desc = self._sifts[which].detectAndCompute(self._clahes[which].apply(gray), mask)
        if not kps:
            return np.zeros((0, 2)), np.zeros((0, 128), np.float32)
        pts = np.array([k.pt for k in kps], np.float64)
        pts = (pts + 0.5) / scale - 0.5
        pts += [x0, y0]
        return pts, desc.astype(np.float32)


ZOOM_HALF_M = 0.3
"""Half side (metres, at the lone match's depth) of a zoom box: a placard up to 0.3 m wide, the match anywhere on it."""

ZOOM_MIN_DEPTH_M = 2.5
"""Only lone matches at least this deep (metres) get a zoom box: nearer objects are large enough for the scans
at their own scale."""

ZOOM_MAX_AREA_PX = 80_000.0
"""Cap on the pixels SIFT processes per image over all zoom boxes (after its internal doubling); past it they are
scanned coarser."""

ZOOM_DEPTH_M = 0.5
"""How far (metres) in depth from its lone match a zoom box's object may lie: the right box covers those disparities."""


def zoom_boxes(found: Candidates, poly: np.ndarray, focal_px: float, baseline_m: float, width: int, height: int,
               n_boxes: int, object_features: int = 3, object_radius_m: float = 0.15
               ) -> list[tuple[tuple[int, int, int, int], float]]:
    """Return up to ``n_boxes`` (left-image box (x0, y0, x1, y1), px; the lone match's disparity magnitude, px)
    around lone matches at least ``ZOOM_MIN_DEPTH_M`` deep, nearest the wedge's axis first (by angle from the wrist).

    A match is lone, too few for an object, with fewer than ``object_features`` matches (itself included) within
    ``object_radius_m`` (metres at its depth; the selector's ``min_object_features`` and ``object_radius_m``) at a
    disparity within 10 % (at least 2 px); a match inside a box already chosen gets none of its own.
    """
    disparity = np.abs(found.disparity_px)
    px_per_m = disparity / max(baseline_m, 1e-6)
    far = disparity <= focal_px * baseline_m / ZOOM_MIN_DEPTH_M
    tree = cKDTree(found.left_px)
    lone = []
    for i, near in enumerate(tree.query_ball_point(found.left_px, object_radius_m * px_per_m)):
        if not far[i]:
            continue
        same = np.abs(disparity[near] - disparity[i]) <= np.maximum(2.0, 0.1 * disparity[i])
        if int(np.count_nonzero(same)) < object_features:
            lone.append(i)
    if not lone:
        return []
    start = 0.5 * (poly[0] + poly[3])
    axis = 0.5 * (poly[1] + poly[2]) - start
    axis = axis / max(float(np.linalg.norm(axis)), 1e-9)
    rel = found.left_px[lone] - start
    off_axis = np.abs(rel[:, 0] * axis[1] - rel[:, 1] * axis[0]) / np.maximum(rel @ axis, 1.0)   # angle's tangent
    boxes: list[tuple[tuple[int, int, int, int], float]] = []
    for k in np.argsort(off_axis, kind="stable"):
        x, y = found.left_px[lone[k]]
        if any(b[0] <= x < b[2] and b[1] <= y < b[3] for b, _ in boxes):
            continue
        half = float(np.clip(ZOOM_HALF_M * px_per_m[lone[k]], 24.0, 160.0))
        box = _clip_box(np.array([[x - half, y - half], [x + half, y + half]]), width, height, margin_px=0)
        if box is not None:
            boxes.append((box, float(disparity[lone[k]])))
        if len(boxes) == n_boxes:
            break
    return boxes


def _zoom_right_box(box: tuple[int, int, int, int], disparity_px: float, focal_baseline_px_m: float, width: int,
                    sign: int) -> tuple[int, int, int, int]:
    """Return the right image's box for a zoom box: where a point within ``ZOOM_DEPTH_M`` of the lone match's depth
    can lie (plus the row match's margin), px."""
    depth = focal_baseline_px_m / max(disparity_px, 1e-6)
    d_hi = focal_baseline_px_m / max(depth - ZOOM_DEPTH_M, 0.1)
    d_lo = focal_baseline_px_m / (depth + ZOOM_DEPTH_M)
    x0, y0, x1, y1 = box
    margin = _RIGHT_MASK_GROW_PX
    if sign > 0:
        return int(max(0, x0 - d_hi - margin)), y0, int(min(width, x1 - d_lo + margin)), y1
    return int(max(0, x0 + d_lo - margin)), y0, int(min(width, x1 + d_hi + margin)), y1


def _pieces(poly: np.ndarray, n: int) -> list[np.ndarray]:
    """Return the wedge cut into ``n`` quadrilaterals along its axis (start edge to far edge)."""
    a0, a1, b1, b0 = poly  # start+, end+, end-, start-
    out = []
    for k in range(n):
        t0, t1 = k / n, (k + 1) / n
        out.append(np.array([a0 + (a1 - a0) * t0, a0 + (a1 - a0) * t1, b0 + (b1 - b0) * t1, b0 + (b1 - b0) * t0]))
    return out


_RIGHT_MASK_GROW_PX = 8
"""Margin of the right image's corridor mask beyond the swept wedge, pixels: more than the row
tolerance plus the left mask's rounding at the scan's scale (a nearest-neighbour resize of ~0.4)."""


def _polygon_mask(poly: np.ndarray, box: tuple[int, int, int, int], grow_px: int = 0) -> np.ndarray:
    """Return a uint8 mask of the convex polygon inside a box (255 inside), grown by ``grow_px``."""
    x0, y0, x1, y1 = box
    mask = np.zeros((y1 - y0, x1 - x0), np.uint8)
    cv2.fillConvexPoly(mask, np.round(poly - [x0, y0]).astype(np.int32), 255)
    if grow_px > 0:
        mask = cv2.dilate(mask, cv2.getStructuringElement(cv2.MORPH_RECT, (2 * grow_px + 1, 2 * grow_px + 1)))
    return mask


BEYOND_OVERLAP_PX = 6
"""``detect_beyond`` looks this far inside the old wedge too, so that no feature on its edge is missed."""
_BEYOND_MIN_PX = 64
"""A piece whose new part has fewer pixels than this is not scanned."""


def _beyond(poly: np.ndarray, scanned: np.ndarray, box: tuple[int, int, int, int]
            ) -> tuple[tuple[int, int, int, int], np.ndarray] | None:
    """Return (box cut to it, mask) of the part of ``poly`` outside ``scanned`` within ``box``, or None if tiny."""
    x0, y0, x1, y1 = box
    mask = _polygon_mask(poly, box)
    old = _polygon_mask(scanned, box)
    size = 2 * BEYOND_OVERLAP_PX + 1
    old = cv2.erode(old, cv2.getStructuringElement(cv2.MORPH_RECT, (size, size)), borderValue=255)
    mask[old > 0] = 0
    ys, xs = np.nonzero(mask)
    if len(xs) < _BEYOND_MIN_PX:
        return None
    margin = 12                                   # SIFT's border, as _clip_box
    cx0, cy0 = max(0, int(xs.min()) - margin), max(0, int(ys.min()) - margin)
    cx1, cy1 = min(x1 - x0, int(xs.max()) + margin + 1), min(y1 - y0, int(ys.max()) + margin + 1)
    return (x0 + cx0, y0 + cy0, x0 + cx1, y0 + cy1), np.ascontiguousarray(mask[cy0:cy1, cx0:cx1])


def _swept_mask(mask: np.ndarray, box: tuple[int, int, int, int], right_box: tuple[int, int, int, int],
                max_disp_px: float, sign: int) -> np.ndarray:
    """Return the right box's mask: where the matches of features inside the left ``mask`` can lie (widened)."""
    canvas = np.zeros((right_box[3] - right_box[1], right_box[2] - right_box[0]), np.uint8)
    dx = box[0] - right_box[0]
    canvas[:, dx:dx + mask.shape[1]] = mask
    reach = int(math.ceil(max_disp_px))
    kernel = np.ones((1, reach + 1), np.uint8)    # sign > 0: x_right = x_left - d, d in [0, reach]
    swept = cv2.dilate(canvas, kernel, anchor=(0 if sign > 0 else reach, 0))
    grow = 2 * _RIGHT_MASK_GROW_PX + 1
    return cv2.dilate(swept, cv2.getStructuringElement(cv2.MORPH_RECT, (grow, grow)))


def _swept_polygon(poly: np.ndarray, shift_x_px: float) -> np.ndarray:
    """Return the convex hull of a convex polygon and its copy moved by ``shift_x_px`` along the rows."""
    both = np.vstack([poly, poly + [shift_x_px, 0.0]]).astype(np.float32)
    return cv2.convexHull(both).reshape(-1, 2).astype(np.float64)


def _in_image(box: tuple[int, int, int, int], width: int, height: int) -> tuple[int, int, int, int] | None:
    """Return a box (x0, y0, x1, y1, px) clipped to the image, or None when less than 16 px remain either way."""
    x0, y0, x1, y1 = int(max(0, box[0])), int(max(0, box[1])), int(min(width, box[2])), int(min(height, box[3]))
    if x1 - x0 < 16 or y1 - y0 < 16:
        return None
    return x0, y0, x1, y1


def _clip_box(poly: np.ndarray, width: int, height: int, margin_px: int = 12) -> tuple[int, int, int, int] | None:
    """Return the polygon's bounding box (plus a margin for SIFT's border) clipped to the image, or None."""
    x0, y0 = np.floor(poly.min(axis=0)).astype(int) - margin_px
    x1, y1 = np.ceil(poly.max(axis=0)).astype(int) + margin_px
    x0, x1 = max(0, x0), min(width, x1)
    y0, y1 = max(0, y0), min(height, y1)
    if x1 - x0 < 8 or y1 - y0 < 8:
        return None
    return int(x0), int(y0), int(x1), int(y1)
