"""Unrecognised spots along the corridor: found, matched to 3D, and weighed as "nothing detected"."""

from __future__ import annotations

from functools import partial

import numpy as np
import pytest

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blobs import BlobFinder, Blobs, object_disparity, unexplained
from dip3d_vehicle.perception.pipeline import Perception

from test_selection import RIG, _arm_right, candidates_of, cluster, project


def _water(seed: int = 0) -> np.ndarray:
    """Return a grey-blue, slightly grainy 1600x1200 image (BGR uint8)."""
    rng = np.random.default_rng(seed)
    img = np.empty((1200, 1600, 3), np.float32)
    img[:] = (120, 100, 40)
    img += rng.normal(0.0, 1.5, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def _paint_spot(img: np.ndarray, centre_px: np.ndarray, half_px: int, seed: int) -> None:
    """Paint a small textured square (a tiny placard) centred at ``centre_px``."""
    rng = np.random.default_rng(seed)
    x, y = int(round(centre_px[0])), int(round(centre_px[1]))
    patch = rng.integers(150, 255, (2 * half_px + 1, 2 * half_px + 1, 1)).astype(np.uint8).repeat(3, axis=2)
    patch[half_px - 2:half_px + 3, half_px - 2:half_px + 3] = 20
    img[y - half_px:y + half_px + 1, x - half_px:x + half_px + 1] = patch


WEDGE = np.array([[900.0, 560.0], [1600.0, 380.0], [1600.0, 760.0], [900.0, 640.0]])


def test_a_small_spot_is_found_and_matched_to_its_depth_and_an_edge_is_not():
    """A 13 px spot at 3 m is found in the wedge at its place and depth; a long straight edge gives no spot."""
    left, right = _water(1), _water(2)
    spot = np.array([1.0, 0.0, 3.0])
    _paint_spot(left, project(spot)[0], 6, seed=3)
    _paint_spot(right, project(spot, -0.12)[0], 6, seed=3)
    left[700:704, 950:1500] = right[700:704, 910:1460] = 10  # a long dark line across the wedge
    blobs = BlobFinder().find(left, right, WEDGE, RIG)
    assert len(blobs) >= 1
    near = np.linalg.norm(blobs.xyz_m - spot, axis=1) < 0.1
    assert near.any()
    assert np.all(np.abs(blobs.left_px[:, 1] - 702) > 8)  # nothing on the line


def _smooth_water(seed: int, grain: float) -> np.ndarray:
    """Return a grey-blue 1600x1200 image with Gaussian grain of ``grain`` grey levels (float, BGR)."""
    img = np.empty((1200, 1600, 3), np.float32)
    img[:] = (120, 100, 40)
    return img + np.random.default_rng(seed).normal(0.0, grain, img.shape)


def test_a_faint_small_spot_in_smooth_water_is_found_and_bare_water_gives_none():
    """A 9 px spot 5 grey levels above smooth water (grain 0.5) is found with the default floor; bare water is not.

    Its difference-of-Gaussians response is under 3 grey levels but many times the grain: the tiny pointed
    placards of the undetectable family (issue 11, session 28's census: 2.3-2.8 grey levels) were lost under
    the old floor of 3.
    """
    finder = BlobFinder.from_params(load_params("default"))
    spot = np.array([1.0, 0.0, 3.0])
    pair = []
    for seed, offset_m in ((1, 0.0), (2, -0.12)):
        img = _smooth_water(seed, 0.5)
        x, y = np.round(project(spot, offset_m)[0]).astype(int)
        img[y - 4:y + 5, x - 4:x + 5] += 5.0
        pair.append(np.clip(np.round(img), 0, 255).astype(np.uint8))
    blobs = finder.find(pair[0], pair[1], WEDGE, RIG)
    assert np.any(np.linalg.norm(blobs.xyz_m - spot, axis=1) < 0.15)
    for seed in range(3):
        bare = [np.clip(np.round(_smooth_water(10 + seed + k, 0.5)), 0, 255).astype(np.uint8) for k in (0, 20)]
        assert len(finder.find(bare[0], bare[1], WEDGE, RIG)) == 0


def test_spots_inside_a_recognised_object_are_its_own():
    """Spots inside a known object's feature hull are skipped; unexplained drops those near its points."""
    left, right = _water(1), _water(2)
    spot = np.array([1.0, 0.0, 3.0])
    _paint_spot(left, project(spot)[0], 6, seed=3)
    _paint_spot(right, project(spot, -0.12)[0], 6, seed=3)
    square = spot + np.array([[dx, dy, 0.0] for dx in (-0.05, 0.05) for dy in (-0.05, 0.05)])
    assert len(BlobFinder().find(left, right, WEDGE, RIG, [project(square)])) == 0
    blobs = Blobs(np.array([[1133.0, 600.0]]), np.array([[1.0, 0.0, 3.0]]), np.array([0.05]))
    assert len(unexplained(blobs, [np.zeros((0, 2))], [cluster(spot + [0.1, 0, 0], 5, 0.02)], np.zeros((0, 3)))) == 0
    assert len(unexplained(blobs, [], [], np.array([[1.2, 0.0, 3.0]]))) == 0  # the diver's own hand
    assert len(unexplained(blobs, [], [], np.array([[-0.4, 0.0, 3.0]]))) == 1


def _beside_scene(object_depth_m: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Return (left, right, spot xyz, the object's feature pixels, its 3D points): a 13 px spot at 3 m and
    a recognised object (66 px wide) whose features end 24 px beside it, at ``object_depth_m`` along the same rays."""
    left, right = _water(1), _water(2)
    spot = np.array([1.0, 0.0, 3.0])
    _paint_spot(left, project(spot)[0], 6, seed=3)
    _paint_spot(right, project(spot, -0.12)[0], 6, seed=3)
    at_3m = spot + np.array([[0.17 + dx, dy, 0.0] for dx in (-0.1, 0.0, 0.1) for dy in (-0.1, 0.0, 0.1)])
    return left, right, spot, project(at_3m), at_3m * (object_depth_m / 3.0)


def test_a_spot_beside_an_object_at_another_depth_is_kept_and_at_its_depth_is_its_own():
    """A spot just beside a recognised object (issue 11 session 21: a 4 cm target 36 px beside a placard
    0.74 m behind it): matched although presumed the object's, kept when its sharp match lies 0.75 m in
    front of the object's plane, dropped when it lies on that plane (the object's own texture)."""
    left, right, spot, known_px, behind = _beside_scene(3.75)
    blobs = BlobFinder().find(left, right, WEDGE, RIG, [known_px], known_xyz=[behind])
    assert len(blobs) >= 1 and np.all(np.linalg.norm(blobs.xyz_m - spot, axis=1) < 0.1)
    assert len(unexplained(blobs, [known_px], [behind], np.zeros((0, 3)))) == 1
    left, right, spot, known_px, same = _beside_scene(3.0)
    assert len(BlobFinder().find(left, right, WEDGE, RIG, [known_px], known_xyz=[same])) == 0
    assert len(BlobFinder(max_beside=0).find(left, right, WEDGE, RIG, [known_px], known_xyz=[behind])) == 0


def test_a_spot_beside_an_object_that_matches_as_well_at_its_depth_is_its_own():
    """A sharp match off the object's plane is not enough: when the patch scores nearly as well at the
    object's own disparity (a placard's edge matched on a repeat of itself) the spot is the object's."""
    left, right, spot, known_px, behind = _beside_scene(6.0)
    assert len(BlobFinder().find(left, right, WEDGE, RIG, [known_px], known_xyz=[behind])) >= 1
    x, y = np.round(project(spot)[0]).astype(int)
    xr = int(round(project(spot, -0.12)[0][0]))
    shift = int(round(RIG.focal_px * RIG.baseline_m / 6.0))
    repeat = right[y - 6:y + 7, xr - 6:xr + 7].astype(float) + np.random.default_rng(5).normal(0.0, 25.0, (13, 13, 3))
    right[y - 6:y + 7, x - shift - 6:x - shift + 7] = np.clip(repeat, 0, 255)  # a fainter repeat at 6 m
    found = BlobFinder().find(left, right, WEDGE, RIG, [known_px], known_xyz=[behind])
    assert len(found) == 0


def test_object_disparity_extrapolates_a_slanted_plane():
    """A placard turned 50 deg about the vertical: its disparity beside its features is the plane's (pixels)."""
    u, v = np.meshgrid(np.linspace(-0.1, 0.1, 4), np.linspace(-0.1, 0.1, 3))
    turn = np.radians(50.0)
    pts = np.c_[u.ravel() * np.cos(turn), v.ravel(), 3.0 + u.ravel() * np.sin(turn)]
    beyond = np.array([[0.2 * np.cos(turn), 0.0, 3.0 + 0.2 * np.sin(turn)]])
    fb = RIG.focal_px * RIG.baseline_m
    d, rms = object_disparity(project(pts), pts, project(beyond)[0], fb)
    assert d == pytest.approx(fb / beyond[0, 2], abs=0.05) and rms < 0.05
    assert object_disparity(project(pts[:2]), pts[:2], project(beyond)[0], fb)[0] == pytest.approx(
        np.median(fb / pts[:2, 2]))


def test_an_unrecognised_spot_on_the_arm_turns_a_decoy_off_the_arm_into_nothing_detected():
    """The arm points at an unrecognised spot; the only object lies on the arm's image line but 15 deg off it
    toward the camera (only the arm's uncertain tilt reaches it): without the spot the object wins, with it
    "nothing detected" does, and the spot itself is never chosen."""
    arm, u = _arm_right(2.5)
    shoulder = np.array([-0.4, 0.0, 2.5])
    ahead = shoulder + 2.2 * u
    tilt = np.radians(15.0)
    toward = shoulder + 2.0 * (np.cos(tilt) * u + np.sin(tilt) * np.array([0.0, 0.0, -1.0]))
    cands, xyz = candidates_of(cluster(toward, 15, 0.08, seed=11))
    perception = Perception(RIG, load_params("default"), None, detector=object())
    arm3d = perception.triangulate_arm(arm)
    spot = Blobs(project(ahead), ahead[None], np.array([0.03]))
    alone = perception.selector.select(arm, arm3d, cands, xyz, RIG)
    seen = perception.selector.select(arm, arm3d, cands, xyz, RIG, partial(unexplained, spot))
    assert alone.index == 0 and alone.confidence > 0.5
    assert seen.index is None and seen.nothing_on_ray and seen.none_probability > 0.6
    assert "unrecognised" in seen.reason
    assert float(np.sum(seen.scores)) + seen.none_probability == pytest.approx(1.0)
    assert seen.scores[0] < alone.scores[0]
    off = load_params("default", overrides={"selection.unrecognised_weight": 0.0})
    ignored = Perception(RIG, off, None, detector=object()).selector.select(
        arm, arm3d, cands, xyz, RIG, partial(unexplained, spot))
    assert ignored.index == alone.index and ignored.confidence == pytest.approx(alone.confidence)


def test_an_overwhelming_object_with_spots_about_does_not_break_the_arithmetic(monkeypatch):
    """Log odds far beyond exp's range (an arm-only fit that converged badly) leave "nothing detected" at 0, no error.

    (A spot source that finds only spots the arm cannot point at once made "nothing detected"'s weight
    underflow to 0 and its logarithm fail: a mission campaign in murky water stopped on it.)
    """
    from dip3d_vehicle.perception import pointing_fit

    arm, u = _arm_right(2.5)
    shoulder = np.array([-0.4, 0.0, 2.5])
    cands, xyz = candidates_of(cluster(shoulder + 2.0 * u, 15, 0.08, seed=8))
    perception = Perception(RIG, load_params("default"), None, detector=object())
    arm3d = perception.triangulate_arm(arm)
    monkeypatch.setattr(pointing_fit._PointingFit, "arm_cost", lambda self, iterations=25: 1e5)
    behind = shoulder - 1.5 * u  # behind the shoulder: outside the arm's image direction
    spot = Blobs(project(behind), behind[None], np.array([0.03]))
    sel = perception.selector.select(arm, arm3d, cands, xyz, RIG, partial(unexplained, spot))
    assert sel.index == 0 and sel.confidence == pytest.approx(1.0) and sel.none_probability < 1e-12
    assert np.isfinite(sel.ambiguity_margin)


def test_the_slots_for_spots_beside_objects_go_to_spots_that_pass_not_to_the_first_tried(monkeypatch):
    """Three rim spots of a placard at 3.75 m lie beside it nearer the wedge's axis than a small thing at 3 m,
    also beside it (issue 11 session 23: undetectable scene 900 #6). The rim spots match on the placard's
    own depth and are set aside; the small thing still gets a slot. The rim spots' patches already match at
    the placard's own disparity, so they are set aside before any row search and cost no try: even one try
    per slot reaches the small thing (issue 11 session 28; before, the rim spots took every try)."""
    from dip3d_vehicle.perception import blobs as blobs_module

    left, right = _water(1), _water(2)
    fb = RIG.focal_px * RIG.baseline_m
    thing_px = np.array([1150.0, 652.0])
    thing = np.array([(thing_px[0] - 800.0) * 3.0 / 1000.0, (thing_px[1] - 600.0) * 3.0 / 1000.0, 3.0])
    _paint_spot(left, thing_px, 6, seed=3)
    _paint_spot(right, thing_px - [fb / 3.0, 0.0], 6, seed=3)
    for k, rim in enumerate(([1150.0, 585.0], [1150.0, 615.0], [1205.0, 553.0])):
        _paint_spot(left, np.array(rim), 6, seed=10 + k)
        _paint_spot(right, np.array(rim) - [fb / 3.75, 0.0], 6, seed=10 + k)
    grid = np.array([[x, y] for x in (1170.0, 1205.0, 1240.0) for y in (570.0, 600.0, 630.0)])
    known_xyz = np.c_[(grid[:, 0] - 800.0) * 3.75 / 1000.0, (grid[:, 1] - 600.0) * 3.75 / 1000.0, np.full(9, 3.75)]
    found = BlobFinder().find(left, right, WEDGE, RIG, [grid], known_xyz=[known_xyz])
    assert np.any(np.linalg.norm(found.xyz_m - thing, axis=1) < 0.1)
    assert np.all(np.abs(found.xyz_m[:, 2] - 3.75) > 0.3)          # no rim spot kept
    monkeypatch.setattr(blobs_module, "BESIDE_TRIES_PER_SLOT", 1)
    tried = []
    match_point = blobs_module.match_point
    monkeypatch.setattr(blobs_module, "match_point", lambda *a: tried.append(a[2:4]) or match_point(*a))
    one_try = BlobFinder().find(left, right, WEDGE, RIG, [grid], known_xyz=[known_xyz])
    assert np.any(np.linalg.norm(one_try.xyz_m - thing, axis=1) < 0.1)
    rims = np.array([[1150.0, 585.0], [1150.0, 615.0], [1205.0, 553.0]])
    assert any(np.hypot(x - thing_px[0], y - thing_px[1]) < 10 for x, y in tried)
    assert not any(np.min(np.hypot(x - rims[:, 0], y - rims[:, 1])) < 10 for x, y in tried)  # no rim spot row-searched
