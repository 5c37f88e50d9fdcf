"""Candidates reused between frames: the matched features followed by optical flow, refreshed every K frames.

While the diver points, the vehicle holds station: the candidates' features barely move from one
frame to the next, yet the full candidate pass (SIFT on the kept half of both images, and the
pointing corridor's CLAHE + SIFT) costs two thirds of a frame's CPU. ``CandidateReuse`` keeps the
last full pass's matched pairs (main pass and corridor apart) and follows them into each new frame
with pyramidal Lucas-Kanade flow in both rectified images. A followed pair is kept only if both
eyes' flows converged, it still lies on one rectified row (``candidates.row_tolerance_px``) and its
disparity changed like its neighbours' (within ``candidates.reuse_max_disparity_change_px``: the
scene is rigid, so neighbouring features' disparities change alike however far the camera moved,
while a flow that slid along an edge in one eye does not); the arm is measured on
every frame, and each frame keeps the followed pairs inside ITS kept columns and corridor wedge.

A new full pass runs on one frame every ``candidates.reuse_frames`` (K) frames (one pass at a
time, on the greyscale images this module owns), spread over the next K - 1 frames in
``PASS_PIECES`` pieces (left features, right features, matching + corridor), each piece in a
background thread beside its frame's own work and waited for by the next frame, so that no frame
carries a whole pass and the result never depends on timing. On the K-th frame the pass is taken
and followed to that frame in one flow step, starting where the pairs followed meanwhile say the
scene has moved (``SceneMotion``: the camera may have moved tens of pixels in K frames): the
decided frames use features found at most 2K - 1 frames earlier. The frame is computed afresh,
exactly as without reuse, when there is nothing to follow (first frame, ``reset``), when fewer than ``candidates.reuse_min_tracked_fraction`` of the
pairs survive a flow step (the camera or the scene moved: a new scene, a moved object; pairs near
the image border or in the margin next to the diver do not count), when this frame's kept columns
reach beyond the scanned ones, and (the corridor alone) when less than
``candidates.reuse_min_corridor_cover`` of this frame's wedge lies in the scanned wedge: then only the
part of the new wedge outside the scanned one is scanned (``CorridorDetector.detect_beyond``), the
followed matches inside it kept, and a background pass in flight keeps that newer corridor.

Single frames (``perceive``, the scene-family checks) never reuse anything: their results are the
full pass's. A live sequence (``Perception(live=True)``: run, sitl, bench) may decide its first frame
on a quicker main pass (``candidates.reuse_start_image_scale``; the corridor as always): the full pass
then starts in the background on that frame and replaces it K frames later. An object that enters the view, or appears, is found by the next background pass.
"""

from __future__ import annotations

from concurrent.futures import Future
from dataclasses import dataclass
from typing import Iterator, Mapping

import cv2
import numpy as np
from scipy.spatial import cKDTree

from .calibration import StereoRig
from .candidates import SiftDetector, hand_extent_px, kept_columns
from .corridor import CorridorDetector
from .images import grey
from .threads import shared_pool
from .values import ArmKeypoints, Candidates

__all__ = ["CandidateReuse", "Views", "follow_pairs", "views_of", "inside_polygon", "polygon_cover", "Anchor",
           "SceneMotion"]

LK_WINDOW_PX = 21
"""Lucas-Kanade window side, pixels (OpenCV's default)."""
LK_LEVELS = 3
"""Pyramid levels above full resolution: converges for shifts up to ~8 x the half window (~80 px)."""
LK_MAX_RESIDUAL = 30.0
"""Largest mean absolute grey difference (0-255) over the window of a followed feature."""
EDGE_PX = 48
"""Pairs this close to the image border may leave the view in a flow step: their loss is not counted."""
COLUMN_SLACK_PX = 24
"""This frame's kept columns may reach this far beyond the scanned ones (the sliver next to the
hand is not looked at again before the next pass) before the frame is computed afresh."""
COLUMN_MARGIN_PX = 80.0
"""The background pass scans the kept columns widened by this toward the diver: a wrist that moves
less than this keeps this frame's columns inside the scanned ones."""

_CRITERIA = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 20, 0.03)


@dataclass(frozen=True)
class Views:
    """One rectified pair in grey (the reuse's own copies: a camera may reuse its buffers)."""

    left: np.ndarray
    right: np.ndarray


def views_of(left_rect: np.ndarray, right_rect: np.ndarray) -> Views:
    """Return the grey pair of a rectified frame."""
    return Views(grey(left_rect, copy=True), grey(right_rect, copy=True))  # kept across frames


def _flow(prev: np.ndarray, cur: np.ndarray, pts: np.ndarray, guess: np.ndarray | None = None
          ) -> tuple[np.ndarray, np.ndarray]:
    """Return (new points, converged mask) of ``pts`` followed from one grey image to the next.

    Both images are cut to the points' bounding box widened by the flow's reach (the pyramids
    OpenCV builds for every call cost in proportion to the area). ``guess``: where the points are
    expected in ``cur`` (the flow starts there), or None (where they were).
    """
    if len(pts) == 0:
        return np.zeros((0, 2)), np.zeros(0, bool)
    h, w = prev.shape[:2]
    reach = LK_WINDOW_PX * 2 ** LK_LEVELS
    span = pts if guess is None else np.vstack([pts, guess])
    x0, y0 = np.maximum(np.floor(span.min(axis=0)).astype(int) - reach, 0)
    x1, y1 = np.minimum(np.ceil(span.max(axis=0)).astype(int) + reach + 1, [w, h])
    p0 = np.ascontiguousarray(pts - [x0, y0], np.float32).reshape(-1, 1, 2)
    start = None if guess is None else np.ascontiguousarray(guess - [x0, y0], np.float32).reshape(-1, 1, 2)
    p1, status, err = cv2.calcOpticalFlowPyrLK(prev[y0:y1, x0:x1], cur[y0:y1, x0:x1], p0, start,
                                               winSize=(LK_WINDOW_PX, LK_WINDOW_PX), maxLevel=LK_LEVELS,
                                               criteria=_CRITERIA,
                                               flags=0 if guess is None else cv2.OPTFLOW_USE_INITIAL_FLOW)
    ok = (status.ravel() == 1) & (err.ravel() <= LK_MAX_RESIDUAL)
    return p1.reshape(-1, 2).astype(np.float64) + [x0, y0], ok


def follow_pairs(prev: Views, cur: Views, cands: Candidates, row_tolerance_px: float,
                 max_disparity_change_px: float, guess: tuple[np.ndarray, np.ndarray] | None = None
                 ) -> tuple[Candidates, np.ndarray]:
    """Return the matched pairs moved from ``prev`` to ``cur`` (every row) and which of them are still consistent.

    A pair survives when both flows converged, both points lie in the image, their rows agree within
    ``row_tolerance_px`` and its disparity change differs by at most ``max_disparity_change_px``
    from the median change of its ``NEIGHBOURS`` nearest pairs (``disparity_outliers``).
    Descriptors and sizes are carried over (they describe the same physical features).
    ``guess``: where the pairs are expected in ``cur`` (left px, right px; the flows start there), or None.
    """
    if len(cands) == 0:
        return cands, np.zeros(0, bool)
    guess_l, guess_r = (None, None) if guess is None else guess
    left, ok_l = _flow(prev.left, cur.left, cands.left_px, guess_l)
    right, ok_r = _flow(prev.right, cur.right, cands.right_px, guess_r)
    h, w = cur.left.shape[:2]
    inside = np.all((left >= 0) & (left <= [w - 1, h - 1]) & (right >= 0) & (right <= [w - 1, h - 1]), axis=1)
    same_row = np.abs(left[:, 1] - right[:, 1]) <= row_tolerance_px
    ok = ok_l & ok_r & inside & same_row
    change = (left[:, 0] - right[:, 0]) - cands.disparity_px
    keep = ok & ~disparity_outliers(cands.left_px, change, ok, max_disparity_change_px)
    return Candidates(left, right, cands.descriptors, cands.sizes_px), keep


NEIGHBOURS = 8
"""Pairs whose disparity change a followed pair's is compared with."""


def disparity_outliers(points_px: np.ndarray, change_px: np.ndarray, valid: np.ndarray, tolerance_px: float
                       ) -> np.ndarray:
    """Return which pairs' disparity change differs by more than ``tolerance_px`` from their neighbours' median.

    Neighbours: the ``NEIGHBOURS`` nearest valid pairs in the image (the pair itself excluded).
    With fewer valid pairs than that the median of all valid ones is used.
    """
    out = np.ones(len(points_px), bool)
    idx = np.nonzero(valid)[0]
    if len(idx) < 2:
        return out
    if len(idx) <= NEIGHBOURS:
        ref = np.full(len(points_px), np.median(change_px[idx]))
    else:
        _, nn = cKDTree(points_px[idx]).query(points_px, k=NEIGHBOURS + 1)
        near = change_px[idx][nn]                              # (N, k + 1): the pair itself is among them
        own = idx[nn] == np.arange(len(points_px))[:, None]
        near = np.where(own, np.nan, near)[:, :NEIGHBOURS + 1]
        ref = np.nanmedian(near, axis=1)
    out = ~(np.abs(change_px - ref) <= tolerance_px)
    return out


@dataclass(frozen=True)
class Anchor:
    """The followed main-pass pairs on the frame a background pass is computed on (rectified px)."""

    ids: np.ndarray
    left_px: np.ndarray
    right_px: np.ndarray


@dataclass(frozen=True)
class SceneMotion:
    """How pairs followed frame by frame moved since an earlier frame: the prediction for other points there.

    A pass is taken K frames after its own frame and followed to the new frame in one flow step;
    the camera may have moved tens of pixels by then (the flow then loses a fifth to a third of the
    pairs, and the frame is computed afresh). The pairs followed meanwhile, one frame at a time,
    tell how the scene moved: each of the pass's points is predicted to have moved as the median of
    its ``NEIGHBOURS`` nearest followed pairs (left image; the same pairs' right-image motion for the
    right point), and the flow starts there.
    """

    from_left_px: np.ndarray        # the followed pairs on the earlier frame, left image
    shift_left_px: np.ndarray       # their motion since, left image
    shift_right_px: np.ndarray      # and right image

    @classmethod
    def between(cls, anchor: "Anchor", ids: np.ndarray, left_px: np.ndarray, right_px: np.ndarray,
                min_pairs: int = NEIGHBOURS) -> "SceneMotion | None":
        """Return the motion of the anchor's pairs still followed (``ids`` at ``left_px`` / ``right_px``), or None if too few."""
        _, a, b = np.intersect1d(anchor.ids, ids, assume_unique=True, return_indices=True)
        if len(a) < min_pairs:
            return None
        return cls(anchor.left_px[a], left_px[b] - anchor.left_px[a], right_px[b] - anchor.right_px[a])

    def moved(self, left_px: np.ndarray, right_px: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return where pairs at ``left_px`` / ``right_px`` on the earlier frame are predicted now, pixels."""
        k = min(NEIGHBOURS, len(self.from_left_px))
        _, nn = cKDTree(self.from_left_px).query(left_px, k=k)
        nn = nn.reshape(len(left_px), k)
        return (left_px + np.median(self.shift_left_px[nn], axis=1),
                right_px + np.median(self.shift_right_px[nn], axis=1))


def inside_polygon(points_px: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Return which points lie inside (or on) a convex polygon."""
    if len(points_px) == 0:
        return np.zeros(0, bool)
    contour = np.asarray(poly, np.float32).reshape(-1, 1, 2)
    return np.array([cv2.pointPolygonTest(contour, (float(x), float(y)), False) >= 0 for x, y in points_px], bool)


def polygon_cover(poly: np.ndarray, scanned: np.ndarray, width: int, height: int) -> float:
    """Return the fraction of ``poly``'s area inside the image that also lies inside ``scanned`` (convex)."""
    frame = np.array([[0, 0], [width, 0], [width, height], [0, height]], np.float32)
    area, clipped = cv2.intersectConvexConvex(np.asarray(poly, np.float32), frame)
    if area <= 0 or clipped is None:
        return 1.0
    common, _ = cv2.intersectConvexConvex(clipped.reshape(-1, 2), np.asarray(scanned, np.float32))
    return float(max(common, 0.0) / area)


SAME_FEATURE_PX = 1.5
"""A corridor match found again this close to a followed one (left px) is the same feature."""


def _not_near(new: Candidates, old_px: np.ndarray) -> Candidates:
    """Return the ``new`` matches farther than ``SAME_FEATURE_PX`` from every point of ``old_px``."""
    if len(new) == 0 or len(old_px) == 0:
        return new
    dist, _ = cKDTree(old_px).query(new.left_px, k=1)
    return new.subset(dist > SAME_FEATURE_PX)


PASS_PIECES = 3
"""Pieces of a full pass (``CandidateReuse._full_pass``), spread over the K - 1 frames before it is taken."""


def _run_pieces(job: _Job, count: int) -> None:
    """Run up to ``count`` pieces of a job's pass (in the background thread, beside the frame's own work)."""
    for _ in range(count):
        if job.scan is not None:
            return
        job.scan = next(job.pieces)


def _finish(job: _Job) -> _Scan:
    """Return a job's scan, running the pieces it has left (none when it kept pace)."""
    while job.scan is None:
        job.scan = next(job.pieces)
    return job.scan


@dataclass
class _Scan:
    """A full candidate pass of one frame: main-pass and corridor matches, and where it looked."""

    views: Views
    main: Candidates
    corridor: Candidates | None            # None: the corridor was not scanned with this pass
    cols: tuple[tuple[int, int], tuple[int, int]]
    wedge: np.ndarray | None
    counted: tuple[int, int]                # left columns whose pairs count for the lost fraction (not the margin)
    corridor_views: Views | None = None     # the views the corridor's points are in, when not ``views``
    main_ids: np.ndarray | None = None      # each main pair's number within its pass (None: 0, 1, ...)

    def ids(self) -> np.ndarray:
        """Return each main pair's number within its pass (the same pair keeps it while followed)."""
        return np.arange(len(self.main)) if self.main_ids is None else self.main_ids


@dataclass
class _Job:
    """A full pass spread over the next frames: its pieces, the piece in flight, frames until it is taken."""

    pieces: Iterator[_Scan | None]       # yields None after each piece, then the scan
    per_frame: int                       # pieces run per frame
    due: int
    future: Future | None = None         # the pieces started on the current frame
    scan: _Scan | None = None
    rescanned: bool = False              # the corridor was scanned afresh after this pass's frame: keep that one
    anchor: Anchor | None = None         # the pairs followed on the pass's frame, to learn the motion since


class CandidateReuse:
    """Follows a frame sequence's candidate matches between full passes (see the module doc).

    Per frame the core calls ``step`` (in a helper thread, while the pose runs), then, once it has
    returned, ``main_candidates`` / ``corridor_candidates`` (or ``fresh``) and ``schedule``. The
    background pass runs on its own detectors (their SIFT objects are not shared with the core's).
    """

    def __init__(self, interval_frames: int, min_tracked_fraction: float, max_disparity_change_px: float,
                 min_corridor_cover: float, detector: SiftDetector, corridor: CorridorDetector | None,
                 row_tolerance_px: float) -> None:
        self.interval_frames = int(interval_frames)
        self.min_tracked_fraction = float(min_tracked_fraction)
        self.max_disparity_change_px = float(max_disparity_change_px)
        self.min_corridor_cover = float(min_corridor_cover)
        self.row_tolerance_px = float(row_tolerance_px)
        self.detector, self.corridor = detector, corridor
        self.detector.concurrent = False            # the background pass runs in one thread
        if corridor is not None:
            corridor.concurrent = False
        self.counts = {"fresh": 0, "reused": 0, "refreshed": 0, "lost": 0, "corridor_scans": 0, "start_passes": 0}
        self.last_reason = ""
        self._state: _Scan | None = None
        self._views: Views | None = None
        self._job: _Job | None = None
        self._scanned_now = False                    # this frame was computed afresh by the full pass

    @classmethod
    def from_params(cls, params: Mapping) -> "CandidateReuse | None":
        """Build the reuse from effective parameters; None when ``candidates.reuse_frames`` is below 2."""
        if int(params["candidates.reuse_frames"]) < 2:
            return None
        corridor = CorridorDetector.from_params(params) if params.get("corridor.enabled") else None
        return cls(params["candidates.reuse_frames"], params["candidates.reuse_min_tracked_fraction"],
                   params["candidates.reuse_max_disparity_change_px"], params["candidates.reuse_min_corridor_cover"],
                   SiftDetector.from_params(params), corridor, params["candidates.row_tolerance_px"])

    def has_matches(self) -> bool:
        """True when there are matches to follow into the next frame (it will probably be reused)."""
        return self._state is not None

    # -- per frame --------------------------------------------------------------------------------
    def step(self, left_rect: np.ndarray, right_rect: np.ndarray) -> bool:
        """Take a new frame: follow the kept matches into it; return whether they can be used.

        Call once per frame, first. False (the frame must be computed afresh) when there
        is nothing to follow or too few pairs survived the flow.
        """
        cur = views_of(left_rect, right_rect)
        self._views = cur
        job, motion = self._job, None
        if job is not None:
            if job.future is not None:
                job.future.result()                  # the pieces the previous frame started
                job.future = None
            job.due -= 1
            if job.due <= 0:
                self._job = None
                motion = self._motion_since(job.anchor)
                self._state = self._taken(job)       # followed from its own frame below, in one step
            else:                                    # this frame's share runs beside the frame's own work
                job.future = shared_pool("reuse", 1).submit(_run_pieces, job, job.per_frame)
        self._scanned_now = False
        if self._state is None:
            self.last_reason = "nothing to follow"
            return False
        return self._follow(cur, motion)

    def _taken(self, job: _Job) -> _Scan:
        """Return a due pass's scan; the corridor of a later rescan (still in the state's views) replaces its own."""
        scan = _finish(job)
        state = self._state
        if job.rescanned and state is not None and state.corridor is not None:
            scan = _Scan(scan.views, scan.main, state.corridor, scan.cols, state.wedge, scan.counted, state.views)
        return scan

    def _motion_since(self, anchor: Anchor | None) -> SceneMotion | None:
        """Return how the followed pairs moved since a pass's frame (``anchor``) up to the last frame, or None."""
        state = self._state
        if anchor is None or state is None:
            return None
        return SceneMotion.between(anchor, state.ids(), state.main.left_px, state.main.right_px)

    def _follow(self, cur: Views, motion: SceneMotion | None = None) -> bool:
        """Follow the state's main and corridor matches into ``cur``; False when too many were lost.

        ``motion``: the scene's motion since the state's frame (a pass taken K frames after its own).
        """
        state = self._state
        n_main = len(state.main)
        both = state.main if state.corridor is None else state.main.stacked(state.corridor)
        together = state.corridor is None or state.corridor_views is None
        flowed = both if together else state.main     # the pairs followed from ``state.views``
        guess = None if motion is None else motion.moved(flowed.left_px, flowed.right_px)
        if together:
            moved, keep = follow_pairs(state.views, cur, both, self.row_tolerance_px, self.max_disparity_change_px,
                                       guess)
        else:                                        # main and corridor found on different frames
            pairs = [follow_pairs(prev, cur, cands, self.row_tolerance_px, self.max_disparity_change_px, g)
                     for prev, cands, g in ((state.views, state.main, guess),
                                            (state.corridor_views, state.corridor, None))]
            moved, keep = pairs[0][0].stacked(pairs[1][0]), np.concatenate([pairs[0][1], pairs[1][1]])
        # pairs in the margin next to the diver (it moves with the diver) or near the border (they
        # leave the view as the camera moves: where they are predicted now) do not tell whether the
        # scene changed
        where = both.left_px if guess is None else np.vstack([guess[0], both.left_px[len(flowed):]])
        x, y = where[:, 0], where[:, 1]
        h, w = cur.left.shape[:2]
        counted = ((x >= max(state.counted[0], EDGE_PX)) & (x < min(state.counted[1], w - EDGE_PX))
                   & (y >= EDGE_PX) & (y < h - EDGE_PX))
        total, kept = int(counted.sum()), int((keep & counted).sum())
        rows = np.arange(len(both))
        main = moved.subset(keep & (rows < n_main))
        corridor = None if state.corridor is None else moved.subset(keep & (rows >= n_main))
        if total and kept < self.min_tracked_fraction * total:
            self.counts["lost"] += 1
            self.last_reason = f"{kept} of {total} matches followed"
            self._state = None
            self._cancel()
            return False
        self._state = _Scan(cur, main, corridor, state.cols, state.wedge, state.counted,
                            main_ids=state.ids()[keep[:n_main]])
        return True

    def main_candidates(self, arm: ArmKeypoints, rig: StereoRig) -> Candidates | None:
        """Return the followed main-pass matches inside this frame's kept columns, or None if not covered."""
        state = self._state
        if state is None:
            return None
        width = state.views.left.shape[1]
        hand = hand_extent_px(arm, rig.baseline_m)
        cols = [kept_columns(arm, side, width, self.detector.mask_side, self.detector.mask_offset_px, hand)
                for side in ("left", "right")]
        for (x0, x1), (s0, s1) in zip(cols, state.cols):
            if x1 - x0 >= 8 and (x0 < s0 - COLUMN_SLACK_PX or x1 > s1 + COLUMN_SLACK_PX):
                self.last_reason = "kept columns outside the scanned ones"
                return None
        m = state.main
        keep = ((m.left_px[:, 0] >= cols[0][0]) & (m.left_px[:, 0] < cols[0][1])
                & (m.right_px[:, 0] >= cols[1][0]) & (m.right_px[:, 0] < cols[1][1]))
        return m.subset(keep)

    def corridor_candidates(self, arm: ArmKeypoints, rig: StereoRig) -> Candidates | None:
        """Return the followed corridor matches inside this frame's wedge, or None if it is not covered."""
        state = self._state
        if state is None or self.corridor is None or state.corridor is None or state.wedge is None:
            return None
        h, w = state.views.left.shape[:2]
        wedge = self.corridor.wedge(arm, w, h, rig)
        if wedge is None:
            return Candidates.empty()
        if polygon_cover(wedge, state.wedge, w, h) < self.min_corridor_cover:
            self.last_reason = "the arm's corridor moved"
            return None
        return state.corridor.subset(inside_polygon(state.corridor.left_px, wedge))

    def rescan_corridor(self, detector: CorridorDetector, left_rect: np.ndarray, right_rect: np.ndarray,
                        arm: ArmKeypoints, rig: StereoRig) -> Candidates:
        """Return this frame's corridor when the arm's wedge moved: scanned only beyond the scanned wedge.

        The followed matches inside the new wedge are kept; ``detector.detect_beyond`` adds those of its
        new part (one of each pair found twice on the overlap). The new wedge is then the scanned one.
        ``detector`` is the caller's (the background pass may be using this object's own).
        """
        state = self._state
        if state is None or state.corridor is None or state.wedge is None:
            found = detector.detect(left_rect, right_rect, arm, rig)
        else:
            h, w = left_rect.shape[:2]
            wedge = detector.wedge(arm, w, h, rig)
            new = detector.detect_beyond(left_rect, right_rect, arm, rig, state.wedge)
            old = state.corridor if wedge is None else state.corridor.subset(inside_polygon(state.corridor.left_px, wedge))
            extra = _not_near(new, old.left_px)
            found = old if len(extra) == 0 else extra if len(old) == 0 else old.stacked(extra)
        self.replace_corridor(found, arm, rig)
        return found

    def replace_corridor(self, found: Candidates, arm: ArmKeypoints, rig: StereoRig) -> None:
        """Keep a corridor scanned afresh on this frame (its wedge from ``arm``) for the next frames."""
        if self._state is not None and self.corridor is not None:
            h, w = self._state.views.left.shape[:2]
            self._state.corridor, self._state.wedge = found, self.corridor.wedge(arm, w, h, rig)
            self.counts["corridor_scans"] += 1
            if self._job is not None:                # its corridor (an older arm's) is not needed now
                self._job.rescanned = True

    def fresh(self, main: Candidates, corridor: Candidates | None, arm: ArmKeypoints, rig: StereoRig,
              start_pass: bool = False) -> None:
        """Keep a frame computed afresh (the core's own full pass) as the matches to follow.

        ``start_pass``: its main pass was the quicker start pass (``candidates.reuse_start_image_scale``):
        the full pass then starts on this very frame (``schedule``) and replaces it K frames later.
        """
        self._cancel()
        views = self._views
        if views is None:
            return
        h, w = views.left.shape[:2]
        cols = self._columns(arm, rig, w, margin_px=0.0)
        wedge = self.corridor.wedge(arm, w, h, rig) if (self.corridor is not None and corridor is not None) else None
        self._state = _Scan(views, main, corridor, cols, wedge, cols[0])
        self._scanned_now = not start_pass
        self.counts["fresh"] += 1
        self.counts["start_passes"] += int(start_pass)

    def schedule(self, arm: ArmKeypoints, rig: StereoRig) -> None:
        """After a frame is decided: start the next background pass on it unless one is in flight."""
        if self._job is not None or self._views is None or self._state is None or self._scanned_now:
            return
        frames = max(self.interval_frames - 1, 1)        # the pass is taken on the K-th frame from now
        state = self._state
        anchor = Anchor(state.ids(), state.main.left_px.copy(), state.main.right_px.copy())
        self._job = _Job(iter(()), -(-PASS_PIECES // frames), self.interval_frames, anchor=anchor)
        self._job.pieces = self._full_pass(self._views, arm, rig, self._job)
        self.counts["refreshed"] += 1

    def reset(self) -> None:
        """Forget everything (a new sequence); waits for a background pass in flight."""
        self._cancel()
        self._state, self._views = None, None

    # -- internals --------------------------------------------------------------------------------
    def _cancel(self) -> None:
        """Drop the background pass in flight (waited for: it holds the detectors)."""
        job, self._job = self._job, None
        if job is not None and job.future is not None:
            job.future.result()

    def _columns(self, arm: ArmKeypoints, rig: StereoRig, width: int, margin_px: float
                 ) -> tuple[tuple[int, int], tuple[int, int]]:
        """Return both images' kept columns for ``arm``, widened by ``margin_px`` where not at the border."""
        hand = hand_extent_px(arm, rig.baseline_m)
        out = []
        for side in ("left", "right"):
            x0, x1 = kept_columns(arm, side, width, self.detector.mask_side, self.detector.mask_offset_px, hand)
            out.append((int(max(0, x0 - margin_px)) if x0 > 0 else 0, int(min(width, x1 + margin_px)) if x1 < width else width))
        return out[0], out[1]

    def _full_pass(self, views: Views, arm: ArmKeypoints, rig: StereoRig, job: _Job) -> Iterator[_Scan | None]:
        """The full pass on one frame in ``PASS_PIECES`` pieces: left features, right features, matches + corridor.

        The corridor is skipped when it was scanned afresh on a later frame before this piece ran
        (``job.rescanned``: that scan is the one kept when the pass is taken).
        """
        width = views.left.shape[1]
        cols = self._columns(arm, rig, width, COLUMN_MARGIN_PX)
        left = self.detector.features(views.left, cols[0], 0)
        yield None
        right = self.detector.features(views.right, cols[1], 1)
        yield None
        main = self.detector.match_features(left, right, rig)
        corridor, wedge = None, None
        if self.corridor is not None and not job.rescanned:
            corridor = self.corridor.detect(views.left, views.right, arm, rig)
            wedge = self.corridor.last_polygon
        yield _Scan(views, main, corridor, cols, wedge, self._columns(arm, rig, width, 0.0)[0])

