"""Unrecognised things along the pointing corridor: small compact blobs no candidate object explains.

A placard of a few centimetres (a few to ~20 pixels) gives the feature detectors nothing to group
into an object, yet it is plainly visible as a compact spot of contrast against the water. When
the arm points at such a spot, "the diver points at something the vehicle cannot recognise" is
what the frame says, and it must weigh against an object the arm only reaches through the
uncertain tilt of the arm (issue 11: a decoy 15-20 deg off the arm, on its image line, chosen at
0.6-0.8 while the pointed 4 cm placard lay 5 deg off it, unseen by the selector).

Here: a difference of Gaussians over the corridor's wedge (left rectified image, at half
resolution), its local extrema above ``min_contrast_sigmas`` times the wedge's own robust noise level and
``min_contrast`` grey levels, edge-like responses rejected by the Hessian's eigenvalue ratio (as
SIFT does), the strongest ``max_blobs`` kept; each matched along its rectified row in the right
image (normalised cross-correlation with a left-right check, ``joint_stereo.match_point``) to a
3D point. The selector never chooses such a point: its probability is part of "nothing detected".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import cv2
import numpy as np

from .calibration import StereoRig
from .corridor import _clip_box, _pieces, _polygon_mask
from .joint_stereo import _grey, match_point
from .triangulation import normalize_q, triangulate

__all__ = ["Blobs", "BlobFinder", "unexplained"]


@dataclass(frozen=True)
class Blobs:
    """Unrecognised compact spots: left rectified pixels (M, 2), 3D points (M, 3, metres), depth sigma (M,, metres)."""

    left_px: np.ndarray
    xyz_m: np.ndarray
    depth_sigma_m: np.ndarray

    @staticmethod
    def empty() -> "Blobs":
        """Return no blobs."""
        return Blobs(np.zeros((0, 2)), np.zeros((0, 3)), np.zeros(0))

    def __len__(self) -> int:
        return len(self.left_px)

    def subset(self, keep: np.ndarray) -> "Blobs":
        """Return the blobs where ``keep`` is True."""
        return Blobs(self.left_px[keep], self.xyz_m[keep], self.depth_sigma_m[keep])


KNOWN_GROW_PX = 15.0
KNOWN_GROW_SHARE = 0.5
"""A spot nearer a recognised object's features' hull than the larger of ``KNOWN_GROW_PX`` pixels and
``KNOWN_GROW_SHARE`` of the hull's width is that object's own (its features may cover part of it only)."""


class BlobFinder:
    """Finds and matches compact spots of contrast inside a corridor wedge (rectified pixels).

    Args:
        inner_sigma_px, outer_sigma_px: the difference of Gaussians' two scales at full size (a spot
            of about 2-6 inner sigmas across responds most).
        min_contrast_sigmas: a spot's response must exceed this many robust noise sigmas of the wedge.
        min_contrast: and this many grey levels.
        edge_ratio: largest accepted ratio of the response's principal curvatures (an edge's is large).
        max_blobs: the strongest this many are matched.
        min_score: the right-image match's lowest normalised cross-correlation.
        min_depth_m, max_depth_m: the depths searched (the disparity span of the row search).
        scale: the image scale the spots are looked for at (their centres are full-size pixels).
    """

    def __init__(self, inner_sigma_px: float = 2.0, outer_sigma_px: float = 5.0, min_contrast_sigmas: float = 6.0,
                 min_contrast: float = 3.0, edge_ratio: float = 6.0, max_blobs: int = 12, min_score: float = 0.7,
                 min_depth_m: float = 1.0, max_depth_m: float = 12.0, scale: float = 0.5) -> None:
        self.scale = scale
        self.inner_sigma_px, self.outer_sigma_px = inner_sigma_px, outer_sigma_px
        self.min_contrast_sigmas, self.min_contrast = min_contrast_sigmas, min_contrast
        self.edge_ratio, self.max_blobs, self.min_score = edge_ratio, max_blobs, min_score
        self.min_depth_m, self.max_depth_m = min_depth_m, max_depth_m

    @classmethod
    def from_params(cls, params: Mapping) -> "BlobFinder":
        """Build from effective parameters (``corridor.blob_*``, the corridor's and the filters' depths)."""
        return cls(min_contrast_sigmas=params["corridor.blob_min_contrast_sigmas"],
                   min_contrast=params["corridor.blob_min_contrast"],
                   min_depth_m=params["corridor.min_depth_m"], max_depth_m=params["filters.max_depth_m"])

    def responses(self, left_rect: np.ndarray, poly: np.ndarray, tiles: int = 4) -> np.ndarray:
        """Return (N, 3) rows (x, y, response) of every compact spot in the wedge, strongest first (left px).

        The costly part (the difference of Gaussians), which needs only the left image and the wedge:
        it may run while the objects are fitted (``Perception``), the rest once they are known.
        """
        height, width = left_rect.shape[:2]
        found: list[tuple[float, float, float]] = []
        for piece in _pieces(poly, tiles):
            box = _clip_box(piece, width, height, margin_px=int(3 * self.outer_sigma_px))
            if box is not None:
                found.extend(self._spots_in(left_rect, piece, box))
        found.sort(key=lambda s: -s[2])
        return np.array(found, float).reshape(-1, 3)

    def spots(self, responses: np.ndarray, known: list[np.ndarray] = ()) -> np.ndarray:
        """Return (M, 2) spot centres of ``responses`` outside the known objects, at most ``max_blobs`` (left px).

        ``known``: each recognised object's feature pixels; spots inside their hull (grown by
        ``KNOWN_GROW_PX`` or ``KNOWN_GROW_SHARE`` of its width) are that object's own texture and are
        skipped before the strongest are kept.
        """
        hulls = [cv2.convexHull(np.asarray(px, np.float32).reshape(-1, 1, 2)) for px in known if len(px)]
        grow = [max(KNOWN_GROW_PX, KNOWN_GROW_SHARE * float(np.ptp(h.reshape(-1, 2), axis=0).max())) for h in hulls]
        out: list[tuple[float, float]] = []
        for x, y, _ in responses:  # neighbouring pieces overlap by their margins: one spot once
            if any((x - a) ** 2 + (y - b) ** 2 <= 9.0 for a, b in out):
                continue
            if any(cv2.pointPolygonTest(h, (float(x), float(y)), True) > -g for h, g in zip(hulls, grow)):
                continue
            out.append((float(x), float(y)))
            if len(out) >= self.max_blobs:
                break
        return np.array(out, float).reshape(-1, 2)

    def _spots_in(self, left_rect: np.ndarray, piece: np.ndarray, box: tuple[int, int, int, int]
                  ) -> list[tuple[float, float, float]]:
        """Return (x, y, response) of the spots of one wedge piece, left rectified pixels.

        Computed at ``scale`` of the image (the spots of interest are 8-20 px across at full size).
        """
        x0, y0, x1, y1 = box
        k = self.scale
        grey = cv2.resize(_grey(left_rect[y0:y1, x0:x1]), None, fx=k, fy=k, interpolation=cv2.INTER_AREA)
        dog = (cv2.GaussianBlur(grey, (0, 0), self.inner_sigma_px * k)
               - cv2.GaussianBlur(grey, (0, 0), self.outer_sigma_px * k))
        inside = cv2.resize(_polygon_mask(piece, box), (dog.shape[1], dog.shape[0]), interpolation=cv2.INTER_NEAREST) > 0
        inside[[0, -1], :] = False
        inside[:, [0, -1]] = False
        if int(inside.sum()) < 64:
            return []
        values = dog[inside]
        noise = 1.4826 * float(np.median(np.abs(values - np.median(values))))
        level = max(self.min_contrast_sigmas * noise, self.min_contrast)
        mag = np.abs(dog)
        ys, xs = np.nonzero((mag > level) & inside & (mag >= cv2.dilate(mag, np.ones((5, 5), np.uint8))))
        if len(ys) == 0:
            return []
        c = dog[ys, xs]
        dxx = dog[ys, xs + 1] + dog[ys, xs - 1] - 2 * c
        dyy = dog[ys + 1, xs] + dog[ys - 1, xs] - 2 * c
        dxy = 0.25 * (dog[ys + 1, xs + 1] - dog[ys + 1, xs - 1] - dog[ys - 1, xs + 1] + dog[ys - 1, xs - 1])
        det, tr = dxx * dyy - dxy * dxy, dxx + dyy
        ratio = (self.edge_ratio + 1) ** 2 / self.edge_ratio
        compact = (det > 0) & (tr * tr < ratio * det)  # not a saddle, not an edge
        return [(float(x / k + x0), float(y / k + y0), float(m)) for x, y, m in zip(xs[compact], ys[compact],
                                                                                    mag[ys, xs][compact])]

    def find(self, left_rect: np.ndarray, right_rect: np.ndarray, poly: np.ndarray | None, rig: StereoRig,
             known: list[np.ndarray] = (), responses: np.ndarray | None = None) -> Blobs:
        """Return the wedge's spots (outside the ``known`` objects' pixels) matched in the right image, 3D in metres.

        ``responses``: ``responses(left_rect, poly)`` when already computed.
        """
        if poly is None:
            return Blobs.empty()
        spots = self.spots(self.responses(left_rect, poly) if responses is None else responses, known)
        if len(spots) == 0:
            return Blobs.empty()
        fb = rig.focal_px * rig.baseline_m
        d_lo, d_hi = fb / self.max_depth_m, fb / self.min_depth_m
        half = int(max(4, round(2.0 * self.inner_sigma_px + 2)))
        keep, disp, sigma = [], [], []
        for x, y in spots:
            m = match_point(left_rect, right_rect, int(round(x)), int(round(y)), d_lo, d_hi, rig.disparity_sign,
                            half, self.min_score, 1.5)
            if m is not None:
                keep.append((x, y))
                disp.append(rig.disparity_sign * m[0])
                sigma.append(m[1])
        if not keep:
            return Blobs.empty()
        px, d = np.array(keep), np.array(disp)
        xyz = triangulate(normalize_q(rig.Q, rig.disparity_sign), px, d)
        ok = np.all(np.isfinite(xyz), axis=1) & (xyz[:, 2] > 0)
        depth_sigma = xyz[:, 2] ** 2 * np.maximum(np.array(sigma), 0.5) / fb
        return Blobs(px[ok], xyz[ok], depth_sigma[ok])


def unexplained(blobs: Blobs, objects_px: list[np.ndarray], objects_xyz_m: list[np.ndarray], joints_xyz_m: np.ndarray,
                object_gap_m: float = 0.25, object_gap_px: float = 12.0, body_gap_m: float = 0.4) -> Blobs:
    """Return the blobs no candidate object and no arm joint explains.

    ``partial(unexplained, blobs)`` is the selector's source of unrecognised things for spots found before.

    A blob within ``object_gap_m`` (3D) of an object's points or within ``object_gap_px`` (left image)
    of its features is part of that object (its printed spots, its corners); one within ``body_gap_m``
    of an arm joint is the diver's own hand or arm.
    """
    if len(blobs) == 0:
        return blobs
    keep = np.ones(len(blobs), bool)
    for px, pts in zip(objects_px, objects_xyz_m):
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if len(pts):
            d3 = np.min(np.linalg.norm(blobs.xyz_m[:, None, :] - pts[None], axis=2), axis=1)
            keep &= d3 > object_gap_m
        if len(px):
            d2 = np.min(np.linalg.norm(blobs.left_px[:, None, :] - px[None], axis=2), axis=1)
            keep &= d2 > object_gap_px
    if len(joints_xyz_m):
        dj = np.min(np.linalg.norm(blobs.xyz_m[:, None, :] - joints_xyz_m[None], axis=2), axis=1)
        keep &= dj > body_gap_m
    return _merged(blobs.subset(keep), object_gap_m)


def _merged(blobs: Blobs, radius_m: float) -> Blobs:
    """Return the blobs with those within ``radius_m`` (3D) of a stronger one folded into it: one thing, one blob."""
    if len(blobs) < 2:
        return blobs
    label = -np.ones(len(blobs), int)
    for i in range(len(blobs)):  # strongest first: each blob joins the first earlier one near it
        if label[i] < 0:
            near = (label < 0) & (np.linalg.norm(blobs.xyz_m - blobs.xyz_m[i], axis=1) <= radius_m)
            label[near] = i
    heads = np.unique(label)
    px = np.array([blobs.left_px[label == h].mean(axis=0) for h in heads])
    xyz = np.array([np.median(blobs.xyz_m[label == h], axis=0) for h in heads])
    sigma = np.array([blobs.depth_sigma_m[label == h].min() for h in heads])
    return Blobs(px, xyz, sigma)

