"""Engage gating: every condition, and the enable latch (no automatic re-engage after the pilot acts)."""

from __future__ import annotations

from dataclasses import replace

import pytest

from dip3d_vehicle.link.engage import EngageInputs, blockers, decide

GO = EngageInputs(autopilot_alive=True, armed=True, mode="ALT_HOLD", engage_mode="ALT_HOLD",
                  operator_enabled=True, gcs_alive=True, gcs_required=True, perception_fresh=True)


def test_all_conditions_met_engages() -> None:
    assert blockers(GO) == []
    d = decide(GO, GO)
    assert d.engaged and d.operator_enabled and d.reason == ""


@pytest.mark.parametrize("change, reason", [
    ({"autopilot_alive": False}, "autopilot not heard"),
    ({"armed": False}, "not armed"),
    ({"mode": "MANUAL"}, "mode is MANUAL, not ALT_HOLD"),
    ({"operator_enabled": False}, "not enabled by the operator"),
    ({"gcs_alive": False}, "ground station not heard"),
    ({"perception_fresh": False}, "perception stale"),
    ({"output_problem": "SYSID_MYGCS not read yet"}, "SYSID_MYGCS not read yet"),
])
def test_each_condition_blocks(change: dict, reason: str) -> None:
    inp = replace(GO, **change)
    assert reason in blockers(inp)
    assert not decide(None, inp).engaged


def test_gcs_not_needed_when_not_required() -> None:
    assert decide(None, replace(GO, gcs_alive=False, gcs_required=False)).engaged


@pytest.mark.parametrize("change, reason", [
    ({"mode": "MANUAL"}, "mode changed ALT_HOLD -> MANUAL"),
    ({"armed": False}, "disarmed"),
    ({"autopilot_alive": False}, "autopilot lost"),
    ({"gcs_alive": False}, "ground station lost"),
])
def test_pilot_action_or_loss_clears_enable_and_mode_return_does_not_reengage(change: dict, reason: str) -> None:
    after = replace(GO, **change)
    d = decide(GO, after)
    assert not d.engaged and d.latched and not d.operator_enabled and d.reason == reason
    # everything comes back, but the operator has not re-enabled
    back = replace(GO, operator_enabled=d.operator_enabled)
    d2 = decide(replace(after, operator_enabled=False), back)
    assert not d2.engaged and d2.reason == "not enabled by the operator"
    assert decide(back, replace(back, operator_enabled=True)).engaged


def test_stale_perception_holds_but_keeps_enable() -> None:
    stale = replace(GO, perception_fresh=False)
    d = decide(GO, stale)
    assert not d.engaged and d.operator_enabled and not d.latched
    assert decide(stale, GO).engaged


def test_mode_change_while_not_engaged_also_clears_enable() -> None:
    stale = replace(GO, perception_fresh=False)
    d = decide(stale, replace(stale, mode="STABILIZE"))
    assert d.latched and not d.operator_enabled


def test_enable_before_handover_survives_arming() -> None:
    idle = replace(GO, armed=False, mode="MANUAL")
    armed = replace(idle, armed=True)
    ready = replace(armed, mode="ALT_HOLD")
    assert decide(idle, armed).operator_enabled
    assert decide(armed, ready).engaged


def test_loss_while_disarmed_blocks_without_clearing_enable() -> None:
    idle = replace(GO, armed=False, mode="MANUAL")
    d = decide(idle, replace(idle, autopilot_alive=False, gcs_alive=False))
    assert not d.engaged and d.operator_enabled


def test_unsteady_autopilot_blocks() -> None:
    d = decide(GO, replace(GO, autopilot_steady=False))
    assert not d.engaged and "slower than the liveness timeout" in d.reason and d.operator_enabled
