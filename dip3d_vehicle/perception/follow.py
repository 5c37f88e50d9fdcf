"""Servoing-time perception: the full core on keyframes, the chosen object's features tracked between.

Once the diver has pointed and the core has chosen an object, the vehicle servos on that object;
re-running pose, SIFT and selection on every frame only re-confirms it. ``FollowingPerception``
runs the full core on a keyframe, then follows the chosen object's matched features in both
ORIGINAL images with pyramidal Lucas-Kanade optical flow (small crops around the features, no
rectification of whole frames), checks the stereo geometry of every tracked pair (same rectified
row, positive disparity) and returns the object's new left-image point and 3D centre (the
keyframe's, moved by the features' median displacement and disparity change). A new
keyframe runs every ``keyframe_interval`` frames, or at once when fewer than ``min_features``
pairs survive. Timings: "track" (ms) on followed frames; the core's stages on keyframes.

Cost: Lucas-Kanade's time grows with the number of points (about 22 us per point and pass) and
with the crop's area (its pyramid: 0.7 ms for 280x280 px, 1.4 ms for 600x600 px per pass), four
passes per frame (forward and backward, both images). So at most ``max_features`` of the object's
features are followed, those nearest the object's point: they give its motion (the followed point
is the keyframe's, moved) from the smallest crops. The left and right images are tracked
concurrently (cv2 releases the GIL).

With ``background=True`` a keyframe runs in its own thread while the following goes on, so no
frame waits for pose, SIFT and selection: when the keyframe's result arrives, the follower is
re-anchored on its chosen object (followed from the keyframe's images to the current ones).
Only when there is nothing to follow (start, object lost) does a frame wait for the core.

Configured by the ``follow.*`` parameters (``with_following`` builds it when
``follow.keyframe_interval`` > 1, as in the ``fast`` profile).
"""

from __future__ import annotations

import math
import time
from concurrent.futures import Future, ThreadPoolExecutor

import cv2
import numpy as np

from .images import grey
from .pipeline import Perception, PerceptionResult
from .threads import shared_pool
from .triangulation import triangulate
from .values import Candidates, ObjectCandidate, Selection

__all__ = ["FollowingPerception", "with_following", "followed_subset"]

_LK_CRITERIA = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 20, 0.03)


class FollowingPerception:
    """Keyframe perception plus optical-flow following of the chosen object.

    Args:
        perception: the full core (any profile).
        keyframe_interval: frames between keyframes (1 = the core on every frame).
        min_features: tracked stereo pairs below which a keyframe is forced.
        window_px: Lucas-Kanade window side, pixels.
        levels: pyramid levels above the base.
        margin_px: crop margin around the features, pixels (largest motion followed per frame).
        row_tolerance_px: largest |y_left - y_right| (rectified) of a kept pair.
        background: run keyframes in a background thread.
        max_features: most features followed per object (0 = all of them).
    """

    def __init__(self, perception: Perception, keyframe_interval: int = 5, min_features: int = 4,
                 window_px: int = 21, levels: int = 3, margin_px: int = 64, row_tolerance_px: float = 2.0,
                 background: bool = False, max_features: int = 0) -> None:
        self.core = perception
        self.background = bool(background)
        self._pool = ThreadPoolExecutor(1, thread_name_prefix="keyframe") if background else None
        self._job: tuple[Future, np.ndarray, np.ndarray] | None = None
        self.rig = perception.rig
        self.keyframe_interval = max(1, int(keyframe_interval))
        self.min_features = int(min_features)
        self.window_px, self.levels, self.margin_px = int(window_px), int(levels), int(margin_px)
        self.row_tolerance_px = float(row_tolerance_px)
        self.max_features = max(0, int(max_features))
        self.counts = {"keyframes": 0, "followed": 0, "lost": 0, "waited": 0, "kept_on_empty_keyframe": 0}
        self.last_kind = ""
        self.reset()

    def reset(self) -> None:
        """Forget the followed object and the core's tracking state (waits for a running keyframe)."""
        job, self._job = getattr(self, "_job", None), None
        if job is not None:
            job[0].result()
        self._track: dict | None = None
        self._since = 0
        self.core.reset()

    def close(self) -> None:
        """Stop the keyframe thread."""
        self.reset()
        if self._pool is not None:
            self._pool.shutdown()

    def process(self, left: np.ndarray, right: np.ndarray) -> PerceptionResult:
        """Return the core's result on keyframes, the followed object's otherwise (ORIGINAL images)."""
        if self.background:
            return self._process_background(left, right)
        if self._track is not None and self._since < self.keyframe_interval:
            followed = self._follow(left, right)
            if followed is not None:
                self._since += 1
                self.counts["followed"] += 1
                self.last_kind = "followed"
                return followed
            self.counts["lost"] += 1
        result = self.core.process(left, right)
        self.counts["keyframes"] += 1
        self.last_kind = "keyframe"
        self._start(result, left, right)
        return result

    def _process_background(self, left: np.ndarray, right: np.ndarray) -> PerceptionResult:
        """Follow on this frame; keyframes run in the keyframe thread and re-anchor when done.

        A keyframe that falls due (or an object lost on this frame) starts after this frame's
        following, so the keyframe's first, most parallel work (remaps, features, pose) does not
        slow it.
        """
        self._collect(wait=self._track is None and self._job is not None)
        if self._track is None:  # nothing to follow: this frame waits for the core
            self._submit(left, right)
            self.counts["waited"] += 1
            result = self._collect(wait=True)
            self.last_kind = "keyframe"
            return result
        self._since += 1
        followed = self._follow(left, right)
        if self._job is None and (self._track is None or self._since > self.keyframe_interval):
            self._submit(left, right)
        if followed is not None:
            self.counts["followed"] += 1
            self.last_kind = "followed"
            return followed
        self.counts["lost"] += 1
        self.last_kind = "lost"
        return PerceptionResult("no_candidates", "followed object lost; keyframe running", timings_ms={"track": 0.0})

    def _submit(self, left: np.ndarray, right: np.ndarray) -> None:
        """Start a keyframe on this pair in the keyframe thread."""
        self._job = (self._pool.submit(self.core.process, left, right), left, right)
        self._since = 1
        self.counts["keyframes"] += 1

    def _collect(self, wait: bool) -> PerceptionResult | None:
        """Take a finished (or, with ``wait``, the running) keyframe and re-anchor on its object."""
        if self._job is None or not (wait or self._job[0].done()):
            return None
        job, key_l, key_r = self._job
        self._job = None
        result = job.result()
        previous = self._track
        self._start(result, key_l, key_r)
        if self._track is None and previous is not None:
            self._track = previous  # the keyframe chose nothing (pose lost, ...): keep the object
            self.counts["kept_on_empty_keyframe"] += 1
        return result

    # -- keyframe ---------------------------------------------------------------------------------
    def _start(self, result: PerceptionResult, left: np.ndarray, right: np.ndarray) -> None:
        """Remember the chosen object's features (original pixels) and the images they were seen in."""
        self._track, self._since = None, 1
        sel = result.selection
        if result.status != "ok" or sel is None or sel.index is None:
            return
        obj = sel.objects[sel.index]
        cands = result.candidates
        members = np.asarray(obj.members, int)
        members = followed_subset(members, cands.left_px[members], obj.left_px, self.max_features)
        if len(members) < self.min_features:
            return
        pts_l = self.rig.to_original(cands.left_px[members], "left").astype(np.float32)
        pts_r = self.rig.to_original(cands.right_px[members], "right").astype(np.float32)
        self._track = {"left": left, "right": right, "pts_l": pts_l, "pts_r": pts_r, "result": result,
                       "score": float(sel.scores[sel.index]), "sigma": obj.depth_sigma_m,
                       "anchor_px": np.asarray(obj.left_px, float),
                       "anchor_disparity_px": self._disparity_of(obj, cands),
                       "key_l": cands.left_px[members], "key_disparity_px": cands.disparity_px[members]}

    def _disparity_of(self, obj: ObjectCandidate, cands: Candidates) -> float:
        """Return the disparity of the object's centre, pixels (its members' median if its depth is unusable)."""
        z = float(obj.xyz_m[2])
        if math.isfinite(z) and z > 0:
            return self.rig.focal_px * self.rig.baseline_m / z
        return float(np.median(cands.disparity_px[np.asarray(obj.members, int)]))

    # -- followed frame ---------------------------------------------------------------------------
    def _follow(self, left: np.ndarray, right: np.ndarray) -> PerceptionResult | None:
        """Track the object's features into this pair; None when too few survive."""
        t0 = time.perf_counter()
        tr = self._track
        right_job = _flow_pool().submit(self._flow, tr["right"], right, tr["pts_r"])
        new_l, ok_l = self._flow(tr["left"], left, tr["pts_l"])
        new_r, ok_r = right_job.result()
        ok = ok_l & ok_r
        if ok.sum() < self.min_features:
            self._track = None
            return None
        rect_l = self.rig.to_rectified(new_l[ok], "left")
        rect_r = self.rig.to_rectified(new_r[ok], "right")
        disp = self.rig.disparity_sign * (rect_l[:, 0] - rect_r[:, 0])
        geo = (np.abs(rect_l[:, 1] - rect_r[:, 1]) <= self.row_tolerance_px) & (disp > 0)
        if geo.sum() < self.min_features:
            self._track = None
            return None
        rect_l, rect_r = rect_l[geo], rect_r[geo]
        keep = np.nonzero(ok)[0][geo]
        tr.update(left=left, right=right, pts_l=new_l[keep], pts_r=new_r[keep], key_l=tr["key_l"][keep],
                  key_disparity_px=tr["key_disparity_px"][keep])
        return self._result(rect_l, rect_r, (time.perf_counter() - t0) * 1e3)

    def _flow(self, prev: np.ndarray, cur: np.ndarray, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return (new points, ok mask) of pyramidal LK on grey crops around the points."""
        h, w = cur.shape[:2]
        m = self.margin_px + self.window_px
        x0, y0 = (int(max(0, v)) for v in np.floor(pts.min(axis=0) - m))
        x1, y1 = int(min(w, np.ceil(pts[:, 0].max() + m))), int(min(h, np.ceil(pts[:, 1].max() + m)))
        if x1 - x0 < 8 or y1 - y0 < 8:
            return pts, np.zeros(len(pts), bool)
        a, b = (grey(img[y0:y1, x0:x1]) for img in (prev, cur))
        off = np.float32([x0, y0])
        start = np.ascontiguousarray(pts - off, np.float32).reshape(-1, 1, 2)
        new, status, _ = cv2.calcOpticalFlowPyrLK(a, b, start, None, winSize=(self.window_px, self.window_px),
                                                  maxLevel=self.levels, criteria=_LK_CRITERIA)
        back, status_b, _ = cv2.calcOpticalFlowPyrLK(b, a, new, None, winSize=(self.window_px, self.window_px),
                                                     maxLevel=self.levels, criteria=_LK_CRITERIA)
        fb = np.linalg.norm(back.reshape(-1, 2) - start.reshape(-1, 2), axis=1)
        ok = (status.ravel() == 1) & (status_b.ravel() == 1) & (fb < 1.0)
        return new.reshape(-1, 2) + off, ok

    def _result(self, rect_l: np.ndarray, rect_r: np.ndarray, track_ms: float) -> PerceptionResult:
        """Return a PerceptionResult holding the followed object (the keyframe's arm and scores).

        The object's point is the keyframe's, moved by the followed features' median displacement
        (rectified px), and its disparity the keyframe's plus their median change: continuous with
        the keyframe's result whichever features are followed.
        """
        tr = self._track
        key = tr["result"]
        cands = Candidates(rect_l, rect_r)
        xyz = triangulate(self.core.Q, rect_l, cands.disparity_px)
        px = tr["anchor_px"] + np.median(rect_l - tr["key_l"], axis=0)
        disparity = tr["anchor_disparity_px"] + float(np.median(cands.disparity_px - tr["key_disparity_px"]))
        centre = triangulate(self.core.Q, px[None], [disparity])[0]
        obj = ObjectCandidate(px, centre, tr["sigma"], tuple(range(len(rect_l))))
        ks = key.selection
        sel = Selection(0, (obj,), np.array([tr["score"]]), ks.confidence, ks.ambiguity_margin, ks.method,
                        ks.ambiguous)
        return PerceptionResult("ok", "followed since the last keyframe", key.arm, key.arm3d, cands, xyz, sel,
                                {"track": track_ms})


def followed_subset(members: np.ndarray, points_px: np.ndarray, centre_px: np.ndarray,
                    max_features: int) -> np.ndarray:
    """Return at most ``max_features`` of an object's feature indices (0 = all): those nearest its point, in order.

    Args:
        members: the object's feature indices.
        points_px: (N, 2) the members' positions, pixels.
        centre_px: (2,) the object's point, pixels.
        max_features: most features kept (0 = all).
    """
    if max_features <= 0 or len(members) <= max_features:
        return members
    dist = np.linalg.norm(np.asarray(points_px, float) - np.asarray(centre_px, float), axis=1)
    return members[np.sort(np.argsort(dist, kind="stable")[:max_features])]


def _flow_pool() -> ThreadPoolExecutor:
    """Return the shared pool for the right image's optical flow (1 thread)."""
    return shared_pool("follow", 1)


def with_following(core: Perception, params) -> "Perception | FollowingPerception":
    """Return ``core`` wrapped in FollowingPerception when ``follow.keyframe_interval`` > 1."""
    if params["follow.keyframe_interval"] <= 1:
        return core
    return FollowingPerception(core, keyframe_interval=params["follow.keyframe_interval"],
                               min_features=params["follow.min_features"], window_px=params["follow.window_px"],
                               margin_px=params["follow.margin_px"], background=params["follow.background"],
                               max_features=params["follow.max_features"])
