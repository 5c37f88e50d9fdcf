"""Keeping clear of the other objects on the way to the target: a way round them, planned on every frame.

The servo drives the camera straight at the target and stops ``standoff_m`` before it. Any object
the diver did not point at that lies near that straight path, or beside the stand-off point, is in
the vehicle's way: in the paper's own set-up (placards at 1, 2 and 3 m along a line) the stand-off
point before placard 2 lies 0.23 m from placard 1, and the simulator measured the vehicle's centre
passing 0.26 m from its face (``sitl --json``'s ``closest_other_m``).

The objects are the decision's other hypotheses (the tracker's known neighbours: offsets from the
target, turned by the commanded yaw), so they are remembered after they leave the image. Geometry
in the rectified left camera frame (x right, y down, z forward, metres), as ``close_in.py``.

The way: the stand-off point may be turned about the target (about the camera's vertical axis, tried in
``ORBIT_STEP_RAD`` steps, the least clear step then narrowed to within ``ORBIT_REFINE_RAD`` of where its way stops
being clear, the vehicle kept within ``MAX_ORBIT_RAD`` of the line it decided from), so the vehicle ends at the
stand-off but looking at the target from the side. A way is the straight segment from the hull's rear (``behind_m``
behind the camera: an object the camera has passed still lies beside the hull) to its stand-off point; its clearance
is the least distance of any object from it, and an object may be asked for more than the others (``extra_m``: the
servo's diver, whose body reaches beyond the points of it the vehicle knows). The direct way is kept when it is
clear; otherwise the least turn whose way is clear, weighing every object at once (two objects on either side of a
gap are one constraint, not two pushes). When no turn is clear, the vehicle holds short: the stand-off grows in
``STANDOFF_STEP_M`` steps until some way is clear, up to where the camera is now (it stops). It never chooses which
object to pass near. The plan is made again on every frame from where the vehicle is (a receding horizon), keeps to
the side it chose unless only the other side is clear, and the caller keeps the stand-off it held short at (it only
grows while the target is the same).

Following the way: the vehicle sways toward the way's stand-off point at ``gain_per_s`` times its
offset across the line of sight to the target (capped by the servo's sway limit; the yaw keeps the
target centred, so the vehicle turns about the target) and advances no faster than the sway would
carry it there along the straight way; the servo stops it at the way's stand-off.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["DIRECT_BAND_M", "HULL_HALF_LENGTH_M", "MAX_ORBIT_RAD", "ORBIT_REFINE_RAD", "ORBIT_STEP_RAD",
           "STANDOFF_STEP_M", "Sidestep", "Way", "across_and_along", "approach_end_m", "distance_to_path_m",
           "orbit_end_m", "orbit_ends_m", "plan_way", "sidestep"]

GAIN_PER_S = 1.0
"""Sway speed per metre of lateral offset from the way's stand-off point, 1/s (capped by the servo's sway limit)."""

HULL_HALF_LENGTH_M = 0.25
"""How far the hull reaches behind the vehicle's reference point, m (a BlueROV2 is 0.457 m long)."""

ORBIT_STEP_RAD = math.radians(5.0)
"""The turns of the stand-off point about the target that are tried, in steps of this, rad."""

ORBIT_REFINE_RAD = math.radians(0.25)
"""The least clear turn is narrowed (bisected) to within this of where its way becomes clear, rad. Replanned from
wherever the vehicle is, a whole 5 deg step is never nearer: on the edge of clear the sway stayed at the full
0.19 m/s until the direct way was clear and the vehicle coasted past it (``paper_pool`` seed 9 from pixels,
issue 11 session 56). Narrowed, the turn, and with it the sway, shrinks as the way comes clear."""

MAX_ORBIT_RAD = math.radians(40.0)
"""The farthest the vehicle goes round the target, either side, from where it decided (what it has gone round
already and the way's turn together), rad. A flat placard is then seen 40 deg off the line it was chosen from: further
round (60 deg, tried) its stereo range and image position jitter so that arrive could not settle in 60 s."""

SIDE_PREFERENCE_RAD = math.radians(10.0)
"""A clear way on the side chosen before wins over one on the other side turned up to this much less, rad."""

DIRECT_BAND_M = 0.05
"""A direct way taken on the last frame stays taken while it falls short of the clearance by no more than this, m:
the plan is made again on every frame, and a way on the edge of clear (the stand-off held short beside the diver)
went direct, turned 5 deg one way, direct, 5 deg the other, each with a 0.19 m sway, and the vehicle could not settle
for 10 s (``paper_pool`` seed 9 from pixels, issue 11 session 55)."""

STANDOFF_STEP_M = 0.1
"""When no way at the stand-off is clear, longer stand-offs are tried in steps of this, m (the vehicle holds short)."""


@dataclass(frozen=True)
class Way:
    """A way to the target (camera frame, metres).

    Attributes:
        angle_rad: the stand-off point's turn about the target (positive: it lies to the right).
        end_xyz: where the camera ends, ``standoff_m`` from the target.
        standoff_m: how far from the target the way ends, m (longer than asked: the vehicle holds short).
        clearance_m: the distance from the way of the object that falls most short of the clearance asked, m.
        index: which object (row of the objects given) that is.
        along_m: that object's nearest point on the way, m along it from its start.
        margin_m: how much further from the way than asked the object that falls most short is, m (>= 0: clear).
    """

    angle_rad: float
    end_xyz: np.ndarray
    standoff_m: float
    clearance_m: float
    index: int
    along_m: float
    margin_m: float


@dataclass(frozen=True)
class Sidestep:
    """How to follow a way round the objects (body sway, m/s; the most forward surge, m/s).

    Attributes:
        sway_m_s: the sway to command (positive = right), m/s.
        max_surge_m_s: the most forward surge that keeps to the way (the sway's pace along it), m/s.
        offset_m: the way's stand-off point's offset across the line of sight to the target, m (positive: right).
        way: the way followed (its ``standoff_m`` is the servo's).
        clear: True when the way keeps every object ``clearance_m`` away.
    """

    sway_m_s: float
    max_surge_m_s: float
    offset_m: float
    way: Way
    clear: bool


def approach_end_m(target_xyz, standoff_m: float) -> np.ndarray:
    """Return where the camera ends its approach: ``standoff_m`` before the target on its line of sight, metres."""
    t = np.asarray(target_xyz, float)
    rng = float(np.linalg.norm(t))
    return t * max(rng - standoff_m, 0.0) / rng if rng > 1e-9 else np.zeros(3)


def orbit_end_m(target_xyz, standoff_m: float, angle_rad: float) -> np.ndarray:
    """Return the stand-off point turned ``angle_rad`` about the target's vertical (positive: to the right), metres.

    Examples:
        >>> np.round(orbit_end_m([0.0, 0.0, 2.0], 1.0, math.radians(90)), 3).tolist()  # beside the target
        [1.0, 0.0, 2.0]
    """
    return orbit_ends_m(target_xyz, standoff_m, np.array([angle_rad]))[0]


def orbit_ends_m(target_xyz, standoff_m: float, angles_rad: np.ndarray) -> np.ndarray:
    """Return the stand-off point turned by each of ``angles_rad`` about the target's vertical, (A, 3) metres
    (``approach_end_m`` for every angle when the target is no farther than the stand-off)."""
    t = np.asarray(target_xyz, float)
    rng = float(np.linalg.norm(t))
    if rng <= standoff_m or rng < 1e-9:
        return np.repeat(approach_end_m(t, standoff_m)[None], len(angles_rad), axis=0)
    u, c, s = t / rng, np.cos(angles_rad), np.sin(angles_rad)
    return t - standoff_m * np.c_[u[0] * c - u[2] * s, np.full(len(angles_rad), u[1]), u[0] * s + u[2] * c]


def distance_to_path_m(points: np.ndarray, start: np.ndarray, end: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return each point's distance from the segment ``start`` -> ``end`` and its nearest point's distance along
    it from ``start``, metres."""
    d = end - start
    length = float(np.linalg.norm(d))
    if length < 1e-9:
        return np.linalg.norm(points - start, axis=1), np.zeros(len(points))
    along = np.clip((points - start) @ d / length, 0.0, length)
    return np.linalg.norm(points - start - along[:, None] * (d / length), axis=1), along


def _angles(side: float, orbited_rad: float = 0.0) -> list[float]:
    """Return the turns to try, 0 first, then by size with ``side``'s sign first at each size, keeping the vehicle
    within ``MAX_ORBIT_RAD`` of where it decided (it has gone ``orbited_rad`` round already), rad."""
    first = 1.0 if side >= 0 else -1.0
    steps = int(round(2 * MAX_ORBIT_RAD / ORBIT_STEP_RAD))
    turns = [sign * k * ORBIT_STEP_RAD for k in range(1, steps + 1) for sign in (first, -first)]
    return [0.0] + [a for a in turns if abs(orbited_rad + a) <= MAX_ORBIT_RAD + 1e-9]


def _way(target: np.ndarray, objects: np.ndarray, standoff_m: float, start: np.ndarray, angle: float,
         needed: np.ndarray) -> Way:
    """Return the way whose stand-off point, ``standoff_m`` from the target, is turned ``angle`` about it
    (``needed``: each object's clearance asked, m)."""
    end = orbit_end_m(target, standoff_m, angle)
    dist, along = distance_to_path_m(objects, start, end)
    k = int(np.argmin(dist - needed))
    return Way(angle, end, standoff_m, float(dist[k]), k, float(along[k]), float(dist[k] - needed[k]))


def _margins(target: np.ndarray, objects: np.ndarray, standoff_m: float, start: np.ndarray, angles: np.ndarray,
             needed: np.ndarray) -> np.ndarray:
    """Return the margin (``Way.margin_m``) of the way turned by each of ``angles``, all at once (the search's
    sieve: ``_way`` gives the way itself), metres."""
    d = orbit_ends_m(target, standoff_m, angles) - start
    length = np.maximum(np.linalg.norm(d, axis=1), 1e-9)
    rel = objects - start
    along = np.clip(rel @ d.T / length, 0.0, length)  # (K, A)
    dist = np.linalg.norm(rel[:, None, :] - along[:, :, None] * (d / length[:, None])[None], axis=2)
    return np.min(dist - needed[:, None], axis=0)


def _standoffs(standoff_m: float, range_m: float) -> list[float]:
    """Return the stand-offs to try: ``standoff_m``, then longer by ``STANDOFF_STEP_M`` up to the target's range
    ``range_m`` (where the camera is: it stops; its depth alone would leave an off-axis target's way ending
    range x (1 - cos bearing) ahead of the camera), m."""
    longer = [standoff_m + k * STANDOFF_STEP_M for k in range(1, int((range_m - standoff_m) / STANDOFF_STEP_M) + 1)]
    return [standoff_m] + [s for s in longer if s < range_m - 1e-9] + ([range_m] if range_m > standoff_m else [])


def _narrowed(target: np.ndarray, objects: np.ndarray, start: np.ndarray, way: Way, needed: np.ndarray) -> Way:
    """Return ``way`` turned less, to within ``ORBIT_REFINE_RAD`` of where it stops being clear (bisected between it
    and the turn one ``ORBIT_STEP_RAD`` nearer the direct way, which is not clear), at its stand-off."""
    if not way.angle_rad:  # the direct way (held short): nothing to narrow
        return way
    clear, short = way, way.angle_rad - math.copysign(ORBIT_STEP_RAD, way.angle_rad)
    while abs(clear.angle_rad - short) > ORBIT_REFINE_RAD:
        mid = _way(target, objects, way.standoff_m, start, 0.5 * (clear.angle_rad + short), needed)
        clear, short = (mid, short) if mid.margin_m >= 0 else (clear, mid.angle_rad)
    return clear


def plan_way(target_xyz, objects_xyz, standoff_m: float, clearance_m: float, behind_m: float = 0.0,
             side: float = 0.0, orbited_rad: float = 0.0, direct_band_m: float = 0.0,
             extra_m: np.ndarray | None = None) -> Way | None:
    """Return the way to take round the objects, or None when the direct way is clear (or no clearance is asked).

    An object already nearer the hull's rear than ``clearance_m`` (beside the hull) can be kept no further than it
    is: the way is clear of it when it passes no nearer than that.

    Args:
        target_xyz: the target (camera frame, metres).
        objects_xyz: the other objects, (K, 3) (camera frame, metres).
        standoff_m: the servo's stand-off (the way ends this far from the target, or further when it holds short).
        clearance_m: how far from the way every object must stay (0: always the direct way).
        behind_m: how far the hull reaches behind the camera (the way starts there), m.
        side: the side chosen before (its sign; 0: none): its clear ways win over the other side's turned up to
            ``SIDE_PREFERENCE_RAD`` less.
        orbited_rad: how far the vehicle has gone round the target already (positive: right), rad: no way takes it
            beyond ``MAX_ORBIT_RAD``.
        direct_band_m: the direct way is taken while it falls short of the clearance by no more than this, m
            (``DIRECT_BAND_M`` when it was taken on the last frame: a hysteresis).
        extra_m: how much further than ``clearance_m`` each object is kept, (K,) metres (None: 0; the diver's points:
            the body beyond the joints the vehicle knows).

    Returns:
        The least turned clear way (narrowed to ``ORBIT_REFINE_RAD``) at the shortest stand-off that has one (from
        ``standoff_m`` up, in ``STANDOFF_STEP_M`` steps, to the target's range: the vehicle holds short); when not even
        stopping where it is keeps clear, the direct way ending there (its margin < 0).

    Examples:
        >>> way = plan_way([0.0, 0.0, 2.0], [[0.1, 0.0, 1.0]], 1.0, 0.5)  # just right of the stand-off point
        >>> way.angle_rad < 0, way.clearance_m >= 0.5, way.standoff_m  # ends turned to the left, clear
        (True, True, 1.0)
    """
    objects = np.asarray(objects_xyz, float).reshape(-1, 3)
    extra = np.zeros(len(objects)) if extra_m is None else np.asarray(extra_m, float).reshape(-1)
    finite = np.all(np.isfinite(objects), axis=1)
    objects, extra = objects[finite], extra[finite]
    if clearance_m <= 0 or not len(objects):
        return None
    target = np.asarray(target_xyz, float)
    start = np.array([0.0, 0.0, -behind_m])
    needed = np.minimum(clearance_m + extra, np.linalg.norm(objects - start, axis=1) - 1e-6)
    angles = _angles(side, orbited_rad)
    if _way(target, objects, standoff_m, start, 0.0, needed).margin_m >= -direct_band_m:
        return None

    def cost(w: Way) -> float:
        """The turn, plus the preference's worth when on the side not chosen before, rad."""
        return abs(w.angle_rad) + (SIDE_PREFERENCE_RAD if side and w.angle_rad * side < 0 else 0.0)
    standoffs = _standoffs(standoff_m, float(np.linalg.norm(target)))
    for s in standoffs:
        sieved = np.asarray(angles)[_margins(target, objects, s, start, np.asarray(angles), needed) >= -1e-9]
        clear = [w for w in (_way(target, objects, s, start, a, needed) for a in sieved.tolist()) if w.margin_m >= 0]
        if clear:
            return _narrowed(target, objects, start, min(clear, key=cost), needed)
    return _way(target, objects, standoffs[-1], start, 0.0, needed)


def sidestep(target_xyz, objects_xyz, standoff_m: float, clearance_m: float, max_sway_m_s: float,
             behind_m: float = 0.0, side: float = 0.0, orbited_rad: float = 0.0,
             gain_per_s: float = GAIN_PER_S, direct_band_m: float = 0.0,
             extra_m: np.ndarray | None = None) -> Sidestep | None:
    """Return how to follow the way round the objects (``plan_way``), or None when the direct way is clear.

    The sway is taken across the line of sight to the target (horizontal), so a target still off-centre does not
    sway the vehicle while the yaw centres it.

    Args:
        target_xyz, objects_xyz, standoff_m, clearance_m, behind_m, side, orbited_rad, direct_band_m, extra_m: as
            ``plan_way``.
        max_sway_m_s: the sway limit, m/s.
        gain_per_s: sway speed per metre of offset from the way's stand-off point, 1/s.

    Examples:
        >>> s = sidestep([0.0, 0.0, 2.0], [[0.1, 0.0, 1.0]], 1.0, 0.5, 0.3)  # just right of the stand-off point
        >>> s.sway_m_s < 0, s.clear  # sway left, round it
        (True, True)
    """
    way = plan_way(target_xyz, objects_xyz, standoff_m, clearance_m, behind_m, side, orbited_rad, direct_band_m,
                   extra_m)
    if way is None:
        return None
    lateral, forward = across_and_along(np.asarray(target_xyz, float), way.end_xyz)
    sway = float(np.clip(gain_per_s * lateral, -max_sway_m_s, max_sway_m_s))
    max_surge = math.inf if abs(lateral) < 0.02 else abs(sway) * max(forward, 0.0) / abs(lateral)
    return Sidestep(sway, max_surge, lateral, way, way.margin_m >= 0)


def across_and_along(target: np.ndarray, point: np.ndarray) -> tuple[float, float]:
    """Return ``point``'s offset across the horizontal line of sight to ``target`` (positive: right) and along it,
    metres."""
    h = math.hypot(float(target[0]), float(target[2]))
    if h < 1e-9:
        return float(point[0]), float(point[2])
    ux, uz = float(target[0]) / h, float(target[2]) / h
    return float(point[0]) * uz - float(point[2]) * ux, float(point[0]) * ux + float(point[2]) * uz
