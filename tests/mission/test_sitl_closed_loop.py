"""The closed loop: router + simulated pilot hand over; one paper_pool mission; one safety trial.

The full campaigns (10 + 10 seeds, >= 20 trials per safety figure) are ``python -m sitl.campaign``.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from dip3d_vehicle.clock import SimClock
from dip3d_vehicle.config import load_params
from dip3d_vehicle.link import VehicleLink
from sitl.autopilot import Autopilot
from sitl.simulation import Fault, Router, SimPilot, run_mission


def test_router_and_pilot_hand_the_vehicle_over_to_the_controller():
    clock = SimClock()
    params = load_params()
    with Autopilot(params, clock, listen=["tcp:127.0.0.1:0"]) as ap:
        router = Router(ap.addresses[0])
        link = VehicleLink(params.with_overrides({"link.url": router.address}), clock)
        link.open()
        pilot = SimPilot(router.address, clock, "ALT_HOLD", arm_at_s=0.2)
        try:
            for _ in range(200):
                clock.advance(0.02)
                ap.step()
                router.step()
                pilot.step()
                link.poll()
                link.tick(None, perception_fresh=True, perception_stamp_s=clock.now())
                router.step()
            assert ap.armed and ap.mode_name == "ALT_HOLD"
            assert link.gcs.last_heartbeat_s is not None  # the GCS heartbeat reached the controller
            assert link.operator_enabled and link.engaged and pilot.enable_acked
            router.mute_autopilot = True
            t0 = clock.now()
            while clock.now() - t0 < 1.0:
                clock.advance(0.02)
                ap.step()
                router.step()
                link.poll()
                link.tick(None, perception_fresh=True, perception_stamp_s=clock.now())
            assert not link.engaged and "autopilot" in link.disengage_reason
        finally:
            link.close()
            pilot.close()
            router.close()


def test_sitl_command_rejects_a_bad_scenario_in_one_line(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "dip3d_vehicle.cli", "sitl", "--scenario", str(tmp_path / "nope.yaml"),
                           "--out", str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0 and "nope.yaml" in proc.stderr


@pytest.mark.slow
def test_paper_pool_mission_reaches_the_pointed_placard():
    result, _ = run_mission("paper_pool", 2)  # diver at position 3 points at placard 1
    assert result.arrived and result.reached, result.story
    assert result.chosen_id == result.target_id == 1
    names = [s["state"] for s in result.states]
    for state in ("wait_for_diver", "confirm_point", "select_target", "acknowledge", "servo", "arrive", "done"):
        assert state in names
    assert abs(result.range_error_at_arrival_m) <= 0.10
    sources = result.to_json()["pose_source"]  # frames per pose source, as sitl --json reports them
    frames = result.counters["frames"]  # the pose runs on tracked frames too (the stop gesture is watched)
    assert sum(sources.values()) == frames["full"] + frames.get("track", 0) > 0
    decided = result.to_json()["decisions"]  # the decision it acted on: fused, and its frames counted as one look
    assert [d["kind"] for d in decided] == ["object"] and decided[0]["frames"] >= 3
    assert 0.5 <= decided[0]["one_look"] <= decided[0]["posterior"] <= 1.0
    looked = decided[0]["one_look_posterior"]  # the rest of the doubt: the best other object, "nothing detected"
    assert looked[next(iter(looked))] == decided[0]["one_look"] and "none" in looked and sum(looked.values()) <= 1.0 + 1e-3
    doc = result.to_json()  # how near the vehicle's centre came to each placard (sitl/clearance.py), metres
    assert set(doc["closest_m"]) == {"1", "2", "3"} and doc["closest_m"]["1"] == pytest.approx(1.0 + 0.25, abs=0.3)
    assert doc["closest_other_m"] == min(doc["closest_m"][k] for k in ("2", "3"))
    assert doc["closest_diver_m"] > 1.0  # the diver stands ~3 m away, beyond placard 1 (1 m): never neared


@pytest.mark.slow
def test_motion_commands_stop_within_1s_of_the_autopilot_going_silent():
    fault = Fault("autopilot_silent", after_s=0.6, state="acknowledge", run_after_s=2.0)
    result, sim = run_mission("paper_pool", 2, fault=fault, **{"sitl.camera_rate_hz": 10 / 3,
                                                                "sitl.perception_latency_s": 0.1})
    s = result.safety
    assert s["fault_at_s"] is not None
    assert s["last_motion_after_fault_s"] <= 1.0
    assert not any(r.motion for r in sim.received if r.t_s > s["fault_at_s"] + 1.0)


@pytest.mark.slow
def test_a_mission_with_no_clear_way_holds_short_and_is_judged_against_the_stand_off_it_held(tmp_path, capsys):
    """``distractor_behind`` seed 0: the pointed placard lies about a metre beyond the diver's hand, with another
    placard beside the way; no way to the 1 m stand-off keeps 0.6 m (``behaviour.servo_clearance_m``) from both, so
    the vehicle holds short, arrives there, keeps clear of the diver and the other placards, and says so."""
    from dip3d_vehicle.commands.sitl import print_outcome

    result, _ = run_mission("distractor_behind", 0)
    assert result.reached and result.chosen_id == result.target_id, result.story
    assert result.held_short_m >= 0.3
    assert result.range_at_arrival_m == pytest.approx(1.0 + result.held_short_m, abs=0.1)
    assert result.closest_diver_m > 0.45 and result.to_json()["closest_other_m"] >= 0.29  # direct way: 0.59, 0.26
    assert any("holding short" in line for line in result.story)
    print_outcome(result, tmp_path, plots=False)
    assert "held short by" in capsys.readouterr().out
