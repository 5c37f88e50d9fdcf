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

The values live in ``sitl.scenario_model`` (and ``sitl.diver``), the file reading (built-ins, ``base``
chains, checked fields) in ``sitl.scenario_file``; this module turns a file's sections into them and
re-exports the public names.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dip3d_vehicle.errors import ScenarioError

from .diver import Diver
from .scenario_file import SCENARIO_DIR, ScenarioNode, read_scenario_yaml, resolve_scenario_path, scenario_names
from .scenario_model import Camera, Placard, PoseSource, Scenario, Water
from .world import VehiclePose, left_camera_pose, unit

__all__ = [
    "Water", "Camera", "Diver", "PoseSource", "Placard", "Scenario", "load_scenario",
    "scenario_names", "SCENARIO_DIR",
]


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
    path = resolve_scenario_path(name_or_path)
    data = read_scenario_yaml(path)
    where = str(path)
    root = ScenarioNode(data, where, "")
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


def _water(n: ScenarioNode) -> Water:
    """Read the ``water`` section (defaults from ``Water()``)."""
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


def _camera(n: ScenarioNode) -> Camera:
    """Read the ``camera`` section (degrees in the file, radians out)."""
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


def _vehicle(n: ScenarioNode) -> VehiclePose:
    """Read the ``vehicle`` section: the vehicle's start pose."""
    ned = n.vec("start_ned_m", 3, (0.0, 0.0, 1.5))
    yaw = math.radians(n.num("start_yaw_deg", 0.0, -360, 360))
    n.done()
    return VehiclePose(ned[0], ned[1], ned[2], yaw)


def _position(n: ScenarioNode, ctx: _Context) -> np.ndarray:
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


def _normal(n: ScenarioNode, centre: np.ndarray, ctx: _Context) -> np.ndarray:
    """Read a placard's ``normal_ned``, or face it horizontally toward the camera's start."""
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


def _placard(n: ScenarioNode, ctx: _Context, index: int) -> Placard:
    """Read a placard placed by ``ned_m`` or range and bearing."""
    pid = n.integer("id", lo=0)
    return _placard_at(n, ctx, pid, _position(n, ctx), "object")


def _diver(n: ScenarioNode, ctx: _Context, placards: list[Placard], rng: np.random.Generator) -> Diver:
    """Read the ``diver`` section; the seed picks the position, the target (``random``) and the error direction."""
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


def _distractor(n: ScenarioNode, ctx: _Context, diver: Diver, placards: list[Placard]) -> Placard:
    """A placard on the backward extension of the forearm, ``behind_elbow_m`` behind the elbow."""
    pid = n.integer("id", lo=0)
    dist = n.num("behind_elbow_m", lo=0.3, hi=50)
    target = next(p for p in placards if p.id == diver.target_id)
    joints = diver.joints(np.asarray(target.centre_ned_m), exact=True)
    shoulder, elbow = joints["shoulder"], joints["elbow"]
    direction = unit(elbow - shoulder)
    return _placard_at(n, ctx, pid, elbow - dist * direction, "distractor")


def _placard_at(n: ScenarioNode, ctx: _Context, pid: int, centre: np.ndarray, role: str) -> Placard:
    """Read the rest of a placard at ``centre`` (normal, size, texture, ``role`` by default) and check it."""
    out = Placard(id=pid, centre_ned_m=_floats(centre), normal_ned=_floats(_normal(n, centre, ctx)),
                  size_m=n.num("size_m", 0.35, 0.02, 5.0), texture_seed=n.integer("texture_seed", pid, 0),
                  role=n.text("role", role, ("object", "distractor")))
    n.done()
    return out


def _track_line(root: ScenarioNode, placards: list[Placard], water: Water) -> tuple:
    """Read ``track_line``: none, ``under_placards`` (on the floor) or a list of NED points."""
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


def _pose_source(n: ScenarioNode) -> PoseSource:
    """Read the ``pose_source`` section."""
    out = PoseSource(noise_px=n.num("noise_px", 1.0, 0, 100), dropout=n.num("dropout", 0.0, 0, 1))
    n.done()
    return out


def _floats(v) -> tuple[float, ...]:
    """Return a tuple of plain Python floats."""
    return tuple(float(x) for x in v)
