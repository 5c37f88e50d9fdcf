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
from .joint_stereo import _grey, match_point, score_at
from .triangulation import normalize_q, triangulate

__all__ = ["Blobs", "BlobFinder", "object_disparity", "unexplained", "wedge_offset"]


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
``KNOWN_GROW_SHARE`` of the hull's width is presumed that object's own (its features may cover part of
it only); ``BlobFinder.max_beside`` of them, those nearest the wedge's axis, are matched all the same
when room is left, and kept only when plainly at another depth (a small thing just beside a placard:
issue 11 sessions 20-21, the undetectable family's scene 500 #11)."""

BESIDE_TRIES_PER_SLOT = 6
"""Up to this many spots beside objects are matched per ``BlobFinder.max_beside`` slot, nearest the wedge's
axis first, until the slots are filled by spots that pass: a slot goes to a spot plainly off its object's
depth, not to the first one tried (issue 11 session 23: the undetectable family's scene 900 #6, a 7 px
target 57 px beside a placard 3 m in front of it, lost both slots to the placard's own rim spots, nearer
the axis, in every noisy draw, and the selector chose the placard beside the pointed one). A spot whose
patch already matches at its object's own disparity (``_on_object``) is that object's texture: it is set
aside before the row search and costs no try (issue 11 session 28: the undetectable family's scene 1300
#12, a 11 px target beside a 96 px placard 1.9 m in front of it, ranked past 12 rim spots of another
placard, all at their placard's depth, in 7 of 8 draws)."""

BESIDE_SCORE_MARGIN = 0.3
BESIDE_DEPTH_SPREAD_PX = 1
"""A spot beside an object is its own thing only when its best row match lies off the object's disparity
plane extrapolated to it (``object_disparity``, widened by ``BESIDE_DEPTH_SPREAD_PX`` plus twice the
fit's rms) and beats the best score there by ``BESIDE_SCORE_MARGIN`` (normalised cross-correlation): a
placard's edge matched on a repeat of itself is sharp, but scores nearly as well at the placard's depth
(issue 11 session 21: two of the bench's frames, spots on a slanted placard's rim)."""


class BlobFinder:
    """Finds and matches compact spots of contrast inside a corridor wedge (rectified pixels).

    Args:
        inner_sigma_px, outer_sigma_px: the difference of Gaussians' two scales at full size (a spot
            of about 2-6 inner sigmas across responds most).
        min_contrast_sigmas: a spot's response must exceed this many robust noise sigmas of the wedge.
        min_contrast: and this many grey levels.
        edge_ratio: largest accepted ratio of the response's principal curvatures (an edge's is large). At
            SIFT's 10, a ~14 px placard with a numeral (ratio ~8; issue 11 session 28, the undetectable family's
            scene 1300 #18) is found, but two truth-pose missions changed (variant_9_05 and 9_19, seed 2: an
            earlier decision, then the target lost in the servo): kept at 6.
        max_blobs: the strongest this many are matched.
        max_beside: at most this many of them may lie just beside a recognised object (``KNOWN_GROW_PX``).
        beside_max_sigma_px: such a spot is kept only when its row match is this sharp (pixels).
        min_score: the right-image match's lowest normalised cross-correlation.
        min_depth_m, max_depth_m: the depths searched (the disparity span of the row search).
        scale: the image scale the spots are looked for at (their centres are full-size pixels).
    """

    def __init__(self, inner_sigma_px: float = 2.0, outer_sigma_px: float = 5.0, min_contrast_sigmas: float = 6.0,
                 min_contrast: float = 2.5, edge_ratio: float = 6.0, max_blobs: int = 12, min_score: float = 0.7,
                 min_depth_m: float = 1.0, max_depth_m: float = 12.0, scale: float = 0.5, max_beside: int = 2,
                 beside_max_sigma_px: float = 1.0) -> None:
        self.scale = scale
        self.inner_sigma_px, self.outer_sigma_px = inner_sigma_px, outer_sigma_px
        self.min_contrast_sigmas, self.min_contrast = min_contrast_sigmas, min_contrast
        self.edge_ratio, self.max_blobs, self.min_score = edge_ratio, max_blobs, min_score
        self.min_depth_m, self.max_depth_m = min_depth_m, max_depth_m
        self.max_beside, self.beside_max_sigma_px = max_beside, beside_max_sigma_px

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

    def spots(self, responses: np.ndarray, known: list[np.ndarray] = (), poly: np.ndarray | None = None
              ) -> tuple[np.ndarray, list[tuple[int, ...]]]:
        """Return (M, 2) spot centres of ``responses`` outside the known objects, and the objects each lies beside.

        ``known``: each recognised object's feature pixels; spots inside their hull are that object's own
        texture and are skipped. Spots just outside it (grown by ``KNOWN_GROW_PX`` or
        ``KNOWN_GROW_SHARE`` of its width) are presumed its texture too: the strongest spots apart from
        every object come first (at most ``max_blobs``, no owners), then, while room is left, every one
        beside one (owners: indices into ``known``), nearest the wedge ``poly``'s axis first (``find``
        tries ``BESIDE_TRIES_PER_SLOT`` per slot of them and keeps at most ``max_beside``). Pixels are left
        rectified.
        """
        hulls = [(j, cv2.convexHull(np.asarray(px, np.float32).reshape(-1, 1, 2))) for j, px in enumerate(known)
                 if len(px)]
        grow = [max(KNOWN_GROW_PX, KNOWN_GROW_SHARE * float(np.ptp(h.reshape(-1, 2), axis=0).max())) for _, h in hulls]
        apart: list[tuple[float, float]] = []
        beside: list[tuple[float, float, tuple[int, ...]]] = []
        taken: list[tuple[float, float]] = []
        for x, y, _ in responses:  # neighbouring pieces overlap by their margins: one spot once
            if any((x - a) ** 2 + (y - b) ** 2 <= 9.0 for a, b in taken):
                continue
            inside = [cv2.pointPolygonTest(h, (float(x), float(y)), True) for _, h in hulls]
            if any(d >= 0.0 for d in inside):
                continue
            owners = tuple(j for d, g, (j, _) in zip(inside, grow, hulls) if d > -g)
            taken.append((float(x), float(y)))
            if owners:
                beside.append((float(x), float(y), owners))
                continue
            apart.append((float(x), float(y)))
            if len(apart) >= self.max_blobs:
                break
        far = np.array(apart, float).reshape(-1, 2)
        room = self._beside_slots(len(far))
        if room <= 0 or not beside:
            return far, [()] * len(far)
        near_px = np.array([q[:2] for q in beside], float)
        order = np.argsort(wedge_offset(poly, near_px), kind="stable") if poly is not None else np.arange(len(beside))
        return np.vstack([far, near_px[order]]), [()] * len(far) + [beside[k][2] for k in order]

    def _beside_slots(self, n_apart: int) -> int:
        """Return how many spots beside objects may be kept next to ``n_apart`` spots apart from every object."""
        return min(self.max_beside, self.max_blobs - n_apart)

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
             known: list[np.ndarray] = (), responses: np.ndarray | None = None,
             known_xyz: list[np.ndarray] = ()) -> Blobs:
        """Return the wedge's spots (outside the ``known`` objects' pixels) matched in the right image, 3D in metres.

        ``responses``: ``responses(left_rect, poly)`` when already computed. ``known_xyz``: the known
        objects' 3D points (metres); a spot beside one is kept only when its match is sharp
        (``beside_max_sigma_px``) and, where the object's points are given, plainly off its disparity
        plane (``_apart_from``); else it is taken for the object's texture. One that matches at an
        object's own disparity is set aside before its row search, and costs none of the
        ``BESIDE_TRIES_PER_SLOT`` tries per slot.
        """
        if poly is None:
            return Blobs.empty()
        spots, owners = self.spots(self.responses(left_rect, poly) if responses is None else responses, known, poly)
        if len(spots) == 0:
            return Blobs.empty()
        fb = rig.focal_px * rig.baseline_m
        d_lo, d_hi = fb / self.max_depth_m, fb / self.min_depth_m
        half = int(max(4, round(2.0 * self.inner_sigma_px + 2)))
        keep, disp, sigma = [], [], []
        room = self._beside_slots(sum(1 for near in owners if not near))
        tries = room * BESIDE_TRIES_PER_SLOT
        for (x, y), near in zip(spots, owners):
            if near and (room <= 0 or tries <= 0):
                break   # the spots beside objects come last: their slots are filled, or their tries spent
            xi, yi = int(round(x)), int(round(y))
            at = [_on_object(left_rect, right_rect, xi, yi, half, rig, known[j], known_xyz[j])
                  for j in near if j < len(known_xyz)]
            if any(a is not None and a[2] is not None and a[2] >= self.min_score for a in at):
                continue  # its patch matches at the object's own disparity: that object's texture, no try spent
            tries -= bool(near)
            m = match_point(left_rect, right_rect, xi, yi, d_lo, d_hi, rig.disparity_sign, half, self.min_score, 1.5)
            if m is None or (near and m[1] > self.beside_max_sigma_px):
                continue
            if any(not _apart_from(m, a) for a in at):
                continue
            room -= bool(near)
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


def object_disparity(px: np.ndarray, xyz_m: np.ndarray, at_px: np.ndarray, fb: float) -> tuple[float, float] | None:
    """Return an object's disparity extrapolated to ``at_px`` and its fit's rms (pixels), or None without points.

    A recognised object's features lie on a surface that is near enough a plane over a placard, and a
    plane's disparity is affine in the rectified pixel: fitted over the features (their median with
    fewer than four, or when they lie on a line), then read off beside them.
    """
    ok = np.all(np.isfinite(xyz_m), axis=1) & (xyz_m[:, 2] > 0)
    if not ok.any():
        return None
    px, d = px[ok], fb / xyz_m[ok, 2]
    if len(d) >= 4:
        a = np.c_[px - px.mean(axis=0), np.ones(len(d))]
        if np.linalg.matrix_rank(a, tol=1.0) == 3:
            coef = np.linalg.lstsq(a, d, rcond=None)[0]
            rms = float(np.sqrt(np.mean((a @ coef - d) ** 2)))
            return float(np.r_[at_px - px.mean(axis=0), 1.0] @ coef), rms
    return float(np.median(d)), float(np.std(d))


def _on_object(left_rect: np.ndarray, right_rect: np.ndarray, x: int, y: int, half: int, rig: StereoRig,
               object_px: np.ndarray, object_xyz_m: np.ndarray) -> tuple[float, int, float | None] | None:
    """Return (the object's disparity at the spot, its spread, the patch's best NCC there) in pixels, or None.

    None when the object has no 3D points; the score is None when the patch or its span falls off the image.
    """
    fit = object_disparity(np.asarray(object_px, float), np.asarray(object_xyz_m, float), np.array([x, y], float),
                           rig.focal_px * rig.baseline_m)
    if fit is None:
        return None
    d_obj, rms = fit
    spread = int(np.ceil(BESIDE_DEPTH_SPREAD_PX + 2.0 * rms))
    return d_obj, spread, score_at(left_rect, right_rect, x, y, d_obj, rig.disparity_sign, half, spread)


def _apart_from(match: tuple[float, float, float], on_object: tuple[float, int, float | None] | None) -> bool:
    """Return whether a spot beside an object is its own thing (not the object's texture), pixels.

    ``match``: the spot's row match (disparity, sigma, score); ``on_object``: ``_on_object``'s reading.
    Its own thing: its best row match lies clearly off the object's disparity extrapolated to it, and the
    patch scores clearly worse there (a placard's edge matched on a repeat of itself is sharp too). When the
    object's disparity puts the patch off the right image (no score there), it cannot be shown apart and stays
    the object's: its true match is out of sight, so any match in sight is another patch's (issue 11 session 71:
    variant_43_06 from pixels, placard 2's edge 104 px from the left border at 106 px disparity, matched at 60
    and 10 px to points 0.8 and 10 m behind it, took half the pointed placard's probability in every frame).
    """
    if on_object is None:
        return True
    d_obj, spread, at = on_object
    if abs(match[0] - d_obj) <= spread + 1:
        return False
    return at is not None and match[2] - at >= BESIDE_SCORE_MARGIN


def wedge_offset(poly: np.ndarray, px: np.ndarray) -> np.ndarray:
    """Return each pixel's distance from the wedge's axis as a share of the wedge's half width there (0: on it).

    ``poly``: ``corridor_polygon``'s (4, 2) wedge, near side first (start + n, end + n, end - n, start - n).
    """
    start, end = 0.5 * (poly[0] + poly[3]), 0.5 * (poly[1] + poly[2])
    length = float(np.linalg.norm(end - start))
    u = (end - start) / max(length, 1e-9)
    n = np.array([-u[1], u[0]])
    rel = px - start
    along = np.clip(rel @ u, 0.0, length)
    near, far = 0.5 * float(np.linalg.norm(poly[0] - poly[3])), 0.5 * float(np.linalg.norm(poly[1] - poly[2]))
    return np.abs(rel @ n) / (near + (far - near) * along / max(length, 1e-9))


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

