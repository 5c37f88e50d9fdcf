"""The calibrated stereo rig: rectification, remap tables, Q, and pixel mapping both ways.

Conventions (OpenCV): ``X_right = R @ X_left + T``; T in metres so depths come out in metres.
Rectified pixels are those of ``P1`` / ``P2``; 3D points are in the rectified left camera frame.
Loading the three file formats lives in ``calibration_io``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np

from ..errors import CalibrationError, ImageError

__all__ = ["StereoRig", "as_matrix"]


def as_matrix(arr, shape: tuple[int, ...], name: str, where: str) -> np.ndarray:
    """Return ``arr`` as a finite float64 array of ``shape``; raise CalibrationError naming the key.

    A flat vector (or a single row / column) of the right size is reshaped; any other shape is an
    error (a 2x8 array is not a 4x4 matrix).
    """
    if arr is None or isinstance(arr, (str, bool)):
        raise CalibrationError(f"{where}: {name} is not a numeric matrix (got {arr!r})")
    try:
        out = np.asarray(arr, dtype=np.float64)
    except (TypeError, ValueError):
        raise CalibrationError(f"{where}: {name} is not a numeric matrix") from None
    if out.size == int(np.prod(shape)) and out.ndim <= 2 and (out.ndim < 2 or 1 in out.shape):
        out = out.reshape(shape)
    if out.shape != shape:
        raise CalibrationError(f"{where}: {name} has shape {out.shape}, expected {shape}")
    if not np.all(np.isfinite(out)):
        raise CalibrationError(f"{where}: {name} has non-finite values")
    return out


def _check_intrinsics(K: np.ndarray, name: str, where: str) -> None:
    """Raise CalibrationError unless K is an upper-triangular camera matrix with positive focal."""
    if K[0, 0] <= 0 or K[1, 1] <= 0:
        raise CalibrationError(f"{where}: {name} focal length must be > 0 (fx={K[0, 0]:g}, fy={K[1, 1]:g})")
    if abs(K[2, 2] - 1.0) > 1e-6 or abs(K[1, 0]) > 1e-9 or abs(K[2, 0]) > 1e-9 or abs(K[2, 1]) > 1e-9:
        raise CalibrationError(f"{where}: {name} is not a camera matrix [[fx,s,cx],[0,fy,cy],[0,0,1]]")


def _dist(D, name: str, where: str) -> np.ndarray:
    """Return distortion coefficients as a (1, N) array with N in 4, 5, 8, 12, 14."""
    out = np.asarray(D if D is not None else np.zeros(5), dtype=np.float64).reshape(1, -1)
    if out.shape[1] not in (4, 5, 8, 12, 14):
        raise CalibrationError(f"{where}: {name} has {out.shape[1]} coefficients, expected 4, 5, 8, 12 or 14")
    if not np.all(np.isfinite(out)):
        raise CalibrationError(f"{where}: {name} has non-finite values")
    return out


@dataclass(frozen=True)
class StereoRig:
    """A calibrated, rectified stereo pair.

    Attributes:
        image_size: (width, height) of the ORIGINAL frames, pixels.
        K1, D1, K2, D2: intrinsics and distortion of the original left/right cameras.
        R, T: right camera pose (X_right = R X_left + T), T in metres.
        R1, R2, P1, P2, Q: rectification rotations, projections and the reprojection matrix.
        prerectified: True when the frames are already rectified (no remap, identity mapping).
        source: where the calibration came from (file path or "parameters").
    """

    image_size: tuple[int, int]
    K1: np.ndarray
    D1: np.ndarray
    K2: np.ndarray
    D2: np.ndarray
    R: np.ndarray
    T: np.ndarray
    R1: np.ndarray
    R2: np.ndarray
    P1: np.ndarray
    P2: np.ndarray
    Q: np.ndarray
    prerectified: bool = False
    source: str = "parameters"
    _maps: dict = field(default_factory=dict, repr=False, compare=False)

    @classmethod
    def from_parameters(cls, K1, D1, K2, D2, R, T, image_size: tuple[int, int], alpha: float = 0.0,
                        source: str = "parameters") -> "StereoRig":
        """Build a rig from raw calibration (OpenCV conventions) and compute its rectification."""
        where = source
        K1, K2 = as_matrix(K1, (3, 3), "K1/M1", where), as_matrix(K2, (3, 3), "K2/M2", where)
        _check_intrinsics(K1, "K1/M1", where)
        _check_intrinsics(K2, "K2/M2", where)
        D1, D2 = _dist(D1, "D1", where), _dist(D2, "D2", where)
        R, T = as_matrix(R, (3, 3), "R", where), as_matrix(T, (3, 1), "T", where)
        if abs(np.linalg.det(R) - 1.0) > 1e-3 or not np.allclose(R @ R.T, np.eye(3), atol=1e-3):
            raise CalibrationError(f"{where}: R is not a rotation matrix (det {np.linalg.det(R):.4f})")
        if np.linalg.norm(T) <= 0:
            raise CalibrationError(f"{where}: T is zero: the two cameras cannot be at the same place")
        if abs(T[1, 0]) > abs(T[0, 0]):
            raise CalibrationError(f"{where}: T = {T.ravel().tolist()} is mostly vertical; only side-by-side "
                                   f"(horizontal) stereo is supported")
        w, h = _size(image_size, where)
        R1, R2, P1, P2, Q, _, _ = cv2.stereoRectify(K1, D1, K2, D2, (w, h), R, T, alpha=alpha,
                                                    flags=cv2.CALIB_ZERO_DISPARITY)
        return cls((w, h), K1, D1, K2, D2, R, T, R1, R2, P1, P2, Q, False, source)

    @classmethod
    def from_rectified(cls, P1, P2, image_size: tuple[int, int], Q=None,
                       source: str = "parameters") -> "StereoRig":
        """Build a rig for frames that are already rectified, from their projection matrices."""
        where = source
        P1, P2 = as_matrix(P1, (3, 4), "P1", where), as_matrix(P2, (3, 4), "P2", where)
        _check_intrinsics(P1[:, :3], "P1", where)
        _check_intrinsics(P2[:, :3], "P2", where)
        if abs(P2[0, 3]) <= 0:
            raise CalibrationError(f"{where}: P2[0,3] is zero: no baseline between the cameras")
        w, h = _size(image_size, where)
        f, cx, cy = P1[0, 0], P1[0, 2], P1[1, 2]
        tx = P2[0, 3] / P2[0, 0]
        if Q is None:
            Q = np.array([[1, 0, 0, -cx], [0, 1, 0, -cy], [0, 0, 0, f],
                          [0, 0, -1.0 / tx, (cx - P2[0, 2]) / tx]], np.float64)
        Q = as_matrix(Q, (4, 4), "Q", where)
        K1 = P1[:, :3].copy()
        K2 = P2[:, :3].copy()
        T = np.array([[tx], [0.0], [0.0]])
        eye = np.eye(3)
        return cls((w, h), K1, np.zeros((1, 5)), K2, np.zeros((1, 5)), eye, T, eye, eye, P1, P2, Q,
                   True, source)

    # -- geometry -------------------------------------------------------------------------
    @property
    def focal_px(self) -> float:
        """Rectified focal length, pixels."""
        return float(self.P1[0, 0])

    @property
    def baseline_m(self) -> float:
        """Baseline between the rectified cameras, metres (positive)."""
        return float(abs(self.P2[0, 3] / self.P2[0, 0]))

    @property
    def disparity_sign(self) -> int:
        """+1 when points in front have x_left > x_right (right camera to the right), else -1."""
        return 1 if self.P2[0, 3] < 0 else -1

    @property
    def principal_point_px(self) -> tuple[float, float]:
        """Rectified left principal point (cx, cy), pixels."""
        return float(self.P1[0, 2]), float(self.P1[1, 2])

    def depth_sigma_m(self, depth_m, disparity_sigma_px: float):
        """Return the one-sigma depth error at ``depth_m`` for a disparity error, metres (Z^2/(fB))."""
        return np.asarray(depth_m, dtype=float) ** 2 / (self.focal_px * self.baseline_m) * disparity_sigma_px

    # -- images ---------------------------------------------------------------------------
    def check_frame(self, image: np.ndarray, where: str) -> None:
        """Raise ImageError unless ``image`` has the rig's (width, height)."""
        h, w = image.shape[:2]
        if (w, h) != tuple(self.image_size):
            raise ImageError(f"{where}: image is {w}x{h} but the calibration ({self.source}) is "
                             f"{self.image_size[0]}x{self.image_size[1]}")

    def maps(self, side: str) -> tuple[np.ndarray, np.ndarray]:
        """Return (and cache) the fixed-point remap tables of one camera."""
        if side not in self._maps:
            K, D, Rr, P = self._camera(side)
            self._maps[side] = cv2.initUndistortRectifyMap(K, D, Rr, P, tuple(self.image_size), cv2.CV_16SC2)
        return self._maps[side]

    def rectify_image(self, image: np.ndarray, side: str) -> np.ndarray:
        """Return one image rectified (the image itself when the input is pre-rectified)."""
        if self.prerectified:
            return image
        m1, m2 = self.maps(side)
        return cv2.remap(image, m1, m2, cv2.INTER_LINEAR)

    def rectify(self, left: np.ndarray, right: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return the rectified (left, right) pair."""
        return self.rectify_image(left, "left"), self.rectify_image(right, "right")

    # -- points ---------------------------------------------------------------------------
    def _camera(self, side: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Return (K, D, R_rect, P) of one side."""
        if side == "left":
            return self.K1, self.D1, self.R1, self.P1
        if side == "right":
            return self.K2, self.D2, self.R2, self.P2
        raise ValueError(f"side must be 'left' or 'right', not {side!r}")

    def to_rectified(self, points_px, side: str) -> np.ndarray:
        """Map (N, 2) original pixels of one camera to rectified pixels."""
        pts = np.asarray(points_px, dtype=np.float64).reshape(-1, 2)
        if self.prerectified or len(pts) == 0:
            return pts.copy()
        K, D, Rr, P = self._camera(side)
        out = cv2.undistortPointsIter(pts.reshape(-1, 1, 2), K, D, Rr, P,
                                      (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 40, 1e-9))
        return out.reshape(-1, 2)

    def to_original(self, points_px, side: str) -> np.ndarray:
        """Map (N, 2) rectified pixels of one camera back to original (distorted) pixels."""
        pts = np.asarray(points_px, dtype=np.float64).reshape(-1, 2)
        if self.prerectified or len(pts) == 0:
            return pts.copy()
        K, D, Rr, P = self._camera(side)
        Kp = P[:, :3]
        rays = np.c_[(pts[:, 0] - Kp[0, 2]) / Kp[0, 0], (pts[:, 1] - Kp[1, 2]) / Kp[1, 1], np.ones(len(pts))]
        cam = rays @ Rr  # R_rect^T applied to each row: back to the original camera frame
        img, _ = cv2.projectPoints(cam.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D)
        return img.reshape(-1, 2)


def _size(image_size, where: str) -> tuple[int, int]:
    """Return a validated (width, height)."""
    try:
        w, h = (int(v) for v in image_size)
    except (TypeError, ValueError):
        raise CalibrationError(f"{where}: image size {image_size!r} is not (width, height)") from None
    if w <= 0 or h <= 0:
        raise CalibrationError(f"{where}: image size {w}x{h} must be positive")
    return w, h
