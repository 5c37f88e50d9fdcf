"""The perception core: a stereo pair in, the pointed-at target (with its evidence) out.

rectify -> pose (both images) -> pose filters -> candidates (masked SIFT, matched) -> triangulate
-> candidate filters -> select. Every stage is timed (milliseconds).
"""

from __future__ import annotations

import dataclasses
import math
import time
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from .blobs import BlobFinder, Blobs, unexplained
from .calibration import StereoRig
from .candidates import CandidateDetector, SiftDetector
from .corridor import CorridorDetector, merge_candidates
from .filters import candidate_keep, pose_rejection
from .given_arm import match_arm
from .joint_stereo import limb_spans_m
from .pose import PoseEstimator
from .reuse import CandidateReuse
from .selection import PointingSelector, make_selector
from .triangulation import normalize_q, triangulate
from .threads import shared_pool, single_threaded_blas, single_threaded_opencv
from .values import JOINTS, Arm3D, ArmKeypoints, Candidates, Selection

__all__ = ["Perception", "PerceptionResult", "make_pose_estimator"]


@dataclass(frozen=True)
class PerceptionResult:
    """Everything the perception core found in one stereo pair.

    Attributes:
        status: "ok", "no_pose", "pose_low_confidence", "pose_rejected", "no_candidates" or
            "nothing_on_ray" (objects were found but the arm points at none of them).
        reason: one line saying why when the status is not "ok".
        arm: the arm keypoints (rectified px) or None.
        arm3d: triangulated joints or None.
        candidates: the kept matched features (rectified px).
        candidates_xyz_m: (N, 3) their 3D points, metres.
        selection: the selector's result (None unless status is "ok").
        timings_ms: milliseconds per stage.
        candidates_followed: the candidates were followed from earlier frames (``candidates.reuse_frames``),
            not computed on this frame alone.
        unrecognised: the compact spots found along the corridor outside every object, matched to 3D
            (``corridor.blobs``; the selector counts those no object explains as "nothing detected").
        recalled: the last this many candidates were not seen in this frame but recalled from an earlier
            frame of the same held point (``held_arm.decide_held``): objects made of them alone were scored
            with this frame's arm, not sighted.
    """

    status: str
    reason: str = ""
    arm: ArmKeypoints | None = None
    arm3d: Arm3D | None = None
    candidates: Candidates = field(default_factory=Candidates.empty)
    candidates_xyz_m: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    selection: Selection | None = None
    timings_ms: dict = field(default_factory=dict)
    candidates_followed: bool = False
    unrecognised: Blobs = field(default_factory=Blobs.empty)
    recalled: int = 0

    @property
    def target_rect_px(self) -> np.ndarray | None:
        """Return the chosen target's rectified left-image point, or None."""
        target = self.selection.target if self.selection else None
        return None if target is None else target.left_px

    def to_json(self, rig: StereoRig) -> dict:
        """Return the contract JSON (DESIGN.md section 3); pixel fields in ORIGINAL pixels."""
        sel = self.selection
        objs = sel.objects if sel else ()
        cands = [{"left_px": _r(rig.to_original(o.left_px, "left")[0]), "left_rect_px": _r(o.left_px),
                  "xyz_m": _r(o.xyz_m, 4), "score": _num(sel.scores[i]), "features": len(o.members)}
                 for i, o in enumerate(objs)]
        target = None
        if sel is not None and sel.index is not None:
            target = dict(cands[sel.index], index=sel.index)
        out = {"status": self.status, "reason": self.reason, "target": target, "candidates": cands,
               "features": len(self.candidates), "arm": self._arm_json(rig),
               "selection": None if sel is None else {
                   "method": sel.method, "confidence": _num(sel.confidence),
                   "ambiguity_margin": _num(sel.ambiguity_margin), "ambiguous": sel.ambiguous,
                   "none_probability": _num(sel.none_probability)},
               "timings_ms": {k: round(v, 2) for k, v in self.timings_ms.items()},
               "candidates_followed": self.candidates_followed,
               "unrecognised": [{"left_px": _r(rig.to_original(px, "left")[0]), "xyz_m": _r(xyz, 4),
                                 "probability": None if sel is None or (q := sel.spot_probability(xyz)) is None
                                 else _num(q)}
                                for px, xyz in zip(self.unrecognised.left_px, self.unrecognised.xyz_m)]}
        return out

    def _arm_json(self, rig: StereoRig) -> dict | None:
        """Return the arm's joints with original pixels, 3D and confidence."""
        if self.arm is None:
            return None
        left = rig.to_original(self.arm.left_px, "left")
        right = rig.to_original(self.arm.right_px, "right")
        out = {}
        for i, name in enumerate(JOINTS):
            out[name] = {"left_px": _r(left[i]), "right_px": _r(right[i]),
                         "confidence": [_num(self.arm.left_conf[i]), _num(self.arm.right_conf[i])],
                         "xyz_m": None if self.arm3d is None else _r(self.arm3d.xyz_m[i], 4)}
        return out


def _num(value: float, nd: int = 4) -> float | None:
    """Return a JSON-safe rounded number (None for NaN/inf)."""
    value = float(value)
    return round(value, nd) if math.isfinite(value) else None


def _r(arr, nd: int = 2) -> list:
    """Return an array as a rounded JSON list (NaN -> None)."""
    return [_num(v, nd) for v in np.asarray(arr, dtype=float).ravel()]


def make_pose_estimator(params: Mapping, keypoints: dict | None = None) -> PoseEstimator:
    """Return the pose backend named by ``pose.backend`` (keypoints file or BlazePose)."""
    if params["pose.backend"] == "keypoints":
        from .keypoints_file import GivenKeypoints
        return GivenKeypoints(params["pose.arm"], keypoints)
    from .blazepose import BlazePoseEstimator  # imported lazily: loads onnxruntime
    return BlazePoseEstimator.from_params(params)


class Perception:
    """The perception core for one rig and one parameter set."""

    def __init__(self, rig: StereoRig, params: Mapping, pose: PoseEstimator,
                 detector: CandidateDetector | None = None, selector: PointingSelector | None = None,
                 live: bool = False) -> None:
        """``live``: the frames are a camera's sequence decided as they come (run, sitl, bench), so a
        sequence's first frame may use the quicker start pass (``candidates.reuse_start_image_scale``);
        False (perceive, evaluate) keeps every frame computed afresh the full pass."""
        self.rig, self.params, self.pose = rig, params, pose
        single_threaded_opencv()
        single_threaded_blas()
        self.detector = detector or SiftDetector.from_params(params)
        self.selector = selector or make_selector(params)
        self.corridor = CorridorDetector.from_params(params) if params.get("corridor.enabled") else None
        # the unrecognised spots, for a selector that weighs them (the default one, its weight above 0)
        weighs = getattr(self.selector, "unrecognised_weight", 0.0) > 0.0 and bool(params.get("corridor.blobs"))
        self.blobs = BlobFinder.from_params(params) if self.corridor is not None and weighs else None
        self.Q = normalize_q(rig.Q, rig.disparity_sign)
        # With pose tracking the frames are a sequence: the previous frame's arm predicts where the
        # candidates' features are, so they are computed while the pose runs (SiftDetector.prefetch);
        # without a previous arm, from the pose's early arm (left measured, right predicted).
        self.overlap = params.get("pose.backend") == "blazepose" and bool(params.get("blazepose.tracking"))
        self._last_arm: ArmKeypoints | None = None
        # The corridor needs only the arm's LEFT joints, which the pose's early arm already has
        # exactly: it starts then, while the right pose and the features run (see _start_corridor).
        self._corridor_job: tuple[np.ndarray, np.ndarray, np.ndarray, Future] | None = None
        # A frame sequence's candidates followed between full passes (candidates.reuse_frames, reuse.py)
        self.reuse = CandidateReuse.from_params(params)
        self.start_detector = self._start_detector(params) if live else None

    def _start_detector(self, params: Mapping) -> SiftDetector | None:
        """Return the main pass for a live sequence's first frame (at ``candidates.reuse_start_image_scale``), or None."""
        scale = float(params.get("candidates.reuse_start_image_scale", 0.0))
        if self.reuse is None or scale <= 0.0 or not isinstance(self.detector, SiftDetector):
            return None
        if scale == self.detector.image_scale:
            return None
        start = SiftDetector.from_params(params)
        start.image_scale = scale
        return start

    def reset(self) -> None:
        """Start a new frame sequence: forget the pose's tracking, the last arm and the followed candidates."""
        self.pose.reset()
        self._last_arm = None  # it predicted the next frame's feature columns: not across sequences
        if self.reuse is not None:
            self.reuse.reset()

    def process(self, left: np.ndarray, right: np.ndarray) -> PerceptionResult:
        """Run the whole core on an ORIGINAL (unrectified) pair."""
        t0 = time.perf_counter()
        if self.rig.prerectified:
            left_rect, right_rect = left, right
        else:  # the two remaps run concurrently (cv2 releases the GIL)
            right_job = _rectify_pool().submit(self.rig.rectify_image, right, "right")
            left_rect = self.rig.rectify_image(left, "left")
            right_rect = right_job.result()
        return self.process_rectified(left_rect, right_rect, {"rectify": (time.perf_counter() - t0) * 1e3})

    def process_rectified(self, left_rect: np.ndarray, right_rect: np.ndarray,
                          timings: dict | None = None) -> PerceptionResult:
        """Run the core on an already rectified pair."""
        tm = dict(timings or {})
        clock = _Stopwatch(tm)
        likely_reused = self.reuse is not None and self.reuse.has_matches()  # read before the step runs
        following = None
        if self.reuse is not None:  # follow the kept matches into this frame while the pose runs
            following = shared_pool("reuse-follow", 1).submit(self.reuse.step, left_rect, right_rect)
        # nothing to follow: a live sequence's first frame takes the quicker start pass (if set)
        detector = self.start_detector if (self.start_detector is not None and not likely_reused) else self.detector
        prefetch = getattr(detector, "prefetch", None) if self.overlap and not likely_reused else None
        features_started = prefetch is not None and self._last_arm is not None
        if features_started:
            prefetch(left_rect, right_rect, self._last_arm)
        elif prefetch is not None and detector is self.start_detector:
            detector.prefetch_right(left_rect, right_rect)   # a first frame: on the core the pose leaves idle

        def on_early_arm(hint: ArmKeypoints) -> None:
            if prefetch is not None and not features_started:  # no previous arm: features from the left pose
                prefetch(left_rect, right_rect, hint)
            if not likely_reused:
                self._start_corridor(left_rect, right_rect, hint)

        if self.overlap:
            self.pose.set_early_arm_listener(on_early_arm)
        with clock("pose"):
            try:
                arm = self.estimate_arm(left_rect, right_rect)
            finally:
                self.pose.set_early_arm_listener(None)
        with clock("triangulate"):
            early = self.check_arm(arm)
        self._last_arm = early.arm if early.status == "ok" else None
        with clock("candidates"):
            reusable = following is not None and following.result()
        if early.status != "ok":
            if prefetch is not None:
                detector.cancel_prefetch()
            self._take_corridor(left_rect, right_rect, None)
            return PerceptionResult(early.status, early.reason, early.arm, early.arm3d, timings_ms=tm)
        if reusable:
            cands = self._reused_candidates(left_rect, right_rect, arm, tm)
            if cands is not None:
                return dataclasses.replace(self._decided(early, cands, tm, (left_rect, right_rect)),
                                           candidates_followed=True)
        with clock("candidates"):
            cands = detector.detect(left_rect, right_rect, arm, self.rig)
        split = getattr(detector, "last_timings_ms", None) or {}
        if "match" in split:  # "candidates" = features (both images), "match" = matching
            tm["match"] = tm.get("match", 0.0) + split["match"]
            tm["candidates"] -= split["match"]
        with clock("corridor"):
            found = self._corridor_found(left_rect, right_rect, arm)
        if self.reuse is not None:
            self.reuse.fresh(cands, found, arm, self.rig, start_pass=detector is not self.detector)
        return self._decided(early, merge_candidates(cands, found) if found is not None else cands, tm,
                             (left_rect, right_rect))

    def _reused_candidates(self, left_rect: np.ndarray, right_rect: np.ndarray, arm: ArmKeypoints,
                           tm: dict) -> Candidates | None:
        """Return this frame's candidates from the followed matches (the corridor scanned afresh if it moved).

        None when the main pass's kept columns are not covered (the frame is then computed afresh).
        """
        clock = _Stopwatch(tm)
        with clock("candidates"):
            main = self.reuse.main_candidates(arm, self.rig)
        if main is None:
            return None
        with clock("corridor"):
            found = self.reuse.corridor_candidates(arm, self.rig) if self.corridor is not None else None
            self._take_corridor(left_rect, right_rect, None)   # (none is started on a frame likely reused)
            if found is None and self.corridor is not None:   # the arm moved: scan where it points now
                found = self.reuse.rescan_corridor(self.corridor, left_rect, right_rect, arm, self.rig)
        self.reuse.counts["reused"] += 1
        return merge_candidates(main, found) if found is not None else main

    def _decided(self, checked: PerceptionResult, cands: Candidates, tm: dict,
                 images: tuple[np.ndarray, np.ndarray]) -> PerceptionResult:
        """Decide, then start the next background candidate pass on this frame when one is due."""
        result = self.decide(checked, cands, tm, images)
        if self.reuse is not None:
            self.reuse.schedule(checked.arm, self.rig)
        return result

    def _corridor_found(self, left_rect: np.ndarray, right_rect: np.ndarray, arm: ArmKeypoints
                        ) -> Candidates | None:
        """Return the corridor's own matches for this frame (the early-started job's if it fits), or None if off."""
        if self.corridor is None:
            return None
        found = self._take_corridor(left_rect, right_rect, arm)
        return found if found is not None else self.corridor.detect(left_rect, right_rect, arm, self.rig)

    def add_corridor(self, left_rect: np.ndarray, right_rect: np.ndarray, arm: ArmKeypoints,
                     cands: Candidates) -> Candidates:
        """Return ``cands`` plus the corridor's matches along where the arm points (if enabled)."""
        found = self._corridor_found(left_rect, right_rect, arm)
        return cands if found is None else merge_candidates(cands, found)

    def _start_corridor(self, left_rect: np.ndarray, right_rect: np.ndarray, hint: ArmKeypoints) -> None:
        """Start the corridor's detection in the background from an early arm (its left joints are final)."""
        if self.corridor is None or self._corridor_job is not None:
            return
        job = shared_pool("corridor", 1).submit(self.corridor.detect, left_rect, right_rect, hint, self.rig)
        self._corridor_job = (np.array(hint.left_px, copy=True), left_rect, right_rect, job)

    def _take_corridor(self, left_rect: np.ndarray, right_rect: np.ndarray, arm: ArmKeypoints | None
                       ) -> Candidates | None:
        """Return the started corridor's result if it ran on these images with ``arm``'s left joints, else None.

        Any started job is waited for (it holds the corridor's SIFT objects) and then forgotten.
        """
        pending, self._corridor_job = self._corridor_job, None
        if pending is None:
            return None
        left_px, left_img, right_img, job = pending
        found = job.result()
        same = (arm is not None and left_img is left_rect and right_img is right_rect
                and np.array_equal(left_px, arm.left_px))
        return found if same else None

    def estimate_arm(self, left_rect: np.ndarray, right_rect: np.ndarray) -> ArmKeypoints | None:
        """Return the pose backend's arm (rectified px), its joints' disparities matched when ``pose.match_disparity``.

        Only for an arm whose backend gives no disparity sigma of its own (keypoints files, the
        simulator's truth; BlazePose's ``joint_disparity: stereo`` already matches): see
        ``given_arm.match_arm``.
        """
        arm = self.pose.estimate(left_rect, right_rect, self.rig)
        if arm is None or arm.disparity_sigma_px is not None or not self.params.get("pose.match_disparity", False):
            return arm
        given_sigma_px = math.sqrt(2.0) * keypoint_noise_px(arm, self.params["selection.keypoint_sigma_px"])
        return match_arm(arm, left_rect, right_rect, self.rig.disparity_sign, self.rig.focal_px, self.rig.baseline_m,
                         float(self.params["pose.match_disparity_floor_px"]), given_sigma_px,
                         float(self.params["pose.match_disparity_patch_m"]), self.rig.principal_point_px,
                         limb_spans_m(self.params), self.params["pose.match_disparity_shoulder"])

    def check_arm(self, arm: ArmKeypoints | None) -> PerceptionResult:
        """Triangulate and filter the arm; status "ok" when it may be used for selection."""
        if arm is None:
            return PerceptionResult("no_pose", "no person found")
        if arm.min_confidence() < self.params["pose.min_confidence"]:
            return PerceptionResult("pose_low_confidence", f"keypoint confidence {arm.min_confidence():.2f} under "
                                    f"pose.min_confidence {self.params['pose.min_confidence']:g}", arm)
        arm3d = self.triangulate_arm(arm)
        why = pose_rejection(arm3d.xyz_m, self.params["filters.max_joint_dz_m"], self.params["filters.min_depth_m"],
                             arm3d.depth_sigma_m, self.params["filters.joint_dz_sigmas"])
        return PerceptionResult("pose_rejected" if why else "ok", why or "", arm, arm3d)

    def decide(self, checked: PerceptionResult, cands: Candidates, timings: dict | None = None,
               images: tuple[np.ndarray, np.ndarray] | None = None) -> PerceptionResult:
        """Triangulate and filter candidates, then select, for an arm that passed ``check_arm``.

        ``images``: the rectified pair, for the unrecognised spots along the corridor (``corridor.blobs``);
        without them the selector weighs the recognised objects only.
        """
        tm = dict(timings or {})
        clock = _Stopwatch(tm)
        arm, arm3d = checked.arm, checked.arm3d
        with clock("triangulate"):
            xyz = triangulate(self.Q, cands.left_px, cands.disparity_px)
            keep = candidate_keep(xyz, self.params["filters.min_depth_m"], self.params["filters.max_depth_m"])
            cands, xyz = cands.subset(keep), xyz[keep]
        if len(cands) == 0:
            return PerceptionResult("no_candidates", "no matched features in the kept region", arm, arm3d, timings_ms=tm)
        found: list[Blobs] = []
        with clock("select"):
            sel = self.selector.select(arm, arm3d, cands, xyz, self.rig, self._unrecognised(images, arm, found))
        spots = found[0] if found else Blobs.empty()
        if sel.nothing_on_ray:
            return PerceptionResult("nothing_on_ray", sel.reason, arm, arm3d, cands, xyz, sel, tm, unrecognised=spots)
        if sel.index is None:
            return PerceptionResult("no_candidates", "no object with enough matched features", arm, arm3d,
                                    cands, xyz, sel, tm, unrecognised=spots)
        return PerceptionResult("ok", "", arm, arm3d, cands, xyz, sel, tm, unrecognised=spots)

    def _unrecognised(self, images: tuple[np.ndarray, np.ndarray] | None, arm: ArmKeypoints, found: list[Blobs]):
        """Return the selector's source of unrecognised spots along ``arm``'s corridor (None: off or no images).

        The spots are looked for once the objects are known (their own texture is skipped); what was
        found is appended to ``found`` (for the result, and a later decision with a held arm).
        """
        if images is None or self.blobs is None:
            return None
        left, right = images
        poly = self.corridor.wedge(arm, left.shape[1], left.shape[0], self.rig)
        if poly is None:
            return None
        # the spots' filtering runs while the selector groups and fits the objects
        responses = shared_pool("blobs", 1).submit(self.blobs.responses, left, poly)

        def source(known_px: list, known_xyz: list, joints_xyz_m: np.ndarray) -> Blobs:
            blobs = self.blobs.find(left, right, poly, self.rig, known_px, responses.result(), known_xyz)
            found.append(blobs)
            return unexplained(blobs, known_px, known_xyz, joints_xyz_m)
        return source

    def triangulate_arm(self, arm: ArmKeypoints, prior_sigma_px: float | None = None) -> Arm3D:
        """Triangulate the three joints; depth sigma from this frame's keypoint noise or the estimator's (metres).

        ``prior_sigma_px`` replaces ``selection.keypoint_sigma_px`` as the noise prior (an arm
        averaged over frames has less); the estimator's own per-joint disparity sigma, where it is
        larger, is kept as it is (it holds systematic errors that do not average).
        """
        disp = arm.left_px[:, 0] - arm.right_px[:, 0]
        rows = (arm.left_px[:, 1] + arm.right_px[:, 1]) / 2.0
        xyz = triangulate(self.Q, np.c_[arm.left_px[:, 0], rows], disp)
        prior = self.params["selection.keypoint_sigma_px"] if prior_sigma_px is None else prior_sigma_px
        disparity_sigma_px = np.full(len(disp), math.sqrt(2.0) * keypoint_noise_px(arm, prior))
        if arm.disparity_sigma_px is not None:  # the estimator's own per-joint figure, where it is larger
            own = np.asarray(arm.disparity_sigma_px, dtype=float)   # NaN: none for that joint
            matched = np.isfinite(own) & (False if arm.disparity_matched is None else arm.disparity_matched)
            disparity_sigma_px = np.where(matched, own, np.fmax(disparity_sigma_px, own))  # a match's own, as it is
        sigma = self.rig.depth_sigma_m(np.abs(xyz[:, 2]), disparity_sigma_px)
        return Arm3D(xyz, np.asarray(sigma, dtype=float))


def _rectify_pool() -> ThreadPoolExecutor:
    """Return the shared pool for the right-image rectification (1 thread)."""
    return shared_pool("rectify", 1)


def keypoint_noise_px(arm: ArmKeypoints, prior_px: float, prior_weight: float = 1.0) -> float:
    """Return this frame's keypoint noise (1 sigma, pixels), estimated from the epipolar residuals.

    In rectified images a joint has the same row in both views, so y_left - y_right of the three
    joints are draws of N(0, 2 sigma^2): their mean square / 2 estimates sigma^2 with 3 degrees of
    freedom, pooled with the configured prior (``prior_weight`` pseudo-observations; one, so that
    clean keypoints are believed: with three the 2 px prior kept 0.13 m of depth doubt at 2.6 m).
    """
    dy = arm.left_px[:, 1] - arm.right_px[:, 1]
    if arm.disparity_matched is not None:  # a matched joint sits on the left joint's row: no residual to read
        dy = dy[~np.asarray(arm.disparity_matched, bool)]
    return math.sqrt((prior_weight * prior_px ** 2 + float(np.sum(dy ** 2)) / 2.0) / (prior_weight + len(dy)))


class _Stopwatch:
    """Accumulates wall time per stage into a dict, milliseconds."""

    def __init__(self, out: dict) -> None:
        self.out = out

    def __call__(self, name: str) -> "_Stopwatch":
        self._name = name
        return self

    def __enter__(self) -> None:
        self._t0 = time.perf_counter()

    def __exit__(self, *exc) -> None:
        self.out[self._name] = self.out.get(self._name, 0.0) + (time.perf_counter() - self._t0) * 1e3
