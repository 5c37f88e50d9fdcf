"""Load a StereoRig from calibration files (OpenCV, Kalibr, ROS camera_info) and write one back.

Formats (DESIGN.md section 3), detected from the keys of each file:

- OpenCV FileStorage YAML/XML as written by OpenCV's ``stereo_calib`` sample: ``M1 D1 M2 D2``
  (intrinsics) and ``R T R1 R2 P1 P2 Q`` (extrinsics), as two files or merged into one;
  ``X_right = R X_left + T``, T in metres; optional ints ``image_width`` / ``image_height``.
- Kalibr ``camchain.yaml``: ``cam0`` / ``cam1`` with ``intrinsics [fu, fv, pu, pv]``,
  ``distortion_model`` (radtan or none), ``distortion_coeffs``, ``resolution [w, h]`` and
  ``cam1.T_cn_cnm1`` (4x4, ``X_cam1 = T X_cam0``).
- A pair of ROS ``camera_info`` YAML files (left first): ``camera_matrix``,
  ``distortion_coefficients``, ``rectification_matrix``, ``projection_matrix``; the right
  camera's ``P[0,3] = -fx * B``.

Raw calibrations are rectified with ``cv2.stereoRectify`` (``alpha``); with
``already_rectified=True`` (or an OpenCV file that only has ``P1``/``P2``, or has
``already_rectified: 1``) the given projections are used as they are. Every problem raises one
:class:`CalibrationError` line naming the file, the key and what is wrong.
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import cv2
import numpy as np
import yaml

from ..errors import CalibrationError
from .calibration import StereoRig, as_matrix

__all__ = ["load_rig", "write_opencv_calibration", "detect_format"]

_OPENCV_KEYS = ("M1", "D1", "M2", "D2", "R", "T", "R1", "R2", "P1", "P2", "Q")
_RAW_KEYS = ("M1", "D1", "M2", "D2", "R", "T")
_DIST_SIZES = (0, 4, 5, 8, 12, 14)
_DIR_LAYOUTS = (("intrinsics.yml", "extrinsics.yml"), ("intrinsics.yaml", "extrinsics.yaml"),
                ("calibration.yml",), ("calibration.yaml",), ("camchain.yaml",),
                ("left.yaml", "right.yaml"), ("left.yml", "right.yml"))


class _Doc:
    """One parsed calibration file: its display name and its top-level mapping."""

    def __init__(self, name: str, data: Mapping[str, Any]) -> None:
        self.name = name
        self.data = data


# -- public API --------------------------------------------------------------------------------
def load_rig(paths: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
             image_size: tuple[int, int] | None = None, alpha: float = 0.0,
             already_rectified: bool = False) -> StereoRig:
    """Load a stereo calibration in any supported format and return its rectified rig.

    Args:
        paths: one merged file, an OpenCV intrinsics + extrinsics pair, a Kalibr camchain, a
            left + right ROS camera_info pair, or a directory holding one of these layouts.
        image_size: (width, height) of the frames, pixels; checked against the file's size, and
            used when the file gives none.
        alpha: ``cv2.stereoRectify`` free-scaling parameter (0 valid pixels only, 1 all pixels).
        already_rectified: the frames are already rectified: use the file's projections as given.

    Returns:
        The StereoRig, its ``source`` naming the file(s).

    Raises:
        CalibrationError: a file is missing, unreadable or malformed, or disagrees with the frames.
    """
    docs = [_read(p) for p in _expand(paths)]
    kinds = [detect_format(d.data, d.name) for d in docs]
    if all(k == "opencv" for k in kinds):
        return _load_opencv(docs, image_size, alpha, already_rectified)
    if kinds == ["kalibr"]:
        return _load_kalibr(docs[0], image_size, alpha, already_rectified)
    if kinds == ["ros", "ros"]:
        return _load_ros(docs[0], docs[1], image_size, alpha, already_rectified)
    names = ", ".join(f"{d.name} ({k})" for d, k in zip(docs, kinds))
    raise CalibrationError(f"{names}: expected one OpenCV file or an intrinsics + extrinsics pair, one "
                           f"Kalibr camchain, or a left + right pair of ROS camera_info files")


def write_opencv_calibration(rig: StereoRig, path: str | os.PathLike[str]) -> Path:
    """Write ``rig`` as one merged OpenCV FileStorage YAML that :func:`load_rig` reads back.

    The file holds ``M1 D1 M2 D2 R T R1 R2 P1 P2 Q image_width image_height`` (and
    ``already_rectified: 1`` for a pre-rectified rig). Reading it back with the same ``alpha``
    gives the same rig.

    Returns:
        The path written.

    Raises:
        CalibrationError: the file cannot be opened for writing.
    """
    out = Path(path)
    try:
        fs = cv2.FileStorage(str(out), cv2.FILE_STORAGE_WRITE | cv2.FILE_STORAGE_FORMAT_YAML)
    except Exception:  # noqa: BLE001 - OpenCV raises cv2.error or SystemError
        fs = None
    if fs is None or not fs.isOpened():
        raise CalibrationError(f"{out}: cannot open the calibration file for writing")
    values = {"M1": rig.K1, "D1": rig.D1, "M2": rig.K2, "D2": rig.D2, "R": rig.R, "T": rig.T,
              "R1": rig.R1, "R2": rig.R2, "P1": rig.P1, "P2": rig.P2, "Q": rig.Q}
    for key, value in values.items():
        fs.write(key, np.asarray(value, dtype=np.float64))
    fs.write("image_width", int(rig.image_size[0]))
    fs.write("image_height", int(rig.image_size[1]))
    if rig.prerectified:
        fs.write("already_rectified", 1)
    fs.release()
    return out


def detect_format(data: Mapping[str, Any], name: str = "calibration") -> str:
    """Return "opencv", "kalibr" or "ros" from a file's top-level keys; raise if none fits."""
    if "cam0" in data:
        return "kalibr"
    if "camera_matrix" in data or "projection_matrix" in data:
        return "ros"
    if any(k in data for k in _OPENCV_KEYS):
        return "opencv"
    raise CalibrationError(f"{name}: not a recognised calibration (no OpenCV keys M1/D1/M2/D2/R/T/P1/P2, "
                           f"no Kalibr cam0, no ROS camera_matrix)")


# -- reading files -----------------------------------------------------------------------------
def _expand(paths: str | os.PathLike[str] | Sequence[str | os.PathLike[str]]) -> list[Path]:
    """Return the list of files to read: ``paths`` itself, or the files of a directory layout."""
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    files = [Path(p) for p in paths]
    if not files:
        raise CalibrationError("calibration: no calibration file given")
    if len(files) == 1 and files[0].is_dir():
        for layout in _DIR_LAYOUTS:
            if all((files[0] / n).is_file() for n in layout):
                return [files[0] / n for n in layout]
        raise CalibrationError(f"{files[0]}: directory holds no known calibration layout "
                               f"(intrinsics.yml + extrinsics.yml, camchain.yaml, left.yaml + right.yaml)")
    return files


def _read(path: Path) -> _Doc:
    """Read one file into a top-level mapping (cv2.FileStorage for OpenCV files, else PyYAML)."""
    name = str(path)
    if not path.is_file():
        raise CalibrationError(f"{name}: calibration file not found")
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise CalibrationError(f"{name}: cannot read the calibration file ({exc.strerror})") from None
    head = raw.lstrip()[:64]
    if head.startswith((b"%YAML", b"<?xml", b"<opencv_storage")):
        return _Doc(name, _read_filestorage(path, name))
    try:
        data = yaml.safe_load(raw.decode("utf-8"))
    except (UnicodeDecodeError, yaml.YAMLError) as exc:
        raise CalibrationError(f"{name}: not a YAML calibration file ({_one_line(exc)})") from None
    if not isinstance(data, dict):
        raise CalibrationError(f"{name}: expected a mapping of calibration keys, got {type(data).__name__}")
    return _Doc(name, {str(k): v for k, v in data.items()})


def _read_filestorage(path: Path, name: str) -> dict[str, Any]:
    """Read an OpenCV FileStorage file into a dict of numpy matrices, numbers and strings."""
    try:
        fs = cv2.FileStorage(str(path), cv2.FILE_STORAGE_READ)
    except Exception as exc:  # noqa: BLE001 - OpenCV raises SystemError wrapping cv2.error
        raise CalibrationError(f"{name}: not a valid OpenCV calibration file ({_cv_reason(exc)})") from None
    try:
        root = fs.root()
        if not fs.isOpened() or not root.isMap():
            raise CalibrationError(f"{name}: expected a mapping of calibration keys at the top level")
        return {key: _fs_value(root.getNode(key), key, name) for key in root.keys()}
    except (UnicodeDecodeError, cv2.error) as exc:  # non-UTF-8 key or string, malformed node
        raise CalibrationError(f"{name}: not a valid OpenCV calibration file ({_cv_reason(exc)})") from None
    finally:
        fs.release()


def _fs_value(node: cv2.FileNode, key: str, name: str) -> Any:
    """Convert one FileStorage node to numpy / Python values."""
    if node.isMap():
        keys = node.keys()
        if "data" in keys and "dt" in keys:
            try:
                return node.mat()
            except cv2.error:
                raise CalibrationError(f"{name}: {key} is a malformed opencv-matrix "
                                       f"(rows x cols does not match its data)") from None
        return {k: _fs_value(node.getNode(k), f"{key}.{k}", name) for k in keys}
    if node.isSeq():
        return [_fs_value(node.at(i), f"{key}[{i}]", name) for i in range(node.size())]
    if node.isInt():
        return int(node.real())
    if node.isReal():
        return float(node.real())
    if node.isString():
        return node.string()
    return None


def _cv_reason(exc: BaseException) -> str:
    """Return the useful one-line part of an OpenCV error."""
    text = str(exc.__cause__ or exc)
    match = re.search(r"error: \([^)]*\)\s*(.*)", text)
    return _one_line(match.group(1) if match else text)


def _one_line(exc: object) -> str:
    """Return ``exc`` as text on one line."""
    return " ".join(str(exc).split())


# -- values ------------------------------------------------------------------------------------
def _matrix(value: Any, shape: tuple[int, int], key: str, where: str) -> np.ndarray:
    """Return ``value`` (array, nested list or {rows, cols, data}) as a finite float64 ``shape``."""
    if isinstance(value, Mapping):
        if "data" not in value:
            raise CalibrationError(f"{where}: {key} has no 'data' entry")
        rows, cols, data = value.get("rows"), value.get("cols"), value["data"]
        value = data
        if isinstance(rows, int) and isinstance(cols, int) and isinstance(data, list):
            if len(data) != rows * cols:
                raise CalibrationError(f"{where}: {key} has {len(data)} values but rows x cols = {rows}x{cols}")
            value = [data[r * cols:(r + 1) * cols] for r in range(rows)]
    return as_matrix(value, shape, key, where)


def _camera_matrix(value: Any, key: str, where: str) -> np.ndarray:
    """Return a validated 3x3 camera matrix (positive focal lengths, last row [0 0 1])."""
    K = _matrix(value, (3, 3), key, where)
    _check_focal(K, key, where)
    if not np.allclose(K[2], [0.0, 0.0, 1.0], atol=1e-9) or abs(K[1, 0]) > 1e-9:
        raise CalibrationError(f"{where}: {key} is not a camera matrix [[fx,s,cx],[0,fy,cy],[0,0,1]]")
    return K


def _projection(value: Any, key: str, where: str) -> np.ndarray:
    """Return a validated 3x4 rectified projection matrix."""
    P = _matrix(value, (3, 4), key, where)
    _check_focal(P, key, where)
    return P


def _check_focal(K: np.ndarray, key: str, where: str) -> None:
    """Raise unless both focal lengths of ``K`` (3x3 or 3x4) are > 0."""
    if not (K[0, 0] > 0 and K[1, 1] > 0):
        raise CalibrationError(f"{where}: {key} focal length must be > 0 (fx={K[0, 0]:g}, fy={K[1, 1]:g})")


def _distortion(value: Any, key: str, where: str) -> np.ndarray:
    """Return distortion coefficients as (1, N), N in 4, 5, 8, 12, 14 (empty or None: zeros)."""
    if isinstance(value, Mapping):
        value = value.get("data", [])
    if value is None:
        value = []
    if isinstance(value, (str, bool)):
        raise CalibrationError(f"{where}: {key} is not a list of numbers (got {value!r})")
    try:
        arr = np.asarray(value, dtype=np.float64).reshape(1, -1)
    except (TypeError, ValueError):
        raise CalibrationError(f"{where}: {key} is not a list of numbers") from None
    if arr.shape[1] not in _DIST_SIZES:
        raise CalibrationError(f"{where}: {key} has {arr.shape[1]} coefficients, expected 4, 5, 8, 12 or 14")
    if not np.all(np.isfinite(arr)):
        raise CalibrationError(f"{where}: {key} has non-finite values")
    return arr if arr.shape[1] else np.zeros((1, 5))


def _rotation(value: Any, key: str, where: str) -> np.ndarray:
    """Return a validated 3x3 rotation matrix."""
    R = _matrix(value, (3, 3), key, where)
    if abs(np.linalg.det(R) - 1.0) > 1e-3 or not np.allclose(R @ R.T, np.eye(3), atol=1e-3):
        raise CalibrationError(f"{where}: {key} is not a rotation matrix (det {np.linalg.det(R):.4f})")
    return R


def _int(value: Any, key: str, where: str) -> int:
    """Return a positive integer (image dimension, pixels)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or value != int(value) or value <= 0:
        raise CalibrationError(f"{where}: {key} must be a positive integer, got {value!r}")
    return int(value)


def _frame_size(file_size: tuple[int, int] | None, keys: str, where: str,
                image_size: tuple[int, int] | None) -> tuple[int, int]:
    """Return the image size, checking the file's against the frames'; raise when neither exists."""
    frames = None if image_size is None else (int(image_size[0]), int(image_size[1]))
    if file_size is not None and frames is not None and tuple(file_size) != frames:
        raise CalibrationError(f"{where}: {keys} {file_size[0]}x{file_size[1]} do not match the frames "
                               f"{frames[0]}x{frames[1]}")
    size = file_size if file_size is not None else frames
    if size is None:
        raise CalibrationError(f"{where}: {keys} missing and no frame size given: cannot rectify")
    return size


def _require(data: Mapping[str, Any], key: str, where: str, prefix: str = "") -> Any:
    """Return ``data[key]``; raise CalibrationError naming ``prefix + key`` when it is absent."""
    if key not in data or data[key] is None:
        raise CalibrationError(f"{where}: missing key {prefix}{key}")
    return data[key]


# -- OpenCV ------------------------------------------------------------------------------------
def _merge(docs: Sequence[_Doc]) -> tuple[dict[str, Any], dict[str, str]]:
    """Merge OpenCV files into one mapping and remember which file each key came from."""
    merged: dict[str, Any] = {}
    origin: dict[str, str] = {}
    for doc in docs:
        for key, value in doc.data.items():
            if key in merged and not _same(merged[key], value):
                raise CalibrationError(f"{origin[key]}, {doc.name}: {key} is given twice with different values")
            merged.setdefault(key, value)
            origin.setdefault(key, doc.name)
    return merged, origin


def _same(a: Any, b: Any) -> bool:
    """Return True when two parsed values are equal (arrays compared element-wise)."""
    try:
        return bool(np.array_equal(np.asarray(a, dtype=object), np.asarray(b, dtype=object)))
    except (TypeError, ValueError):
        return a == b


def _load_opencv(docs: Sequence[_Doc], image_size: tuple[int, int] | None, alpha: float,
                 already_rectified: bool) -> StereoRig:
    """Build the rig from OpenCV stereo_calib keys (one merged file or several)."""
    data, origin = _merge(docs)
    names = ", ".join(d.name for d in docs)

    def src(key: str) -> str:
        """Return the file to blame for ``key``."""
        return origin.get(key, names)

    size = _opencv_size(data, src, names, image_size)
    flag = data.get("already_rectified", 0)
    has_raw = any(k in data for k in _RAW_KEYS)
    if already_rectified or flag not in (0, None, False) or not has_raw:
        P1 = _projection(_require(data, "P1", names), "P1", src("P1"))
        P2 = _projection(_require(data, "P2", names), "P2", src("P2"))
        Q = _matrix(data["Q"], (4, 4), "Q", src("Q")) if data.get("Q") is not None else None
        _check_baseline(P2, "P2", src("P2"))
        return StereoRig.from_rectified(P1, P2, size, Q, source=names)
    K1 = _camera_matrix(_require(data, "M1", names), "M1", src("M1"))
    K2 = _camera_matrix(_require(data, "M2", names), "M2", src("M2"))
    D1 = _distortion(_require(data, "D1", names), "D1", src("D1"))
    D2 = _distortion(_require(data, "D2", names), "D2", src("D2"))
    R = _rotation(_require(data, "R", names), "R", src("R"))
    T = _matrix(_require(data, "T", names), (3, 1), "T", src("T"))
    _check_translation(T, "T", src("T"))
    return StereoRig.from_parameters(K1, D1, K2, D2, R, T, size, alpha=alpha, source=names)


def _opencv_size(data: Mapping[str, Any], src: Callable[[str], str], names: str,
                 image_size: tuple[int, int] | None) -> tuple[int, int]:
    """Return the frame size from optional image_width/image_height, checked against the frames."""
    has_w, has_h = data.get("image_width") is not None, data.get("image_height") is not None
    if has_w != has_h:
        missing = "image_height" if has_w else "image_width"
        raise CalibrationError(f"{names}: {missing} missing (image_width and image_height go together)")
    file_size = None
    if has_w:
        file_size = (_int(data["image_width"], "image_width", src("image_width")),
                     _int(data["image_height"], "image_height", src("image_height")))
    return _frame_size(file_size, "image_width/image_height", src("image_width") if has_w else names,
                       image_size)


def _check_translation(T: np.ndarray, key: str, where: str) -> None:
    """Raise unless T is a non-zero, mainly horizontal baseline."""
    t = T.reshape(3)
    if np.linalg.norm(t) <= 0:
        raise CalibrationError(f"{where}: {key} is zero: the two cameras cannot be at the same place")
    if abs(t[1]) > abs(t[0]):
        raise CalibrationError(f"{where}: {key} = {t.tolist()} is mostly vertical; only side-by-side "
                               f"(horizontal) stereo is supported")


def _check_baseline(P2: np.ndarray, key: str, where: str) -> None:
    """Raise unless the rectified right projection has a horizontal baseline (P2[0,3] != 0)."""
    if P2[0, 3] == 0:
        raise CalibrationError(f"{where}: {key}[0,3] is 0: no baseline between the rectified cameras")
    if abs(P2[1, 3]) > 1e-9 * max(1.0, abs(P2[0, 3])):
        raise CalibrationError(f"{where}: {key}[1,3] = {P2[1, 3]:g}: vertical stereo is not supported")


# -- Kalibr ------------------------------------------------------------------------------------
def _load_kalibr(doc: _Doc, image_size: tuple[int, int] | None, alpha: float,
                 already_rectified: bool) -> StereoRig:
    """Build the rig from a Kalibr camchain (cam0 = left, cam1 = right)."""
    where = doc.name
    if already_rectified:
        raise CalibrationError(f"{where}: a Kalibr camchain has no rectified projections; already-rectified "
                               f"frames need an OpenCV (P1, P2) or ROS camera_info calibration")
    cams = []
    for cam in ("cam0", "cam1"):
        node = _require(doc.data, cam, where)
        if not isinstance(node, Mapping):
            raise CalibrationError(f"{where}: {cam} must be a mapping, got {type(node).__name__}")
        cams.append(_kalibr_camera(node, cam, where))
    (K1, D1, size0), (K2, D2, size1) = cams
    if size0 != size1:
        raise CalibrationError(f"{where}: cam0.resolution {size0} and cam1.resolution {size1} differ")
    T_cn = _matrix(_require(doc.data["cam1"], "T_cn_cnm1", where, "cam1."), (4, 4), "cam1.T_cn_cnm1", where)
    if not np.allclose(T_cn[3], [0.0, 0.0, 0.0, 1.0], atol=1e-9):
        raise CalibrationError(f"{where}: cam1.T_cn_cnm1 last row must be [0, 0, 0, 1]")
    R = _rotation(T_cn[:3, :3], "cam1.T_cn_cnm1 rotation", where)
    T = T_cn[:3, 3:4].copy()
    _check_translation(T, "cam1.T_cn_cnm1 translation", where)
    size = _frame_size(size0, "cam0.resolution", where, image_size)
    return StereoRig.from_parameters(K1, D1, K2, D2, R, T, size, alpha=alpha, source=where)


def _kalibr_camera(node: Mapping[str, Any], cam: str, where: str
                   ) -> tuple[np.ndarray, np.ndarray, tuple[int, int] | None]:
    """Return (K, D, resolution or None) of one Kalibr camera entry."""
    model = node.get("camera_model", "pinhole")
    if model != "pinhole":
        raise CalibrationError(f"{where}: {cam}.camera_model {model!r} is not supported (only pinhole)")
    fu, fv, pu, pv = _matrix(_require(node, "intrinsics", where, f"{cam}."), (1, 4),
                             f"{cam}.intrinsics", where).ravel()
    K = np.array([[fu, 0.0, pu], [0.0, fv, pv], [0.0, 0.0, 1.0]])
    _check_focal(K, f"{cam}.intrinsics", where)
    dmodel = node.get("distortion_model", "radtan")
    if dmodel in ("none", None):
        D = np.zeros((1, 5))
    elif dmodel == "radtan":
        D = _matrix(_require(node, "distortion_coeffs", where, f"{cam}."), (1, 4),
                    f"{cam}.distortion_coeffs", where)
    else:
        raise CalibrationError(f"{where}: {cam}.distortion_model {dmodel!r}: unsupported distortion model "
                               f"(supported: radtan, none)")
    res = node.get("resolution")
    size = None
    if res is not None:
        if not isinstance(res, (list, tuple)) or len(res) != 2:
            raise CalibrationError(f"{where}: {cam}.resolution must be [width, height], got {res!r}")
        size = (_int(res[0], f"{cam}.resolution[0]", where), _int(res[1], f"{cam}.resolution[1]", where))
    return K, D, size


# -- ROS camera_info ---------------------------------------------------------------------------
def _load_ros(left: _Doc, right: _Doc, image_size: tuple[int, int] | None, alpha: float,
             already_rectified: bool) -> StereoRig:
    """Build the rig from the left and right ROS camera_info files."""
    cams = [_ros_camera(doc) for doc in (left, right)]
    (K1, D1, R1, P1, size1), (K2, D2, R2, P2, size2) = cams
    if size1 is not None and size2 is not None and size1 != size2:
        raise CalibrationError(f"{left.name}, {right.name}: image_width/image_height {size1[0]}x{size1[1]} "
                               f"and {size2[0]}x{size2[1]} differ")
    if P1[0, 3] != 0 and P2[0, 3] == 0:
        raise CalibrationError(f"{left.name}: projection_matrix P[0,3] = {P1[0, 3]:g} is that of a right "
                               f"camera: give the left camera_info first, then the right")
    _check_baseline(P2, "projection_matrix", right.name)
    file_size = size1 if size1 is not None else size2
    size = _frame_size(file_size, "image_width/image_height",
                       left.name if size1 is not None else right.name, image_size)
    source = f"{left.name}, {right.name}"
    if already_rectified:
        return StereoRig.from_rectified(P1, P2, size, source=source)
    tx = (P2[0, 3] - P1[0, 3]) / P2[0, 0]  # rectified right camera = rectified left shifted by tx
    R = R2.T @ R1
    T = R2.T @ np.array([[tx], [0.0], [0.0]])
    return StereoRig.from_parameters(K1, D1, K2, D2, R, T, size, alpha=alpha, source=source)


def _ros_camera(doc: _Doc) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple[int, int] | None]:
    """Return (K, D, R_rect, P, size or None) of one camera_info file."""
    data, where = doc.data, doc.name
    model = data.get("distortion_model", "plumb_bob")
    if model not in ("plumb_bob", "rational_polynomial", None):
        raise CalibrationError(f"{where}: distortion_model {model!r}: unsupported distortion model "
                               f"(supported: plumb_bob, rational_polynomial)")
    K = _camera_matrix(_require(data, "camera_matrix", where), "camera_matrix", where)
    D = _distortion(data.get("distortion_coefficients"), "distortion_coefficients", where)
    R = _rotation(_require(data, "rectification_matrix", where), "rectification_matrix", where)
    P = _projection(_require(data, "projection_matrix", where), "projection_matrix", where)
    has_w, has_h = data.get("image_width") is not None, data.get("image_height") is not None
    size = None
    if has_w and has_h:
        size = (_int(data["image_width"], "image_width", where), _int(data["image_height"], "image_height", where))
    elif has_w or has_h:
        raise CalibrationError(f"{where}: {'image_height' if has_w else 'image_width'} missing "
                               f"(image_width and image_height go together)")
    return K, D, R, P, size
