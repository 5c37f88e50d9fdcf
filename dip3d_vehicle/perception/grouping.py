"""Matched features into objects: chains of neighbours, split where two objects touch, then fragments joined.

Stage 1 chains features that are neighbours in the left image with agreeing depths. A chain wider
than any target (``max_extent_m`` across the line of sight) that a few links hold together is two
objects side by side (two placards whose edges come within a neighbour's reach, a stray feature
bridging the water between them): it is cut there (``split_chain``). Stage 2 merges fragments of one
object whose centres are close; stage 3 joins fragments too small to be objects alone.
"""

from __future__ import annotations

import math

import cv2
import numpy as np
from scipy.spatial import cKDTree

from .calibration import StereoRig
from .triangulation import normalize_q, triangulate
from .values import Candidates, ObjectCandidate

__all__ = ["group_objects", "objects_of", "split_chain", "extent_m", "target_groups", "MATCH_SIGMA_PX"]

MATCH_SIGMA_PX = 0.3
"""Assumed disparity error of a matched feature, pixels (SIFT on Middlebury: median error 0.1-0.3 px)."""

SPLIT_MIN_PART = 10
"""The fewest features on each side of a cut of one chain into two objects."""

SPLIT_MAX_CONDUCTANCE = 0.03
"""A chain is cut only where the cut's links over the smaller side's link ends (its conductance) are below this.
Two placards joined by a stray feature: 0.005 (line_of_sight seed 2900 scene 19, issue 11 session 45)."""

SPLIT_COHESION_RATIO = 3.0
"""A cut is kept only when each side's own weakest cut is this many times stronger than it. One placard's weakest
cut is 0.010-0.017 (its features gather around the printed shapes), and one of its sides then holds together
less than 3 times better (sides 0.015-0.059); scene 19's sides: 0.029 and 0.032 against its cut's 0.005. Not asked
of a cut whose two sides each fit one target (a chain wider than any target is not one): side_by_side seed 1's two
placards, cut 0.002, one placard's own weakest cut 0.006 (issue 11 session 48)."""

TARGET_DEPTH_GAP_M = 0.3
"""Objects whose centres' depths differ by more than this (plus twice their combined depth sigma) are never parts of
one target (``target_groups``): a 0.3 m placard seen edge-on spans at most its own width in depth."""

SPLIT_MAX_FEATURES = 400
"""Chains of more features than this are not looked at for a cut (the eigenvector's cost grows with the cube)."""


def group_objects(candidates: Candidates, xyz_m: np.ndarray, rig: StereoRig, radius_px: float,
                  radius_m: float, min_features: int, object_radius_m: float = 0.15,
                  max_extent_m: float = math.inf, surface_slope: float = 0.0) -> list[ObjectCandidate]:
    """Group matched features into objects: chains of neighbours, then fragments of one object.

    Stage 1 links two features within ``radius_px`` in the left image whose depths differ by less
    than max(radius_m, 3 sigma); a chain wider than ``max_extent_m`` (metres across the line of
    sight) is cut where a few links hold two parts together (``split_chain``); stage 2 merges the
    resulting fragments whose robust 3D centres are within ``object_radius_m`` and pass the same
    depth test (a sparse, distant placard often falls apart into pieces; two placards side by side
    at different depths must not be chained). Objects with fewer than ``min_features`` members are
    dropped. An object's centre is the median disparity triangulated at the median left-image
    position (robust to stray matches).

    With ``surface_slope`` > 0, two fragments whose centres lie within ``object_radius_m`` ACROSS the line
    of sight also merge when their depths differ by at most ``surface_slope`` times that distance: one
    surface seen obliquely. A placard seen 50-60 deg from face-on at 1 m breaks around its featureless
    middle into a near and a far part 0.12 m apart across and 0.13 m in depth (0.18 m in 3D); the tracker
    then took one part or the other from frame to frame and the target's range jumped by 0.07 m (paper_pool
    seed 0 on the ArduSub firmware, issue 11 session 54). Two objects one behind the other (little across,
    much in depth) stay apart.
    """
    n = len(candidates)
    if n == 0:
        return []
    z = xyz_m[:, 2]
    sig = rig.depth_sigma_m(z, MATCH_SIGMA_PX)
    pairs = cKDTree(candidates.left_px).query_pairs(radius_px, output_type="ndarray") if n > 1 else np.zeros((0, 2), int)
    if len(pairs):
        i, j = pairs[:, 0], pairs[:, 1]
        pairs = pairs[_depths_agree(z[i], z[j], sig[i], sig[j], radius_m)]
    labels = _components(n, pairs)
    Q = normalize_q(rig.Q, rig.disparity_sign)
    groups = [part for members in _groups(labels)
              for part in split_chain(members, pairs, candidates.left_px, z, rig.focal_px, max_extent_m)]
    centres = _centres(candidates, Q, groups)[1]
    ok = np.all(np.isfinite(centres), axis=1)
    if ok.sum() > 1:
        idx = np.nonzero(ok)[0]
        close = _close_fragments(centres[idx], rig, radius_m, object_radius_m, surface_slope)
        merged = _components(len(idx), close)
        groups = [np.concatenate([groups[idx[k]] for k in ks]) for ks in _groups(merged)]
    groups = _join_small_fragments(groups, xyz_m, sig, radius_m, min_features, object_radius_m)
    return objects_of(candidates, rig, [g for g in groups if len(g) >= min_features])


def objects_of(candidates: Candidates, rig: StereoRig, groups: list[np.ndarray]) -> list[ObjectCandidate]:
    """Return an object per group of feature indices: the median disparity triangulated at the median left-image
    position (metres), its depth sigma shrinking with the group's size; a group with no finite centre ahead is left out.
    """
    out = []
    for members, px, centre in zip(groups, *_centres(candidates, normalize_q(rig.Q, rig.disparity_sign), groups)):
        if not np.all(np.isfinite(centre)) or centre[2] <= 0:
            continue
        sigma = float(rig.depth_sigma_m(centre[2], max(1.25 * MATCH_SIGMA_PX / math.sqrt(len(members)), 0.1)))
        out.append(ObjectCandidate(px, centre, sigma, tuple(int(m) for m in members)))
    return out


def extent_m(left_px: np.ndarray, depth_m: float, focal_px: float) -> float:
    """Return the widest span of features (rectified left px) across the line of sight at ``depth_m``, metres."""
    if len(left_px) < 2:
        return 0.0
    hull = cv2.convexHull(np.asarray(left_px, np.float32)).reshape(-1, 2).astype(float)
    return float(np.max(np.linalg.norm(hull[:, None] - hull[None], axis=2))) * depth_m / focal_px


def target_groups(objects: list[ObjectCandidate], left_px: np.ndarray, focal_px: float,
                  max_extent_m: float) -> np.ndarray:
    """Return a label per object: objects that together could be one target share it (int array, labels 0..K-1).

    Greedy from the object of most features: each unlabelled object joins it while the features' union
    (``left_px``: the candidates' rectified left pixels) stays at most ``max_extent_m`` across the line of
    sight and the centres' depths agree (``TARGET_DEPTH_GAP_M`` plus twice their combined sigma).
    """
    z = np.array([o.xyz_m[2] for o in objects], float)
    sigma = np.array([o.depth_sigma_m for o in objects], float)
    first_px = np.array([left_px[o.members[0]] for o in objects], float).reshape(-1, 2)
    labels = np.full(len(objects), -1)
    order = np.array(sorted(range(len(objects)), key=lambda i: -len(objects[i].members)), int)
    for label, i in enumerate(k for k in order if labels[k] < 0):
        labels[i], members = label, list(objects[i].members)
        depth_m = 0.5 * (z[i] + z[order])
        # cheap tests first: depths that disagree, or two of the union's features already spanning too far
        near = (np.abs(z[order] - z[i]) <= TARGET_DEPTH_GAP_M + 2.0 * np.hypot(sigma[i], sigma[order])) & (
            np.linalg.norm(first_px[order] - first_px[i], axis=1) * depth_m / focal_px <= max_extent_m)
        for j, d in zip(order[near].tolist(), depth_m[near].tolist()):
            if labels[j] >= 0:
                continue
            union = members + list(objects[j].members)
            if extent_m(left_px[union], d, focal_px) <= max_extent_m:
                labels[j], members = label, union
    return labels


def split_chain(members: np.ndarray, pairs: np.ndarray, left_px: np.ndarray, depth_m: np.ndarray, focal_px: float,
                max_extent_m: float, depth: int = 2, cut: tuple | None = None) -> list[np.ndarray]:
    """Return a chain of features (indices, linked by ``pairs``) as the objects it holds: itself, or its two sides.

    A chain no wider than ``max_extent_m`` (metres across the line of sight, at its median depth) is one
    object. A wider one is cut at the spectral cut of least conductance when that cut is weak (a few
    links: two placards side by side, or a stray feature between them) and either each side fits one
    target or each side holds together far better than the cut; each side is looked at again, ``depth``
    times at most. ``cut``: the chain's own ``_least_cut`` when already known.
    """
    if depth <= 0 or not _wider(members, left_px, depth_m, focal_px, max_extent_m):
        return [members]
    phi, first, second = cut if cut is not None else _least_cut(members, pairs)
    if not phi < SPLIT_MAX_CONDUCTANCE:
        return [members]
    sides = [(first, _least_cut(first, pairs)), (second, _least_cut(second, pairs))]
    if not min(side_cut[0] for _, side_cut in sides) >= SPLIT_COHESION_RATIO * phi \
            and any(_wider(side, left_px, depth_m, focal_px, max_extent_m) for side, _ in sides):
        return [members]
    return [part for side, side_cut in sides
            for part in split_chain(side, pairs, left_px, depth_m, focal_px, max_extent_m, depth - 1, side_cut)]


def _wider(members: np.ndarray, left_px: np.ndarray, depth_m: np.ndarray, focal_px: float, max_extent_m: float) -> bool:
    """True when features span more than ``max_extent_m`` across the line of sight at their median depth (metres)."""
    return extent_m(left_px[members], float(np.median(depth_m[members])), focal_px) > max_extent_m


def _least_cut(members: np.ndarray, pairs: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Return the conductance of a chain's spectral cut of least conductance and its two sides (inf: no cut).

    The features are ordered by the Fiedler vector of the links' normalised Laplacian; every split of
    that order leaving at least ``SPLIT_MIN_PART`` features a side is scored by its conductance (links
    cut over the smaller side's link ends).
    """
    size = len(members)
    none = (math.inf, members, members[:0])
    if size < 2 * SPLIT_MIN_PART or size > SPLIT_MAX_FEATURES or len(pairs) == 0:
        return none
    index = np.full(int(max(pairs.max(), members.max())) + 1, -1)
    index[members] = np.arange(size)
    inside = pairs[(index[pairs[:, 0]] >= 0) & (index[pairs[:, 1]] >= 0)]
    if len(inside) == 0:
        return none
    i, j = index[inside[:, 0]], index[inside[:, 1]]
    adjacency = np.zeros((size, size))
    adjacency[i, j] = adjacency[j, i] = 1.0
    degree = adjacency.sum(axis=1)
    scale = 1.0 / np.sqrt(np.maximum(degree, 1e-12))
    fiedler = np.linalg.eigh(np.eye(size) - scale[:, None] * adjacency * scale[None, :])[1][:, 1] * scale
    order = np.argsort(fiedler, kind="stable")
    rank = np.empty(size, int)
    rank[order] = np.arange(size)
    lo, hi = np.minimum(rank[i], rank[j]), np.maximum(rank[i], rank[j])
    change = np.zeros(size + 1)
    np.add.at(change, lo + 1, 1.0)
    np.add.at(change, hi + 1, -1.0)
    cut = np.cumsum(change)[1:size]
    volume = np.cumsum(degree[order])[:-1]
    k = np.arange(1, size)
    phi = np.where((k >= SPLIT_MIN_PART) & (size - k >= SPLIT_MIN_PART),
                   cut / np.maximum(np.minimum(volume, float(degree.sum()) - volume), 1e-12), np.inf)
    best = int(np.argmin(phi))
    return float(phi[best]), np.sort(members[order[:best + 1]]), np.sort(members[order[best + 1:]])


def _depths_agree(za: np.ndarray, zb: np.ndarray, sigma_a: np.ndarray, sigma_b: np.ndarray,
                  radius_m: float) -> np.ndarray:
    """Return whether two depths (metres) may be one surface: apart by at most max(radius_m, 3 combined sigmas)."""
    return np.abs(za - zb) <= np.maximum(radius_m, 3.0 * np.hypot(sigma_a, sigma_b))


def _close_fragments(centres: np.ndarray, rig: StereoRig, radius_m: float, object_radius_m: float,
                     surface_slope: float) -> np.ndarray:
    """Return the pairs (K, 2) of fragment centres (metres) that are one object: within ``object_radius_m`` in 3D
    with agreeing depths, or (``surface_slope`` > 0) within it across the line of sight with depths apart by at most
    ``surface_slope`` times that distance."""
    across = surface_slope > 0
    close = cKDTree(centres[:, :2] if across else centres).query_pairs(object_radius_m, output_type="ndarray")
    if not len(close):
        return close
    a, b = centres[close[:, 0]], centres[close[:, 1]]
    agree = _depths_agree(a[:, 2], b[:, 2], *rig.depth_sigma_m(np.stack([a[:, 2], b[:, 2]]), MATCH_SIGMA_PX), radius_m)
    if across:
        sloped = np.abs(a[:, 2] - b[:, 2]) <= surface_slope * np.hypot(*(a[:, :2] - b[:, :2]).T)
        agree = (agree & (np.linalg.norm(a - b, axis=1) <= object_radius_m)) | sloped
    return close[agree]


def _join_small_fragments(groups: list[np.ndarray], xyz_m: np.ndarray, sigma_m: np.ndarray, radius_m: float,
                          min_features: int, object_radius_m: float) -> list[np.ndarray]:
    """Return ``groups`` with the fragments too small to be objects joined where their features nearly touch.

    A far, sparse placard (0.25 m at 4.7 m, 53 px) often yields a handful of features in pairs more than
    ``radius_px`` apart, whose two-feature centres lie 0.15-0.2 m apart: none is an object, and "nothing
    detected" then wins on the placard's own spots (far seed 500 scene 1, far_diver scene 6). Fragments
    with fewer than ``min_features`` members are linked when two of their features lie within
    ``object_radius_m`` of each other ACROSS the line of sight (the points' x, y at their depths) and
    their depths agree as in stage 1; objects that already stand alone are left as they are (a merge
    of two placards close along the line of sight is what the centres' test guards against).
    """
    small = [k for k, g in enumerate(groups) if len(g) < min_features]
    if len(small) < 2:
        return groups
    members = np.concatenate([groups[k] for k in small])
    owner = np.repeat(np.arange(len(small)), [len(groups[k]) for k in small])
    pts = xyz_m[members]
    finite = np.flatnonzero(np.all(np.isfinite(pts), axis=1))
    pairs = cKDTree(pts[finite, :2]).query_pairs(object_radius_m, output_type="ndarray")
    if not len(pairs):
        return groups
    i, j = finite[pairs[:, 0]], finite[pairs[:, 1]]
    keep = (_depths_agree(pts[i, 2], pts[j, 2], sigma_m[members[i]], sigma_m[members[j]], radius_m)
            & (owner[i] != owner[j]))
    joined = _components(len(small), np.c_[owner[i], owner[j]][keep])
    big = [g for k, g in enumerate(groups) if len(g) >= min_features]
    return big + [np.sort(np.concatenate([groups[small[k]] for k in ks])) for ks in _groups(joined)]


def _groups(labels: np.ndarray) -> list[np.ndarray]:
    """Return the (ascending) indices of each label 0..max, as ``np.nonzero(labels == k)[0]`` for every k."""
    order = np.argsort(labels, kind="stable")
    return np.split(order, np.cumsum(np.bincount(labels))[:-1])


def _components(n: int, pairs: np.ndarray) -> np.ndarray:
    """Return connected-component labels of n nodes linked by (k, 2) index pairs.

    Labels are numbered by each component's lowest node (as scipy's ``connected_components``):
    every node takes the lowest label among its links, with pointer jumping, until nothing changes.
    """
    labels = np.arange(n)
    if len(pairs) == 0:
        return labels
    i, j = pairs[:, 0], pairs[:, 1]
    while True:
        low = np.minimum(labels[i], labels[j])
        new = labels.copy()
        np.minimum.at(new, i, low)
        np.minimum.at(new, j, low)
        new = new[new]
        if np.array_equal(new, labels):
            return np.unique(labels, return_inverse=True)[1]
        labels = new


def _centres(candidates: Candidates, Q: np.ndarray, groups: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Return every group's (median left px, centre triangulated at the median disparity), pixels and metres."""
    if not groups:
        return np.empty((0, 2)), np.zeros((0, 3))
    members = np.concatenate(groups)
    label = np.repeat(np.arange(len(groups)), [len(g) for g in groups])
    values = np.c_[candidates.left_px[members], candidates.disparity_px[members]]
    med = np.column_stack([_group_medians(label, values[:, c], len(groups)) for c in range(3)])
    return med[:, :2], triangulate(Q, med[:, :2], med[:, 2])


def _group_medians(label: np.ndarray, values: np.ndarray, count: int) -> np.ndarray:
    """Return the median of ``values`` per group label 0..count-1 (as ``np.median``: mean of the middle two)."""
    order = np.lexsort((values, label))
    sizes = np.bincount(label, minlength=count)
    start = np.r_[0, np.cumsum(sizes)[:-1]]
    ranked = values[order]
    low, high = ranked[start + (sizes - 1) // 2], ranked[start + sizes // 2]
    return (low + high) / 2.0
