"""The one outcome word of a simulated mission and its exit code."""

from __future__ import annotations

import pytest

from sitl.outcome import OUTCOME_EXIT_CODES, mission_outcome

DONE = ["idle", "wait_for_diver", "confirm_point", "select_target", "acknowledge", "servo", "arrive", "done"]


def _outcome(**kw):
    base = dict(arrived=True, chosen_id=2, target_id=2, range_error_at_arrival_m=-0.03, tolerance_m=0.1,
                states=DONE, sim_time_s=40.0)
    base.update(kw)
    return mission_outcome(**base)


def test_reached_only_at_the_pointed_object_within_tolerance():
    o = _outcome()
    assert o.word == "reached" and o.exit_code == 0 and "placard 2" in o.reason


def test_far_diver_seed_0_case_is_wrong_object_even_within_the_range_tolerance():
    o = _outcome(chosen_id=1, range_error_at_arrival_m=-0.03)
    assert o.word == "wrong_object" and o.exit_code == 3
    assert "placard 1" in o.reason and "pointed at placard 2" in o.reason


@pytest.mark.parametrize("kw, word", [
    (dict(range_error_at_arrival_m=0.25), "outside_tolerance"),
    (dict(arrived=False, states=DONE[:6]), "not_arrived"),
    (dict(arrived=False, chosen_id=None, states=DONE[:4]), "no_decision"),
    (dict(arrived=False, chosen_id=None, states=DONE[:6] + ["abort", "wait_for_diver"]), "aborted"),
    (dict(arrived=False, states=DONE[:6] + ["suspended"]), "suspended"),
    (dict(arrived=False, chosen_id=3, states=DONE[:6]), "wrong_object"),
    (dict(chosen_id=None), "wrong_object"),
])
def test_every_other_ending_has_its_word_and_a_nonzero_code(kw, word):
    o = _outcome(**kw)
    assert o.word == word and o.exit_code == OUTCOME_EXIT_CODES[word] != 0 and o.reason


def test_exit_codes_are_distinct_and_avoid_1_and_2():
    codes = [c for w, c in OUTCOME_EXIT_CODES.items() if w != "reached"]
    assert len(set(codes)) == len(codes) and not {1, 2} & set(codes)
