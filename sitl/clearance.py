"""How near the vehicle came to each placard in a simulated run: a safety figure the mission does not see.

The mission knows objects only by what perception finds; the simulator knows where every placard
is. The least distance between the vehicle's centre (its NED position) and each placard's square
over the run says whether the vehicle drove into, or close past, an object it was not sent to
(``sitl --json``: ``closest_m`` per placard id, ``closest_other_m`` over every placard but the
pointed one). The vehicle's own size is not subtracted (a BlueROV2 is ~0.46 x 0.34 x 0.25 m, so a
centre distance under ~0.25 m means its hull touched the placard). Metres, world NED.
"""

from __future__ import annotations

import math
from typing import Iterable, Sequence

import numpy as np

from behaviours.clearance import distance_to_path_m

from .scenario_model import Placard

__all__ = ["square_distance_m", "closest_approach_m", "closest_other_m", "BODY_SEGMENTS", "body_distance_m",
           "closest_diver_m"]

BODY_SEGMENTS = (("head", "neck"), ("neck", "chest"), ("chest", "pelvis"), ("shoulder", "o_shoulder"),
                 ("shoulder", "elbow"), ("elbow", "wrist"), ("wrist", "hand"), ("o_shoulder", "o_elbow"),
                 ("o_elbow", "o_wrist"), ("pelvis", "hip_r"), ("pelvis", "hip_l"), ("hip_r", "knee_r"),
                 ("hip_l", "knee_l"), ("knee_r", "ankle_r"), ("knee_l", "ankle_l"), ("ankle_r", "fin_r"),
                 ("ankle_l", "fin_l"), ("tank_top", "tank_bottom"))
"""The diver's body as segments between its joints (``Diver.joints``): its axes, not its surface."""


def square_distance_m(points_ned: np.ndarray, placard: Placard) -> np.ndarray:
    """Return each (N, 3) NED point's distance to the placard's square (its face, a plane square), metres."""
    corners = placard.corners_ned()
    origin = corners[0]
    right, down = corners[1] - corners[0], corners[3] - corners[0]
    size = float(np.linalg.norm(right))
    right, down = right / size, down / size
    rel = np.asarray(points_ned, float).reshape(-1, 3) - origin
    a, b = np.clip(rel @ right, 0.0, size), np.clip(rel @ down, 0.0, size)
    nearest = origin + a[:, None] * right + b[:, None] * down
    return np.linalg.norm(np.asarray(points_ned, float).reshape(-1, 3) - nearest, axis=1)


def closest_approach_m(positions_ned: Iterable[Sequence[float]], placards: Iterable[Placard]) -> dict[int, float]:
    """Return, per placard id, the least distance from any of the vehicle's positions (NED, m) to its square, m."""
    pts = np.asarray(list(positions_ned), float).reshape(-1, 3)
    if len(pts) == 0:
        return {}
    return {p.id: round(float(square_distance_m(pts, p).min()), 3) for p in placards}


def closest_other_m(closest: dict[int, float], target_id: int) -> float | None:
    """Return the least of ``closest`` over every placard but the pointed one (None when there is none), m."""
    others = [d for pid, d in closest.items() if pid != target_id and math.isfinite(d)]
    return min(others) if others else None


def body_distance_m(point_ned, joints: dict[str, np.ndarray]) -> float:
    """Return one NED point's least distance to the diver's body axes (``BODY_SEGMENTS`` of ``joints``), metres."""
    p = np.asarray(point_ned, float).reshape(1, 3)
    return min(float(distance_to_path_m(p, joints[a], joints[b])[0][0]) for a, b in BODY_SEGMENTS)


def closest_diver_m(samples, diver, target_ned_m) -> float | None:
    """Return the least distance from the vehicle's centre to the diver's body axes over the run, metres.

    Args:
        samples: (time s, north m, east m, depth m) rows of the vehicle's trajectory.
        diver: the scenario's ``Diver`` (posed at each sample's time).
        target_ned_m: the placard the diver points at (the arm's aim).
    """
    rows = list(samples)
    if not rows:
        return None
    return round(min(body_distance_m(r[1:4], diver.joints(np.asarray(target_ned_m, float), r[0])) for r in rows), 3)
