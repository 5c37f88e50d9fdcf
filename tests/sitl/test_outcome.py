"""The one outcome word of a simulated mission and its exit code."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from sitl.outcome import OUTCOME_EXIT_CODES, Sightings, mission_outcome

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


def _meta(**centres):
    """A frame meta whose placards (id -> camera xyz, metres) are the keywords p1, p2, ..."""
    return {"placards": {int(k[1:]): {"xyz_cam_m": list(v)} for k, v in centres.items()}}


def test_the_choice_is_the_placard_of_the_trackers_last_sighting_not_its_stale_position():
    # variant_10_01 seed 1 (issue 11 session 57): the target was last seen on placard 2; after the abort the
    # vehicle drifted while the tracker's last position stood still, and at the end that stale position lay
    # 0.48 m from placard 3 in the camera: the run chose placard 2, not 3.
    s = Sightings(np.eye(3))
    first = _meta(p2=(-0.34, 0.15, 1.43), p3=(0.6, 0.1, 2.2))
    s.frame(19.4, first)
    s.frame(19.6, _meta(p2=(-0.3, 0.15, 1.2), p3=(0.5, 0.1, 2.0)))
    seen = SimpleNamespace(stamp_s=19.4, xyz_m=np.array([-0.39, 0.0, 1.44]))
    s.note(seen, fallback_meta=None)
    assert s.seen and s.placard == 2
    s.note(seen, fallback_meta=_meta(p3=(-0.2, 0.1, 1.2)))  # the same sighting again: nothing changes
    assert s.placard == 2


def test_a_new_sighting_on_another_placard_or_on_none_is_the_new_choice():
    s = Sightings(np.eye(3))
    s.frame(1.0, _meta(p1=(0.0, 0.0, 2.0), p2=(1.0, 0.0, 2.0)))
    s.frame(2.0, _meta(p1=(0.0, 0.0, 1.5), p2=(1.0, 0.0, 1.5)))
    s.note(SimpleNamespace(stamp_s=1.0, xyz_m=np.array([0.05, 0.0, 2.0])), None)
    assert s.placard == 1
    s.note(SimpleNamespace(stamp_s=2.0, xyz_m=np.array([0.95, 0.0, 1.5])), None)  # re-acquired a neighbour
    assert s.placard == 2
    s.note(SimpleNamespace(stamp_s=2.0, xyz_m=np.array([0.5, 0.0, 1.5])), None)   # 0.5 m from both: none
    assert s.placard is None


def test_a_sighting_whose_frame_is_no_longer_kept_is_named_from_the_fallback_frame():
    s = Sightings(np.eye(3))
    for i in range(Sightings.KEEP_FRAMES + 5):
        s.frame(float(i), _meta(p1=(0.0, 0.0, 2.0)))
    s.note(SimpleNamespace(stamp_s=0.0, xyz_m=np.array([0.0, 0.0, 1.0])), _meta(p4=(0.0, 0.1, 1.0)))
    assert s.placard == 4
