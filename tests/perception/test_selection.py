"""Selectors: the paper's rule on hand-computed cases; the default selector's direction awareness."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.calibration import StereoRig
from dip3d_vehicle.perception.pipeline import Perception
from dip3d_vehicle.perception.selection import DefaultSelector, PaperSelector, paper_distances
from dip3d_vehicle.perception.triangulation import normalize_q, triangulate
from dip3d_vehicle.perception.values import ArmKeypoints, Candidates

K = np.array([[1000.0, 0, 800], [0, 1000.0, 600], [0, 0, 1]])
RIG = StereoRig.from_parameters(K, np.zeros(5), K, np.zeros(5), np.eye(3), [-0.12, 0, 0], (1600, 1200))


def project(xyz: np.ndarray, tx: float = 0.0) -> np.ndarray:
    """Project rectified-frame points (m) to pixels of the left (tx=0) or right (tx=-B) camera."""
    p = (np.atleast_2d(xyz) + [tx, 0, 0]) @ K.T
    return p[:, :2] / p[:, 2:]


def arm_from_3d(joints: np.ndarray) -> ArmKeypoints:
    """Return exact keypoints of 3D joints (rows shoulder, elbow, wrist) in both images."""
    return ArmKeypoints("right", project(joints), project(joints, -0.12), np.ones(3), np.ones(3))


def cluster(centre: np.ndarray, n: int = 12, half: float = 0.1, seed: int = 0) -> np.ndarray:
    """Return n points on a square patch (facing the camera) around centre, metres."""
    rng = np.random.default_rng(seed)
    return centre + np.c_[rng.uniform(-half, half, (n, 2)), np.zeros(n)]


def candidates_of(points: np.ndarray) -> tuple[Candidates, np.ndarray]:
    """Return exact candidates (both images) and their triangulated xyz."""
    c = Candidates(project(points), project(points, -0.12))
    return c, triangulate(normalize_q(RIG.Q, RIG.disparity_sign), c.left_px, c.disparity_px)


def test_paper_distance_hand_computed():
    """w=(0,0,2), e=(-0.3,0,2): ext=(0.9,0,2); the line is the x axis at z=2."""
    w, e = np.array([0.0, 0, 2]), np.array([-0.3, 0, 2])
    pts = np.array([[2.0, 0.5, 2.0], [1.0, 0.0, 2.3], [-5.0, 0.1, 2.0]])
    d = paper_distances(w, e, pts, 3.0)
    assert d == pytest.approx([0.5, 0.3, 0.1])


def test_paper_selector_picks_argmin_feature():
    """The paper's selector returns the single feature nearest the infinite line."""
    joints = np.array([[-0.6, 0, 2.0], [-0.3, 0, 2.0], [0.0, 0, 2.0]])
    pts = np.array([[1.0, 0.3, 2.0], [1.5, 0.05, 2.0], [2.0, -0.2, 2.0]])
    cands, xyz = candidates_of(pts)
    arm = arm_from_3d(joints)
    arm3d = Perception(RIG, load_params("paper"), None, detector=object()).triangulate_arm(arm)
    sel = PaperSelector(3.0).select(arm, arm3d, cands, xyz, RIG)
    assert sel.index == 1
    assert sel.scores == pytest.approx([0.3, 0.05, 0.2], abs=1e-6)
    assert sel.ambiguity_margin == pytest.approx(0.15, abs=1e-6)
    assert sel.method == "paper"


def _distractor_scene():
    """Arm pointing right (+x); target ahead of the wrist; distractor on the backward extension."""
    shoulder = np.array([-0.2, 0.0, 2.5])
    u = np.array([1.0, 0.0, 0.15])
    u /= np.linalg.norm(u)
    joints = np.array([shoulder, shoulder + 0.3 * u, shoulder + 0.58 * u])
    target = shoulder + 1.6 * u + np.array([0.0, 0.06, 0.0])       # ~2 deg off the arm, ahead
    distractor = shoulder - 0.9 * u + np.array([0.0, 0.01, 0.0])   # behind the shoulder, on the line
    pts = np.vstack([cluster(target, seed=1), cluster(distractor, seed=2)])
    labels = np.r_[np.zeros(12, int), np.ones(12, int)]
    return arm_from_3d(joints), pts, labels


def test_default_picks_object_ahead_where_paper_picks_distractor_behind():
    """With a distractor on the line's backward extension the paper's rule picks it; ours does not."""
    arm, pts, labels = _distractor_scene()
    cands, xyz = candidates_of(pts)
    p_paper, p_default = load_params("paper"), load_params("default")
    arm3d = Perception(RIG, p_default, None, detector=object()).triangulate_arm(arm)
    paper = PaperSelector(3.0).select(arm, arm3d, cands, xyz, RIG)
    assert labels[paper.index] == 1, "the paper's rule should choose the distractor (nearest the infinite line)"
    default = Perception(RIG, p_default, None, detector=object()).selector.select(arm, arm3d, cands, xyz, RIG)
    members = list(default.target.members)
    assert np.all(labels[members] == 0)
    # confidence is absolute (the "nothing detected" hypothesis holds the rest): high, and the
    # target takes > 95 % of what the two objects share
    assert default.confidence > 0.85 and not default.ambiguous
    assert default.confidence / float(np.sum(default.scores)) > 0.95
    assert default.none_probability < 0.15
    assert p_paper["selection.method"] == "paper"


def test_default_groups_features_into_objects_with_robust_centre():
    """Two placards become two objects; one stray match does not move a centre."""
    a, b = np.array([0.5, 0.0, 2.0]), np.array([1.2, 0.2, 3.0])
    pts = np.vstack([cluster(a, 20, seed=3), cluster(b, 20, seed=4)])
    cands, xyz = candidates_of(pts)
    xyz[0, 2] += 0.8  # a gross depth error on one feature
    from dip3d_vehicle.perception.grouping import group_objects
    objs = group_objects(cands, xyz, RIG, 60.0, 0.05, 3)
    assert len(objs) == 2
    centres = sorted(o.xyz_m[2] for o in objs)
    assert centres == pytest.approx([2.0, 3.0], abs=0.02)


def test_a_far_sparse_placard_in_pairs_of_features_is_one_object_two_placards_along_the_line_of_sight_are_not():
    """Fragments too small to be objects join where their features nearly touch across the line of sight.

    far seed 500 scene 1: a 0.25 m placard at 4.7 m gave three pairs of features, each pair more than
    20 px from the next and with centres 0.15-0.2 m apart, so no object, and "nothing detected" won.
    Joined, the six are one object. Two objects that stand alone are never joined by it, and a pair at
    the same image place 0.4 m farther along the line of sight (beyond the depth test) stays apart.
    """
    from dip3d_vehicle.perception.grouping import group_objects
    z = 4.7
    pairs = np.array([[-0.12, -0.02], [-0.12, 0.03], [0.0, -0.10], [0.04, -0.10], [0.05, 0.04], [0.09, 0.06]])
    pts = np.c_[pairs, np.full(len(pairs), z)]
    cands, xyz = candidates_of(pts)
    assert group_objects(cands, xyz, RIG, 20.0, 0.05, 3, object_radius_m=0.0) == []  # no pair is an object alone
    objs = group_objects(cands, xyz, RIG, 20.0, 0.05, 3)
    assert len(objs) == 1 and len(objs[0].members) == 6
    assert objs[0].xyz_m[2] == pytest.approx(z, abs=0.05)
    behind = np.vstack([pts[:2], pts[:2] + [0.004, 0.0, 0.4]])  # two pairs, one 0.4 m behind the other
    cands, xyz = candidates_of(behind)
    assert group_objects(cands, xyz, RIG, 20.0, 0.05, 3) == []


def test_group_medians_equal_numpy_median():
    """The vectorised per-group median is numpy's (mean of the two middle values), ties and singletons included."""
    from dip3d_vehicle.perception.grouping import _group_medians
    rng = np.random.default_rng(7)
    for trial in range(300):
        n = int(rng.integers(1, 40))
        k = int(rng.integers(1, n + 1))
        label = np.r_[np.arange(k), rng.integers(0, k, n - k)]
        values = rng.normal(0, 50, n)
        if trial % 3 == 0:
            values = np.round(values / 10)
        expected = [np.median(values[label == g]) for g in range(k)]
        np.testing.assert_array_equal(_group_medians(label, values, k), expected)


def test_groups_list_each_labels_indices_in_order():
    """The grouping by label is the per-label ``np.nonzero`` it replaced: same indices, same order."""
    from dip3d_vehicle.perception.grouping import _groups
    rng = np.random.default_rng(11)
    for _ in range(300):
        n = int(rng.integers(1, 60))
        k = int(rng.integers(1, n + 1))
        labels = rng.permutation(np.r_[np.arange(k), rng.integers(0, k, n - k)]).astype(np.int32)
        got = _groups(labels)
        assert len(got) == k
        for g in range(k):
            np.testing.assert_array_equal(got[g], np.nonzero(labels == g)[0])


def test_default_reports_ambiguity_for_two_objects_on_the_ray():
    """Two objects both within the pointing spread: low confidence, flagged ambiguous."""
    shoulder = np.array([-0.2, 0.0, 2.0])
    u = np.array([1.0, 0.0, 0.0])
    joints = np.array([shoulder, shoulder + 0.3 * u, shoulder + 0.58 * u])
    a = shoulder + 1.5 * u + np.array([0, 0.15, 0])
    b = shoulder + 1.5 * u + np.array([0, -0.15, 0.05])
    pts = np.vstack([cluster(a, 12, 0.04, seed=5), cluster(b, 12, 0.04, seed=6)])
    cands, xyz = candidates_of(pts)
    arm = arm_from_3d(joints)
    sel = DefaultSelector(group_radius_px=10.0, min_confidence=0.9)
    arm3d = Perception(RIG, load_params(), None, detector=object()).triangulate_arm(arm)
    out = sel.select(arm, arm3d, cands, xyz, RIG)
    assert len(out.objects) == 2
    assert out.ambiguous and out.confidence < 0.9
    assert math.isfinite(out.ambiguity_margin)


def test_no_objects_gives_no_target():
    """With no candidates at all both selectors return no index."""
    arm, _, _ = _distractor_scene()
    arm3d = Perception(RIG, load_params(), None, detector=object()).triangulate_arm(arm)
    empty = Candidates.empty()
    for sel in (PaperSelector(), DefaultSelector()):
        assert sel.select(arm, arm3d, empty, np.zeros((0, 3)), RIG).index is None


def _arm_right(z: float = 2.5) -> tuple[ArmKeypoints, np.ndarray]:
    """Return an arm pointing to the right and a little up (+x, -y) at depth z, and its unit direction."""
    shoulder = np.array([-0.4, 0.0, z])
    u = np.array([1.0, -0.25, 0.0])
    u /= np.linalg.norm(u)
    return arm_from_3d(np.array([shoulder, shoulder + 0.3 * u, shoulder + 0.58 * u])), u


def _select(arm: ArmKeypoints, pts: np.ndarray, **sets):
    """Run the default selector (profile defaults plus ``sets``) on exact candidates at ``pts``."""
    cands, xyz = candidates_of(pts)
    params = load_params("default", overrides=sets)
    perception = Perception(RIG, params, None, detector=object())
    arm3d = perception.triangulate_arm(arm)
    return perception.selector.select(arm, arm3d, cands, xyz, RIG), perception, cands


def test_nothing_on_ray_when_the_only_object_lies_off_the_arm():
    """The arm points up-right; the one detected object is below-right of the wrist: nothing detected wins."""
    arm, u = _arm_right()
    wrist = np.array([-0.4, 0.0, 2.5]) + 0.58 * u
    off = wrist + np.array([0.5, 0.45, 0.0])  # below-right of the wrist, ~60 deg off the arm
    sel, _, _ = _select(arm, cluster(off, 20, 0.1, seed=7))
    assert sel.index is None and sel.nothing_on_ray
    assert sel.none_probability > 0.9 and sel.confidence == pytest.approx(sel.none_probability)
    assert "nothing detected" in sel.reason
    assert float(np.sum(sel.scores)) + sel.none_probability == pytest.approx(1.0)


def test_object_on_the_ray_beats_nothing_detected_and_probabilities_are_absolute():
    """An object 2 deg off the arm, ahead: chosen with high absolute probability; all sum to 1."""
    arm, u = _arm_right()
    shoulder = np.array([-0.4, 0.0, 2.5])
    target = shoulder + 2.0 * u + np.array([0.0, 0.0, 0.05])
    other = shoulder + 2.0 * u + np.array([0.3, 0.8, 0.0])
    sel, _, _ = _select(arm, np.vstack([cluster(target, 15, 0.08, seed=8), cluster(other, 15, 0.08, seed=9)]))
    assert sel.index is not None and not sel.ambiguous
    assert sel.confidence > 0.8 and sel.none_probability < 0.2
    assert float(np.sum(sel.scores)) + sel.none_probability == pytest.approx(1.0)


def test_object_outside_the_arms_image_direction_can_never_win():
    """Even with "nothing detected" made very unlikely, an object behind the wrist in the image loses."""
    arm, u = _arm_right()
    shoulder = np.array([-0.4, 0.0, 2.5])
    behind = shoulder - 0.6 * u + np.array([0.0, 0.05, 0.0])
    sel, _, _ = _select(arm, cluster(behind, 20, 0.1, seed=10), **{"selection.none_prior": 0.001})
    assert sel.index is None and sel.nothing_on_ray
    assert sel.scores[0] == 0.0


def test_the_pointing_hands_own_features_are_never_the_target():
    """A few features just beyond the wrist, on the arm's line (the glove's): never chosen over the placard.

    Without the hand rule they are the best-pointed object there is (0 deg off the arm, P ~0.5); a
    placard of the same size 0.25 m beyond the wrist, on the same line, stays a candidate.
    """
    arm, u = _arm_right()
    shoulder = np.array([-0.4, 0.0, 2.5])
    wrist = shoulder + 0.58 * u
    hand = cluster(wrist + 0.07 * u, 4, 0.02, seed=11)
    placard = cluster(shoulder + 1.6 * u + np.array([0.0, 0.0, 0.3]), 20, 0.1, seed=12)
    sel, _, _ = _select(arm, np.vstack([hand, placard]))
    assert len(sel.objects) == 2
    hand_index = int(np.argmin([np.linalg.norm(o.xyz_m - wrist) for o in sel.objects]))
    assert sel.scores[hand_index] == 0.0
    assert sel.index == 1 - hand_index and not sel.ambiguous
    near, _, _ = _select(arm, cluster(wrist + 0.25 * u, 20, 0.06, seed=13))
    assert near.index == 0
    # a placard at arm's length: its centre 0.12 m beyond the wrist, but 0.3 m wide (variant_10_04)
    at_hand, _, _ = _select(arm, cluster(wrist + 0.12 * u + np.array([0.0, 0.0, 0.05]), 20, 0.15, seed=14))
    assert at_hand.index == 0 and at_hand.scores[0] > 0.5


def test_pipeline_reports_nothing_on_ray_with_reason_and_json():
    """decide() turns the open-set answer into status nothing_on_ray, target null, a one-line reason."""
    arm, u = _arm_right()
    wrist = np.array([-0.4, 0.0, 2.5]) + 0.58 * u
    cands, _ = candidates_of(cluster(wrist + np.array([0.5, 0.45, 0.0]), 20, 0.1, seed=7))
    perception = Perception(RIG, load_params("default"), None, detector=object())
    result = perception.decide(perception.check_arm(arm), cands)
    assert result.status == "nothing_on_ray" and result.target_rect_px is None
    doc = result.to_json(RIG)
    assert doc["target"] is None and "\n" not in doc["reason"] and doc["reason"]
    assert doc["selection"]["none_probability"] > 0.9
    assert len(doc["candidates"]) == 1


def test_paper_selector_has_no_open_set():
    """The paper's rule is unchanged: always the nearest feature, none_probability 0."""
    arm, u = _arm_right()
    wrist = np.array([-0.4, 0.0, 2.5]) + 0.58 * u
    cands, xyz = candidates_of(cluster(wrist + np.array([0.5, 0.45, 0.0]), 5, 0.1, seed=7))
    perception = Perception(RIG, load_params("paper"), None, detector=object())
    sel = perception.selector.select(arm, perception.triangulate_arm(arm), cands, xyz, RIG)
    assert sel.index is not None and sel.none_probability == 0.0 and sel.confidence == 1.0


def test_fragments_of_one_placard_count_as_one_target():
    """A placard split into two touching fragments: the confidence is their summed probability, not half."""
    arm, u = _arm_right()
    shoulder = np.array([-0.4, 0.0, 2.5])
    centre = shoulder + 2.0 * u
    top = centre + np.c_[np.linspace(-0.12, 0.12, 16), np.full(16, -0.06), np.zeros(16)]
    bottom = centre + np.c_[np.linspace(-0.12, 0.12, 16), np.full(16, 0.02), np.zeros(16)]
    sel, _, _ = _select(arm, np.vstack([top, bottom]), **{"selection.group_radius_px": 10.0,
                                                          "selection.object_radius_m": 0.05})
    assert len(sel.objects) == 2
    assert sel.confidence == pytest.approx(float(np.sum(sel.scores)))
    assert sel.confidence > 0.8 and not sel.ambiguous


def _far_diver_scene(target: str):
    """A diver 5 m away pointing toward the camera at one of three placards on nearly one image line
    (far_diver's layout); the wrist placed 6 px short along the arm, as a pose model may."""
    import dataclasses

    placards = {"p1": [0.66, 0.22, 1.35], "p2": [0.65, 0.12, 2.41], "p3": [0.43, 0.02, 3.47]}
    shoulder = np.array([-0.75, -0.45, 4.9])
    u = np.asarray(placards[target]) - shoulder
    u /= np.linalg.norm(u)
    arm = arm_from_3d(np.array([shoulder, shoulder + 0.3 * u, shoulder + 0.58 * u]))
    along = (arm.left_px[2] - arm.left_px[0]) / np.linalg.norm(arm.left_px[2] - arm.left_px[0])
    off = np.array([[0.0, 0.0], [0.0, 0.0], -6.0 * along])
    arm = dataclasses.replace(arm, left_px=arm.left_px + off, right_px=arm.right_px + off)
    pts = np.vstack([cluster(np.asarray(c), 15, 0.12, seed=i) for i, c in enumerate(placards.values())])
    return arm, pts


@pytest.mark.parametrize("evidence", ["laplace", "sampled"])
def test_a_pose_models_own_landmark_error_keeps_a_far_foreshortened_arm_from_being_sure(evidence):
    """At 5 m the arm's tilt decides between placards on one image line; with the landmarks' own 5 cm
    error (BlazePose) every frame is ambiguous and less sure than with exact keypoints (which claim
    0.67 (laplace) / 0.80 (sampled) for the first placard), and no WRONG placard is more likely than
    not. The Gaussian Occam factor (laplace) keeps even the pointed placard under 0.5 (0.48); the
    sampled evidence, which keeps the limb lengths' two tilts, gives the pointed p1 0.51."""
    import dataclasses

    sets = {"selection.evidence": evidence}
    arm, pts = _far_diver_scene("p1")
    exact, _, _ = _select(arm, pts, **sets)
    assert exact.index == 0 and not exact.ambiguous and exact.confidence > 0.6
    zero, _, _ = _select(dataclasses.replace(arm, keypoint_sigma_m=0.0), pts, **sets)  # none = the exact model
    assert np.allclose(zero.scores, exact.scores)
    for k, target in enumerate(("p1", "p2", "p3")):
        arm, pts = _far_diver_scene(target)
        exact, _, _ = _select(arm, pts, **sets)
        sel, _, _ = _select(dataclasses.replace(arm, keypoint_sigma_m=0.05), pts, **sets)
        assert sel.ambiguous and float(np.max(sel.scores)) < float(np.max(exact.scores))
        assert float(np.max(np.delete(sel.scores, k))) < 0.5
        if evidence == "laplace":
            assert float(np.max(sel.scores)) < 0.5


def test_a_pose_models_own_landmark_error_barely_matters_for_an_arm_seen_at_full_length():
    """The paper's range, the arm across the view: the object on the ray still wins clearly."""
    import dataclasses

    arm, u = _arm_right()
    shoulder = np.array([-0.4, 0.0, 2.5])
    target = shoulder + 2.0 * u + np.array([0.0, 0.0, 0.05])
    other = shoulder + 2.0 * u + np.array([0.3, 0.8, 0.0])
    pts = np.vstack([cluster(target, 15, 0.08, seed=8), cluster(other, 15, 0.08, seed=9)])
    sel, _, _ = _select(dataclasses.replace(arm, keypoint_sigma_m=0.05), pts)
    assert sel.index is not None and not sel.ambiguous and sel.confidence > 0.8


def test_feature_chains_are_labelled_like_scipy_connected_components():
    """The grouping's own component labelling numbers components by their lowest node, as scipy does."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    from dip3d_vehicle.perception.grouping import _components

    rng = np.random.default_rng(3)
    for n, k in ((1, 0), (5, 0), (40, 25), (300, 400), (300, 1200)):
        pairs = rng.integers(0, n, size=(k, 2)) if k else np.zeros((0, 2), int)
        graph = coo_matrix((np.ones(k), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        assert np.array_equal(_components(n, pairs), connected_components(graph, directed=False)[1])
    chain = np.c_[np.arange(199, 0, -1), np.arange(198, -1, -1)]  # one long chain, linked from its far end
    assert np.array_equal(_components(200, chain), np.zeros(200, int))


def test_batched_levenberg_marquardt_minimises_each_problem_on_its_own():
    """Each problem of the batch reaches its own minimum, whatever the others do (one call per iteration)."""
    from dip3d_vehicle.perception.pointing_fit import _levenberg_marquardt

    target = np.array([[1.0, 2.0], [3.0, 0.5], [0.2, 4.0]])
    calls = []

    def fun(z: np.ndarray) -> np.ndarray:
        calls.append(len(z))
        t = np.tile(target, (len(z) // len(target), 1))
        return np.c_[z - t, 0.1 * (z[:, :1] * z[:, 1:] - t[:, :1] * t[:, 1:])]

    cost = _levenberg_marquardt(fun, np.full((3, 2), 5.0), 50)
    assert np.all(cost < 1e-8)
    assert set(calls) == {9}   # a point and its 2 shifts for each of the 3 problems, in one call


def _spots_at(xyz: np.ndarray):
    """Unrecognised spots at ``xyz`` (metres; one point or (N, 3)), each with a 0.05 m depth sigma."""
    from dip3d_vehicle.perception.blobs import Blobs

    xyz = np.atleast_2d(xyz)
    return Blobs(project(xyz), xyz, np.full(len(xyz), 0.05))


def _spot_source(xyz: np.ndarray):
    """An ``unrecognised`` source that finds spots at ``xyz`` (metres) whatever the objects."""
    spots = _spots_at(xyz)
    return lambda px, pts, joints: spots


def test_a_spot_down_the_pointing_line_behind_the_pointed_placard_is_not_nothing_detected():
    """Issue 11 session 63 (variant_31_00 seed 1): a spot 2 m behind the pointed placard, on the line through it,
    took "nothing detected" to 0.8. Hidden behind the placard it is not scored; beside it, it is."""
    arm, u = _arm_right()
    shoulder = np.array([-0.4, 0.0, 2.5])
    placard = cluster(shoulder + 1.0 * u, 30, 0.12, seed=3)
    spot = shoulder + 3.0 * u + np.array([0.0, 0.03, 0.0])
    cands, xyz = candidates_of(placard)
    params = load_params("default")
    perception = Perception(RIG, params, None, detector=object())
    arm3d = perception.triangulate_arm(arm)
    hidden = perception.selector.select(arm, arm3d, cands, xyz, RIG, _spot_source(spot))
    assert hidden.spots == () and hidden.index is not None and hidden.confidence > 0.8
    aside = placard + np.array([0.0, 0.0, 0.4])             # the placard 0.4 m farther: no longer in front of the spot
    cands, xyz = candidates_of(aside)
    seen = perception.selector.select(arm, arm3d, cands, xyz, RIG, _spot_source(spot))
    assert len(seen.spots) == 1 and seen.spots[0][1] > 0.05
    assert seen.none_probability >= seen.spots[0][1]


def test_hidden_behind_needs_the_object_across_the_line_and_plainly_nearer():
    from dip3d_vehicle.perception.selection import hidden_behind

    shoulder = np.zeros(3)
    face = cluster(np.array([0.0, 0.0, 1.0]), 20, 0.1, seed=1)      # a 0.2 m placard 1 m ahead
    spots = np.array([[0.0, 0.0, 3.0],      # straight behind it
                      [0.5, 0.0, 3.0],      # the line passes 0.17 m beside it (pointing spread 0.08 m there)
                      [0.0, 0.0, 1.1]])     # just behind it, within the depths' sigmas
    got = hidden_behind(spots, np.array([0.05, 0.05, 0.05]), [face], [0.02], shoulder, 0.08)
    assert got.tolist() == [True, False, False]
    assert hidden_behind(spots, np.full(3, 0.05), [face[:2]], [0.02], shoulder, 0.08).tolist() == [False] * 3


def test_json_and_annotation_say_which_unrecognised_spots_were_scored():
    """``perceive --json`` gives each unrecognised spot the probability the selector gave it (null: not scored,
    here hidden behind the pointed placard); ``--annotate`` rings a scored spot orange, the other grey."""
    from dip3d_vehicle.perception.annotate import GREY, ORANGE, annotate
    from dip3d_vehicle.perception.pipeline import PerceptionResult

    arm, u = _arm_right()
    shoulder = np.array([-0.4, 0.0, 2.5])
    hidden = shoulder + 2.0 * u + np.array([0.0, 0.03, 0.0])
    seen = shoulder + 0.8 * u + np.array([0.0, 0.02, 0.0])    # in front of the placard: nothing hides it
    placard = cluster(shoulder + 1.0 * u, 30, 0.12, seed=3)
    cands, xyz = candidates_of(placard)
    perception = Perception(RIG, load_params("default"), None, detector=object())
    arm3d = perception.triangulate_arm(arm)
    spots = np.vstack([hidden, seen])
    sel = perception.selector.select(arm, arm3d, cands, xyz, RIG, _spot_source(spots))
    result = PerceptionResult("ok", "", arm, arm3d, cands, xyz, sel, unrecognised=_spots_at(spots))
    probs = [s["probability"] for s in result.to_json(RIG)["unrecognised"]]
    scored = [p is not None for p in probs]
    assert len(sel.spots) == sum(scored) >= 1 and not all(scored)
    img = annotate(np.zeros((1200, 1600, 3), np.uint8), result, RIG)
    for (x, y), ok in zip(RIG.to_original(project(spots), "left"), scored):
        ring = img[int(round(y)) - 12:int(round(y)) + 13, int(round(x)) - 12:int(round(x)) + 13].reshape(-1, 3)
        assert any(tuple(int(c) for c in px) == (ORANGE if ok else GREY) for px in ring)
