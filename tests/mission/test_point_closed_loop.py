"""Issue 12 in the closed loop: "nothing there" answered with the shake; the stop gesture holds the vehicle.

The campaigns (10 seeds, 20 stop trials) are ``python -m sitl.point_campaign``.
"""

from __future__ import annotations

import pytest

from sitl.point_campaign import nothing_trial, stop_trial


@pytest.mark.slow
def test_nothing_there_shakes_and_never_moves_toward_a_placard():
    """The diver keeps pointing after the shake: with ``behaviour.nothing_there_relook_s`` one fresh look, which
    finds nothing there either; no motion at any time."""
    row = nothing_trial(("nothing_there", 0, {"sitl.max_sim_time_s": 15.0, "behaviour.nothing_there_relook_s": 3.0}))
    assert row["nothing_there"] and row["shake"], row
    assert row["translation_commands"] == 0 and row["max_displacement_m"] < 0.05 and row["chosen_id"] is None
    assert not row["arrived"] and "acknowledge" not in row["states"]
    after = row["states"][row["states"].index("nothing_there") + 1:]
    assert after[:3] == ["confirm_point", "select_target", "nothing_there"], row["states"]


@pytest.mark.slow
def test_the_stop_gesture_holds_the_vehicle_within_half_a_second():
    row = stop_trial(("paper_pool", 4, {}))  # trial 4: the gesture at 3.84 s, during the acknowledgement
    assert row["visible_from_s"] is not None and row["stopped_at_s"] is not None, row
    assert row["last_motion_after_due_s"] <= 0.5 and row["motion_after_stopped"] == 0
    assert row["neutral_after_due"] and row["states"][-1] == "stopped"


@pytest.mark.slow
def test_a_diver_at_3_4_m_leaning_weakly_is_closed_in_on_before_the_vehicle_decides(tmp_path):
    """variant_9_19 (issue 11 session 26): the diver at 3.4 m, the arm's tilt deciding between two placards.

    With ``behaviour.decide_max_range_m`` 3.5 m and no close-in for a weak decision, seed 0 gave up undecided
    and seed 2 first drove toward placard 2 (one look 0.504) before it came back to the pointed placard 3.

    Seed 2 runs with the corridor's zoom off (``corridor.zoom_boxes`` 0, the default until session 38). With the
    zoom its weak lean comes at 6.6 s (one look 0.53), when a close-in could advance 0.6 m only (32 % less arm
    depth error: not worth it); the second look's view leans to placard 2, so the views disagree and the mission
    abstains, never moving toward either (docs/issue11/session38). Seed 0 runs with the defaults.
    """
    from sitl.point_campaign import mission_trial
    from sitl.variants import write_variants
    path = write_variants(tmp_path, 20, 9, ["clear", "murky"], 15.0)[19]
    for seed, over in ((0, {}), (2, {"corridor.zoom_boxes": 0})):
        row = mission_trial((str(path), seed, over))
        assert row["outcome"] == "arrived" and row["chosen_id"] == row["target_id"] == 3, row
        assert "close_in" in row["states"] and len(row["decisions"]) == 1, row
        assert row["states"].index("close_in") < row["states"].index("acknowledge"), row
