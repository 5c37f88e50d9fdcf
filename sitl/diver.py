"""The scenario's diver: where they stand, which arm points at which placard, when, and their joints."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .world import perpendicular_basis, unit

__all__ = ["Diver", "UPPER_ARM_M", "FOREARM_M"]

UPPER_ARM_M = 0.30
FOREARM_M = 0.28


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
