"""The one word a simulated mission ends with, its reason and the exit code of ``dip3d-vehicle sitl``.

A run ends in exactly one outcome; the text, the JSON (``"outcome"``, ``"outcome_reason"``), the
plot title and the exit code all use the same word:

==================  ====  =====================================================================
outcome             exit  meaning
==================  ====  =====================================================================
reached             0     arrived at the object the diver pointed at, within the stand-off tolerance
wrong_object        3     chose (and arrived at, or was going to) an object the diver did NOT point at
outside_tolerance   4     arrived at the pointed object, but the true range at arrival was outside
                          ``behaviour.arrive_tolerance_m`` of the stand-off
not_arrived         5     chose the pointed object but had not arrived when the run ended
no_decision         6     never chose an object (e.g. every selection ambiguous) before the run ended
aborted             7     the mission gave up on its target (state ``abort``) and did not arrive
suspended           8     the run ended while the mission was suspended (link lost, pilot took over)
==================  ====  =====================================================================

Exit code 2 stays "bad input" (every command), 1 an unexpected crash.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

__all__ = ["OUTCOME_EXIT_CODES", "CHOSEN_WITHIN_M", "Outcome", "Sightings", "mission_outcome", "nearest_placard"]

CHOSEN_WITHIN_M = 0.5
"""A tracked target names the placard whose true centre is nearest it within this, metres (else none)."""

OUTCOME_EXIT_CODES: dict[str, int] = {
    "reached": 0, "wrong_object": 3, "outside_tolerance": 4, "not_arrived": 5, "no_decision": 6,
    "aborted": 7, "suspended": 8,
}
"""Every outcome word and the exit code of ``dip3d-vehicle sitl`` for it."""


@dataclass(frozen=True)
class Outcome:
    """How a mission ended: one word (a key of ``OUTCOME_EXIT_CODES``) and a one-sentence reason."""

    word: str
    reason: str

    @property
    def exit_code(self) -> int:
        """The exit code of ``dip3d-vehicle sitl`` for this outcome (0 only for ``reached``)."""
        return OUTCOME_EXIT_CODES[self.word]


def mission_outcome(*, arrived: bool, chosen_id: int | None, target_id: int, range_error_at_arrival_m: float | None,
                    tolerance_m: float, states: list[str], sim_time_s: float) -> Outcome:
    """Return the outcome of one run.

    Args:
        arrived: the mission reached its ``done`` state (at whatever object it chose).
        chosen_id: the placard the tracker last saw as its target (``Sightings``), or None.
        target_id: the placard the diver pointed at.
        range_error_at_arrival_m: true range minus stand-off when the mission arrived, or None.
        tolerance_m: ``behaviour.arrive_tolerance_m``.
        states: the mission's states in the order entered.
        sim_time_s: simulated time when the run ended.

    Returns:
        The Outcome.
    """
    if arrived and chosen_id == target_id:
        err = range_error_at_arrival_m
        if err is not None and abs(err) <= tolerance_m:
            return Outcome("reached", f"arrived at the pointed placard {target_id}, true range error {err:+.2f} m "
                                      f"(tolerance {tolerance_m:.2f} m)")
        shown = "unknown" if err is None else f"{err:+.2f} m"
        return Outcome("outside_tolerance", f"arrived at the pointed placard {target_id} but the true range error "
                                            f"at arrival was {shown} (tolerance {tolerance_m:.2f} m)")
    if arrived:
        where = f"placard {chosen_id}" if chosen_id is not None else "a point more than 0.5 m from every placard"
        return Outcome("wrong_object", f"arrived at {where}; the diver pointed at placard {target_id}")
    last = states[-1] if states else "idle"
    if chosen_id is not None and chosen_id != target_id:
        return Outcome("wrong_object", f"was going to placard {chosen_id} (state {last}) when the run ended after "
                                       f"{sim_time_s:.1f} s; the diver pointed at placard {target_id}")
    if last == "suspended":
        return Outcome("suspended", f"the run ended after {sim_time_s:.1f} s with the mission suspended "
                                    f"(link lost or the pilot took over)")
    if "abort" in states:
        return Outcome("aborted", f"the mission gave up on its target (state abort) and had not arrived when the "
                                  f"run ended after {sim_time_s:.1f} s")
    if chosen_id is not None or any(s in states for s in ("acknowledge", "servo")):
        return Outcome("not_arrived", f"chose {'the pointed placard ' + str(target_id) if chosen_id is not None else 'an object'}"
                                      f" but had not arrived when the run ended after {sim_time_s:.1f} s "
                                      f"(state {last})")
    return Outcome("no_decision", f"no object chosen in {sim_time_s:.1f} s (state {last})")


def nearest_placard(xyz_rect_m: Any, placards: Mapping[Any, Mapping], r1: np.ndarray) -> Any | None:
    """Return the id of the placard whose true centre is nearest ``xyz_rect_m`` (rectified left camera, metres)
    within ``CHOSEN_WITHIN_M``, or None; ``placards`` is a frame meta's ``"placards"`` (``xyz_cam_m``, camera)."""
    best, best_d = None, CHOSEN_WITHIN_M
    for pid, info in placards.items():
        d = float(np.linalg.norm(r1 @ np.asarray(info["xyz_cam_m"], float) - np.asarray(xyz_rect_m, float)))
        if d < best_d:
            best, best_d = pid, d
    return best


class Sightings:
    """Which placard the vehicle's tracker last saw as its target, from the true positions of that very frame.

    A run's choice is this, not where the tracker's dead-reckoned position stands at the end: after a loss the
    tracker keeps its last position while the vehicle drifts, so an aborted run's stale position can end within
    ``CHOSEN_WITHIN_M`` of a placard the vehicle never tracked (issue 11 session 57, ``variant_10_01`` seed 1).
    """

    KEEP_FRAMES = 64
    """How many recent frames' metas are kept to find a sighting's own frame."""

    def __init__(self, r1: np.ndarray) -> None:
        self.r1 = np.asarray(r1, float)
        self._metas: dict[float, Mapping] = {}
        self._last: Any = None
        self.placard: Any | None = None
        """the placard the newest sighting lay on, or None (none within ``CHOSEN_WITHIN_M``, or no sighting)"""

    @property
    def seen(self) -> bool:
        """Whether the tracker has seen a target yet."""
        return self._last is not None

    def frame(self, stamp_s: float, meta: Mapping | None) -> None:
        """Keep the meta (true positions) of the frame captured at ``stamp_s``, seconds."""
        if meta:
            self._metas[stamp_s] = meta
            while len(self._metas) > self.KEEP_FRAMES:
                del self._metas[next(iter(self._metas))]

    def note(self, last: Any, fallback_meta: Mapping | None) -> None:
        """Take the tracker's newest sighting ``last`` (a ``TrackedTarget`` or None): a new one names its placard
        from its own frame's meta (``fallback_meta`` when that frame is no longer kept)."""
        if last is None or last is self._last:
            return
        self._last = last
        meta = self._metas.get(last.stamp_s) or fallback_meta or {}
        self.placard = nearest_placard(last.xyz_m, meta.get("placards", {}), self.r1) if meta else None
