"""The fault campaign's fast tier (one seeded trial per fault) and one whole mission under a fault plan."""

from __future__ import annotations

import pytest

from sitl.fault_campaign import BOUNDS_S, run_trial

QUICK = ["link_cut", "autopilot_reboot", "pilot_disarm", "camera_one_eye"]


def _check(r):
    assert not r.crashed, r.crashed
    assert r.log_written == r.log_read > 0
    if r.bound_s is not None:
        assert r.events, "the fault never fired"
        assert r.within_bound, (r.last_motion_sent_s, r.last_motion_received_s, r.bound_s)
        assert r.recovered, "did not move again after the fault cleared"


@pytest.mark.parametrize("fault", QUICK)
def test_fault_trial(fault):
    _check(run_trial(fault, 1))


@pytest.mark.slow
@pytest.mark.parametrize("fault", [f for f in BOUNDS_S if f not in QUICK])
def test_fault_trial_slow(fault):
    _check(run_trial(fault, 2))


@pytest.mark.slow
def test_whole_mission_with_a_missing_eye_holds_then_continues():
    """A whole mission: the right eye goes missing for 2 s at t = 12 s; nothing 3D is decided from
    those frames, no motion is commanded 0.6 s after the onset until they are back, and the mission goes on."""
    from sitl.fault_campaign import run_faulted_mission
    from sitl.faults import parse_fault_plan

    plan = parse_fault_plan({"events": [{"kind": "camera_one_eye", "at_s": 12.0, "duration_s": 2.0}]}, "test")
    result, sim = run_faulted_mission("paper_pool", 1, plan, **{"sitl.max_sim_time_s": 20.0})
    assert sim.guard.rejected.get("right eye missing", 0) >= 5
    late = [r for r in sim.received if 12.0 + 0.6 < r.t_s < 14.0 and r.motion]
    assert late == []
    assert any(r.motion for r in sim.received if r.t_s > 14.0) or result.arrived
