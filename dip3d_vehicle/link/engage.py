"""When the controller may move the vehicle: pure gating logic, one tick at a time.

The controller is *engaged* (its commands reach the thrusters) only when every condition holds:
the autopilot is heard (any message within ``link.autopilot_timeout_s``), armed, in the configured
mode, the operator has enabled the controller, the ground station is heard (if required),
perception is fresh and the output path is usable (manual_control: SYSID_MYGCS read and different
from the controller's own system id).

Re-engage policy (the operator's enable is a latch):
- The pilot taking the vehicle back - leaving the *handover state* "armed and in the engage mode"
  by a mode change or a disarm - clears the enable, whether or not the controller was engaged at
  that moment. The vehicle does not start moving again when the mode comes back; the operator
  re-enables (MAV_CMD_USER_1 or ``VehicleLink.enable()``).
- Losing the autopilot or the ground station while the vehicle is armed also clears the enable:
  after either, the pilot must look at the situation before the controller acts again. (While
  disarmed a loss only blocks: arming and selecting the mode is the pilot's deliberate handover.)
- Stale perception and a not-yet-usable output only *hold* the controller (the enable stays): they
  are the controller's own transient conditions, and the behaviour layer decides what to do.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["EngageInputs", "EngageDecision", "blockers", "decide", "LATCHING_REASONS", "PERCEPTION_STALE",
           "PERCEPTION_STARTING", "PERCEPTION_HOLDS"]

PERCEPTION_STALE = "perception stale"
PERCEPTION_STARTING = "perception starting"
PERCEPTION_HOLDS = (PERCEPTION_STALE, PERCEPTION_STARTING)
"""The blockers that only hold the controller (the last in priority order: with one of them first, all else holds)."""


@dataclass(frozen=True)
class EngageInputs:
    """Everything the gate looks at in one tick.

    Attributes:
        autopilot_alive: a message from the configured autopilot arrived within the timeout.
        armed: the autopilot's last HEARTBEAT had MAV_MODE_FLAG_SAFETY_ARMED.
        mode: the autopilot's mode name (e.g. "ALT_HOLD"), "" when unknown.
        engage_mode: the mode the controller may act in.
        operator_enabled: the operator's enable latch.
        gcs_alive: a ground-station HEARTBEAT arrived within the timeout.
        gcs_required: whether a live ground station is needed.
        perception_fresh: perception is fresh this tick.
        output_problem: why the output path cannot be used ("" when it can).
        autopilot_steady: the autopilot has been heard without a gap for a while, i.e. its
            message stream is fast enough for the liveness timeout (a bare 1 Hz HEARTBEAT is not).
        perception_steady: perception has been fresh without a break for a while (hysteresis: a
            flickering or just-started perception holds instead of engaging and disengaging).
        gcs_quiet: the ground station's HEARTBEAT is overdue (not yet lost): hold, so that the stop
            stream ends before the loss, after which nothing may carry the GCS's system id.
    """

    autopilot_alive: bool
    armed: bool
    mode: str
    engage_mode: str
    operator_enabled: bool
    gcs_alive: bool = True
    gcs_required: bool = True
    perception_fresh: bool = True
    output_problem: str = ""
    autopilot_steady: bool = True
    gcs_quiet: bool = False
    perception_steady: bool = True

    @property
    def in_handover(self) -> bool:
        """True when the pilot has handed the vehicle over: alive, armed and in the engage mode."""
        return self.autopilot_alive and self.armed and self.mode == self.engage_mode


@dataclass(frozen=True)
class EngageDecision:
    """The gate's answer for one tick.

    Attributes:
        engaged: the controller may send motion commands.
        operator_enabled: the enable latch after this tick (cleared by latching reasons).
        reason: why not engaged ("" when engaged); the first blocker in priority order.
        latched: True when this tick cleared the operator's enable.
    """

    engaged: bool
    operator_enabled: bool
    reason: str
    latched: bool = False


LATCHING_REASONS = ("autopilot lost", "disarmed", "mode changed", "ground station lost")
"""Reasons (prefixes) that clear the operator's enable when they end an engagement or a handover."""


def blockers(inp: EngageInputs) -> list[str]:
    """Return every reason the controller may not engage now, most important first (empty = go).

    Args:
        inp: this tick's inputs.

    Returns:
        Human-readable reasons, e.g. ``["not armed", "mode is MANUAL, not ALT_HOLD"]``.
    """
    out: list[str] = []
    if not inp.autopilot_alive:
        out.append("autopilot not heard")
    else:
        if not inp.armed:
            out.append("not armed")
        if inp.mode != inp.engage_mode:
            out.append(f"mode is {inp.mode or 'unknown'}, not {inp.engage_mode}")
        if not inp.autopilot_steady:
            out.append("autopilot messages come slower than the liveness timeout (is the ATTITUDE stream running?)")
    if inp.gcs_required and not inp.gcs_alive:
        out.append("ground station not heard")
    elif inp.gcs_required and inp.gcs_quiet:
        out.append("ground station quiet")
    if not inp.operator_enabled:
        out.append("not enabled by the operator")
    if inp.output_problem:
        out.append(inp.output_problem)
    if not inp.perception_fresh:
        out.append(PERCEPTION_STALE)
    elif not inp.perception_steady:
        out.append(PERCEPTION_STARTING)
    return out


def decide(prev: EngageInputs | None, inp: EngageInputs) -> EngageDecision:
    """Gate one tick, given the previous tick's inputs (None at the first tick).

    Args:
        prev: the inputs of the previous tick, to detect the pilot leaving the handover state.
        inp: this tick's inputs.

    Returns:
        The decision; ``reason`` names a latching event ("mode changed ALT_HOLD -> MANUAL",
        "disarmed", "autopilot lost", "ground station lost") when this tick cleared the enable.
    """
    enabled = inp.operator_enabled
    latch_reason = ""
    if prev is not None and enabled:
        latch_reason = _latch_reason(prev, inp)
    if latch_reason:
        enabled = False
    gated = EngageInputs(**{**inp.__dict__, "operator_enabled": enabled})
    reasons = blockers(gated)
    if latch_reason:
        return EngageDecision(False, False, latch_reason, latched=True)
    return EngageDecision(not reasons, enabled, reasons[0] if reasons else "")


def _latch_reason(prev: EngageInputs, inp: EngageInputs) -> str:
    """Return the pilot/loss event between two ticks that clears the enable, or ""."""
    if prev.autopilot_alive and not inp.autopilot_alive and prev.armed:
        return "autopilot lost"
    if inp.gcs_required and prev.gcs_alive and not inp.gcs_alive and prev.armed:
        return "ground station lost"
    if prev.in_handover and not inp.in_handover and inp.autopilot_alive:
        if prev.armed and not inp.armed:
            return "disarmed"
        return f"mode changed {prev.mode} -> {inp.mode or 'unknown'}"
    return ""
