"""Candidate detection: masking, the two matchers, and sparse disparity on real Middlebury pairs."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from dip3d_vehicle.perception.calibration import StereoRig
from dip3d_vehicle.perception.candidates import SiftDetector, kept_columns, match_bruteforce, match_row_band
from dip3d_vehicle.perception.values import ArmKeypoints

# name: (left, right, ground truth of the left image, value scale = stored value per pixel of disparity)
MIDDLEBURY = {
    "aloe": ("aloeL.jpg", "aloeR.jpg", "aloeGT.png", 1.0),
    "cones": ("im2.png", "im6.png", "disp2.pgm", 4.0),
    "teddy": ("im2.png", "im6.png", "disp2.pgm", 4.0),
    "tsukuba": ("scene1.row3.col3.ppm", "scene1.row3.col4.ppm", "truedisp.row3.col3.pgm", 16.0),
}


def arm_at(wrist_x: float, elbow_x: float) -> ArmKeypoints:
    """Return an arm with the given wrist/elbow columns in both images (row 100)."""
    px = np.array([[elbow_x - 100, 100.0], [elbow_x, 100.0], [wrist_x, 100.0]])
    return ArmKeypoints("right", px, px - [10, 0], np.ones(3), np.ones(3))


def test_mask_keeps_the_side_the_arm_points_to():
    """Paper: right of wrist + offset; 'pointing' follows the forearm; no arm keeps everything."""
    arm = arm_at(500.0, 400.0)
    assert kept_columns(arm, "left", 1600, "right", 40.0) == (540, 1600)
    assert kept_columns(arm, "right", 1600, "right", 40.0) == (530, 1600)
    assert kept_columns(arm, "left", 1600, "pointing", 40.0) == (540, 1600)
    assert kept_columns(arm_at(500.0, 600.0), "left", 1600, "pointing", 40.0) == (0, 460)
    assert kept_columns(None, "left", 1600, "right", 40.0) == (0, 1600)


def test_a_neural_poses_hand_moves_the_region_a_hand_length_beyond_the_wrist():
    """With a reported hand (BlazePose) the region starts 0.2 m (at the wrist's depth) past the wrist."""
    from dataclasses import replace

    from dip3d_vehicle.perception.candidates import hand_extent_px

    arm = arm_at(500.0, 400.0)                      # disparity 10 px, baseline 1.2 cm: f / Z = 833 px per metre
    assert hand_extent_px(arm, 0.012) == 0.0        # truth / keypoint files: no hand, no change
    with_hand = replace(arm, extra_left_px={"hand": (520.0, 100.0)})
    hand = hand_extent_px(with_hand, 0.012)
    assert abs(hand - 0.2 * 10 / 0.012) < 1e-9      # a level forearm: the whole 0.2 m across the image
    assert kept_columns(with_hand, "left", 1600, "pointing", 40.0, hand) == (667, 1600)
    assert kept_columns(with_hand, "left", 1600, "pointing", 40.0, hand_extent_px(with_hand, 0.12)) == (540, 1600)


def _features(n: int, seed: int):
    """Return (left pts, left desc, right pts, right desc) of n true matches at random rows, disparity 20-60."""
    rng = np.random.default_rng(seed)
    desc = rng.random((n, 128)).astype(np.float32) * 100
    pl = np.c_[rng.uniform(100, 1500, n), rng.uniform(0, 1200, n)]
    pr = pl - np.c_[rng.uniform(20, 60, n), np.zeros(n)]
    noise = rng.normal(0, 2.0, desc.shape).astype(np.float32)
    return pl, desc, pr, desc + noise


def test_row_band_finds_the_same_true_matches_as_bruteforce():
    """On distinct descriptors both matchers recover the true correspondences."""
    pl, dl, pr, dr = _features(3000, 1)
    qb, tb = match_bruteforce(dl, dr, 0.6)
    qr, tr = match_row_band(pl, dl, pr, dr, 0.6, 1.5, (0.5, 400.0), 1)
    assert np.all(qb == tb) and np.all(qr == tr)
    assert len(qr) >= 0.99 * len(pl) and len(qb) >= 0.99 * len(pl)


def test_row_band_drops_a_right_feature_claimed_twice():
    """Two left features on one row matching one right feature are both dropped (row-aligned edge)."""
    pl = np.array([[300.0, 50.0], [340.0, 50.0]])
    pr = np.array([[280.0, 50.0]])
    d = np.ones((1, 128), np.float32)
    q, t = match_row_band(pl, np.vstack([d, d]), pr, d, 0.6, 1.5, (0.5, 400.0), 1)
    assert len(q) == 0


def test_row_band_respects_rows_and_disparity_sign():
    """A right feature off the row band, or at negative disparity, is never matched."""
    d = np.eye(2, 128, dtype=np.float32)
    pl = np.array([[300.0, 50.0], [300.0, 80.0]])
    pr = np.array([[350.0, 50.0], [280.0, 85.0]])  # first: negative disparity; second: 5 px off the row
    q, _ = match_row_band(pl, d, pr, d, 0.6, 1.5, (0.5, 400.0), 1)
    assert len(q) == 0
    q, _ = match_row_band(pl, d, pr, d, 0.6, 1.5, (0.5, 400.0), -1)
    assert list(q) == [0]


@pytest.mark.parametrize("name", sorted(MIDDLEBURY))
@pytest.mark.parametrize("matcher,ratio", [("bruteforce", 0.3), ("row_band", 0.6)])
def test_sparse_disparity_on_middlebury(shared_dir, name, matcher, ratio):
    """Matched features' disparity agrees with Middlebury ground truth: median error < 0.5 px."""
    folder = shared_dir / "data" / "stereo" / "middlebury" / name
    left_f, right_f, gt_f, scale = MIDDLEBURY[name]
    left, right = cv2.imread(str(folder / left_f)), cv2.imread(str(folder / right_f))
    gt = cv2.imread(str(folder / gt_f), cv2.IMREAD_UNCHANGED).astype(np.float64) / scale
    h, w = left.shape[:2]
    rig = StereoRig.from_rectified([[1000, 0, w / 2, 0], [0, 1000, h / 2, 0], [0, 0, 1, 0]],
                                   [[1000, 0, w / 2, -100], [0, 1000, h / 2, 0], [0, 0, 1, 0]], (w, h))
    det = SiftDetector(matcher=matcher, lowe_ratio=ratio, min_depth_m=0.05)
    cands = det.detect(left, right, None, rig)
    xy = np.round(cands.left_px).astype(int)
    truth = gt[xy[:, 1], xy[:, 0]]
    known = truth > 0
    err = np.abs(cands.disparity_px[known] - truth[known])
    print(f"{name} {matcher}: {known.sum()} matches with truth, median {np.median(err):.3f} px, "
          f"p90 {np.percentile(err, 90):.3f} px, within 1 px {np.mean(err < 1):.1%}")
    assert known.sum() >= 50
    assert np.median(err) < 0.5
