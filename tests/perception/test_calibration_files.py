"""calibration_io: the three file formats give the same rig; every bad file is one clear error line."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml

from dip3d_vehicle.errors import CalibrationError
from dip3d_vehicle.perception.calibration import StereoRig
from dip3d_vehicle.perception.calibration_io import detect_format, load_rig, write_opencv_calibration

SIZE = (640, 480)
DATA = Path(__file__).resolve().parents[1] / "data" / "calib"


@pytest.fixture(scope="module")
def rig() -> StereoRig:
    """A distorted 640x480 rig with 4 distortion coefficients (what Kalibr radtan can hold)."""
    K1 = np.array([[700.0, 0, 330.0], [0, 702.0, 245.0], [0, 0, 1]])
    K2 = np.array([[705.0, 0, 318.0], [0, 704.0, 236.0], [0, 0, 1]])
    D1 = np.array([-0.12, 0.05, 0.001, -0.0008])
    D2 = np.array([-0.10, 0.03, -0.0005, 0.0007])
    R, _ = cv2.Rodrigues(np.array([0.01, -0.02, 0.005]))
    return StereoRig.from_parameters(K1, D1, K2, D2, R, np.array([-0.12, 0.002, 0.001]), SIZE)


# -- writers of each format (what the tools write) -----------------------------------------------
def write_fs(path: Path, values: dict) -> Path:
    """Write ``values`` with cv2.FileStorage (OpenCV YAML, ``%YAML:1.0`` and ``!!opencv-matrix``)."""
    fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE | cv2.FILE_STORAGE_FORMAT_YAML)
    for key, value in values.items():
        fs.write(key, value if isinstance(value, (int, str)) else np.asarray(value, np.float64))
    fs.release()
    return path


def opencv_values(rig: StereoRig, size: bool = True) -> dict:
    """Return the keys of a merged OpenCV stereo_calib file for ``rig``."""
    out = {"M1": rig.K1, "D1": rig.D1, "M2": rig.K2, "D2": rig.D2, "R": rig.R, "T": rig.T,
           "R1": rig.R1, "R2": rig.R2, "P1": rig.P1, "P2": rig.P2, "Q": rig.Q}
    if size:
        out.update(image_width=rig.image_size[0], image_height=rig.image_size[1])
    return out


def kalibr_values(rig: StereoRig) -> dict:
    """Return a Kalibr camchain mapping for ``rig`` (with the extra keys Kalibr writes)."""
    def cam(K, D):
        return {"camera_model": "pinhole", "intrinsics": [float(K[0, 0]), float(K[1, 1]), float(K[0, 2]),
                                                          float(K[1, 2])],
                "distortion_model": "radtan", "distortion_coeffs": [float(v) for v in D.ravel()[:4]],
                "resolution": list(rig.image_size), "rostopic": "/cam/image_raw", "cam_overlaps": [1]}
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = rig.R, rig.T.ravel()
    cam1 = cam(rig.K2, rig.D2)
    cam1["T_cn_cnm1"] = T.tolist()
    return {"cam0": cam(rig.K1, rig.D1), "cam1": cam1}


def ros_values(rig: StereoRig, side: str) -> dict:
    """Return a ROS camera_info mapping (camera_calibration layout) of one camera of ``rig``."""
    K, D, Rr, P = (rig.K1, rig.D1, rig.R1, rig.P1) if side == "left" else (rig.K2, rig.D2, rig.R2, rig.P2)
    d = np.zeros(5)
    d[:D.size] = D.ravel()

    def mat(a):
        a = np.asarray(a, np.float64).reshape(a.shape[0], -1)
        return {"rows": a.shape[0], "cols": a.shape[1], "data": [float(v) for v in a.ravel()]}
    return {"image_width": rig.image_size[0], "image_height": rig.image_size[1], "camera_name": side,
            "camera_matrix": mat(K), "distortion_model": "plumb_bob", "distortion_coefficients": mat(d[None]),
            "rectification_matrix": mat(Rr), "projection_matrix": mat(P)}


def write_yaml(path: Path, data) -> Path:
    """Write plain YAML."""
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def write_ros_pair(rig: StereoRig, folder: Path) -> tuple[Path, Path]:
    """Write left.yaml and right.yaml camera_info files for ``rig``."""
    return (write_yaml(folder / "left.yaml", ros_values(rig, "left")),
            write_yaml(folder / "right.yaml", ros_values(rig, "right")))


def assert_same_rectification(a: StereoRig, b: StereoRig) -> None:
    """Assert two rigs rectify identically (to float precision)."""
    assert tuple(a.image_size) == tuple(b.image_size)
    for name in ("P1", "P2", "R1", "R2", "Q"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), rtol=1e-7, atol=1e-7, err_msg=name)
    assert a.disparity_sign == b.disparity_sign


# -- the three formats agree ---------------------------------------------------------------------
def test_opencv_merged_file(rig, tmp_path):
    loaded = load_rig([write_fs(tmp_path / "cal.yml", opencv_values(rig))])
    assert_same_rectification(loaded, rig)
    assert not loaded.prerectified and loaded.source == str(tmp_path / "cal.yml")


def test_opencv_xml_file(rig, tmp_path):
    fs = cv2.FileStorage(str(tmp_path / "cal.xml"), cv2.FILE_STORAGE_WRITE | cv2.FILE_STORAGE_FORMAT_XML)
    for key, value in opencv_values(rig).items():
        fs.write(key, value if isinstance(value, int) else np.asarray(value, np.float64))
    fs.release()
    assert_same_rectification(load_rig(tmp_path / "cal.xml"), rig)


@pytest.mark.parametrize("order", [1, -1])
def test_opencv_intrinsics_and_extrinsics_files(rig, tmp_path, order):
    values = opencv_values(rig, size=False)
    intr = write_fs(tmp_path / "intrinsics.yml", {k: values[k] for k in ("M1", "D1", "M2", "D2")})
    extr = write_fs(tmp_path / "extrinsics.yml", {k: values[k] for k in ("R", "T", "R1", "R2", "P1", "P2", "Q")})
    loaded = load_rig([intr, extr][::order], image_size=SIZE)
    assert_same_rectification(loaded, rig)


def test_kalibr_camchain(rig, tmp_path):
    loaded = load_rig([write_yaml(tmp_path / "camchain.yaml", kalibr_values(rig))], image_size=SIZE)
    assert_same_rectification(loaded, rig)
    np.testing.assert_allclose(loaded.T, rig.T)


def test_ros_camera_info_pair(rig, tmp_path):
    loaded = load_rig(write_ros_pair(rig, tmp_path))
    assert_same_rectification(loaded, rig)
    np.testing.assert_allclose(loaded.R, rig.R, atol=1e-12)
    np.testing.assert_allclose(loaded.T, rig.T, atol=1e-12)


def test_ros_pair_for_right_camera_on_the_left(tmp_path):
    K = np.array([[600.0, 0, 320], [0, 600, 240], [0, 0, 1]])
    mirrored = StereoRig.from_parameters(K, np.zeros(5), K, np.zeros(5), np.eye(3), [0.1, 0, 0], SIZE)
    loaded = load_rig(write_ros_pair(mirrored, tmp_path))
    assert loaded.disparity_sign == -1
    assert_same_rectification(loaded, mirrored)


@pytest.mark.parametrize("layout", ["opencv", "kalibr", "ros"])
def test_directory_layouts(rig, tmp_path, layout):
    if layout == "opencv":
        values = opencv_values(rig)
        write_fs(tmp_path / "intrinsics.yml", {k: values[k] for k in ("M1", "D1", "M2", "D2")})
        write_fs(tmp_path / "extrinsics.yml", {k: values[k] for k in ("R", "T")})
    elif layout == "kalibr":
        write_yaml(tmp_path / "camchain.yaml", kalibr_values(rig))
    else:
        write_ros_pair(rig, tmp_path)
    assert_same_rectification(load_rig(tmp_path, image_size=SIZE), rig)


def test_committed_fixture_files_agree():
    """The hand-laid-out files in tests/data/calib (one per format, same rig) give the same geometry."""
    opencv = load_rig([DATA / "opencv_stereo.yml"])
    kalibr = load_rig([DATA / "kalibr_camchain.yaml"])
    ros = load_rig([DATA / "ros_left.yaml", DATA / "ros_right.yaml"])
    for other in (kalibr, ros):
        np.testing.assert_allclose(other.P1, opencv.P1, rtol=1e-6, atol=1e-5)
        np.testing.assert_allclose(other.P2, opencv.P2, rtol=1e-6, atol=1e-5)
    assert opencv.image_size == (752, 480)
    assert opencv.baseline_m == pytest.approx(0.110, abs=1e-3)


def test_detect_format():
    assert detect_format({"cam0": {}}) == "kalibr"
    assert detect_format({"camera_matrix": {}}) == "ros"
    assert detect_format({"M1": 1}) == "opencv"
    with pytest.raises(CalibrationError, match="x.yml: not a recognised calibration"):
        detect_format({"foo": 1}, "x.yml")


def test_real_opencv_sample_intrinsics_file(shared_dir, tmp_path):
    """The stereo_calib sample's own intrinsics.yml (FileStorage YAML) plus an extrinsics file."""
    intr = shared_dir / "data" / "stereo" / "opencv_chessboard" / "intrinsics.yml"
    with pytest.raises(CalibrationError, match=r"intrinsics.yml: missing key R$"):
        load_rig([intr], image_size=SIZE)
    extr = write_fs(tmp_path / "extrinsics.yml", {"R": np.eye(3), "T": np.array([[-0.0836], [0.0], [0.0]])})
    loaded = load_rig([intr, extr], image_size=SIZE)
    assert loaded.K1[0, 0] == pytest.approx(534.80326845051309)
    assert loaded.D1.shape == (1, 5)
    assert loaded.baseline_m == pytest.approx(0.0836)


# -- writing and reading back ----------------------------------------------------------------------
def test_write_then_load_is_identical(rig, tmp_path):
    path = write_opencv_calibration(rig, tmp_path / "out.yml")
    assert path.read_text().startswith("%YAML:1.0")
    back = load_rig([path])
    for name in ("K1", "D1", "K2", "D2", "R", "T", "R1", "R2", "P1", "P2", "Q"):
        assert np.array_equal(getattr(back, name), getattr(rig, name)), name
    assert back.image_size == rig.image_size and not back.prerectified


def test_write_then_load_prerectified_rig(rig, tmp_path):
    pre = StereoRig.from_rectified(rig.P1, rig.P2, SIZE)
    back = load_rig([write_opencv_calibration(pre, tmp_path / "rect.yml")])
    assert back.prerectified
    for name in ("P1", "P2", "Q"):
        assert np.array_equal(getattr(back, name), getattr(pre, name)), name


def test_write_to_missing_directory(rig, tmp_path):
    with pytest.raises(CalibrationError, match="cannot open"):
        write_opencv_calibration(rig, tmp_path / "no" / "such" / "dir" / "cal.yml")


# -- already-rectified input ---------------------------------------------------------------------
def test_already_rectified_uses_the_given_projections(rig, tmp_path):
    values = opencv_values(rig)
    values["P1"] = values["P1"] * np.array([[1.01], [1.01], [1.0]])  # differs from what stereoRectify gives
    path = write_fs(tmp_path / "cal.yml", values)
    loaded = load_rig([path], already_rectified=True)
    assert loaded.prerectified
    np.testing.assert_array_equal(loaded.P1, values["P1"])
    np.testing.assert_array_equal(loaded.Q, rig.Q)


def test_projections_only_imply_rectified(rig, tmp_path):
    path = write_fs(tmp_path / "rect.yml", {"P1": rig.P1, "P2": rig.P2, "image_width": 640, "image_height": 480})
    loaded = load_rig([path])
    assert loaded.prerectified
    np.testing.assert_allclose(loaded.Q, rig.Q, rtol=1e-9, atol=1e-9)


def test_ros_already_rectified(rig, tmp_path):
    loaded = load_rig(write_ros_pair(rig, tmp_path), already_rectified=True)
    assert loaded.prerectified
    np.testing.assert_array_equal(loaded.P2, rig.P2)


def test_kalibr_cannot_be_already_rectified(rig, tmp_path):
    path = write_yaml(tmp_path / "camchain.yaml", kalibr_values(rig))
    with pytest.raises(CalibrationError, match="camchain.yaml: a Kalibr camchain has no rectified projections"):
        load_rig([path], image_size=SIZE, already_rectified=True)


def test_alpha_changes_the_rectified_focal(rig, tmp_path):
    path = write_fs(tmp_path / "cal.yml", opencv_values(rig))
    assert load_rig([path], alpha=1.0).focal_px < load_rig([path], alpha=0.0).focal_px


# -- image size ------------------------------------------------------------------------------------
def test_size_from_frames_when_file_has_none(rig, tmp_path):
    path = write_fs(tmp_path / "cal.yml", opencv_values(rig, size=False))
    assert load_rig([path], image_size=SIZE).image_size == SIZE
    with pytest.raises(CalibrationError, match=r"cal.yml: image_width/image_height missing and no frame size"):
        load_rig([path])


def test_size_mismatch_message(rig, tmp_path):
    path = write_fs(tmp_path / "cal.yml", opencv_values(rig))
    with pytest.raises(CalibrationError) as info:
        load_rig([path], image_size=(1600, 1200))
    assert str(info.value) == f"{path}: image_width/image_height 640x480 do not match the frames 1600x1200"


# -- bad files: one line naming the file and the key ---------------------------------------------------
def _opencv(rig: StereoRig, **changes) -> dict:
    """Return merged OpenCV values with keys replaced (None removes the key)."""
    values = opencv_values(rig)
    for key, value in changes.items():
        if value is None:
            values.pop(key)
        else:
            values[key] = value
    return values


BAD_OPENCV = {
    "missing key": ({"R": None}, "missing key R"),
    "wrong shape": ({"M1": np.ones((2, 3))}, r"M1 has shape \(2, 3\), expected \(3, 3\)"),
    "wrong T shape": ({"T": np.ones((2, 1))}, r"T has shape \(2, 1\), expected \(3, 1\)"),
    "non-finite": ({"T": np.array([[-0.12], [np.nan], [0.0]])}, "T has non-finite values"),
    "infinite": ({"M2": np.array([[np.inf, 0, 320], [0, 700, 240], [0, 0, 1]])}, "M2 has non-finite values"),
    "focal <= 0": ({"M1": np.array([[0.0, 0, 320], [0, 700, 240], [0, 0, 1]])}, "M1 focal length must be > 0"),
    "negative focal": ({"M2": np.array([[700.0, 0, 320], [0, -700, 240], [0, 0, 1]])},
                       "M2 focal length must be > 0"),
    "distortion length": ({"D2": np.zeros((1, 3))}, "D2 has 3 coefficients"),
    "not a rotation": ({"R": np.ones((3, 3))}, "R is not a rotation matrix"),
    "zero baseline": ({"T": np.zeros((3, 1))}, "T is zero"),
    "vertical baseline": ({"T": np.array([[0.0], [0.12], [0.0]])}, "T = .* is mostly vertical"),
    "bad width": ({"image_width": -640}, "image_width must be a positive integer"),
    "half a size": ({"image_height": None}, "image_height missing"),
    "text matrix": ({"M1": "identity"}, "M1 is not a numeric matrix"),
}


@pytest.mark.parametrize("case", sorted(BAD_OPENCV))
def test_bad_opencv_file(rig, tmp_path, case):
    changes, match = BAD_OPENCV[case]
    path = write_fs(tmp_path / "cal.yml", _opencv(rig, **changes))
    with pytest.raises(CalibrationError, match=match) as info:
        load_rig([path], image_size=SIZE)
    _assert_one_line_naming(info.value, path)


def test_bad_rectified_opencv_file(rig, tmp_path):
    path = write_fs(tmp_path / "rect.yml", {"P1": rig.P1, "P2": rig.P1, "Q": rig.Q})
    with pytest.raises(CalibrationError, match=r"rect.yml: P2\[0,3\] is 0") as info:
        load_rig([path], image_size=SIZE)
    _assert_one_line_naming(info.value, path)
    path = write_fs(tmp_path / "rect2.yml", {"P1": rig.P1, "P2": rig.P2, "Q": np.eye(3)})
    with pytest.raises(CalibrationError, match=r"rect2.yml: Q has shape \(3, 3\)"):
        load_rig([path], image_size=SIZE)


def test_bad_key_blames_the_file_that_holds_it(rig, tmp_path):
    values = opencv_values(rig, size=False)
    values["T"] = np.array([[np.nan], [0.0], [0.0]])
    intr = write_fs(tmp_path / "intrinsics.yml", {k: values[k] for k in ("M1", "D1", "M2", "D2")})
    extr = write_fs(tmp_path / "extrinsics.yml", {k: values[k] for k in ("R", "T")})
    with pytest.raises(CalibrationError) as info:
        load_rig([intr, extr], image_size=SIZE)
    assert str(info.value) == f"{extr}: T has non-finite values"


def test_conflicting_keys_in_two_files(rig, tmp_path):
    a = write_fs(tmp_path / "a.yml", _opencv(rig))
    b = write_fs(tmp_path / "b.yml", {"M1": rig.K1 * 2 + np.diag([0, 0, -1.0])})
    with pytest.raises(CalibrationError, match="M1 is given twice with different values"):
        load_rig([a, b])


def test_missing_file(tmp_path):
    path = tmp_path / "nope.yml"
    with pytest.raises(CalibrationError) as info:
        load_rig([path])
    assert str(info.value) == f"{path}: calibration file not found"


@pytest.mark.parametrize("content, match", [
    (b"\x00\xff\xfe\x89PNG garbage \x00", "not a YAML calibration file"),
    (b"%YAML:1.0\nM1: [1, 2\n", r"not a valid OpenCV calibration file \(.*Missing , between the elements"),
    (b"%YAML:1.0\n\x00\xff\xfe", "not a valid OpenCV calibration file|expected a mapping of calibration keys"),
    (b"M1: [1, 2\n  - : :\n", "not a YAML calibration file"),
    (b"- 1\n- 2\n", "expected a mapping of calibration keys, got list"),
    (b"", "expected a mapping of calibration keys, got NoneType"),
    (b"just some text\n", "expected a mapping of calibration keys, got str"),
    (b"foo: 1\nbar: [1, 2]\n", "not a recognised calibration"),
    (b"%YAML:1.0\nM1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [1, 2]\n",
     "M1 is a malformed opencv-matrix"),
])
def test_unreadable_files(tmp_path, content, match):
    path = tmp_path / "cal.yml"
    path.write_bytes(content)
    with pytest.raises(CalibrationError, match=match) as info:
        load_rig([path], image_size=SIZE)
    _assert_one_line_naming(info.value, path)


def test_plain_yaml_with_opencv_keys(rig, tmp_path):
    """OpenCV keys in plain YAML (nested lists or {rows, cols, data}) are read too."""
    values = {k: np.asarray(v).tolist() for k, v in opencv_values(rig, size=False).items()}
    values["M1"] = {"rows": 3, "cols": 3, "data": np.asarray(rig.K1).ravel().tolist()}
    path = write_yaml(tmp_path / "cal.yaml", values)
    assert_same_rectification(load_rig([path], image_size=SIZE), rig)
    values["M1"]["data"] = values["M1"]["data"][:8]
    write_yaml(path, values)
    with pytest.raises(CalibrationError, match="M1 has 8 values but rows x cols = 3x3"):
        load_rig([path], image_size=SIZE)


def _kalibr_with(rig: StereoRig, cam: str, key: str, value) -> dict:
    """Return camchain values with one camera key replaced (None removes it)."""
    data = kalibr_values(rig)
    if value is None:
        data[cam].pop(key)
    else:
        data[cam][key] = value
    return data


@pytest.mark.parametrize("cam, key, value, match", [
    ("cam1", "T_cn_cnm1", None, "missing key cam1.T_cn_cnm1"),
    ("cam1", "T_cn_cnm1", [[1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, 0]], r"cam1.T_cn_cnm1 has shape \(3, 4\)"),
    ("cam0", "intrinsics", [700.0, 700.0, 320.0], r"cam0.intrinsics has shape"),
    ("cam0", "intrinsics", [-700.0, 700.0, 320.0, 240.0], "cam0.intrinsics focal length must be > 0"),
    ("cam0", "intrinsics", [700.0, float("nan"), 320.0, 240.0], "cam0.intrinsics has non-finite values"),
    ("cam1", "distortion_model", "equidistant", "cam1.distortion_model 'equidistant': unsupported distortion model"),
    ("cam0", "camera_model", "omni", "cam0.camera_model 'omni' is not supported"),
    ("cam0", "resolution", [800, 600], "cam0.resolution .* and cam1.resolution .* differ"),
    ("cam0", "distortion_coeffs", None, "missing key cam0.distortion_coeffs"),
])
def test_bad_kalibr_file(rig, tmp_path, cam, key, value, match):
    path = write_yaml(tmp_path / "camchain.yaml", _kalibr_with(rig, cam, key, value))
    with pytest.raises(CalibrationError, match=match) as info:
        load_rig([path], image_size=SIZE)
    _assert_one_line_naming(info.value, path)


def test_kalibr_size_mismatch(rig, tmp_path):
    path = write_yaml(tmp_path / "camchain.yaml", kalibr_values(rig))
    with pytest.raises(CalibrationError, match="cam0.resolution 640x480 do not match the frames 1600x1200"):
        load_rig([path], image_size=(1600, 1200))


@pytest.mark.parametrize("side, key, value, match", [
    ("right", "projection_matrix", None, "right.yaml: missing key projection_matrix"),
    ("left", "camera_matrix", {"rows": 2, "cols": 3, "data": [1, 0, 0, 0, 1, 0]},
     r"left.yaml: camera_matrix has shape \(2, 3\)"),
    ("left", "rectification_matrix", {"rows": 3, "cols": 3, "data": [1, 0, 0, 0, 1, 0, 0, 0, float("nan")]},
     "left.yaml: rectification_matrix has non-finite values"),
    ("right", "distortion_model", "equidistant", "right.yaml: distortion_model 'equidistant': unsupported"),
    ("right", "image_width", 1280, "left.yaml, .*right.yaml: image_width/image_height 640x480 and 1280x480 differ"),
])
def test_bad_ros_files(rig, tmp_path, side, key, value, match):
    data = {s: ros_values(rig, s) for s in ("left", "right")}
    if value is None:
        data[side].pop(key)
    else:
        data[side][key] = value
    paths = [write_yaml(tmp_path / f"{s}.yaml", data[s]) for s in ("left", "right")]
    with pytest.raises(CalibrationError, match=match) as info:
        load_rig(paths)
    _assert_one_line_naming(info.value, tmp_path / f"{side}.yaml")


def test_ros_files_swapped(rig, tmp_path):
    left, right = write_ros_pair(rig, tmp_path)
    match = "right.yaml: projection_matrix P.0,3. = .* give the left camera_info first"
    with pytest.raises(CalibrationError, match=match):
        load_rig([right, left])


def test_one_ros_file_is_not_enough(rig, tmp_path):
    left, _ = write_ros_pair(rig, tmp_path)
    with pytest.raises(CalibrationError, match=r"left.yaml \(ros\): expected"):
        load_rig([left])


def test_no_files_and_empty_directory(tmp_path):
    with pytest.raises(CalibrationError, match="no calibration file given"):
        load_rig([])
    with pytest.raises(CalibrationError, match="directory holds no known calibration layout"):
        load_rig(tmp_path)


def _assert_one_line_naming(exc: Exception, path: Path) -> None:
    """Assert the error is one line that names ``path``."""
    text = str(exc)
    assert "\n" not in text
    assert str(path) in text
