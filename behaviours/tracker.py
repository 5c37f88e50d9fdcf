"""Keep the chosen object identified in every new frame while the vehicle moves.

The target is remembered by its appearance (the SIFT descriptors of its member features) and its 3D
centre. In each new frame the full-frame matched features (no arm mask: the diver no longer matters)
are grouped into objects (``group_objects``, as the selector does); the target is the object with
the most descriptor matches to the model (Lowe's ratio test; each model descriptor counts once) whose
centre lies inside a gate around the predicted centre; of an object wider than one target (two placards joined by a
line on the floor), only the part around the features that match. The prediction moves the last centre by the
vehicle's motion under the commands since then (``behaviour.track_reckoning`` vehicle, ``coast.py``: in ALT_HOLD it
coasts on after a neutral command; ``commands``: as commanded); yaw turns the scene about the camera's vertical
axis, surge/sway/heave translate it; the gate
grows with the time since the last sighting. The model keeps the first sighting's descriptors (the
identity) plus the latest sighting's (the appearance up close). A target whose decision sighting holds
few descriptors starts with those of all its sightings over the decision's frames (``pooled_model``).
The search box of a target predicted far away holds a zoom box around it, scanned closer
(``TrackRegion``, ``zoom_box``). A target too small for that count (a
few features) is still taken when it is the only object in the gate, near the prediction, and shares a
descriptor with the model. Lost after N frames in a row without a match; any later frame with a match
re-acquires it. The decision's other objects go along as offsets from the target (known neighbours): an object
nearer one of them than the target's prediction, by more than the prediction's own doubt, is never the target.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, NamedTuple

import cv2
import numpy as np
from scipy.spatial import cKDTree

from dip3d_vehicle.perception.calibration import StereoRig
from dip3d_vehicle.perception.corridor import ZOOM_MIN_DEPTH_M
from dip3d_vehicle.perception.grouping import extent_m, group_objects, objects_of
from dip3d_vehicle.perception.values import Candidates, ObjectCandidate
from dip3d_vehicle.servo.command import NEUTRAL, VelocityCommand

from .coast import MotionModel

__all__ = ["TrackerConfig", "TrackedTarget", "TargetTracker", "TrackRegion", "predict_xyz", "pooled_model",
           "project_px", "turn_xyz", "zoom_box"]

ZOOM_MARGIN_PX = 30.0
"""Margin (px) on each side of the tracker's zoom box beyond the target's projected size, doubled after a miss."""

DRIFT_DOUBT = 2.0
"""How far off the dead-reckoned prediction may be, as a multiple of how far it moved since its last fix. The vehicle
lags its commands: through the acknowledge nod's yaw swings it may still turn one way while the command turns the
other, so the prediction can be off by the commanded motion plus as much again (``side_by_side_far`` seed 6: one
frame after a sighting, a 0.21 m move put the prediction 0.37-0.43 m from the pointed placard, issue 11 session 50)."""

POOL_MIN_DISTANCE = 200.0
"""A pooled descriptor joins the model only this far (L2, SIFT units: OpenCV's descriptors have norm ~512) from every
descriptor already in it. Nearer, it is taken for the same feature seen again (not measured here: about 40 % of
the norm), and two copies in the model would fail every frame feature's ratio test between them."""


@dataclass(frozen=True)
class TrackerConfig:
    """Tracker settings (``behaviour.track_*`` and the selector's grouping: ``selection.group_*``,
    ``selection.object_radius_m`` and ``selection.target_max_extent_m``, so the tracker's objects are
    the selector's)."""

    ratio: float = 0.8
    min_matches: int = 4
    gate_m: float = 0.5
    gate_growth_m_s: float = 0.4
    model_size: int = 600
    lost_frames: int = 3
    group_radius_px: float = 20.0
    group_radius_m: float = 0.05
    min_object_features: int = 3
    gate_max_m: float = 0.75
    near_m: float = 0.25
    pool_below: int = 50
    object_radius_m: float = 0.15
    max_extent_m: float = 0.6
    refuse_neighbours: bool = True
    surface_slope: float = 2.0
    motion: MotionModel = MotionModel(coast_m=0.23, surge_lag_s=0.56, sway_lag_s=0.35, yaw_lag_s=0.6)
    """The schema's defaults: vehicle reckoning under manual_control (``behaviour.track_coast_m``, ``servo.tau_*``)."""

    @classmethod
    def from_params(cls, params: Mapping) -> "TrackerConfig":
        """Build from effective parameters."""
        return cls(params["behaviour.track_ratio"], params["behaviour.track_min_matches"],
                   params["behaviour.track_gate_m"], params["behaviour.track_gate_growth_m_s"],
                   params["behaviour.track_model_size"], params["behaviour.track_lost_frames"],
                   params["selection.group_radius_px"], params["selection.group_radius_m"],
                   params["selection.min_object_features"], gate_max_m=params["behaviour.track_gate_max_m"],
                   near_m=params["behaviour.track_near_m"], pool_below=params["behaviour.track_pool_below"],
                   object_radius_m=params["selection.object_radius_m"],
                   max_extent_m=params["selection.target_max_extent_m"],
                   refuse_neighbours=params["behaviour.track_neighbours"],
                   surface_slope=params["behaviour.track_surface_slope"], motion=MotionModel.from_params(params))


@dataclass(frozen=True)
class TrackedTarget:
    """The target as seen in one frame."""

    left_px: np.ndarray
    xyz_m: np.ndarray
    matches: int
    stamp_s: float
    obj: ObjectCandidate


class TrackRegion(NamedTuple):
    """Where the tracker looks in the next frame: the search box and, for a far target, a zoom box.

    Attributes:
        box: (x0, y0, x1, y1) rectified left px, the search box.
        zoom: (x0, y0, x1, y1) rectified left px around the predicted target, scanned again closer, or None.
        zoom_disparity_px: the predicted target's disparity (the zoom's right box lies around it), px.
    """

    box: tuple[int, int, int, int]
    zoom: tuple[int, int, int, int] | None = None
    zoom_disparity_px: float = 0.0


def project_px(xyz_m: np.ndarray, rig: StereoRig) -> tuple[float, float]:
    """Return where a camera-frame point (metres) lies in the rectified left image, (u, v) px."""
    cx, cy = rig.principal_point_px
    return rig.focal_px * xyz_m[0] / xyz_m[2] + cx, rig.focal_px * xyz_m[1] / xyz_m[2] + cy


def zoom_box(xyz_m: np.ndarray, rig: StereoRig, image_size: tuple[int, int], half_m: float,
             misses: int) -> tuple[tuple[int, int, int, int] | None, float]:
    """Return the zoom box (rectified left px) around a target predicted at ``xyz_m`` and its disparity (px).

    ``half_m`` (metres at the target's depth) plus ``ZOOM_MARGIN_PX`` (doubled after a miss) on each side;
    None for a target nearer than ``ZOOM_MIN_DEPTH_M`` (large enough for the search box's own scan), for
    ``half_m`` 0, or for a box mostly outside the image.
    """
    if half_m <= 0.0 or xyz_m[2] < ZOOM_MIN_DEPTH_M:
        return None, 0.0
    f = rig.focal_px
    u, v = project_px(xyz_m, rig)
    half = f * half_m / xyz_m[2] + ZOOM_MARGIN_PX * (2.0 if misses else 1.0)
    w, h = image_size
    x0, y0, x1, y1 = int(max(0, u - half)), int(max(0, v - half)), int(min(w, u + half)), int(min(h, v + half))
    if x1 - x0 < 16 or y1 - y0 < 16:
        return None, 0.0
    return (x0, y0, x1, y1), f * abs(rig.baseline_m) / xyz_m[2]


def pooled_model(first: np.ndarray, pool: list[np.ndarray], size: int) -> np.ndarray:
    """Return ``first`` plus the pooled descriptors (newest sighting first) that lie at least
    ``POOL_MIN_DISTANCE`` from every descriptor already kept, at most ``size`` in all."""
    first = np.asarray(first, np.float32).reshape(-1, 128)
    kept = np.zeros((max(size, len(first)), 128), np.float32)
    kept[: len(first)] = first
    count = len(first)
    for d in (d for block in pool for d in np.asarray(block, np.float32).reshape(-1, 128)):
        if count >= size:
            break
        if count and float(np.min(np.linalg.norm(kept[:count] - d, axis=1))) < POOL_MIN_DISTANCE:
            continue
        kept[count] = d
        count += 1
    return kept[:count]


def _distinct(model_index: np.ndarray) -> int:
    """Return how many distinct model descriptors the features match (``model_index``: -1 for none).

    Each model descriptor counts once: several features of a big, self-similar object that all match the same
    few descriptors of a small target's model are not several matches.
    """
    return int(np.count_nonzero(np.unique(model_index) >= 0))


def _anchor_matches(min_matches: int) -> int:
    """Return how many matches to the first sighting's model an object needs (half the minimum, >= 2)."""
    return max(2, min_matches // 2)


def bearing_rad(xyz_m) -> float:
    """Return a camera-frame point's bearing about the camera's vertical axis, rad (right +)."""
    return math.atan2(float(xyz_m[0]), float(xyz_m[2]))


def turn_xyz(xyz_m: np.ndarray, command: VelocityCommand | None, dt_s: float) -> np.ndarray:
    """Turn camera-frame points or offsets (metres, (3,) or (K, 3)) by the commanded yaw over ``dt_s``.

    Yaw right (positive rate) turns the scene left about the camera's vertical axis; the vehicle's
    translation leaves offsets between two points unchanged, so this alone moves them.
    """
    p = np.array(xyz_m, dtype=float)
    if command is None or dt_s <= 0 or not p.size:
        return p
    a = command.yaw_rate_rad_s * dt_s
    x, z = p[..., 0].copy(), p[..., 2].copy()
    p[..., 0], p[..., 2] = x * math.cos(a) - z * math.sin(a), x * math.sin(a) + z * math.cos(a)
    return p


def predict_xyz(xyz_m: np.ndarray, command: VelocityCommand | None, dt_s: float) -> np.ndarray:
    """Move a camera-frame point by the vehicle's commanded motion over ``dt_s`` (small-motion model).

    Yaw right (positive rate) turns the scene left about the camera's vertical axis; surge brings
    it closer (z decreases); heave down moves it up in the image (y decreases).

    Examples:
        >>> predict_xyz(np.array([0.0, 0.0, 2.0]), VelocityCommand(surge_m_s=0.5), 1.0).round(3).tolist()
        [0.0, 0.0, 1.5]
    """
    p = turn_xyz(xyz_m, command, dt_s)
    if command is None or dt_s <= 0:
        return p
    p[0] -= command.sway_m_s * dt_s
    p[1] -= command.heave_m_s * dt_s
    p[2] -= command.surge_m_s * dt_s
    return p


class TargetTracker:
    """Follows one object across frames by appearance and 3D position.

    Args:
        config: the tracker settings.
        rig: the stereo rig (for grouping features into objects).
    """

    def __init__(self, config: TrackerConfig, rig: StereoRig) -> None:
        self.config = config
        self.rig = rig
        self._matcher = cv2.BFMatcher(cv2.NORM_L2)
        self._first: np.ndarray = np.zeros((0, 128), np.float32)
        self._latest: np.ndarray = np.zeros((0, 128), np.float32)
        self.xyz_m: np.ndarray | None = None
        self.last: TrackedTarget | None = None
        self.last_seen_s: float | None = None
        self.last_frame_s: float | None = None
        self.misses = 0
        self.frames = 0
        self.reacquisitions = 0
        self.neighbours_m: np.ndarray = np.zeros((0, 3))
        self.neighbours_half_m: np.ndarray = np.zeros(0)
        self.diver_m: np.ndarray = np.zeros((0, 3))
        self.yawed_rad = 0.0  # the commanded yaw since start, rad (right +)
        self.start_bearing_rad = 0.0  # the target's bearing in the camera at start, rad (right +)
        self.fix_xyz_m: np.ndarray | None = None  # where the target was last seen (or started, or rewound)
        self.refused = 0  # objects inside the gate refused as a known neighbour, over the track
        self.velocity = NEUTRAL  # the vehicle's modelled velocity at the last frame (``MotionModel``)

    @property
    def active(self) -> bool:
        """True once started with a target."""
        return self.xyz_m is not None

    @property
    def lost(self) -> bool:
        """True after ``lost_frames`` frames in a row without the target."""
        return self.misses >= self.config.lost_frames

    def start(self, obj: ObjectCandidate, candidates: Candidates, stamp_s: float,
              pool: list[tuple[ObjectCandidate, Candidates]] | None = None,
              neighbours_m: np.ndarray | None = None, diver_m: np.ndarray | None = None,
              neighbours_half_m: np.ndarray | None = None) -> None:
        """Start tracking ``obj`` (members index into ``candidates``), seen at ``stamp_s``.

        ``pool``: the target's sightings over the decision's frames, (object, its frame's candidates),
        newest first; their descriptors join a model of fewer than ``pool_below`` (``pooled_model``): a
        small far target's one sighting holds a handful, and a frame of it rarely matches enough of them.
        ``neighbours_m``: the other objects the decision knew, as offsets from the target (camera frame,
        metres, (K, 3)); they follow the target's prediction, turned by the commanded yaw (``_refused``).
        ``diver_m``: points of the diver's body at the decision, as offsets from the target (camera frame, metres,
        (J, 3)); turned as the neighbours, kept clear of by the servo (never refused as the target).
        ``neighbours_half_m``: how far each neighbour's edge lies from its centre across the line of sight
        (metres, (K,); None: 0), added to the servo's clearance of it.
        """
        members = list(obj.members)
        desc = candidates.descriptors[members] if len(candidates.descriptors) == len(candidates) else None
        self._first = np.asarray(desc if desc is not None else np.zeros((0, 128)), np.float32)
        self._first = self._first[: self.config.model_size]
        if pool and len(self._first) < self.config.pool_below:
            blocks = [c.descriptors[list(o.members)] for o, c in pool if len(c.descriptors) == len(c)]
            self._first = pooled_model(self._first, blocks, min(self.config.model_size, self.config.pool_below))
        self._latest = np.zeros((0, self._first.shape[1] if self._first.size else 128), np.float32)
        self.xyz_m = np.asarray(obj.xyz_m, dtype=float)
        self.fix_xyz_m = self.xyz_m.copy()
        self.last = TrackedTarget(np.asarray(obj.left_px, float), self.xyz_m, len(members), stamp_s, obj)
        self.last_seen_s = self.last_frame_s = stamp_s
        self.misses = 0
        self.know_neighbours(np.zeros((0, 3)) if neighbours_m is None else neighbours_m, neighbours_half_m)
        self.diver_m = np.zeros((0, 3)) if diver_m is None else np.asarray(diver_m, float).reshape(-1, 3)
        self.yawed_rad, self.start_bearing_rad = 0.0, bearing_rad(self.xyz_m)
        self.velocity = NEUTRAL  # the decision is taken holding still

    def know_neighbours(self, neighbours_m: np.ndarray, half_m: np.ndarray | None = None) -> None:
        """Set the known neighbours: offsets from the target (camera frame, metres, (K, 3)) and how far each one's
        edge lies from its centre (metres, (K,); None: 0, points)."""
        self.neighbours_m = np.asarray(neighbours_m, float).reshape(-1, 3)
        self.neighbours_half_m = (np.zeros(len(self.neighbours_m)) if half_m is None
                                  else np.asarray(half_m, float).reshape(len(self.neighbours_m)))

    def orbited_rad(self, xyz_m) -> float:
        """Return how far the vehicle has gone round the target since start, seen from the target (the line of
        sight's turn, from the commanded yaw and the target's bearing now at ``xyz_m``), rad (positive: the vehicle
        went right, as ``clearance.orbit_end_m``)."""
        return -(self.yawed_rad + bearing_rad(xyz_m) - self.start_bearing_rad)

    def rewind(self, xyz_m: np.ndarray, stamp_s: float) -> None:
        """The vehicle is back where it saw the target at ``xyz_m`` (after a zero-net manoeuvre, the nod):
        predict from there again, and forgive the misses of the manoeuvre (its dead reckoning drifts)."""
        if self.xyz_m is None:
            return
        self.xyz_m = np.asarray(xyz_m, dtype=float).copy()
        self.fix_xyz_m = self.xyz_m.copy()
        self.last_frame_s = stamp_s
        if self.misses:
            self.misses, self.last_seen_s = 0, stamp_s

    def predicted_xyz(self, stamp_s: float, command: VelocityCommand | None) -> np.ndarray | None:
        """Return where the target should be at ``stamp_s`` given the command in force since the last frame."""
        if self.xyz_m is None:
            return None
        since_s = self._since_frame_s(stamp_s)
        return predict_xyz(self.xyz_m, self.config.motion.advance(self.velocity, command, since_s)[0], since_s)

    def _since_frame_s(self, stamp_s: float) -> float:
        """Return the time from the last frame to ``stamp_s`` (s; 0 before any)."""
        return 0.0 if self.last_frame_s is None else stamp_s - self.last_frame_s

    def update(self, candidates: Candidates, xyz_m: np.ndarray, stamp_s: float,
               command: VelocityCommand | None = None) -> TrackedTarget | None:
        """Find the target in a new frame's full-frame candidates.

        Args:
            candidates: matched features of the frame (rectified px, with descriptors).
            xyz_m: their 3D points (camera frame, metres).
            stamp_s: capture time of the frame.
            command: the vehicle command in force since the previous frame (for the prediction).

        Returns:
            The target in this frame, or None (a miss).
        """
        if self.xyz_m is None:
            return None
        self.frames += 1
        since_s = self._since_frame_s(stamp_s)
        moved, self.velocity = self.config.motion.advance(self.velocity, command, since_s)
        predicted = predict_xyz(self.xyz_m, moved, since_s)
        self.neighbours_m = turn_xyz(self.neighbours_m, moved, since_s)
        self.diver_m = turn_xyz(self.diver_m, moved, since_s)
        self.yawed_rad += moved.yaw_rate_rad_s * max(since_s, 0.0)
        self.xyz_m = predicted  # dead reckoning while unseen keeps the gate centred
        self.last_frame_s = stamp_s
        found = self._find(candidates, xyz_m, predicted, stamp_s)
        if found is None:
            self.misses += 1
            return None
        if self.lost:
            self.reacquisitions += 1
        self.misses = 0
        self.xyz_m = np.asarray(found.xyz_m, dtype=float)
        self.fix_xyz_m = self.xyz_m.copy()
        self.last, self.last_seen_s = found, stamp_s
        members = list(found.obj.members)
        room = max(self.config.model_size - len(self._first), 0)
        self._latest = np.asarray(candidates.descriptors[members][:room], np.float32)
        return found

    def _find(self, candidates: Candidates, xyz_m: np.ndarray, predicted: np.ndarray,
              stamp_s: float) -> TrackedTarget | None:
        """Return the best gated object of the frame, or None."""
        if len(candidates) == 0 or len(self._first) < 2 or len(candidates.descriptors) != len(candidates):
            return None
        c = self.config
        objects = group_objects(candidates, xyz_m, self.rig, c.group_radius_px, c.group_radius_m,
                                c.min_object_features, c.object_radius_m, c.max_extent_m, c.surface_slope)
        if not objects:
            return None
        # each part of the model separately: the same feature in both would defeat the ratio test
        first = self._matched_descriptors(self._first, candidates.descriptors)
        latest = (self._matched_descriptors(self._latest, candidates.descriptors) if len(self._latest) >= 2
                  else np.full(len(candidates), -1))
        since = stamp_s - (self.last_seen_s if self.last_seen_s is not None else stamp_s)
        gate = min(c.gate_m + c.gate_growth_m_s * max(since, 0.0), c.gate_max_m)
        members = [list(obj.members) for obj in objects]
        anchors = [_distinct(first[m]) for m in members]
        # a feature matched by both parts counts once, by its first-sighting match
        latest = np.where(first >= 0, -1, latest)
        counts = [a + _distinct(latest[m]) for a, m in zip(anchors, members)]
        distances = [float(np.linalg.norm(obj.xyz_m - predicted)) for obj in objects]
        # only an object inside the gate can be the target: only there is the neighbour rule (and its hull) asked
        refused = [d <= gate and self._refused(obj, d, predicted, candidates) for obj, d in zip(objects, distances)]
        self.refused += sum(refused)
        best, best_key, best_count = None, (0, 0), 0
        for obj, anchored, count, distance, no in zip(objects, anchors, counts, distances, refused):
            # identity is anchored on the first sighting: the latest model only adds support, so one
            # wrong acceptance cannot carry the track over to a neighbouring object
            if no or count < c.min_matches or anchored < _anchor_matches(c.min_matches) or distance > gate:
                continue
            if (anchored, count) > best_key:
                best, best_key, best_count = obj, (anchored, count), count
        if best is None:
            best, best_count = self._near_and_alone(objects, counts, distances, gate, refused)
        else:
            best = self._matched_part(best, first, candidates, xyz_m, predicted)
        if best is None:
            return None
        return TrackedTarget(np.asarray(best.left_px, float), np.asarray(best.xyz_m, float), best_count,
                             stamp_s, best)

    def _matched_part(self, obj: ObjectCandidate, first: np.ndarray, candidates: Candidates,
                      xyz_m: np.ndarray, predicted: np.ndarray) -> ObjectCandidate:
        """Return the part of ``obj`` around its features matching the first sighting, if it is wider than a target.

        Two placards joined by what lies between them (a line on the floor) stay one object, whose centre lies
        between them: the target is then the matched features and their neighbours (``group_radius_px``). A known
        neighbour of the same texture matches the model too (two placards 0.05 m apart seen whole from 1.3 m:
        ``stacked`` seed 6, issue 11 session 53; the centre then jumped 0.12 m every other frame): with the
        neighbours on (``refuse_neighbours``), the part is also taken without the features nearer a predicted
        neighbour than the predicted target, and of the two the one whose centre lies nearer the prediction is the
        target (a neighbour's offset is only as good as the decision's view of it).
        """
        c = self.config
        members = np.asarray(obj.members)
        matched = members[first[members] >= 0]
        if len(matched) < c.min_matches:
            return obj
        depth_m = float(np.median(xyz_m[matched, 2]))
        if not extent_m(candidates.left_px[members], depth_m, self.rig.focal_px) > c.max_extent_m:
            return obj
        parts = [self._part_around(members, first, candidates)]
        if c.refuse_neighbours and len(self.neighbours_m):
            parts.append(self._part_around(members[self._nearer_target(xyz_m[members], predicted)], first, candidates))
        parts = [p for p in parts if p is not None]
        return min(parts, key=lambda p: float(np.linalg.norm(p.xyz_m - predicted))) if parts else obj

    def _part_around(self, members: np.ndarray, first: np.ndarray, candidates: Candidates) -> ObjectCandidate | None:
        """Return the features of ``members`` within ``group_radius_px`` of those matching the first sighting, as one
        object, or None when fewer than ``min_matches`` match."""
        c = self.config
        matched = members[first[members] >= 0]
        if len(matched) < c.min_matches:
            return None
        gap_px = cKDTree(candidates.left_px[matched]).query(candidates.left_px[members], k=1)[0]
        part = objects_of(candidates, self.rig, [members[gap_px <= c.group_radius_px]])
        return part[0] if part else None

    def _nearer_target(self, points_m: np.ndarray, predicted: np.ndarray) -> np.ndarray:
        """Return which points lie nearer the predicted target than every predicted known neighbour (camera frame,
        metres; a point without a finite position is kept)."""
        to_target = np.linalg.norm(points_m - predicted, axis=1)
        to_neighbour = np.min(np.linalg.norm(points_m[:, None, :] - (predicted + self.neighbours_m)[None], axis=2),
                              axis=1)
        return ~(to_neighbour < to_target)

    def _refused(self, obj: ObjectCandidate, distance_m: float, predicted: np.ndarray, candidates: Candidates) -> bool:
        """True when ``obj`` lies nearer one of the decision's other objects (predicted) than the target's prediction,
        by more than ``DRIFT_DOUBT`` times what the prediction moved since its last fix (``fix_xyz_m``: the last
        sighting, start or rewind).

        Such an object is that neighbour, however many descriptors it shares with the target: two placards of one
        texture match each other's models, and a neighbour inside the gate took the track over while the target
        was missed (issue 11 sessions 49-50, ``stacked`` seed 9). The margin is the dead reckoning's own doubt: the
        neighbours move with the prediction, so a prediction that swung by the offset between two placards (the
        acknowledge nod swings it by decimetres) puts a neighbour on the target, which was then refused
        (``side_by_side_far`` seed 6). An object wider than one target (a chain holding the target and a
        neighbour) is never refused: its matched part is the target (``_matched_part``).
        """
        if not self.config.refuse_neighbours or not len(self.neighbours_m):
            return False
        nearest_m = float(np.min(np.linalg.norm(predicted + self.neighbours_m - obj.xyz_m, axis=1)))
        if nearest_m + DRIFT_DOUBT * float(np.linalg.norm(predicted - self.fix_xyz_m)) >= distance_m:
            return False
        depth_m = float(obj.xyz_m[2])
        return not (depth_m > 0 and extent_m(candidates.left_px[list(obj.members)], depth_m, self.rig.focal_px)
                    > self.config.max_extent_m)

    def _near_and_alone(self, objects: list[ObjectCandidate], counts: list[int], distances_m: list[float],
                        gate_m: float, refused: list[bool]) -> tuple[ObjectCandidate | None, int]:
        """Return the one object of the gate, if it lies within ``near_m`` of the prediction and matches the model.

        A small, faint target (a few features, found by the pointing corridor) often shares only one or two
        descriptors with its model from one frame to the next, under the count the identity test asks. Its
        position then identifies it, as long as nothing else is in the gate: the only object within ``gate_m``,
        within ``near_m`` (metres) of the prediction (``distances_m``), with at least one feature matching the
        model (``counts``); an object nearer another of the decision's objects (``refused``) is that object, not a
        second candidate. Only while the target was seen in one of the last two frames: after a longer gap the
        prediction is dead reckoning (the nod's swing drifts by decimetres) and may sit on another object.
        """
        if self.misses > 1:
            return None, 0
        inside = [k for k, d in enumerate(distances_m) if d <= gate_m and not refused[k]]
        if len(inside) != 1 or distances_m[inside[0]] > self.config.near_m or counts[inside[0]] < 1:
            return None, 0
        return objects[inside[0]], counts[inside[0]]

    def _matched_descriptors(self, model: np.ndarray, frame_desc: np.ndarray) -> np.ndarray:
        """Return per frame feature the index of the model descriptor it matches (ratio test), or -1."""
        out = np.full(len(frame_desc), -1)
        if len(frame_desc) < 2:
            return out
        pairs = self._matcher.knnMatch(np.asarray(frame_desc, np.float32), model, k=2)
        for m in pairs:
            if len(m) == 2 and m[0].distance < self.config.ratio * m[1].distance:
                out[m[0].queryIdx] = m[0].trainIdx
        return out
