"""StereoRig: real chessboard rectification, pixel mapping both ways, properties and bad parameters."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from dip3d_vehicle.errors import CalibrationError, ImageError
from dip3d_vehicle.perception.calibration import StereoRig

PATTERN = (9, 6)  # inner corners of the OpenCV sample chessboard
SQUARE_M = 0.025
PAIRS = ("01", "02", "03", "04", "05", "06", "07", "08", "09", "11", "12", "13", "14")
SIZE = (640, 480)


def distorted_rig(tx_sign: float = -1.0, alpha: float = 0.0) -> StereoRig:
    """Return a 640x480 rig with visible distortion and a small rotation (right camera to the right)."""
    K1 = np.array([[700.0, 0, 330.0], [0, 702.0, 245.0], [0, 0, 1]])
    K2 = np.array([[705.0, 0, 318.0], [0, 704.0, 236.0], [0, 0, 1]])
    D1 = np.array([-0.12, 0.05, 0.001, -0.0008, 0.0])
    D2 = np.array([-0.10, 0.03, -0.0005, 0.0007, 0.0])
    R, _ = cv2.Rodrigues(np.array([0.01, -0.02, 0.005]))
    T = np.array([0.12 * tx_sign, 0.002, 0.001])
    return StereoRig.from_parameters(K1, D1, K2, D2, R, T, SIZE, alpha=alpha)


# -- real data: the OpenCV chessboard sample -----------------------------------------------------
def _corners(gray: np.ndarray) -> np.ndarray | None:
    """Return the (54, 2) sub-pixel chessboard corners of a grey image, or None."""
    ok, found = cv2.findChessboardCorners(gray, PATTERN, cv2.CALIB_CB_ADAPTIVE_THRESH | cv2.CALIB_CB_NORMALIZE_IMAGE)
    if not ok:
        return None
    crit = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_COUNT, 30, 0.01)
    return cv2.cornerSubPix(gray, found, (11, 11), (-1, -1), crit).reshape(-1, 2)


@pytest.fixture(scope="module")
def chessboard(shared_dir: Path) -> dict:
    """Calibrate the stereo sample (each camera, then the pair with fixed intrinsics)."""
    folder = shared_dir / "data" / "stereo" / "opencv_chessboard"
    obj = np.zeros((PATTERN[0] * PATTERN[1], 3), np.float32)
    obj[:, :2] = np.mgrid[0:PATTERN[0], 0:PATTERN[1]].T.reshape(-1, 2) * SQUARE_M
    images, left_pts, right_pts = [], [], []
    for n in PAIRS:
        left = cv2.imread(str(folder / f"left{n}.jpg"), cv2.IMREAD_GRAYSCALE)
        right = cv2.imread(str(folder / f"right{n}.jpg"), cv2.IMREAD_GRAYSCALE)
        assert left is not None and right is not None, f"cannot read pair {n} in {folder}"
        cl, cr = _corners(left), _corners(right)
        assert cl is not None and cr is not None, f"chessboard not found in pair {n}"
        images.append((left, right))
        left_pts.append(cl.astype(np.float32))
        right_pts.append(cr.astype(np.float32))
    objs = [obj] * len(images)
    _, K1, D1, _, _ = cv2.calibrateCamera(objs, left_pts, SIZE, None, None)
    _, K2, D2, _, _ = cv2.calibrateCamera(objs, right_pts, SIZE, None, None)
    rms, K1, D1, K2, D2, R, T, _, _ = cv2.stereoCalibrate(objs, left_pts, right_pts, K1, D1, K2, D2, SIZE,
                                                          flags=cv2.CALIB_FIX_INTRINSIC)
    rig = StereoRig.from_parameters(K1, D1, K2, D2, R, T, SIZE, alpha=0.0)
    return {"rms": rms, "rig": rig, "images": images, "left_pts": left_pts, "right_pts": right_pts}


def test_chessboard_stereo_calibration_matches_the_sample(chessboard, record_property):
    rig = chessboard["rig"]
    record_property("stereo_rms_px", chessboard["rms"])
    record_property("baseline_m", rig.baseline_m)
    assert chessboard["rms"] < 0.6  # measured 0.447 px
    assert rig.baseline_m == pytest.approx(0.0836, abs=0.002)
    assert rig.disparity_sign == 1  # right camera to the right


def test_rectified_chessboard_rows_align(chessboard, record_property):
    rig = chessboard["rig"]
    dys = []
    for left, right in chessboard["images"]:
        rl, rr = rig.rectify(left, right)
        assert rl.shape == left.shape and rr.shape == right.shape
        cl, cr = _corners(rl), _corners(rr)
        if cl is not None and cr is not None:
            dys.append(np.abs(cl[:, 1] - cr[:, 1]))
    assert len(dys) >= 10, "chessboard lost in too many rectified pairs"
    dy = np.concatenate(dys)
    record_property("rectified_dy_median_px", float(np.median(dy)))
    record_property("rectified_dy_p90_px", float(np.percentile(dy, 90)))
    assert np.median(dy) < 1.0  # measured 0.088 px
    assert np.percentile(dy, 90) < 1.0  # measured 0.27 px


def test_mapped_chessboard_corners_align_and_are_in_front(chessboard):
    rig = chessboard["rig"]
    for cl, cr in zip(chessboard["left_pts"], chessboard["right_pts"]):
        ml, mr = rig.to_rectified(cl, "left"), rig.to_rectified(cr, "right")
        assert np.median(np.abs(ml[:, 1] - mr[:, 1])) < 1.0
        assert np.all(ml[:, 0] - mr[:, 0] > 0)  # positive disparity: right camera to the right


# -- pixel mapping -----------------------------------------------------------------------------
def _grid(w: int, h: int, n: int = 15) -> np.ndarray:
    """Return an (n*n, 2) grid of pixels covering the image."""
    xs, ys = np.meshgrid(np.linspace(0, w - 1, n), np.linspace(0, h - 1, n))
    return np.c_[xs.ravel(), ys.ravel()]


@pytest.mark.parametrize("side", ["left", "right"])
@pytest.mark.parametrize("tx_sign", [-1.0, 1.0])
def test_original_rectified_original_round_trip(side, tx_sign):
    rig = distorted_rig(tx_sign)
    pts = _grid(*SIZE)
    back = rig.to_original(rig.to_rectified(pts, side), side)
    assert np.max(np.linalg.norm(back - pts, axis=1)) < 0.01


@pytest.mark.parametrize("side", ["left", "right"])
def test_rectified_original_rectified_round_trip(side):
    rig = distorted_rig()
    pts = _grid(*SIZE)
    back = rig.to_rectified(rig.to_original(pts, side), side)
    assert np.max(np.linalg.norm(back - pts, axis=1)) < 0.01


def test_distortion_really_moves_points():
    rig = distorted_rig()
    pts = _grid(*SIZE)
    assert np.max(np.linalg.norm(rig.to_rectified(pts, "left") - pts, axis=1)) > 5.0


def test_rectify_image_matches_point_mapping():
    rig = distorted_rig()
    img = np.zeros((SIZE[1], SIZE[0]), np.uint8)
    x, y = 470.0, 130.0
    cv2.circle(img, (int(x), int(y)), 6, 255, -1, lineType=cv2.LINE_AA)
    rect = rig.rectify_image(img, "left").astype(float)
    ys, xs = np.nonzero(rect > 0)
    weights = rect[ys, xs]
    centre = np.array([np.average(xs, weights=weights), np.average(ys, weights=weights)])
    expected = rig.to_rectified([[x, y]], "left")[0]
    assert np.linalg.norm(centre - expected) < 0.5


def test_already_rectified_rig_maps_identically():
    base = distorted_rig()
    rig = StereoRig.from_rectified(base.P1, base.P2, SIZE)
    pts = _grid(*SIZE)
    for side in ("left", "right"):
        assert np.array_equal(rig.to_rectified(pts, side), pts)
        assert np.array_equal(rig.to_original(pts, side), pts)
    img = np.arange(SIZE[0] * SIZE[1], dtype=np.uint32).reshape(SIZE[1], SIZE[0])
    left, right = rig.rectify(img, img)
    assert left is img and right is img
    assert rig.prerectified
    np.testing.assert_allclose(rig.Q, base.Q, rtol=1e-9, atol=1e-9)
    assert rig.baseline_m == pytest.approx(base.baseline_m)


def test_empty_point_arrays():
    rig = distorted_rig()
    assert rig.to_rectified(np.zeros((0, 2)), "left").shape == (0, 2)
    assert rig.to_original([], "right").shape == (0, 2)
    with pytest.raises(ValueError):
        rig.to_rectified([[1.0, 2.0]], "middle")


# -- properties --------------------------------------------------------------------------------
@pytest.mark.parametrize("tx_sign, sign", [(-1.0, 1), (1.0, -1)])
def test_properties(tx_sign, sign):
    rig = distorted_rig(tx_sign)
    assert rig.disparity_sign == sign
    assert rig.baseline_m == pytest.approx(np.linalg.norm([0.12, 0.002, 0.001]), rel=1e-9)
    assert rig.focal_px == rig.P1[0, 0] > 0
    cx, cy = rig.principal_point_px
    assert 0 < cx < SIZE[0] and 0 < cy < SIZE[1]
    sigma = rig.depth_sigma_m(np.array([1.0, 2.0]), 0.5)
    np.testing.assert_allclose(sigma, np.array([1.0, 4.0]) * 0.5 / (rig.focal_px * rig.baseline_m))


def test_maps_are_cached_and_sized():
    rig = distorted_rig()
    m1, m2 = rig.maps("left")
    assert m1.shape[:2] == (SIZE[1], SIZE[0])
    assert rig.maps("left")[0] is m1


def test_check_frame():
    rig = distorted_rig()
    rig.check_frame(np.zeros((480, 640, 3), np.uint8), "left.png")
    with pytest.raises(ImageError, match=r"left.png: image is 800x600 .* 640x480"):
        rig.check_frame(np.zeros((600, 800, 3), np.uint8), "left.png")


# -- bad parameters ----------------------------------------------------------------------------
def _params(**over):
    """Return from_parameters arguments of a plain rig, with overrides."""
    args = {"K1": np.array([[500.0, 0, 320], [0, 500, 240], [0, 0, 1]]), "D1": np.zeros(5),
            "K2": np.array([[500.0, 0, 320], [0, 500, 240], [0, 0, 1]]), "D2": np.zeros(5),
            "R": np.eye(3), "T": np.array([-0.1, 0.0, 0.0]), "image_size": SIZE}
    args.update(over)
    return args


@pytest.mark.parametrize("over, match", [
    ({"K1": np.array([[-500.0, 0, 320], [0, 500, 240], [0, 0, 1]])}, "K1/M1 focal length must be > 0"),
    ({"K2": np.zeros((2, 3))}, r"K2/M2 has shape \(2, 3\)"),
    ({"D1": np.zeros(3)}, "D1 has 3 coefficients"),
    ({"D2": np.array([0.0, np.nan, 0, 0, 0])}, "D2 has non-finite values"),
    ({"R": np.diag([1.0, 1.0, -1.0])}, "R is not a rotation matrix"),
    ({"T": np.zeros(3)}, "T is zero"),
    ({"T": np.array([0.0, -0.1, 0.0])}, "mostly vertical"),
    ({"T": np.array([np.inf, 0.0, 0.0])}, "T has non-finite values"),
    ({"image_size": (0, 480)}, "image size 0x480 must be positive"),
])
def test_from_parameters_rejects_bad_values(over, match):
    with pytest.raises(CalibrationError, match=match):
        StereoRig.from_parameters(**_params(**over), source="cal.yml")


def test_from_rectified_rejects_zero_baseline():
    P = np.array([[500.0, 0, 320, 0], [0, 500, 240, 0], [0, 0, 1, 0]])
    with pytest.raises(CalibrationError, match=r"cal.yml: P2\[0,3\] is zero"):
        StereoRig.from_rectified(P, P, SIZE, source="cal.yml")
