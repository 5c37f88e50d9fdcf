"""Simulator scenarios: the water, the stereo camera, the diver and the numbered placards.

A scenario is a YAML file (built-ins in ``sitl/scenarios/*.yaml``). ``load_scenario(name, seed)``
reads it, checks every field (a bad file raises ScenarioError naming the file, the field and the
problem) and resolves the parts the seed varies (which of the listed diver positions, which
placard is pointed at, the direction of the pointing error). Units in the files are metres and
degrees; the dataclasses hold metres and radians. File format (all sections but ``placards`` and
``diver`` optional; see ``paper_pool.yaml`` for a commented example)::

    base: paper_pool            # optional: start from another scenario and override (deep merge)
    description: text
    water: {colour_bgr, attenuation_per_m [b,g,r], turbidity_per_m, light_falloff_per_m2,
            ambient_light, noise_sigma, blur_px, floor_depth_m, floor_bgr}
    camera: {model, image_size [w,h], focal_px or fx/fy, principal_point_px, baseline_m,
             distortion_left [k1,k2,p1,p2,k3], distortion_right, right_rotation_deg [rx,ry,rz],
             mount_frd_m [f,r,d], mount_pitch_deg, mount_yaw_deg}
    vehicle: {start_ned_m [n,e,d], start_yaw_deg}
    placards: [{id, ned_m [n,e,d] | range_m + bearing_deg + depth_m | behind_elbow_m,
                size_m, facing: camera | normal_ned [..], texture_seed, role: object|distractor}]
    track_line: under_placards | [[n,e,d], ...] | null
    diver: {positions: [{name, ned_m | range_m + bearing_deg + depth_m}], heading_deg: auto | deg,
            turn_to_placards_deg,
            arm, target: random | id, target_choices, pointing_error_deg, start_s, hold_s, raise_s,
            sway_amplitude_m, sway_period_s, suit_bgr, tank_bgr, stop_gesture_at_s, stop_gesture_hold_s}
    pose_source: {noise_px, dropout}

``range_m`` / ``bearing_deg`` are measured from the left camera at the vehicle's start pose
(horizontal range; bearing relative to the start heading, positive to the right) and ``depth_m`` is
the world depth (for the diver: the depth of the chest, between the shoulders).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import yaml

from dip3d_vehicle.errors import ScenarioError
from dip3d_vehicle.perception.calibration import StereoRig

from .world import VehiclePose, left_camera_pose, perpendicular_basis, unit

__all__ = [
    "Water", "Camera", "Diver", "PoseSource", "Placard", "Scenario", "load_scenario",
    "scenario_names", "SCENARIO_DIR",
]

SCENARIO_DIR = Path(__file__).resolve().parent / "scenarios"
"""Folder of the built-in scenario files."""

UPPER_ARM_M = 0.30
FOREARM_M = 0.28


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
class Diver:
    """The diver: where, facing where, which arm, which placard, how well and when they point.

    Attributes:
        position_name: name of the chosen position (e.g. the paper's "2" or "3").
        chest_ned_m: point between the shoulders, world NED, metres (before sway).
        heading_rad: direction the diver faces (0 = north, clockwise +).
        arm: "right" or "left" (the pointing arm).
        target_id: id of the placard pointed at.
        pointing_error_rad: angle between the arm and the true direction to the target.
        error_direction_rad: direction of that error around the true direction (seeded).
        start_s, hold_s: pointing holds from start_s for hold_s seconds.
        raise_s: time to raise (before start_s) and lower (after) the arm.
        sway_amplitude_m, sway_period_s: slow body sway.
        stop_gesture_at_s, stop_gesture_hold_s: both wrists held above the head from this time
            (None: never) for this long, raised and lowered over raise_s; the pointing arm joins in.
    """

    position_name: str
    chest_ned_m: tuple[float, float, float]
    heading_rad: float
    arm: str
    target_id: int
    pointing_error_rad: float
    error_direction_rad: float
    start_s: float
    hold_s: float
    raise_s: float = 0.6
    sway_amplitude_m: float = 0.03
    sway_period_s: float = 7.0
    suit_bgr: tuple[float, float, float] = (40.0, 35.0, 30.0)
    tank_bgr: tuple[float, float, float] = (30.0, 200.0, 230.0)
    stop_gesture_at_s: float | None = None
    stop_gesture_hold_s: float = 3.0

    def pointing_at(self, t_s: float) -> bool:
        """Return True while the arm is fully raised and held on the target (not during a stop gesture)."""
        return self.start_s <= t_s < self.start_s + self.hold_s and self.stop_fraction(t_s) == 0.0

    def stop_gesture_at(self, t_s: float) -> bool:
        """Return True while both wrists are held above the head (the stop gesture)."""
        s = self.stop_gesture_at_s
        return s is not None and s <= t_s < s + self.stop_gesture_hold_s

    def stop_fraction(self, t_s: float) -> float:
        """Return how far both arms are raised into the stop gesture (raised over raise_s from
        stop_gesture_at_s, lowered over raise_s before stop_gesture_at_s + stop_gesture_hold_s)."""
        s = self.stop_gesture_at_s
        if s is None:
            return 0.0
        r = max(self.raise_s, 1e-6)
        return float(np.clip(min((t_s - s) / r, ((s + self.stop_gesture_hold_s) - t_s) / r), 0.0, 1.0))

    def raised_fraction(self, t_s: float) -> float:
        """Return how far the arm is raised: 0 hanging, 1 pointing (linear ramps of raise_s)."""
        r = max(self.raise_s, 1e-6)
        up = (t_s - (self.start_s - r)) / r
        down = ((self.start_s + self.hold_s + r) - t_s) / r
        return float(np.clip(min(up, down), 0.0, 1.0))

    def sway_ned_m(self, t_s: float) -> np.ndarray:
        """Return the body's sway offset at ``t_s`` (slow, incommensurate sinusoids), metres."""
        w = 2 * math.pi / self.sway_period_s
        a = self.sway_amplitude_m
        return a * np.array([math.sin(w * t_s), 0.6 * math.sin(0.71 * w * t_s + 1.3),
                             0.4 * math.sin(1.37 * w * t_s + 2.1)])

    def joints(self, target_ned_m: np.ndarray, t_s: float = 0.0, exact: bool = False) -> dict[str, np.ndarray]:
        """Return the 3D joints (world NED, metres) of the diver's simple standing body.

        The pointing arm is straight from the shoulder toward ``target_ned_m`` with the pointing
        error, blended with a hanging arm while it is raised or lowered.

        Args:
            target_ned_m: centre of the placard pointed at.
            t_s: time (sway and the arm's timeline).
            exact: ignore sway and pointing error and hold the arm fully raised.

        Returns:
            Joints by name: "shoulder", "elbow", "wrist", "hand" (pointing arm), "o_shoulder",
            "o_elbow", "o_wrist" (other arm), "head", "neck", "chest", "pelvis", "hip_r", "hip_l",
            "knee_r", "knee_l", "ankle_r", "ankle_l", "fin_r", "fin_l", "tank_top", "tank_bottom".
        """
        chest = np.asarray(self.chest_ned_m, float) + (0.0 if exact else self.sway_ned_m(t_s))
        fwd = np.array([math.cos(self.heading_rad), math.sin(self.heading_rad), 0.0])
        right = np.array([-math.sin(self.heading_rad), math.cos(self.heading_rad), 0.0])
        down = np.array([0.0, 0.0, 1.0])
        side = right if self.arm == "right" else -right
        j = {"chest": chest, "neck": chest - 0.06 * down, "head": chest - 0.27 * down,
             "pelvis": chest + 0.5 * down}
        j["shoulder"], j["o_shoulder"] = chest + 0.19 * side, chest - 0.19 * side
        for name, sgn in (("r", 1.0), ("l", -1.0)):
            hip = j["pelvis"] + sgn * 0.1 * right
            knee = hip + 0.44 * down + 0.06 * fwd + sgn * 0.02 * right
            ankle = knee + 0.42 * down - 0.05 * fwd
            j[f"hip_{name}"], j[f"knee_{name}"], j[f"ankle_{name}"] = hip, knee, ankle
            j[f"fin_{name}"] = ankle + 0.3 * unit(down * 0.5 + fwd * 0.85)
        j["tank_top"] = chest - 0.17 * fwd - 0.05 * down
        j["tank_bottom"] = chest - 0.17 * fwd + 0.5 * down
        hang = unit(down + 0.18 * side + 0.05 * fwd)
        aim = unit(np.asarray(target_ned_m, float) - j["shoulder"])
        if not exact and self.pointing_error_rad > 0:
            u, v = perpendicular_basis(aim)
            e, phi = self.pointing_error_rad, self.error_direction_rad
            aim = math.cos(e) * aim + math.sin(e) * (math.cos(phi) * u + math.sin(phi) * v)
        a = 1.0 if exact else self.raised_fraction(t_s)
        arm_dir = unit((1 - a) * hang + a * aim)
        j["elbow"] = j["shoulder"] + UPPER_ARM_M * arm_dir
        j["wrist"] = j["elbow"] + FOREARM_M * arm_dir
        j["hand"] = j["wrist"] + 0.09 * arm_dir
        j["o_elbow"] = j["o_shoulder"] + UPPER_ARM_M * unit(down - 0.18 * side)
        j["o_wrist"] = j["o_elbow"] + FOREARM_M * unit(down + 0.35 * fwd - 0.1 * side)
        g = 0.0 if exact else self.stop_fraction(t_s)
        if g > 0.0:  # both arms up and out, forearms up: the wrists above the head
            for p, s in (("", side), ("o_", -side)):
                upper = unit((1 - g) * unit(j[p + "elbow"] - j[p + "shoulder"]) + g * unit(-down + 0.55 * s + 0.1 * fwd))
                fore = unit((1 - g) * unit(j[p + "wrist"] - j[p + "elbow"]) + g * unit(-down + 0.1 * s + 0.15 * fwd))
                j[p + "elbow"] = j[p + "shoulder"] + UPPER_ARM_M * upper
                j[p + "wrist"] = j[p + "elbow"] + FOREARM_M * fore
            j["hand"] = j["wrist"] + 0.09 * unit(j["wrist"] - j["elbow"])
        return j


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


# ---------------------------------------------------------------------------------------------
# Reading and checking the YAML


class _Node:
    """A mapping from a scenario file with typed, checked accessors that name file and field."""

    def __init__(self, data: Any, where: str, path: str) -> None:
        if not isinstance(data, dict):
            raise ScenarioError(f"{where}: {path or 'top level'}: expected a mapping, got {type(data).__name__}")
        self.data, self.where, self.path = data, where, path
        self.used: set[str] = set()

    def _name(self, key: str) -> str:
        return f"{self.path}.{key}" if self.path else key

    def fail(self, key: str, problem: str) -> ScenarioError:
        """Return a ScenarioError for ``key``."""
        return ScenarioError(f"{self.where}: {self._name(key)}: {problem}")

    def has(self, key: str) -> bool:
        return key in self.data and self.data[key] is not None

    def raw(self, key: str, default: Any = ...) -> Any:
        self.used.add(key)
        if key not in self.data or self.data[key] is None:
            if default is ...:
                raise self.fail(key, "missing (required)")
            return default
        return self.data[key]

    def num(self, key: str, default: Any = ..., lo: float | None = None, hi: float | None = None) -> float:
        value = self.raw(key, default)
        if value is None:
            return None
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.fail(key, f"{value!r} is not a finite number")
        if (lo is not None and value < lo) or (hi is not None and value > hi):
            raise self.fail(key, f"{value!r} is out of range [{lo}, {hi}]")
        return float(value)

    def vec(self, key: str, n: int, default: Any = ..., lo: float | None = None,
            hi: float | None = None) -> tuple[float, ...]:
        value = self.raw(key, default)
        if value is None:
            return None
        ok = isinstance(value, (list, tuple)) and len(value) == n and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
        if not ok:
            raise self.fail(key, f"{value!r} is not a list of {n} numbers")
        if any((lo is not None and v < lo) or (hi is not None and v > hi) for v in value):
            raise self.fail(key, f"{value!r} has values out of range [{lo}, {hi}]")
        return tuple(float(v) for v in value)

    def text(self, key: str, default: Any = ..., choices: tuple[str, ...] | None = None) -> str:
        value = self.raw(key, default)
        if not isinstance(value, str):
            raise self.fail(key, f"{value!r} is not text")
        if choices and value not in choices:
            raise self.fail(key, f"{value!r} is not one of {', '.join(choices)}")
        return value

    def integer(self, key: str, default: Any = ..., lo: int | None = None) -> int:
        value = self.raw(key, default)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.fail(key, f"{value!r} is not an integer")
        if lo is not None and value < lo:
            raise self.fail(key, f"{value!r} must be >= {lo}")
        return value

    def child(self, key: str, required: bool = False) -> "_Node":
        value = self.raw(key, ... if required else {})
        if not isinstance(value, dict):
            raise self.fail(key, f"expected a mapping, got {type(value).__name__}")
        return _Node(value, self.where, self._name(key))

    def items(self, key: str) -> list["_Node"]:
        value = self.raw(key)
        if not isinstance(value, list) or not value:
            raise self.fail(key, "expected a non-empty list")
        return [_Node(v, self.where, f"{self._name(key)}[{i}]") for i, v in enumerate(value)]

    def done(self) -> None:
        """Raise ScenarioError on keys that were never read (typos, unsupported fields)."""
        extra = [k for k in self.data if k not in self.used]
        if extra:
            raise self.fail(str(extra[0]), "unknown field")


def scenario_names() -> list[str]:
    """Return the names of the built-in scenarios (``sitl/scenarios/*.yaml``)."""
    return sorted(p.stem for p in SCENARIO_DIR.glob("*.yaml"))


def _resolve_path(name_or_path: str, relative_to: Path | None = None) -> Path:
    """Return the file of a built-in scenario name or a path; ScenarioError when there is none."""
    text = str(name_or_path)
    if text in scenario_names():
        return SCENARIO_DIR / f"{text}.yaml"
    path = Path(text)
    if relative_to is not None and not path.is_absolute() and not path.exists():
        path = relative_to / path
    if path.is_file():
        return path
    if not text.endswith((".yaml", ".yml")) and "/" not in text:
        raise ScenarioError(f"{text}: unknown scenario (built-in: {', '.join(scenario_names())})")
    raise ScenarioError(f"{text}: scenario file not found")


def _read_yaml(path: Path, chain: tuple[str, ...] = ()) -> dict:
    """Read a scenario file and merge it over its ``base`` (recursively)."""
    where = str(path)
    if where in chain:
        raise ScenarioError(f"{where}: base: circular base chain ({' -> '.join(chain + (where,))})")
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = f":{mark.line + 1}" if mark else ""
        raise ScenarioError(f"{where}{line}: not valid YAML ({getattr(exc, 'problem', exc)})") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError(f"{where}: cannot read scenario file ({exc.__class__.__name__})") from None
    if not isinstance(data, dict):
        raise ScenarioError(f"{where}: top level: expected a mapping of sections")
    base = data.pop("base", None)
    if base is None:
        return data
    if not isinstance(base, str):
        raise ScenarioError(f"{where}: base: {base!r} is not a scenario name or path")
    try:
        base_path = _resolve_path(base, path.parent)
    except ScenarioError as exc:
        raise ScenarioError(f"{where}: base: {exc}") from None
    return _merge(_read_yaml(base_path, chain + (where,)), data)


def _merge(base: dict, over: dict) -> dict:
    """Deep-merge mappings (``over`` wins; lists and scalars are replaced)."""
    out = copy.deepcopy(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def load_scenario(name_or_path: str, seed: int = 0) -> Scenario:
    """Load a built-in scenario by name, or a scenario file, and resolve the seed's choices.

    Args:
        name_or_path: a built-in name (see ``scenario_names()``) or a YAML file path.
        seed: picks the diver position, the target placard (when ``target: random``), the
            direction of the pointing error; the renderer also seeds noise with it.

    Returns:
        The resolved Scenario.

    Raises:
        ScenarioError: the file is missing, not YAML, or a field is missing or invalid (the
            message names the file, the field and the problem).
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ScenarioError(f"--seed {seed!r}: expected an integer >= 0")
    path = _resolve_path(name_or_path)
    data = _read_yaml(path)
    where = str(path)
    root = _Node(data, where, "")
    rng = np.random.default_rng(int(seed))
    description = root.text("description", "")
    water = _water(root.child("water"))
    camera = _camera(root.child("camera"))
    start = _vehicle(root.child("vehicle"))
    station = left_camera_pose(start, camera.mount_frd_m, camera.mount_pitch_rad,
                               camera.mount_yaw_rad).centre_w
    ctx = _Context(station, start.yaw_rad)
    diver_node = root.child("diver", required=True)
    placard_nodes = root.items("placards")
    placards = [_placard(n, ctx, i) for i, n in enumerate(placard_nodes) if not n.has("behind_elbow_m")]
    diver = _diver(diver_node, ctx, placards, rng)
    for node in placard_nodes:
        if node.has("behind_elbow_m"):
            placards.append(_distractor(node, ctx, diver, placards))
    ids = [p.id for p in placards]
    if len(set(ids)) != len(ids):
        raise ScenarioError(f"{where}: placards: duplicate id {[i for i in ids if ids.count(i) > 1][0]}")
    track = _track_line(root, placards, water)
    pose_source = _pose_source(root.child("pose_source"))
    root.raw("name", "")
    root.done()
    return Scenario(name=path.stem, source=where, seed=int(seed), description=description,
                    water=water, camera=camera, diver=diver, pose_source=pose_source,
                    placards=tuple(sorted(placards, key=lambda p: p.id)),
                    initial_vehicle_pose=start, track_line_ned_m=track, raw=data)


@dataclass(frozen=True)
class _Context:
    """Where the camera starts: the reference for range/bearing positions."""

    station_ned: np.ndarray
    heading_rad: float


def _water(n: _Node) -> Water:
    d = Water()
    floor = n.num("floor_depth_m", None, 0.0)
    out = Water(
        colour_bgr=n.vec("colour_bgr", 3, d.colour_bgr, 0, 255),
        attenuation_per_m=n.vec("attenuation_per_m", 3, d.attenuation_per_m, 0, 20),
        turbidity_per_m=n.num("turbidity_per_m", d.turbidity_per_m, 0, 20),
        light_falloff_per_m2=n.num("light_falloff_per_m2", d.light_falloff_per_m2, 0, 100),
        ambient_light=n.num("ambient_light", d.ambient_light, 0, 1),
        noise_sigma=n.num("noise_sigma", d.noise_sigma, 0, 60),
        blur_px=n.num("blur_px", d.blur_px, 0, 20),
        floor_depth_m=floor,
        floor_bgr=n.vec("floor_bgr", 3, d.floor_bgr, 0, 255),
    )
    n.done()
    return out


def _camera(n: _Node) -> Camera:
    d = Camera()
    size = n.vec("image_size", 2, d.image_size, 16, 10000)
    if any(not v.is_integer() for v in size):
        raise n.fail("image_size", f"{list(size)} is not two integers")
    w, h = int(size[0]), int(size[1])
    focal = n.num("focal_px", None, 1.0, 1e5)
    fx = n.num("fx", focal if focal is not None else d.fx, 1.0, 1e5)
    fy = n.num("fy", focal if focal is not None else d.fy, 1.0, 1e5)
    pp = n.vec("principal_point_px", 2, ((w - 1) / 2, (h - 1) / 2))
    dist_l = n.vec("distortion_left", 5, d.distortion_left, -2, 2)
    out = Camera(
        model=n.text("model", d.model), image_size=(w, h), fx=fx, fy=fy, cx=pp[0], cy=pp[1],
        distortion_left=dist_l, distortion_right=n.vec("distortion_right", 5, dist_l, -2, 2),
        baseline_m=n.num("baseline_m", d.baseline_m, 0.005, 5.0),
        right_rotation_rad=tuple(math.radians(v) for v in n.vec("right_rotation_deg", 3, (0, 0, 0), -10, 10)),
        mount_frd_m=n.vec("mount_frd_m", 3, d.mount_frd_m, -5, 5),
        mount_pitch_rad=math.radians(n.num("mount_pitch_deg", 0.0, -90, 90)),
        mount_yaw_rad=math.radians(n.num("mount_yaw_deg", 0.0, -180, 180)),
    )
    n.done()
    return out


def _vehicle(n: _Node) -> VehiclePose:
    ned = n.vec("start_ned_m", 3, (0.0, 0.0, 1.5))
    yaw = math.radians(n.num("start_yaw_deg", 0.0, -360, 360))
    n.done()
    return VehiclePose(ned[0], ned[1], ned[2], yaw)


def _position(n: _Node, ctx: _Context) -> np.ndarray:
    """Read ``ned_m`` or ``range_m`` + ``bearing_deg`` + ``depth_m`` (relative to the camera start)."""
    if n.has("ned_m"):
        if n.has("range_m") or n.has("bearing_deg"):
            raise n.fail("ned_m", "give either ned_m or range_m/bearing_deg, not both")
        return np.array(n.vec("ned_m", 3))
    rng = n.num("range_m", ..., 0.05, 1000)
    bearing = ctx.heading_rad + math.radians(n.num("bearing_deg", ..., -180, 180))
    depth = n.num("depth_m", ..., -100, 10000)
    s = ctx.station_ned
    return np.array([s[0] + rng * math.cos(bearing), s[1] + rng * math.sin(bearing), depth])


def _normal(n: _Node, centre: np.ndarray, ctx: _Context) -> np.ndarray:
    if n.has("normal_ned"):
        v = np.array(n.vec("normal_ned", 3))
        if np.linalg.norm(v) < 1e-9:
            raise n.fail("normal_ned", "must not be zero")
        return unit(v)
    n.text("facing", "camera", ("camera",))
    to_cam = ctx.station_ned - centre
    to_cam[2] = 0.0
    if np.linalg.norm(to_cam) < 1e-6:
        raise n.fail("facing", "placard is at the camera's position: give normal_ned")
    return unit(to_cam)


def _placard(n: _Node, ctx: _Context, index: int) -> Placard:
    pid = n.integer("id", lo=0)
    centre = _position(n, ctx)
    out = Placard(id=pid, centre_ned_m=_floats(centre), normal_ned=_floats(_normal(n, centre, ctx)),
                  size_m=n.num("size_m", 0.35, 0.02, 5.0), texture_seed=n.integer("texture_seed", pid, 0),
                  role=n.text("role", "object", ("object", "distractor")))
    n.done()
    return out


def _diver(n: _Node, ctx: _Context, placards: list[Placard], rng: np.random.Generator) -> Diver:
    positions = n.items("positions")
    names, chests = [], []
    for i, node in enumerate(positions):  # check them all, not only the chosen one
        name = node.raw("name", str(i + 1))
        if not isinstance(name, (str, int)) or isinstance(name, bool):
            raise node.fail("name", f"{name!r} is not a name")
        names.append(str(name))
        chests.append(_position(node, ctx))
        node.done()
    pick = int(rng.integers(len(positions)))
    chest, name = chests[pick], names[pick]
    objects = [p.id for p in placards if p.role == "object"]
    choices = n.raw("target_choices", objects)
    if not isinstance(choices, list) or not choices or not all(
            isinstance(c, int) and not isinstance(c, bool) for c in choices):
        raise n.fail("target_choices", f"{choices!r} is not a non-empty list of placard ids")
    for c in choices:
        if c not in [p.id for p in placards]:
            raise n.fail("target_choices", f"no placard with id {c}")
    target = n.raw("target", "random")
    if target == "random":
        target_id = choices[int(rng.integers(len(choices)))]
    elif isinstance(target, int) and not isinstance(target, bool) and target in [p.id for p in placards]:
        target_id = target
    else:
        raise n.fail("target", f"{target!r} is not 'random' or the id of a placard "
                                f"({', '.join(str(p.id) for p in placards)})")
    arm = n.text("arm", "right", ("right", "left"))
    heading = n.raw("heading_deg", "auto")
    turn = math.radians(n.num("turn_to_placards_deg", 0.0, 0, 90))  # used with heading_deg: auto
    if heading == "auto":
        centroid = np.mean([p.centre_ned_m for p in placards if p.role == "object"], axis=0)
        side = math.atan2(centroid[1] - chest[1], centroid[0] - chest[0])
        heading_rad = side - math.pi / 2 + turn if arm == "right" else side + math.pi / 2 - turn
    else:
        heading_rad = math.radians(n.num("heading_deg", lo=-360, hi=360))
    error_dir = float(rng.uniform(0, 2 * math.pi))
    out = Diver(position_name=name, chest_ned_m=_floats(chest), heading_rad=heading_rad, arm=arm,
                target_id=target_id,
                pointing_error_rad=math.radians(n.num("pointing_error_deg", 5.0, 0, 90)),
                error_direction_rad=error_dir,
                start_s=n.num("start_s", 1.0, 0), hold_s=n.num("hold_s", 30.0, 0),
                raise_s=n.num("raise_s", 0.6, 0, 10),
                sway_amplitude_m=n.num("sway_amplitude_m", 0.03, 0, 1),
                sway_period_s=n.num("sway_period_s", 7.0, 0.1, 1000),
                suit_bgr=n.vec("suit_bgr", 3, Diver.suit_bgr, 0, 255),
                tank_bgr=n.vec("tank_bgr", 3, Diver.tank_bgr, 0, 255),
                stop_gesture_at_s=n.num("stop_gesture_at_s", None, 0),
                stop_gesture_hold_s=n.num("stop_gesture_hold_s", 3.0, 0, 1000))
    n.done()
    return out


def _distractor(n: _Node, ctx: _Context, diver: Diver, placards: list[Placard]) -> Placard:
    """A placard on the backward extension of the forearm, ``behind_elbow_m`` behind the elbow."""
    pid = n.integer("id", lo=0)
    dist = n.num("behind_elbow_m", lo=0.3, hi=50)
    target = next(p for p in placards if p.id == diver.target_id)
    joints = diver.joints(np.asarray(target.centre_ned_m), exact=True)
    shoulder, elbow = joints["shoulder"], joints["elbow"]
    direction = unit(elbow - shoulder)
    centre = elbow - dist * direction
    out = Placard(id=pid, centre_ned_m=_floats(centre), normal_ned=_floats(_normal(n, centre, ctx)),
                  size_m=n.num("size_m", 0.35, 0.02, 5.0), texture_seed=n.integer("texture_seed", pid, 0),
                  role=n.text("role", "distractor", ("object", "distractor")))
    n.done()
    return out


def _track_line(root: _Node, placards: list[Placard], water: Water) -> tuple:
    value = root.raw("track_line", None)
    if value is None:
        return ()
    if value == "under_placards":
        floor = water.floor_depth_m
        if floor is None:
            raise root.fail("track_line", "under_placards needs water.floor_depth_m")
        objs = sorted((p for p in placards if p.role == "object"), key=lambda p: p.id)
        pts = [np.array([p.centre_ned_m[0], p.centre_ned_m[1], floor]) for p in objs]
        if len(pts) >= 2:
            pts = [pts[0] - 0.6 * unit(pts[1] - pts[0])] + pts + [pts[-1] + 0.8 * unit(pts[-1] - pts[-2])]
        return tuple(tuple(float(v) for v in p) for p in pts)
    if not isinstance(value, list) or len(value) < 2:
        raise root.fail("track_line", "expected under_placards or a list of at least two [n, e, d] points")
    out = []
    for i, p in enumerate(value):
        if not (isinstance(p, list) and len(p) == 3 and all(isinstance(v, (int, float)) for v in p)):
            raise root.fail(f"track_line[{i}]", f"{p!r} is not [n, e, d]")
        out.append(tuple(float(v) for v in p))
    return tuple(out)


def _pose_source(n: _Node) -> PoseSource:
    out = PoseSource(noise_px=n.num("noise_px", 1.0, 0, 100), dropout=n.num("dropout", 0.0, 0, 1))
    n.done()
    return out


def _floats(v) -> tuple[float, ...]:
    """Return a tuple of plain Python floats."""
    return tuple(float(x) for x in v)
