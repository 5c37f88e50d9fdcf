"""One decision over the whole point: the frames' posteriors fused into one, "nothing detected" included.

Each frame with a raised arm gives the open-set selector's absolute probabilities: one per object
it scored (``Selection.scores``) and ``Selection.none_probability`` that the arm points at nothing
detected. The hypotheses over the whole point are the objects (clustered by 3D position across
frames: the vehicle holds still while it watches) and "none". Their fused log score is

    L(h) = w * sum_frames log max(p_frame(h), floor_p),   w = min(temper, 1 / W, max_effective_frames / n)

(an object a frame did not see gets ``floor_p``: that frame gave it no support; but with
``recall_s`` an object an earlier frame of the point saw is first recalled into the frame,
``recall``, and scored with its arm, and one first seen late starts from "none"'s frames), and the
fused posterior is softmax(L). ``temper`` < 1 accounts for the frames not being independent (the same
pointing error, the same scene): with ``temper`` = 0.5, six frames count as three independent ones.
Each frame is decided with the mean arm of the last W frames (``held_arm``,
``behaviour.fusion_arm_frames``), so one frame's keypoints (and their noise) are in W frames' arms:
the exponent is at most 1 / W, so that the frames together count each arm they measured once (with
0.5, an unlucky few frames' noise counted twice: a murky layout's arm leaning 0.63 to the wrong
placard after 6 frames fused to 0.93, issue 11, session 17). And however long the diver holds, the n
frames never count as more than ``max_effective_frames`` independent ones (a systematic lean of an
ambiguous selector does not become certainty with time: past that, the fused score is the frames'
mean log probability times ``max_effective_frames``). A frame whose arm was fine but that found no
object at all counts as ``no_objects_none_p`` for "none". The geometry is averaged too: each
object's position is the probability-weighted mean of its sightings; objects of one frame on one
hypothesis are its fragments and add up, while together they fit one target (``max_extent_m``).
Every frame's part (its log probability per hypothesis) is kept for the story and the log.

The frames of one held point share errors no number of frames averages away: the diver's own
pointing error (the arm aims a few degrees off the object, the same in every frame) and, with a pose
model that places its landmarks off the joints' centres (``ArmKeypoints.keypoint_sigma_m``:
BlazePose), that model's landmark error. Such frames are one look, not several: the winner must also
hold with the frames counted as ONE (the posterior from the frames' mean log probabilities) at
``min_shared_posterior``. ``shared_rule`` says when: "always" (the diver's pointing error is in every
point) or "pose_model" (only frames whose arms carry ``keypoint_sigma_m``). A steady lean of
ambiguous frames (far_diver at 5 m, BlazePose: 0.5 for a wrong placard frame after frame, issue 14;
far_diver seed 8, truth pose, sampled evidence: a wrong placard 4.7 deg from the arm against the
pointed one's 5.0, issue 11) is not made certain by repetition.

Pure data and arithmetic: no clock, no link.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import cv2
import numpy as np

from dip3d_vehicle.perception.grouping import extent_m
from dip3d_vehicle.perception.held_arm import HeldArm
from dip3d_vehicle.perception.pipeline import PerceptionResult
from dip3d_vehicle.perception.values import Candidates, ObjectCandidate

from .evidence import Vote
from .spot_ledger import SpotLedger

__all__ = ["NONE", "SHARED_RULES", "Hypothesis", "FrameEvidence", "FusedDecision", "PointFusion", "frame_probabilities"]

NONE = "none"
"""The name of the "nothing detected along the arm" hypothesis."""

POOL_SIGHTINGS = 30
"""How many of a hypothesis's latest sightings (objects) it keeps for the tracker's model."""

SHARED_RULES = ("always", "pose_model")
"""When the "counted as one" check applies: every point, or only frames with a pose model's own error."""


@dataclass
class Hypothesis:
    """One object over the frames: averaged position, latest sighting, and how often it led a frame.

    Attributes:
        key: "o1", "o2", ... in order of first sighting.
        xyz_m: probability-weighted mean 3D centre (camera frame, metres).
        weight: summed per-frame probability (the mean's weight).
        log_sum: summed log probability (floored) over the counted frames.
        led: frames in which it had the highest probability of all hypotheses (none included).
        obj, candidates, stamp_s: its sighting for the tracker (``_tracker_sighting``).
        best_p: its highest single-frame probability.
        pool: its sightings, (object, its frame's candidates) for every object that fell on it, newest
            first (the tracker's model for a target whose sighting holds few; at most ``POOL_SIGHTINGS``).
        across_m: the widest span across the line of sight of one sighting's 3D features, metres (the largest
            over its sightings; 0 until a sighting with two features ahead of the camera): how far its edge
            lies from its centre, for the servo's clearance (``behaviour.servo_clearance_m``).
    """

    key: str
    xyz_m: np.ndarray
    weight: float
    log_sum: float
    led: int = 0
    obj: ObjectCandidate | None = None
    candidates: Candidates | None = None
    stamp_s: float = 0.0
    best_p: float = 0.0
    pool: list = field(default_factory=list)
    across_m: float = 0.0


@dataclass(frozen=True)
class FrameEvidence:
    """One frame's part in the fused decision: its probability per hypothesis key ("none" included)."""

    stamp_s: float
    status: str
    probabilities: dict

    def summary(self) -> str:
        """Return e.g. ``t=3.20 ok o1 0.62 o2 0.30 none 0.08``."""
        parts = " ".join(f"{k} {p:.2f}" for k, p in sorted(self.probabilities.items(), key=lambda kv: -kv[1]))
        return f"t={self.stamp_s:.2f} {self.status} {parts}"


@dataclass(frozen=True)
class FusedDecision:
    """The fused posterior and what it decides.

    Attributes:
        kind: "object" (a winner), "none" (nothing detected wins), or "undecided".
        winner: the winning object's Hypothesis (kind "object"), else None.
        posterior: fused probability per hypothesis key ("none" included), summing to 1.
        best, second: the two most probable keys (second may be None).
        frames: frames fused.
        reason: one line.
        one_look: the best hypothesis' posterior with the frames counted as ONE look (None: no
            frame). The frames of a point share the diver's pointing error, so this, not
            ``posterior[best]``, is what the point says about it once: a steady lean of 0.8 per
            frame fuses to ~1.0 but stays 0.8 here (issue 11's near_miss).
        one_look_posterior: every hypothesis' posterior with the frames counted as one look ("none"
            included; empty: no frame): where the rest of the doubt lies, on other objects or on
            "nothing detected".
    """

    kind: str
    winner: Hypothesis | None
    posterior: dict
    best: str | None
    second: str | None
    frames: int
    reason: str
    one_look: float | None = None
    one_look_posterior: dict = field(default_factory=dict)

    def record(self, t_s: float) -> dict:
        """Return a small record of the decision at ``t_s`` seconds: kind, frames, fused and one-look posterior.

        ``one_look_posterior`` holds the best hypothesis, the best other object and "none" (rounded).
        """
        p = self.posterior.get(self.best) if self.best is not None else None
        return {"t_s": round(t_s, 3), "kind": self.kind, "frames": self.frames,
                "posterior": None if p is None else round(p, 4),
                "one_look": None if self.one_look is None else round(self.one_look, 4),
                "one_look_posterior": self._one_look_summary()}

    def _one_look_summary(self) -> dict:
        """Return the one-look posterior of the best hypothesis, the best other object and "none", rounded."""
        post = self.one_look_posterior
        others = sorted((k for k in post if k not in (self.best, NONE)), key=post.get, reverse=True)
        keys = [k for k in (self.best, *others[:1], NONE) if k in post]
        return {k: round(post[k], 4) for k in dict.fromkeys(keys)}

    def summary(self) -> str:
        """Return the posterior as text, best first, e.g. ``o1 0.93, none 0.05, o2 0.02``."""
        return ", ".join(f"{k} {p:.2f}" for k, p in sorted(self.posterior.items(), key=lambda kv: -kv[1]))


def frame_probabilities(result: PerceptionResult, no_objects_none_p: float) -> tuple[list, float] | None:
    """Return ([(object, probability), ...], none probability) of one frame, or None if it says nothing.

    A frame says something when the arm passed the checks: statuses "ok" and "nothing_on_ray"
    (the selector's absolute probabilities; mass they leave unassigned counts for "none"; the paper
    selector's choice counts as certain) and
    "no_candidates" (no object at all: "none" with ``no_objects_none_p``, the rest unassigned).
    The none probability includes the unrecognised spots' (``Selection.spots``).
    """
    sel = result.selection
    if result.status in ("ok", "nothing_on_ray") and sel is not None and len(sel.objects):
        if sel.method != "default":
            objs = [(o, 1.0 if i == sel.index else 0.0) for i, o in enumerate(sel.objects)]
            return objs, 0.0 if sel.index is not None else 1.0
        scores = np.clip(np.nan_to_num(np.asarray(sel.scores, dtype=float), nan=0.0), 0.0, 1.0)
        rest = max(0.0, 1.0 - float(scores.sum()) - float(sel.none_probability))  # unnamed mass: not an object
        return [(o, float(scores[i])) for i, o in enumerate(sel.objects)], float(sel.none_probability) + rest
    if result.status == "no_candidates" and result.arm3d is not None:
        return [], float(no_objects_none_p)
    return None


def _tracker_sighting(h: Hypothesis, obj: ObjectCandidate, same_frame: bool) -> bool:
    """True when ``obj`` should become ``h``'s sighting for the tracker (its appearance model and start).

    The tracker knows the chosen target by its sighting's features only, and predicts it from the
    sighting's time. So the latest frame's sighting is taken (an older one would be dead-reckoned
    through the nod: variant_10_01 seed 1 then lost its target twice), and within that frame the
    largest object on the hypothesis. A fragment (a placard split into a large and a 3-feature
    cluster, the fragment second in its frame) gave a 3-descriptor model, which matched a
    neighbouring placard 0.86 m away at once: variant_10_03 seed 1 decided placard 2 at p 0.94 and
    arrived at placard 3 (issue 11, session 22).
    """
    return not same_frame or h.obj is None or len(obj.members) > len(h.obj.members)


def _ahead(xyz_m: np.ndarray) -> np.ndarray:
    """Return the 3D points (camera frame, metres) with a finite position ahead of the camera."""
    return xyz_m[np.all(np.isfinite(xyz_m), axis=1) & (xyz_m[:, 2] > 0)]


def _across_m(xyz_m: np.ndarray) -> float:
    """Return the widest span of 3D points (camera frame, metres) across the line of sight at their median depth, m.

    Points with no finite position or not ahead of the camera are left out.
    """
    pts = _ahead(xyz_m)
    if len(pts) < 2:
        return 0.0
    return extent_m(pts[:, :2] / pts[:, 2:3], float(np.median(pts[:, 2])), 1.0)


def _span_m(obj: ObjectCandidate, points_m: np.ndarray) -> float:
    """Return the widest span of ``obj``'s 3D features (rows of ``points_m``) across the line of sight, m."""
    members = np.asarray(obj.members, dtype=int)
    if not len(members) or members.max() >= len(points_m):
        return 0.0
    return _across_m(points_m[members])


def _pool(h: Hypothesis, obj: ObjectCandidate, candidates: Candidates) -> None:
    """Put the sighting ``obj`` (members index into ``candidates``) first in ``h``'s pool (the newest
    ``POOL_SIGHTINGS`` kept)."""
    h.pool.insert(0, (obj, candidates))
    del h.pool[POOL_SIGHTINGS:]


@dataclass
class PointFusion:
    """Accumulates the frames of one point into the fused posterior.

    Args:
        radius_m: an object within this distance of a hypothesis' mean position is that hypothesis.
        temper: exponent on each frame's probabilities (frame correlation), in (0, 1].
        floor_p: the smallest probability a frame gives any hypothesis (also for unseen objects).
        no_objects_none_p: "none" probability of a frame that found no object at all.
        max_effective_frames: the most independent frames the whole point may count as.
        min_shared_posterior: a point whose frames share one error (``shared_error``) needs this
            posterior with its frames counted as one.
        min_pose_shared_posterior: the same when the frames' arms carry a pose model's own landmark error
            (``pose_error``), which every frame of the held pose repeats too (the higher of the two applies).
        shared_rule: "always" (every point: the diver's pointing error) or "pose_model" (only frames
            whose arms carry ``keypoint_sigma_m``).
        recall_s: a frame's missed detection is not a vote against an object (0: off, it is). An
            object seen within this many seconds and missed by the frame is recalled into it
            (``recall``); one first seen late starts from "none"'s frames, not the floor's (``add``).
        max_extent_m: objects of one frame whose features together span more than this across the
            line of sight (metres) are never one hypothesis (``add``; inf: any within ``radius_m`` are).
        spot_support: an unrecognised spot of a frame (``Selection.spots``, part of its "none") within
            ``radius_m`` of a hypothesis that frame found no object on supports that hypothesis instead,
            also back in the earlier frames of a hypothesis first seen late (``_spot_support``,
            ``_back_support``; with ``recall_s`` those frames are "none"'s anyway: not back).

    Raises:
        ValueError: an unknown ``shared_rule``.
    """

    radius_m: float
    temper: float = 0.5
    floor_p: float = 0.02
    no_objects_none_p: float = 0.8
    max_effective_frames: float = 4.0
    min_shared_posterior: float = 0.5
    shared_rule: str = "always"
    min_pose_shared_posterior: float = 0.5
    recall_s: float = 0.0
    max_extent_m: float = math.inf
    spot_support: bool = False
    shared_error: bool = False
    pose_error: bool = False
    direction: np.ndarray | None = None
    hypotheses: list[Hypothesis] = field(default_factory=list)
    none_log_sum: float = 0.0
    none_led: int = 0
    frames: list[FrameEvidence] = field(default_factory=list)
    held_arm: HeldArm = field(default_factory=lambda: HeldArm(1))
    spots: SpotLedger | None = None

    def __post_init__(self) -> None:
        if self.shared_rule not in SHARED_RULES:
            raise ValueError(f"PointFusion shared_rule {self.shared_rule!r}: expected one of {', '.join(SHARED_RULES)}")
        self.spots = SpotLedger(self.radius_m)

    def reset(self) -> None:
        """Forget every frame (a new point, or a new viewpoint)."""
        self.hypotheses, self.none_log_sum, self.none_led, self.frames = [], 0.0, 0, []
        self.spots.clear()
        self.direction = None
        self.shared_error = self.pose_error = False
        self.held_arm.clear()

    @property
    def weight(self) -> float:
        """The exponent on every frame: ``min(temper, 1 / arm window, max_effective_frames / frames)``."""
        return min(self.temper, 1.0 / self.held_arm.window, self.max_effective_frames / max(len(self.frames), 1))

    def _log(self, p: float) -> float:
        return math.log(max(float(p), self.floor_p))

    def match(self, xyz: np.ndarray) -> Hypothesis | None:
        """Return the nearest hypothesis within ``radius_m`` of ``xyz`` (camera frame, m), or None."""
        return next(iter(self._near(xyz)), None)

    def _near(self, xyz: np.ndarray) -> list[Hypothesis]:
        """Return the hypotheses within ``radius_m`` of ``xyz`` (camera frame, m), nearest first."""
        dist = [(float(np.linalg.norm(h.xyz_m - xyz)), i) for i, h in enumerate(self.hypotheses)]
        return [self.hypotheses[i] for d, i in sorted(dist) if d <= self.radius_m]

    def _home(self, obj: ObjectCandidate, xyz: np.ndarray, taken: dict, points_m: np.ndarray) -> Hypothesis | None:
        """Return the hypothesis a frame's object falls on: the nearest within ``radius_m`` whose objects of
        this frame (``taken``: key -> feature indices) it fits one target with (``max_extent_m`` across the line
        of sight, ``points_m``: the frame's 3D features; members without a point are summed as before), or
        None (a new hypothesis).

        Objects of one frame that fall on one hypothesis are fragments of one object; two placards 0.35 m
        apart are not: summed, they made one hypothesis of 0.93 per frame, and the tracker was started on
        the wrong one (issue 11 session 47, side_by_side seed 0).
        """
        for h in self._near(xyz):
            if h.key not in taken or not math.isfinite(self.max_extent_m):
                return h
            union = np.concatenate([taken[h.key], np.asarray(obj.members, dtype=int)])
            if not len(union) or union.max() >= len(points_m) or _across_m(points_m[union]) <= self.max_extent_m:
                return h
        return None

    def _within(self, obj: ObjectCandidate, points_m: np.ndarray, span_m: float) -> list[Hypothesis]:
        """Return the hypotheses an object wider than one target holds: empty when it fits one target.

        An object wider than ``max_extent_m`` across the line of sight is not one target: two placards
        chained into one object by the grouping. Such a frame says "one of these", so the object supports
        every hypothesis whose centre lies in its features' hull (the camera's image plane, depth within
        ``radius_m``) alike and sights none; fused as one object, it gave its whole probability to the
        nearest placard, and the tracker the chain's centre (issue 11 sessions 48-49, side_by_side_close seed 1).
        Empty also when it holds no hypothesis (it is then fused as any object). ``span_m``: the object's own span
        across the line of sight (``_span_m``), metres.
        """
        members = np.asarray(obj.members, dtype=int)
        if not math.isfinite(self.max_extent_m) or not self.hypotheses or not len(members) \
                or members.max() >= len(points_m):
            return []
        pts = _ahead(points_m[members])
        if len(pts) < 3 or not span_m > self.max_extent_m:
            return []
        hull = cv2.convexHull((pts[:, :2] / pts[:, 2:3]).astype(np.float32))
        z = float(np.median(pts[:, 2]))
        return [h for h in self.hypotheses if abs(float(h.xyz_m[2]) - z) <= self.radius_m and cv2.pointPolygonTest(
            hull, (float(h.xyz_m[0] / h.xyz_m[2]), float(h.xyz_m[1] / h.xyz_m[2])), False) >= 0]

    def add(self, result: PerceptionResult, stamp_s: float, arm_frames: int = 1) -> FrameEvidence | None:
        """Fuse one frame (with a raised arm); return its part, or None when the frame says nothing.

        Objects of one frame that fall on the same hypothesis (a placard split into two clusters)
        add their probabilities: the frame's part for that hypothesis is their sum, while together
        they fit one target (``max_extent_m``; else the next nearest hypothesis, or a new one). An
        object wider than one target adds its probability to each hypothesis it holds (``_within``).
        ``arm_frames``: how many frames' arms the frame was decided with (the held arm's mean; for the story).
        """
        probs = frame_probabilities(result, self.no_objects_none_p)
        if probs is None:
            return None
        if result.arm is not None and result.arm.keypoint_sigma_m:
            self.shared_error = self.pose_error = True
        if self.shared_rule == "always":
            self.shared_error = True
        objects, p_none = probs
        floor = self._log(0.0)
        seen: dict[str, float] = {}
        fresh = len(result.candidates) - result.recalled
        taken: dict[str, np.ndarray] = {}
        either: dict[str, float] = {}
        for obj, p in sorted(objects, key=lambda op: -op[1]):
            xyz = np.asarray(obj.xyz_m, dtype=float)
            if not np.all(np.isfinite(xyz)):
                continue
            span = _span_m(obj, result.candidates_xyz_m)
            within = self._within(obj, result.candidates_xyz_m, span)
            if within:  # wider than one target: evidence for each hypothesis it holds, a sighting of none
                for h in within:
                    either[h.key] = either.get(h.key, 0.0) + p
                continue
            h = self._home(obj, xyz, taken, result.candidates_xyz_m)
            if h is not None:
                taken[h.key] = np.concatenate([taken.get(h.key, np.zeros(0, int)), np.asarray(obj.members, dtype=int)])
            if min(obj.members, default=0) >= fresh:  # recalled alone: scored with this frame's arm, not sighted
                if h is not None:
                    seen[h.key] = seen.get(h.key, 0.0) + p
                continue
            if h is None:
                h = Hypothesis(f"o{len(self.hypotheses) + 1}", xyz.copy(), 0.0, self._unseen_log_sum(floor))
                self.hypotheses.append(h)
                self._back_support(h)
            w = max(p, 1e-6)
            h.xyz_m = (h.weight * h.xyz_m + w * xyz) / (h.weight + w)
            h.weight += w
            if _tracker_sighting(h, obj, h.key in seen):
                h.obj, h.candidates, h.stamp_s = obj, result.candidates, stamp_s
            _pool(h, obj, result.candidates)
            h.across_m = max(h.across_m, span)
            seen[h.key] = seen.get(h.key, 0.0) + p
        moved, unclaimed = self._spot_support(result, seen, either)
        p_none -= moved
        for h in self.hypotheses:
            support = seen.get(h.key, 0.0) + either.get(h.key, 0.0)
            h.log_sum += self._log(support) if h.key in seen or h.key in either else floor
            if h.key in seen:
                h.best_p = max(h.best_p, seen[h.key])
        self.none_log_sum += self._log(p_none)
        part = dict(seen, **{NONE: p_none})
        leader = max(part, key=part.get)
        if leader == NONE and p_none < max(either.values(), default=0.0):
            leader = None  # "one of these" outweighs "none": no one led the frame
        part = {k: part.get(k, 0.0) + either.get(k, 0.0) for k in {**part, **either}}
        if leader is not None:
            self._count_led(leader, +1)
        ev = FrameEvidence(stamp_s, result.status if arm_frames < 2 else f"{result.status}/arm{arm_frames}", part)
        self.frames.append(ev)
        if self.spot_support:  # the ledger is read only by the back support
            self.spots.record(unclaimed, p_none, leader)
        return ev

    def _spot_support(self, result: PerceptionResult, seen: dict, either: dict) -> tuple[float, list]:
        """Move each unrecognised spot's probability from "none" to the hypothesis it lies on; return the sum moved
        and the spots left to "none".

        Only onto a hypothesis (within ``radius_m``) this frame found no object on: there the spot is the
        object seen a feature or two short of being recognised. A faint far placard recognised in some frames
        of a point shows as spots on its face in the others, which voted "nothing detected" (0.8-1.0 each):
        "none" won over the placard the arm pointed at (issue 11 session 63: variant_31_07 seed 2, variant_31_05
        seed 1). ``seen`` gains the support (no sighting: the tracker's model is unchanged).
        """
        sel = result.selection
        if not self.spot_support or sel is None or not sel.spots:
            return 0.0, []
        support, rest = self.spots.claim(sel.spots, self.match, set(seen) | set(either))
        for key, p in support.items():
            seen[key] = seen.get(key, 0.0) + p
        return float(sum(support.values())), rest

    def _back_support(self, h: Hypothesis) -> None:
        """Give a hypothesis first seen now the earlier frames' unclaimed spots on it, taken from their "none".

        Each such frame's part in ``h.log_sum`` becomes its spots' probability instead of the floor, "none"'s
        loses it, and the frame's leader is recounted (the part kept for the story changes with them). Without
        it, a 4 cm target first recognised after the close in started from the floor in every earlier frame
        while its spots there, now given to it in the later frames, no longer held "none" up: the decoy won
        (issue 11 session 63: near_miss seed 3, fused 0.95 at one look 0.59).
        """
        if not self.spot_support or self.recall_s > 0.0:
            return
        floor = self._log(0.0)
        for j, p in self.spots.claim_back(h.xyz_m):
            frame, part = self.spots.frames[j], self.frames[j].probabilities
            h.log_sum += self._log(p) - floor
            self.none_log_sum += self._log(frame.none_p - p) - self._log(frame.none_p)
            frame.none_p -= p
            part[h.key], part[NONE] = p, frame.none_p
            leader = max(part, key=part.get)
            if frame.leader is not None and leader != frame.leader:
                self._count_led(frame.leader, -1)
                self._count_led(leader, +1)
                frame.leader = leader

    def _count_led(self, key: str, step: int) -> None:
        """Add ``step`` to the frames led by the hypothesis ``key`` ("none" included)."""
        if key == NONE:
            self.none_led += step
        else:
            self.hypothesis(key).led += step

    def _unseen_log_sum(self, floor: float) -> float:
        """Return a new hypothesis' log sum over the frames before its first sighting.

        With recall on, "none"'s: in those frames it was one of the undetected objects "none" stands
        for. With the floor (recall off) an object first detected late could never win, and once
        recalled it took "none"'s share of the later frames: ``near_miss`` seed 3 (truth pose) found
        the 4 cm pointed placard after 50 frames of the point, and the decoy won at one look 0.57
        (issue 11, session 39).
        """
        return self.none_log_sum if self.recall_s > 0.0 else len(self.frames) * floor

    def recall(self, result: PerceptionResult, stamp_s: float) -> Candidates | None:
        """Return the sighted features of every hypothesis this frame found no object on, or None.

        Only sightings at most ``recall_s`` seconds before ``stamp_s`` are recalled (0: none). The
        vehicle holds still while it watches a point (the evidence restarts when the viewpoint
        changes), so an object seen in one frame is there in the next. A small, far or faint one is
        often missed in some frames (a feature or two short of an object, or outside a zoom box), and
        such a frame gave it the floor probability: the detector's miss counted as the arm pointing
        elsewhere. Recalled, it is scored with every frame's arm (``held_arm.decide_held``):
        ``variant_9_03`` seed 1 from BlazePose's arm decided the other placard on the pointed one's
        image line, seen in every frame, at one look 0.78 (issue 11, session 39).
        """
        if self.recall_s <= 0.0 or not self.hypotheses:
            return None
        sel = result.selection
        found = [np.asarray(o.xyz_m, float) for o in (sel.objects if sel is not None else ())]
        parts = []
        for h in self.hypotheses:
            if h.obj is None or h.candidates is None or stamp_s - h.stamp_s > self.recall_s:
                continue
            if any(float(np.linalg.norm(xyz - h.xyz_m)) <= self.radius_m for xyz in found):
                continue
            parts.append(h.candidates.subset(np.asarray(h.obj.members, dtype=int)))
        if not parts:
            return None
        out = parts[0]
        for part in parts[1:]:
            out = out.stacked(part)
        return out

    def posterior(self, weight: float | None = None) -> dict:
        """Return the fused posterior per hypothesis key ("none" included), summing to 1.

        ``weight``: the exponent on every frame instead of ``self.weight`` (1 / frames: the frames
        counted as one).
        """
        w = self.weight if weight is None else weight
        logs = {h.key: w * h.log_sum for h in self.hypotheses}
        logs[NONE] = w * self.none_log_sum
        top = max(logs.values())
        w = {k: math.exp(v - top) for k, v in logs.items()}
        total = sum(w.values())
        return {k: v / total for k, v in w.items()}

    def decide(self, min_posterior: float, min_led: int) -> FusedDecision:
        """Decide when the best hypothesis has ``min_posterior`` and led at least ``min_led`` frames.

        The leading-frames count keeps the per-frame safety of the old vote: a hypothesis wins only
        when single frames chose it too, not from the floors of its rivals alone.
        """
        n = len(self.frames)
        if n == 0:
            return FusedDecision("undecided", None, {}, None, None, 0, "no frame with evidence")
        post = self.posterior()
        ranked = sorted(post, key=post.get, reverse=True)
        best, second = ranked[0], (ranked[1] if len(ranked) > 1 else None)
        looked = self.posterior(1.0 / n)
        one = looked[best]
        led = self.none_led if best == NONE else next(h.led for h in self.hypotheses if h.key == best)
        if post[best] < min_posterior:
            why = f"fused {best} {post[best]:.2f} < {min_posterior:g} over {n} frames"
            return FusedDecision("undecided", None, post, best, second, n, why, one, looked)
        if led < min_led:
            why = f"{best} led {led} of {n} frames (< {min_led})"
            return FusedDecision("undecided", None, post, best, second, n, why, one, looked)
        need = max(self.min_shared_posterior, self.min_pose_shared_posterior if self.pose_error else 0.0)
        if self.shared_error and best != NONE and one < need:
            cause = "the pose model's and the diver's pointing error" if self.pose_error else "the diver's pointing error"
            why = f"{best} {one:.2f} < {need:g} with the {n} frames counted as one (they share {cause})"
            return FusedDecision("undecided", None, post, best, second, n, why, one, looked)
        looks = f"{one:.2f} counted as one look"
        if best == NONE:
            return FusedDecision("none", None, post, best, second, n, f"nothing detected: fused {post[best]:.2f}, {looks}",
                                 one, looked)
        h = next(h for h in self.hypotheses if h.key == best)
        return FusedDecision("object", h, post, best, second, n, f"fused {post[best]:.2f} over {n} frames, {looks}", one,
                             looked)

    def hypothesis(self, key: str) -> Hypothesis | None:
        """Return the object hypothesis with this key, or None."""
        return next((h for h in self.hypotheses if h.key == key), None)

    def as_vote(self, h: Hypothesis) -> Vote:
        """Return a hypothesis as the mission's chosen-target record (``Blackboard.chosen``)."""
        return Vote(h.xyz_m.copy(), h.weight, h.led, h.obj, h.candidates, h.stamp_s, list(h.pool))

    def describe(self) -> str:
        """Return the hypotheses' averaged positions, e.g. ``o1 (0.46, -0.21, 2.96) led 5``."""
        parts = [f"{h.key} ({', '.join(f'{c:.2f}' for c in h.xyz_m)}) led {h.led}" for h in self.hypotheses]
        return "; ".join(parts + [f"none led {self.none_led}"])
