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


@pytest.mark.parametrize("argv, named", [(["--scenario", "no_such_scenario"], "no_such_scenario"),
                                         (["--plan", "/no/such/plan.yaml"], "/no/such/plan.yaml")])
def test_missions_names_a_bad_scenario_or_plan_before_any_run(argv, named, capsys):
    from sitl.fault_campaign import main

    with pytest.raises(SystemExit) as exc:
        main(["missions", "--seeds", "1", *argv])
    assert exc.value.code == 2
    assert named in capsys.readouterr().err


def test_mission_campaign_runs_the_given_scenario(monkeypatch):
    """Each run of the campaign gets the scenario asked for (paper_pool unless told), and the summary says which."""
    import sitl.fault_mission_campaign as fmc

    seen = []

    def fake_run(scenario, seed, plan, params, log=None, **kw):
        seen.append((scenario, seed))
        raise RuntimeError("stop here")  # reported as a crash of that run; enough to see the arguments

    monkeypatch.setattr(fmc, "run_faulted_mission", fake_run)
    out = fmc.mission_campaign(2, fmc.FAULT_DIR / "link_cut.yaml", verbose=False, first_seed=3, scenario="far_diver")
    assert seen == [("far_diver", 3), ("far_diver", 4)]
    assert out["scenario"] == "far_diver" and out["crashes"] == 2
    fmc.mission_campaign(1, fmc.FAULT_DIR / "link_cut.yaml", verbose=False)
    assert seen[-1] == ("paper_pool", 0)
