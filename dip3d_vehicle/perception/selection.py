"""Which candidate the diver points at: the paper's rule, and the project's default selector.

``paper``: ext = w + s_f (w - e); D_i = |(o_i - ext) x (w - ext)| / |w - ext|; target = argmin D_i,
over single matched features, ignoring which way the arm points.

``default``: features are grouped into objects (robust 3D centres); for each object a small
maximum-a-posteriori fit asks "could the arm be pointing at it?": the joints must lie on their
camera rays (the 2D image positions are precise) at depths consistent with the stereo depths and
their uncertainty (sigma_Z = Z^2 sigma_d / (f B)), with plausible limb lengths and a nearly
straight arm, and the object must lie AHEAD of the wrist (and not on the pointing hand itself,
``on_hand``) and near the ray from the shoulder
through the wrist (measured from the shoulder: seen from the wrist, a few degrees of pointing
error become tens of degrees for an object close to the hand). "Near" is a miss distance in
metres to points spread over the object, sigma = hypot(pointing_sigma * distance, tolerance),
averaged over the object's points (the diver points at some part of the object, not its centre). A pose
model that places its landmarks off the joints' centres (``ArmKeypoints.keypoint_sigma_m``, BlazePose
~5 cm at the body) widens the limb lengths, the bend and the pointing sigma by that error: at 5 m an
arm seen foreshortened says little about its tilt, and the fit must not pretend otherwise. The fit's
cost becomes a posterior over objects: confidence = posterior of the best, ambiguity margin =
difference in log-likelihood between the best and the second best (``selection.evidence: laplace``,
the Occam factor below, the default). The ``sampled`` evidence (``evidence.py``) instead averages the
pointing density at each object over draws of the arm weighted by the same priors, which keeps the
two tilts (toward / away) a foreshortened arm's limb lengths allow, where a Gaussian blurs them.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Callable, Mapping

import cv2
import numpy as np
from scipy.spatial import cKDTree

from .blobs import Blobs
from .calibration import StereoRig
from .candidates import HAND_LENGTH_M
from .evidence import arm_evidence
from .grouping import MATCH_SIGMA_PX, extent_m, group_objects, target_groups
from .joint_stereo import limb_spans_m
from .pointing_fit import SHAPE_POINTS, ArmModel, _PointingFit, _rays, object_shape
from .values import Arm3D, ArmKeypoints, Candidates, ObjectCandidate, Selection

__all__ = ["PointingSelector", "PaperSelector", "DefaultSelector", "OpenSet", "image_gate", "group_objects", "make_selector",
           "paper_distances", "on_hand", "hidden_behind"]

MAX_TILT_SIGMA_RAD = 0.25
"""Cap on the arm's tilt uncertainty (toward / away from the camera), radians: the anthropometric
limb lengths bound the tilt of an arm seen at its full image length to about +-25 deg, whose
standard deviation is 0.25 rad, however noisy the stereo depths of the joints."""

UnrecognisedSource = Callable[[list, list, np.ndarray], Blobs]
"""Called with the objects' feature pixels and 3D points (lists of arrays) and the arm's joints (3, 3), metres:
returns the unrecognised things along the arm that none of them explains (``Perception``'s blob finder)."""


class PointingSelector(ABC):
    """Chooses the candidate the pointing arm indicates."""

    method = "selector"

    @abstractmethod
    def select(self, arm: ArmKeypoints, arm3d: Arm3D, candidates: Candidates, xyz_m: np.ndarray,
               rig: StereoRig, unrecognised: UnrecognisedSource | None = None) -> Selection:
        """Return the selection among ``candidates`` (rectified px) with 3D points ``xyz_m``.

        ``unrecognised``: where to find the things along the arm no object explains (``blobs.py``);
        a selector that cannot use them ignores it.
        """


def paper_distances(wrist: np.ndarray, elbow: np.ndarray, points: np.ndarray, extension: float) -> np.ndarray:
    """Return the paper's D_i: distance of each point to the line through ext and w, metres."""
    ext = wrist + extension * (wrist - elbow)
    line = wrist - ext
    norm = np.linalg.norm(line)
    if norm == 0:
        return np.linalg.norm(points - wrist, axis=1)
    return np.linalg.norm(np.cross(points - ext, line), axis=1) / norm


class PaperSelector(PointingSelector):
    """The paper's selector: argmin perpendicular distance to the extended forearm line."""

    method = "paper"

    def __init__(self, extension_factor: float = 3.0) -> None:
        self.extension_factor = extension_factor

    def select(self, arm: ArmKeypoints, arm3d: Arm3D, candidates: Candidates, xyz_m: np.ndarray,
               rig: StereoRig, unrecognised: UnrecognisedSource | None = None) -> Selection:
        """Score every matched feature by D_i and choose the smallest (the paper knows no unrecognised things)."""
        dist = paper_distances(arm3d.joint("wrist"), arm3d.joint("elbow"), xyz_m, self.extension_factor)
        sig = rig.depth_sigma_m(xyz_m[:, 2], MATCH_SIGMA_PX)
        objects = tuple(ObjectCandidate(candidates.left_px[i], xyz_m[i], float(sig[i]), (i,))
                        for i in range(len(candidates)))
        if not objects:
            return Selection(None, (), np.zeros(0), 0.0, math.inf, self.method, True)
        order = np.argsort(dist)
        margin = float(dist[order[1]] - dist[order[0]]) if len(order) > 1 else math.inf
        return Selection(int(order[0]), objects, dist, 1.0, margin, self.method, False)


@dataclass(frozen=True)
class OpenSet:
    """The "nothing detected there" hypothesis of the default selector.

    Attributes:
        none_prior: prior probability that the pointed object produced no candidate at all
            (small, far, faint, hidden), before the arm is looked at.
        none_solid_angle_sr: solid angle (steradians, seen from the shoulder) over which such an
            undetected target is spread uniformly; an object competes with it through the pointing
            model's own angular density 1 / (2 pi sigma^2).
        gate_sigmas: an object farther than this many sigmas from the arm's direction IN THE LEFT
            IMAGE (or behind the wrist there) can never be chosen, whatever the 3D fit says.
        gate_min_rad: the image gate is never narrower than this, radians.
        none_min_probability: "nothing detected" is the answer when it is the most likely
            hypothesis with at least this probability (0.5: every object then has at most 0.5,
            below ``min_confidence``, so no decided pick is lost); below it, when it merely leads,
            the best object is returned flagged ambiguous. Per-frame status only: the
            probabilities, which the fused decision over the point uses, do not depend on it.
        same_target_gap_m: objects whose points come this close to the chosen one's are parts of
            the same target (a placard split into fragments) while together they fit in one target
            (``DefaultSelector.target_max_extent_m``): the confidence is their summed probability.
    """

    none_prior: float = 0.25
    none_solid_angle_sr: float = 1.0
    gate_sigmas: float = 4.0
    gate_min_rad: float = 0.26
    none_min_probability: float = 0.5
    same_target_gap_m: float = 0.1

    def log_prior(self, n_objects: int) -> float:
        """Return each of ``n_objects`` objects' log prior odds against "nothing detected"."""
        return math.log((1.0 - self.none_prior) / (n_objects * self.none_prior))


def image_gate(arm: ArmKeypoints, objects: list[ObjectCandidate], points_px: list[np.ndarray], rig: StereoRig,
               arm3d: Arm3D, model: ArmModel, open_set: OpenSet, pointing_sigma_rad: float | None = None) -> np.ndarray:
    """Return a bool per object: can the arm's direction in the left image point at it?

    The shoulder-to-wrist line in the image, seen from the shoulder, must pass within the gate of
    some point of the object, and the object must not lie behind the wrist along it. The gate
    widens when the arm is foreshortened (pointing toward or away from the camera: its image
    direction then says little) and with the keypoints' own noise over the arm's image length.
    """
    s2, w2 = arm.joint("shoulder"), arm.joint("wrist")
    axis = w2 - s2
    length_px = float(np.linalg.norm(axis))
    if length_px < 1.0:
        return np.ones(len(objects), bool)
    u = axis / length_px
    full_px = rig.focal_px * float(np.linalg.norm(arm3d.joint("wrist") - arm3d.joint("shoulder")))
    full_px /= max(float(arm3d.joint("shoulder")[2]), 0.1)
    shortening = float(np.clip(length_px / max(full_px, 1e-6), 0.1, 1.0))
    pointing = model.pointing_sigma_rad if pointing_sigma_rad is None else pointing_sigma_rad
    sigma = math.hypot(pointing / shortening, 2.0 * model.keypoint_sigma_px / length_px)
    gate = float(np.clip(open_set.gate_sigmas * sigma, open_set.gate_min_rad, math.pi / 2))
    keep = np.zeros(len(objects), bool)
    for k, pts in enumerate(points_px):
        rel = pts - s2
        along = rel @ u
        angle = np.arctan2(np.abs(rel[:, 0] * u[1] - rel[:, 1] * u[0]), along)
        ahead = along > length_px
        keep[k] = bool(np.any(ahead & (angle <= gate)))
    return keep


HAND_HALF_WIDTH_M = 0.07
"""Half the width of a gloved hand across the forearm's line, with room for stereo noise, metres."""


def on_hand(points_m: list[np.ndarray], depth_sigma_m: list[float], arm3d: Arm3D,
            reach_m: float = HAND_LENGTH_M, half_width_m: float = HAND_HALF_WIDTH_M) -> np.ndarray:
    """Return a bool per object (its 3D points, metres): does all of it lie where the pointing hand is?

    The hand beyond the wrist joint (glove, fingers) has texture of its own: matched, its features form an
    object a few centimetres ahead of the wrist, exactly on the arm's line, which the pointing fit then
    rates as the best pointed object there is (line_of_sight, seed 900, scene 9: a 3-feature object
    0.07 m from the wrist took P 0.53 from the pointed placard). The diver's own hand is never the
    target. The hand is a capsule: up to ``reach_m`` beyond the wrist along the forearm, ``half_width_m``
    across it, measured in the plane at the wrist's depth (each point's image position scaled to that
    depth, so a wrong stereo depth does not move it), and within ``reach_m`` of the wrist's depth beyond
    one sigma of both depths. EVERY point of the object must lie in it: a placard at arm's length, the
    hand in front of it, spreads beyond (variant_10_04: a 0.31 m placard 0.6 m from the diver's shoulder).
    """
    _, elbow, wrist = arm3d.xyz_m
    w2 = wrist[:2]
    e2 = elbow[:2] * (wrist[2] / max(float(elbow[2]), 1e-6))
    forearm = w2 - e2
    norm = float(np.linalg.norm(forearm))
    out = np.zeros(len(points_m), bool)
    if norm < 1e-6:
        return out
    u = forearm / norm
    for k, (pts, sigma) in enumerate(zip(points_m, depth_sigma_m)):
        pts = pts[np.all(np.isfinite(pts), axis=1) & (pts[:, 2] > 0)]
        if not len(pts):
            continue
        rel = pts[:, :2] * (wrist[2] / pts[:, 2:3]) - w2
        along = rel @ u
        across = np.abs(rel[:, 0] * u[1] - rel[:, 1] * u[0])
        gap = np.abs(pts[:, 2] - wrist[2]) - math.hypot(float(arm3d.depth_sigma_m[2]), sigma)
        out[k] = bool(np.all((along >= -half_width_m) & (along <= reach_m) & (across <= half_width_m)
                             & (gap <= reach_m)))
    return out


class DefaultSelector(PointingSelector):
    """Direction-aware, object-level, open-set selection with stereo depth uncertainty."""

    method = "default"

    def __init__(self, model: ArmModel = ArmModel(), group_radius_px: float = 20.0, group_radius_m: float = 0.05,
                 min_object_features: int = 3, min_confidence: float = 0.6, object_radius_m: float = 0.15,
                 open_set: OpenSet = OpenSet(), evidence: str = "laplace", evidence_samples: int = 2048,
                 unrecognised_weight: float = 1.0, target_max_extent_m: float = 0.6,
                 prior_per_target: bool = True) -> None:
        self.model, self.open_set = model, open_set
        self.prior_per_target = prior_per_target
        self.target_max_extent_m = target_max_extent_m
        self.unrecognised_weight = unrecognised_weight
        self.evidence, self.evidence_samples = evidence, evidence_samples
        self.object_radius_m = object_radius_m
        self.group_radius_px, self.group_radius_m = group_radius_px, group_radius_m
        self.min_object_features, self.min_confidence = min_object_features, min_confidence

    def select(self, arm: ArmKeypoints, arm3d: Arm3D, candidates: Candidates, xyz_m: np.ndarray,
               rig: StereoRig, unrecognised: UnrecognisedSource | None = None) -> Selection:
        """Group candidates into objects, fit the pointing hypothesis for each, return the posterior.

        The hypotheses are "the arm points at object i" for every object and "it points at
        something that was not detected"; their probabilities are absolute (they sum to 1). The
        latter includes each unrecognised thing ``unrecognised`` finds along the arm (a compact spot
        no object explains: ``blobs.py``), scored by the same pointing fit as an object, with an
        object's prior times ``unrecognised_weight``: never chosen, its probability is "nothing
        detected"'s.
        """
        objects = group_objects(candidates, xyz_m, rig, self.group_radius_px, self.group_radius_m,
                                self.min_object_features, self.object_radius_m, self.target_max_extent_m)
        if not objects:
            return Selection(None, (), np.zeros(0), 0.0, math.inf, self.method, True, 0.0,
                             "no object with enough matched features")
        n_prior, log_share = self._prior_shares(objects, candidates, rig)
        joints_px = np.c_[arm.left_px[:, 0], (arm.left_px[:, 1] + arm.right_px[:, 1]) / 2.0]  # rows: both eyes
        rays = _rays(joints_px, rig)
        given = arm.keypoint_sigma_m
        keypoint_sigma_m = self.model.keypoint_sigma_m if given is None else float(given)
        fit = _PointingFit(rays, arm3d.xyz_m[:, 2], arm3d.depth_sigma_m, self.model, keypoint_sigma_m)
        points = [xyz_m[list(o.members)] for o in objects]
        shapes = np.stack([object_shape(pts, o.xyz_m) for pts, o in zip(points, objects)])
        allowed = image_gate(arm, objects, [candidates.left_px[list(o.members)] for o in objects], rig, arm3d,
                             self.model, self.open_set, fit.pointing_sigma_rad)
        allowed &= ~on_hand(points, [o.depth_sigma_m for o in objects], arm3d)
        log_odds = np.full(len(objects), -np.inf)
        if np.any(allowed):  # an object the image gate rules out never wins: no evidence needed
            idx = np.flatnonzero(allowed)
            kept = [objects[i] for i in idx]
            if self.evidence == "sampled":
                log_odds[idx] = self._sampled_log_odds(fit, joints_px, arm3d, kept, shapes[idx], rig, n_prior)
            else:
                costs = fit.costs(_rays(np.array([o.left_px for o in kept]), rig), np.array([o.xyz_m[2] for o in kept]),
                                  np.array([o.depth_sigma_m for o in kept]), shapes[idx])
                log_odds[idx] = self._log_odds(costs, fit.arm_cost(), kept, arm, arm3d, fit.pointing_sigma_rad,
                                               n_prior)
            log_odds[idx] -= log_share[idx]
        spot_xyz, spots = self._unrecognised_log_odds(unrecognised, fit, arm, arm3d, objects, candidates, xyz_m, rig,
                                                      n_prior)
        none_log = float(np.logaddexp.reduce(np.r_[0.0, spots]))  # "nothing detected": uniform, or a spot
        top = max(float(log_odds.max()), none_log)
        weights = np.exp(log_odds - top)
        none_weight = math.exp(none_log - top)
        total = float(weights.sum()) + none_weight
        post, p_none = weights / total, none_weight / total
        spotted = tuple((xyz, float(math.exp(lo - top) / total)) for xyz, lo in zip(spot_xyz, spots))
        order = np.argsort(-log_odds)
        best = int(order[0])
        ranked = sorted([*log_odds.tolist(), none_log], reverse=True)
        margin = (ranked[0] - ranked[1]) if len(ranked) > 1 else math.inf
        # "nothing detected" is the answer when it is the confident winner (or no object is allowed);
        # when it merely leads, the best object is returned flagged ambiguous: no decision either way
        # fragments of one object (a placard split by its own texture, or its edge) are one target:
        # the best object's probability is that of every object whose points touch it, within one target's extent
        mass = float(post[_touching(objects, candidates, xyz_m, best, self.open_set.same_target_gap_m,
                                    self.target_max_extent_m, rig.focal_px, post)].sum())
        if not np.isfinite(log_odds[best]) or (p_none >= mass and p_none >= self.open_set.none_min_probability):
            seen = f", {len(spots)} unrecognised thing(s) along it" if len(spots) else ""
            why = (f"the arm points at nothing detected (P {p_none:.2f}{seen}); best object P {mass:.2f}"
                   if np.isfinite(log_odds[best]) else
                   "the arm points at nothing detected: every object lies outside the arm's direction in the image "
                   "or on the pointing hand")
            return Selection(None, tuple(objects), post, float(p_none), float(margin), self.method,
                             p_none < self.min_confidence, float(p_none), why, spotted)
        confidence = mass
        return Selection(best, tuple(objects), post, confidence, float(margin), self.method,
                         confidence < self.min_confidence, float(p_none), spots=spotted)

    def _prior_shares(self, objects: list[ObjectCandidate], candidates: Candidates,
                      rig: StereoRig) -> tuple[int, np.ndarray]:
        """Return the number of prior shares (1 - none_prior split evenly) and each object's log part of its share.

        With ``prior_per_target`` (the default since issue 11 session 70) objects that together could be one target
        (``target_groups``) split one share: a placard broken into 4 clusters of features by murky water no longer
        has 4 times the prior of one seen whole (issue 11 sessions 68-69, variant_41_15); without, every object has
        one share.
        """
        if not self.prior_per_target:
            return len(objects), np.zeros(len(objects))
        labels = target_groups(objects, candidates.left_px, rig.focal_px, self.target_max_extent_m)
        return int(labels.max()) + 1, np.log(np.bincount(labels)[labels])

    def _unrecognised_log_odds(self, unrecognised: UnrecognisedSource | None, fit: _PointingFit, arm: ArmKeypoints,
                               arm3d: Arm3D, objects: list[ObjectCandidate], candidates: Candidates, xyz_m: np.ndarray,
                               rig: StereoRig, n_prior: int) -> tuple[np.ndarray, np.ndarray]:
        """Return the unrecognised things the arm may point at (K, 3; metres) and their log odds against "nothing
        detected" (uniform), (K,).

        Each is a point hypothesis (the object's pointing fit with no extent of its own) with an object's
        prior times ``unrecognised_weight``; those outside the arm's image direction are left out, and so
        are those a recognised object hides from the diver (``hidden_behind``).
        """
        none = (np.zeros((0, 3)), np.zeros(0))
        if unrecognised is None or self.unrecognised_weight <= 0.0:
            return none
        object_points = [xyz_m[list(o.members)] for o in objects]
        blobs = unrecognised([candidates.left_px[list(o.members)] for o in objects], object_points, arm3d.xyz_m)
        if len(blobs) == 0:
            return none
        points = [ObjectCandidate(px, xyz, float(sig), ()) for px, xyz, sig in
                  zip(blobs.left_px, blobs.xyz_m, blobs.depth_sigma_m)]
        allowed = image_gate(arm, points, [px[None] for px in blobs.left_px], rig, arm3d, self.model, self.open_set,
                             fit.pointing_sigma_rad)
        pointing = self.model.pointing_sigma_rad if fit.pointing_sigma_rad is None else fit.pointing_sigma_rad
        allowed &= ~hidden_behind(blobs.xyz_m, blobs.depth_sigma_m, object_points, [o.depth_sigma_m for o in objects],
                                  arm3d.joint("shoulder"), pointing)
        if not np.any(allowed):
            return none
        kept = [p for p, ok in zip(points, allowed) if ok]
        costs = fit.costs(_rays(blobs.left_px[allowed], rig), blobs.xyz_m[allowed, 2], blobs.depth_sigma_m[allowed],
                          np.zeros((len(kept), SHAPE_POINTS, 3)))
        return blobs.xyz_m[allowed], (self._log_odds(costs, fit.arm_cost(), kept, arm, arm3d, fit.pointing_sigma_rad,
                                                     n_prior) + math.log(self.unrecognised_weight))

    def _sampled_log_odds(self, fit: _PointingFit, joints_px: np.ndarray, arm3d: Arm3D,
                          objects: list[ObjectCandidate], shapes: np.ndarray, rig: StereoRig,
                          n_objects: int) -> np.ndarray:
        """Return each object's log odds against "nothing detected", the evidence averaged over the arm's draws.

        ``n_objects`` is the number of prior shares (1 - none_prior split evenly: ``_prior_shares``). A
        pose model's own landmark error widens the limb lengths, the bend and the pointing spread as in the
        MAP fit (``fit``): drawn as image noise instead (~18 px at 2.5 m), it spreads the draws far wider
        than the pointing density and 2048 draws no longer estimate the evidence (the pointed placard of
        a bench frame at 0.09 with 2048 draws, 0.25 with 8192).
        """
        m, o = self.model, self.open_set
        ev = arm_evidence(joints_px, arm3d.xyz_m[:, 2], arm3d.depth_sigma_m, rig.focal_px, rig.principal_point_px,
                          m.keypoint_sigma_px,
                          m.forearm_m, m.upperarm_m, fit.length_sigma_m, fit.straightness_sigma_m,
                          fit.pointing_sigma_rad, m.object_extent_m,
                          [obj.xyz_m + shape for obj, shape in zip(objects, shapes)],
                          np.array([obj.depth_sigma_m for obj in objects]), self.evidence_samples)
        return o.log_prior(n_objects) + math.log(o.none_solid_angle_sr) + ev.log_density

    def _log_odds(self, costs: np.ndarray, arm_cost: float, objects: list[ObjectCandidate], arm: ArmKeypoints,
                  arm3d: Arm3D, pointing_sigma_rad: float | None = None, n_objects: int | None = None) -> np.ndarray:
        """Return each object's log odds against "nothing detected" (prior x likelihood ratio).

        ``n_objects``: the number of prior shares (1 - none_prior split evenly: ``_prior_shares``; default
        ``len(objects)``).

        "Nothing detected" spreads the target uniformly over ``none_solid_angle_sr``; an object
        concentrates it by the pointing model's density, widened by how well this frame's arm
        direction is known (Laplace's Occam factor: the stereo depths of shoulder and wrist leave
        the arm's tilt toward or away from the camera uncertain, its direction in the image is
        sharp). The exponent is the MAP fit's cost over the arm's own cost.
        """
        m, o = self.model, self.open_set
        shoulder, wrist = arm3d.joint("shoulder"), arm3d.joint("wrist")
        length_m = max(float(np.linalg.norm(wrist - shoulder)), 0.1)
        tilt = min(float(np.hypot(arm3d.depth_sigma_m[0], arm3d.depth_sigma_m[2])) / length_m, MAX_TILT_SIGMA_RAD)
        length_px = max(float(np.linalg.norm(arm.joint("wrist") - arm.joint("shoulder"))), 1.0)
        across = math.sqrt(2.0) * m.keypoint_sigma_px / length_px
        dist = np.array([float(np.linalg.norm(obj.xyz_m - shoulder)) for obj in objects])
        pointing = m.pointing_sigma_rad if pointing_sigma_rad is None else pointing_sigma_rad
        sigma2 = pointing ** 2 + (m.object_extent_m / np.maximum(dist, 0.1)) ** 2
        density = math.log(o.none_solid_angle_sr / (2.0 * math.pi)) - 0.5 * np.log((sigma2 + tilt ** 2) *
                                                                                 (sigma2 + across ** 2))
        return o.log_prior(n_objects or len(objects)) + density - (costs - arm_cost) / 2.0


def hidden_behind(spots_m: np.ndarray, spot_sigma_m: np.ndarray, objects_m: list[np.ndarray],
                  object_sigma_m: list[float], shoulder_m: np.ndarray, pointing_sigma_rad: float) -> np.ndarray:
    """Return a bool per spot (K, 3; metres): does a recognised object lie across the line from the shoulder to it?

    The line from the diver's shoulder to such a spot passes through the object's outline (the hull of its
    features seen along the line, grown by the pointing spread at the object's distance, ``pointing_sigma_rad``
    times it: a placard's features stop short of its edges, and the line is known no better than the pointing)
    nearer the diver by more than twice both depth sigmas (metres): the diver pointing that way points through
    the object first. Without this, a spot far down the pointing line (the end of a floor line 2 m behind the
    pointed placard, the line grazing the placard's features' hull 2-5 cm off) is a point hypothesis on the arm's
    line that fits it better than the placard's extent does, and its probability went to "nothing detected"
    (issue 11 session 63: variant_31_00 seed 1, "nothing there" at 0.92).
    """
    out = np.zeros(len(spots_m), bool)
    shoulder = np.asarray(shoulder_m, float)
    for k, (spot, sigma) in enumerate(zip(np.asarray(spots_m, float), spot_sigma_m)):
        line = spot - shoulder
        length = float(np.linalg.norm(line))
        if length < 1e-6:
            continue
        u = line / length
        e1 = np.cross(u, [0.0, 1.0, 0.0] if abs(u[1]) < 0.9 else [1.0, 0.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(u, e1)
        for pts, osig in zip(objects_m, object_sigma_m):
            pts = pts[np.all(np.isfinite(pts), axis=1)]
            if len(pts) < 3:
                continue
            rel = pts - shoulder
            along = float(np.median(rel @ u))
            if along + 2.0 * math.hypot(float(sigma), float(osig)) >= length:
                continue  # not plainly nearer the diver than the spot
            flat, grow = np.c_[rel @ e1, rel @ e2], pointing_sigma_rad * along
            if np.any(flat.min(axis=0) > grow) or np.any(flat.max(axis=0) < -grow):
                continue  # the line passes outside even the box round the outline
            hull = cv2.convexHull(flat.astype(np.float32))
            if len(hull) >= 3 and cv2.pointPolygonTest(hull, (0.0, 0.0), True) >= -grow:
                out[k] = True
                break
    return out


def _touching(objects: list[ObjectCandidate], candidates: Candidates, xyz_m: np.ndarray, best: int, gap_m: float,
              max_extent_m: float, focal_px: float, posterior: np.ndarray) -> np.ndarray:
    """Return a bool per object: is it a fragment of object ``best``'s target?

    A fragment's points come within ``gap_m`` (metres) of the best's, and the best with its fragments
    still fits in one target (``max_extent_m`` across the line of sight, ``grouping.extent_m``): two
    placards side by side are not one. Fragments are taken most probable first.
    """
    tree = cKDTree(xyz_m[list(objects[best].members)])
    out = np.zeros(len(objects), bool)
    out[best] = True
    members = list(objects[best].members)
    for k in np.argsort(-posterior, kind="stable"):
        pts = xyz_m[list(objects[k].members)]
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if out[k] or len(pts) == 0 or float(tree.query(pts, k=1)[0].min()) > gap_m:
            continue
        union = members + list(objects[k].members)
        if extent_m(candidates.left_px[union], float(np.median(xyz_m[union, 2])), focal_px) <= max_extent_m:
            out[k] = True
            members = union
    return out


def arm_model_from_params(params: Mapping) -> ArmModel:
    """Return the default selector's arm priors from ``selection.*`` parameters."""
    upperarm_m, forearm_m = limb_spans_m(params)   # the same spans the stereo limb check reads
    return ArmModel(params["selection.keypoint_sigma_px"], params["selection.pointing_sigma_rad"], forearm_m,
                    upperarm_m, params["selection.object_extent_m"])


def open_set_from_params(params: Mapping) -> OpenSet:
    """Return the default selector's "nothing detected" hypothesis from ``selection.*`` parameters."""
    return OpenSet(params["selection.none_prior"], params["selection.none_solid_angle_sr"],
                   params["selection.gate_sigmas"], params["selection.gate_min_rad"],
                   params["selection.none_min_probability"], params["selection.same_target_gap_m"])


def make_selector(params: Mapping) -> PointingSelector:
    """Return the selector named by ``selection.method``."""
    if params["selection.method"] == "paper":
        return PaperSelector(params["selection.extension_factor"])
    return DefaultSelector(arm_model_from_params(params), params["selection.group_radius_px"],
                           params["selection.group_radius_m"], params["selection.min_object_features"],
                           params["selection.min_confidence"], params["selection.object_radius_m"],
                           open_set_from_params(params), params["selection.evidence"],
                           params["selection.evidence_samples"], params["selection.unrecognised_weight"],
                           params["selection.target_max_extent_m"], params["selection.prior_per_target"])
