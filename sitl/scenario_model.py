"""A resolved scenario's values: the water, the stereo camera, the pose source, the placards, and
``Scenario`` holding them with the diver (``sitl.diver``). ``sitl.scenario`` reads them from a file."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import cv2
import numpy as np

from dip3d_vehicle.perception.calibration import StereoRig

from .diver import Diver
from .world import VehiclePose, unit

__all__ = ["Water", "Camera", "PoseSource", "Placard", "Scenario"]


@dataclass(frozen=True)
class Water:
    """Water optics: observed = albedo * light * exp(-c d) + colour * (1 - exp(-c d)).

    Attributes:
        colour_bgr: colour of the water veil (backscatter) and of the far background, 0-255.
        attenuation_per_m: absorption per metre for the B, G, R channels.
        turbidity_per_m: extra scattering per metre (all channels): stronger veil, less contrast.
        light_falloff_per_m2: illumination = ambient + (1 - ambient) / (1 + k d^2).
        ambient_light: illumination that does not fall off with distance, 0-1.
        noise_sigma: sensor noise, grey levels (Gaussian).
        blur_px: Gaussian blur sigma of the whole image, pixels (0 = none).
        floor_depth_m: depth of a flat floor (pool bottom) or None for open water.
        floor_bgr: floor albedo colour, 0-255.
    """

    colour_bgr: tuple[float, float, float] = (110.0, 95.0, 30.0)
    attenuation_per_m: tuple[float, float, float] = (0.04, 0.06, 0.35)
    turbidity_per_m: float = 0.02
    light_falloff_per_m2: float = 0.02
    ambient_light: float = 0.7
    noise_sigma: float = 2.0
    blur_px: float = 0.0
    floor_depth_m: float | None = None
    floor_bgr: tuple[float, float, float] = (170.0, 170.0, 160.0)

    def transmission(self, distance_m: float) -> np.ndarray:
        """Return the (B, G, R) fraction of an object's light that reaches the camera."""
        c = np.asarray(self.attenuation_per_m) + self.turbidity_per_m
        return np.exp(-c * max(distance_m, 0.0))

    def illumination(self, distance_m: float) -> float:
        """Return the light on an object at ``distance_m`` from the vehicle (0-1)."""
        a = self.ambient_light
        return a + (1.0 - a) / (1.0 + self.light_falloff_per_m2 * distance_m ** 2)

    def gain_offset(self, distance_m: float) -> tuple[np.ndarray, np.ndarray]:
        """Return per-channel (gain, offset) so that observed = albedo * gain + offset."""
        t = self.transmission(distance_m)
        return t * self.illumination(distance_m), np.asarray(self.colour_bgr) * (1.0 - t)

    def apply(self, albedo_bgr, distance_m: float) -> tuple[float, float, float]:
        """Return the observed colour of an albedo at ``distance_m``."""
        gain, offset = self.gain_offset(distance_m)
        out = np.clip(np.asarray(albedo_bgr, float) * gain + offset, 0, 255)
        return tuple(float(v) for v in out)


@dataclass(frozen=True)
class Camera:
    """The stereo camera: intrinsics (same for both), distortion per camera, baseline, mount."""

    model: str = "generic stereo"
    image_size: tuple[int, int] = (1600, 1200)
    fx: float = 920.0
    fy: float = 920.0
    cx: float = 799.5
    cy: float = 599.5
    distortion_left: tuple[float, ...] = (0.0,) * 5
    distortion_right: tuple[float, ...] = (0.0,) * 5
    baseline_m: float = 0.12
    right_rotation_rad: tuple[float, float, float] = (0.0, 0.0, 0.0)
    mount_frd_m: tuple[float, float, float] = (0.2, 0.0, 0.0)
    mount_pitch_rad: float = 0.0
    mount_yaw_rad: float = 0.0

    @property
    def K(self) -> np.ndarray:
        """Camera matrix of both cameras."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    @property
    def D1(self) -> np.ndarray:
        """Left distortion (1, 5): k1, k2, p1, p2, k3."""
        return np.asarray(self.distortion_left, float).reshape(1, -1)

    @property
    def D2(self) -> np.ndarray:
        """Right distortion (1, 5)."""
        return np.asarray(self.distortion_right, float).reshape(1, -1)

    @property
    def R(self) -> np.ndarray:
        """Rotation of the stereo extrinsics (X_right = R X_left + T)."""
        return cv2.Rodrigues(np.asarray(self.right_rotation_rad, float))[0]

    @property
    def T(self) -> np.ndarray:
        """Translation (3, 1), metres: the right camera is ``baseline_m`` to the left camera's right."""
        return (-self.R @ np.array([self.baseline_m, 0.0, 0.0])).reshape(3, 1)

    @property
    def hfov_deg(self) -> float:
        """Horizontal field of view (pinhole), degrees."""
        return math.degrees(2 * math.atan(self.image_size[0] / 2 / self.fx))


@dataclass(frozen=True)
class PoseSource:
    """The simulated pose source: ground-truth keypoints plus Gaussian noise and dropouts."""

    noise_px: float = 1.0
    dropout: float = 0.0


@dataclass(frozen=True)
class Placard:
    """A numbered, textured square placard.

    Attributes:
        id: the printed number.
        centre_ned_m: centre, world NED, metres.
        normal_ned: unit normal of the printed face (pointing toward the viewer).
        size_m: side length, metres.
        texture_seed: seed of its random texture.
        role: "object" (a candidate target) or "distractor".
    """

    id: int
    centre_ned_m: tuple[float, float, float]
    normal_ned: tuple[float, float, float]
    size_m: float = 0.35
    texture_seed: int = 0
    role: str = "object"

    def corners_ned(self) -> np.ndarray:
        """Return the (4, 3) corners: top-left, top-right, bottom-right, bottom-left (face view)."""
        n = unit(self.normal_ned)
        down = np.array([0.0, 0.0, 1.0])
        down = unit(down - n * (n @ down)) if abs(n[2]) < 0.99 else unit(np.cross(n, [1.0, 0, 0]))
        right = np.cross(n, down)  # seen from the front (looking along -n): x right, y down
        h = self.size_m / 2
        c = np.asarray(self.centre_ned_m, float)
        return np.array([c - h * right - h * down, c + h * right - h * down,
                         c + h * right + h * down, c - h * right + h * down])


@dataclass(frozen=True)
class Scenario:
    """A resolved scenario (the seed's choices made)."""

    name: str
    source: str
    seed: int
    description: str
    water: Water
    camera: Camera
    diver: Diver
    pose_source: PoseSource
    placards: tuple[Placard, ...]
    initial_vehicle_pose: VehiclePose
    track_line_ned_m: tuple[tuple[float, float, float], ...] = ()
    raw: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def target_id(self) -> int:
        """Id of the placard the diver points at."""
        return self.diver.target_id

    def placard(self, placard_id: int) -> Placard:
        """Return the placard with this id."""
        for p in self.placards:
            if p.id == placard_id:
                return p
        raise KeyError(placard_id)

    def rig(self, alpha: float = 0.0) -> StereoRig:
        """Return the true stereo calibration (with distortion) of the scenario's camera."""
        cam = self.camera
        return StereoRig.from_parameters(cam.K, cam.D1, cam.K, cam.D2, cam.R, cam.T, cam.image_size,
                                         alpha=alpha, source=f"scenario {self.name}")
