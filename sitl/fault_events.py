"""A fault plan's timed events applied to a run: the autopilot, the simulated pilot, the relay, the camera."""

from __future__ import annotations

from typing import Any

from .faults import CAMERA_KINDS, FaultEvent, FaultPlan

__all__ = ["FaultEvents"]


class FaultEvents:
    """Applies a plan's timed events to a run (autopilot, pilot, relay, camera) and re-hands over."""

    def __init__(self, plan: FaultPlan, ap, pilot, relay, camera) -> None:
        self.pending = list(plan.events)
        self.ap, self.pilot, self.relay, self.camera = ap, pilot, relay, camera
        self.applied: list[dict] = []
        self._actions: list[tuple[float, str]] = []

    def step(self, now: float, start_of: Any) -> None:
        """Fire due events; ``start_of(state)`` gives the first time a state was entered (or None)."""
        for ev in list(self.pending):
            if ev.at_s is not None:
                onset = ev.at_s
            else:
                t0 = start_of(ev.after_state)
                if t0 is None:
                    continue
                onset = t0 + ev.after_s
            if now + 1e-9 < onset:
                continue
            self.pending.remove(ev)
            self._fire(ev, now)
        for item in list(self._actions):
            t, what = item
            if now + 1e-9 >= t:
                self._actions.remove(item)
                if what == "gcs_back":
                    self.pilot.heartbeats = True
                elif what == "hand_over":
                    self.pilot.handed_over = self.pilot.enable_acked = False
                    self.pilot._next_try = now

    def _fire(self, ev: FaultEvent, now: float) -> None:
        clear = now + ev.lasting_s
        k = ev.kind
        if k == "link_cut":
            if self.relay is None:
                raise ValueError("link_cut needs the relay")
            self.relay.cut(now, clear)
        elif k == "autopilot_reboot":
            self.ap.reboot(ev.gap_s)
        elif k == "pilot_mode_change":
            self.pilot.set_mode(ev.mode)
        elif k == "pilot_disarm":
            self.pilot.disarm()
        elif k == "gcs_loss":
            self.pilot.heartbeats = False
            self._actions.append((clear, "gcs_back"))
        elif k in CAMERA_KINDS:
            self.camera.add(now, ev)
        handover = k not in CAMERA_KINDS and ev.reenable_s >= 0
        if handover:
            self._actions.append((clear + ev.reenable_s, "hand_over"))
        self.applied.append({"kind": k, "onset_s": round(now, 3), "clear_s": round(clear, 3),
                             "recover_from_s": round(clear + (ev.reenable_s if handover else 0.0), 3)})
