"""Grouping features into objects: a chain wider than any target is cut where two placards touch."""

from __future__ import annotations

import numpy as np
import pytest

from dip3d_vehicle.perception.grouping import extent_m, group_objects

from test_selection import RIG, _arm_right, _select, candidates_of, cluster

Z_M = 2.6


def placard(centre_x_m: float, side_m: float = 0.3, y_m: float = 0.0, step_m: float = 0.03,
            seed: int = 0) -> np.ndarray:
    """Return features on a square placard facing the camera at ``Z_M`` (a jittered grid), metres."""
    rng = np.random.default_rng(seed)
    ticks = np.arange(-side_m / 2, side_m / 2 + 1e-9, step_m)
    grid = np.array([(x, y) for x in ticks for y in ticks]) + rng.normal(0.0, 0.003, (len(ticks) ** 2, 2))
    return np.c_[grid + [centre_x_m, y_m], np.full(len(grid), Z_M)]


def two_placards_bridged() -> tuple[np.ndarray, np.ndarray]:
    """Return two 0.3 m placards 0.08 m apart (31 px at 2.6 m) and one stray feature between them, and labels."""
    a, b = placard(-0.19, seed=1), placard(0.19, seed=2)
    bridge = np.array([[0.0, 0.0, Z_M]])  # 15 px from each placard's edge: chains both within 20 px
    return np.vstack([a, b, bridge]), np.r_[np.zeros(len(a), int), np.ones(len(b), int), [-1]]


def test_two_placards_chained_by_a_stray_feature_are_cut_apart_when_wider_than_any_target():
    """Wider than 0.6 m and held by a few links: two objects, one on each placard (line_of_sight seed 2900 scene 19)."""
    pts, labels = two_placards_bridged()
    cands, xyz = candidates_of(pts)
    whole = group_objects(cands, xyz, RIG, 20.0, 0.05, 3)
    assert len(whole) == 1
    assert extent_m(cands.left_px, Z_M, RIG.focal_px) == pytest.approx(0.74, abs=0.03)
    objs = group_objects(cands, xyz, RIG, 20.0, 0.05, 3, max_extent_m=0.6)
    assert len(objs) == 2
    for obj in objs:
        own = labels[list(obj.members)]
        assert len(set(own[own >= 0])) == 1 and np.sum(own >= 0) >= len(own) - 1
        assert abs(abs(obj.xyz_m[0]) - 0.19) < 0.02


def test_two_placards_are_cut_apart_where_one_holds_together_less_firmly_than_usual():
    """A weak cut whose two sides each fit one target is kept, however firmly each side holds together.

    side_by_side seed 1 (issue 11 session 48): two placards 0.05 m apart chained into one 0.69 m object by
    a cut of 0.002, one placard's own weakest cut 0.006 (under the cohesion ratio's 3 times): the one
    object lay between them, the selector gave it 0.91, and the vehicle went to the other placard.
    """
    a = placard(-0.19, seed=1)
    a = a[np.abs(a[:, 1]) > 0.04]  # a placard printed in two halves 0.12 m apart, joined at two places
    a = np.vstack([a] + [[[x, -0.02, Z_M], [x, 0.02, Z_M]] for x in (-0.25, -0.13)])
    b = placard(0.19, seed=2)
    cands, xyz = candidates_of(np.vstack([a, b, [[0.0, 0.09, Z_M]]]))  # a stray feature joins the placards
    assert len(group_objects(cands, xyz, RIG, 20.0, 0.05, 3)) == 1
    objs = group_objects(cands, xyz, RIG, 20.0, 0.05, 3, max_extent_m=0.6)
    owner = np.r_[np.zeros(len(a), int), np.ones(len(b), int), [-1]]
    assert sorted(tuple(np.unique(owner[list(o.members)])) for o in objs) in ([(-1, 0), (1,)], [(0,), (-1, 1)])
    assert sorted(round(float(o.xyz_m[0]), 2) for o in objs) == pytest.approx([-0.19, 0.19], abs=0.01)
    cands, xyz = candidates_of(a)
    assert len(group_objects(cands, xyz, RIG, 20.0, 0.05, 3, max_extent_m=0.6)) == 1  # a placard alone: whole


def test_one_wide_placard_is_never_cut_nor_a_narrow_chain_looked_at():
    """A 0.7 m placard holds together across every cut; two placards within the extent are left as one chain."""
    wide = placard(0.0, side_m=0.7, seed=3)
    cands, xyz = candidates_of(wide)
    objs = group_objects(cands, xyz, RIG, 20.0, 0.05, 3, max_extent_m=0.6)
    assert len(objs) == 1 and len(objs[0].members) == len(wide)
    pts, _ = two_placards_bridged()
    cands, xyz = candidates_of(pts)
    assert len(group_objects(cands, xyz, RIG, 20.0, 0.05, 3, max_extent_m=0.8)) == 1


def test_two_placards_side_by_side_are_never_summed_as_one_target():
    """The arm points between two placards 0.08 m apart: each object keeps its own probability (not one target).

    Fragments of one placard are summed (``test_fragments_of_one_placard_count_as_one_target``); two placards
    are not, whether stage 1 chained them (then cut) or not: together they are wider than any target.
    """
    arm, u = _arm_right()
    centre = np.array([-0.4, 0.0, 2.5]) + 2.2 * u
    side = np.array([-u[1], u[0], 0.0])  # across the arm in the image plane
    rng = np.random.default_rng(4)
    a = centre - 0.19 * side + np.c_[rng.uniform(-0.15, 0.15, (100, 2)), np.zeros(100)]
    b = centre + 0.19 * side + np.c_[rng.uniform(-0.15, 0.15, (100, 2)), np.zeros(100)]
    for pts in (np.vstack([a, b]), np.vstack([a, b, centre])):  # apart; chained by a stray feature between them
        sel, _, _ = _select(arm, pts)
        assert len(sel.objects) == 2
        assert sel.confidence == pytest.approx(float(sel.scores[sel.index])) and sel.ambiguous
        summed, _, _ = _select(arm, pts, **{"selection.target_max_extent_m": 5.0})
        assert summed.confidence > 0.8 and not summed.ambiguous  # one target of two placards: confidently wrong


def oblique_placard(angle_deg: float, depth_m: float = 1.0, gap_m: float = 0.12) -> np.ndarray:
    """Return features on a 0.3 m placard turned ``angle_deg`` from face-on about the vertical at ``depth_m``, with
    a plain band ``gap_m`` wide down its middle (the digit's disc), metres."""
    grid = placard(0.0, seed=5)[:, :2]
    grid = grid[np.abs(grid[:, 0]) > gap_m / 2]
    a = np.radians(angle_deg)
    return np.c_[grid[:, 0] * np.cos(a), grid[:, 1], depth_m + grid[:, 0] * np.sin(a)]


def test_an_obliquely_seen_placard_broken_around_its_plain_middle_is_one_object_with_a_surface_slope():
    """55 deg from face-on at 1 m, the two halves lie 0.12 m apart across and 0.17 m in depth (0.21 m in 3D): two
    objects for the selector's grouping, one for the tracker's (``surface_slope`` 2, paper_pool seed 0 on the
    firmware, issue 11 session 54); a placard behind another (0.1 m across, 0.3 m deeper) stays apart."""
    pts = oblique_placard(55.0)
    cands, xyz = candidates_of(pts)
    assert len(group_objects(cands, xyz, RIG, 20.0, 0.05, 3)) == 2
    objs = group_objects(cands, xyz, RIG, 20.0, 0.05, 3, surface_slope=2.0)
    assert len(objs) == 1 and len(objs[0].members) == len(pts)
    assert objs[0].xyz_m == pytest.approx([0.0, 0.0, 1.0], abs=0.02)
    behind = placard(0.1, side_m=0.15, seed=6) + [0.0, 0.0, 1.3 - Z_M]
    cands, xyz = candidates_of(np.vstack([placard(0.0, side_m=0.15, seed=7) + [0.0, 0.0, 1.0 - Z_M], behind]))
    assert len(group_objects(cands, xyz, RIG, 20.0, 0.05, 3, surface_slope=2.0)) == 2


def test_a_placard_in_four_clusters_holds_one_prior_share_per_target_not_four():
    """Two placards 8 deg either side of the arm, equal distances: one seen whole, one broken into 4 clusters.

    One prior share per object (``selection.prior_per_target`` false, the default until issue 11 session 70)
    gives the broken placard 4 shares and it outweighs the whole one ~4 to 1 at equal angles (variant_41_15 in
    murky water, session 68: the decoy led though 16 deg from the arm against the pointed placard's 5). One
    share per target (the default) splits one share among its 4 clusters: neither placard outweighs the other
    by more than 2 to 1.
    """
    arm, u = _arm_right()
    shoulder = np.array([-0.4, 0.0, 2.5])

    def towards(deg: float) -> np.ndarray:
        """Return the point 2.2 m from the shoulder, ``deg`` from the arm in the image plane, metres."""
        a = np.radians(deg)
        return shoulder + 2.2 * np.array([np.cos(a) * u[0] - np.sin(a) * u[1], np.sin(a) * u[0] + np.cos(a) * u[1], 0])

    whole = cluster(towards(8.0), 80, 0.15, seed=1)
    corners = [(-0.12, -0.12), (0.12, -0.12), (-0.12, 0.12), (0.12, 0.12)]
    broken = np.vstack([cluster(towards(-8.0) + [dx, dy, 0.0], 12, 0.03, seed=2 + k)
                        for k, (dx, dy) in enumerate(corners)])
    owner = np.r_[np.zeros(len(whole), int), np.ones(len(broken), int)]
    ratios = {}
    for per_target in (False, True):
        sel, _, _ = _select(arm, np.vstack([whole, broken]), **{"selection.prior_per_target": per_target})
        of = np.array([np.median(owner[list(o.members)]) for o in sel.objects])
        assert sorted(of.tolist()) == [0, 1, 1, 1, 1]
        ratios[per_target] = float(sel.scores[of == 1].sum() / sel.scores[of == 0].sum())
    assert ratios[False] > 3.0
    assert 0.5 < ratios[True] < 2.0
