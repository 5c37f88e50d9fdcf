"""Issue 11 session 39: an object a frame of the held point missed is recalled and scored with that frame's arm."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from behaviours.fusion import PointFusion
from dip3d_vehicle.perception.values import Candidates, ObjectCandidate
from mission_driver import engaged_mission, enter
from sitl.scenario import load_scenario
from test_point_decision import _feed, _frame


@pytest.fixture(scope="module")
def rig():
    return load_scenario("paper_pool", 0).rig()


def _recalled(result, objects: dict, none_p: float):
    """``result`` with its candidates followed by 3 recalled ones and one object of them alone per x (metres)."""
    sel = result.selection
    n = len(result.candidates)
    extra = Candidates(np.ones((3, 2)), np.ones((3, 2)), np.zeros((3, 128), np.float32), np.zeros(3))
    objs = list(sel.objects)
    scores = list(sel.scores)
    for x, p in objects.items():
        objs.append(ObjectCandidate(np.array([800.0 + 100 * x, 600.0]), np.array([x, 0.0, 3.0]), 0.02,
                                    (n, n + 1, n + 2)))
        scores.append(p)
    sel = dataclasses.replace(sel, objects=tuple(objs), scores=np.array(scores), none_probability=none_p)
    return dataclasses.replace(result, candidates=result.candidates.stacked(extra),
                               candidates_xyz_m=np.vstack([result.candidates_xyz_m, np.full((3, 3), 3.0)]),
                               selection=sel, recalled=3)


def test_a_hypothesis_the_frame_missed_is_recalled_while_its_sighting_is_recent():
    f = PointFusion(0.3, recall_s=4.0)
    f.add(_frame({1.0: 0.5, 2.0: 0.3}, 0.2), 0.0)
    missed = _frame({1.0: 0.7}, 0.3)                       # placard 2 not detected in this frame
    got = f.recall(missed, 0.2)
    assert got is not None and len(got) == 3                # o2's sighting: its 3 features
    assert f.recall(_frame({1.0: 0.5, 2.0: 0.3}, 0.2), 0.2) is None   # seen: nothing to recall
    assert f.recall(missed, 5.0) is None                    # the sighting is too old
    off = PointFusion(0.3)
    off.add(_frame({1.0: 0.5, 2.0: 0.3}, 0.2), 0.0)
    assert off.recall(missed, 0.2) is None                  # off


def test_a_recalled_object_counts_its_probability_but_is_not_a_sighting():
    f = PointFusion(0.3, floor_p=0.02, recall_s=4.0)
    f.add(_frame({1.0: 0.5, 2.0: 0.3}, 0.2), 0.0)
    o2 = f.hypothesis("o2")
    pool, stamp = len(o2.pool), o2.stamp_s
    part = f.add(_recalled(_frame({1.0: 0.4}, 0.2), {2.0: 0.4}, 0.2), 0.2)
    assert part.probabilities["o2"] == pytest.approx(0.4)   # scored with the frame's arm, not the floor 0.02
    assert len(o2.pool) == pool and o2.stamp_s == stamp     # the tracker's sighting stays the one seen
    assert len(f.hypotheses) == 2


def test_without_recall_a_missed_frame_votes_against_the_object_with_it_the_point_stays_undecided():
    """Frames that miss placard 2 (3 of 4) gave it the floor: the steadily seen neighbour won. With
    its probability from each frame's arm, the two stay apart by what the arm says, not by the detector."""
    def run(recall: bool) -> dict:
        f = PointFusion(0.3, floor_p=0.02, recall_s=4.0 if recall else 0.0)
        for k in range(8):
            if k % 4 == 0:
                f.add(_frame({1.0: 0.45, 2.0: 0.4}, 0.15), 0.2 * k)
            else:
                missed = _frame({2.0: 0.75}, 0.25)
                if f.recall(missed, 0.2 * k) is not None:
                    missed = _recalled(_frame({2.0: 0.4}, 0.15), {1.0: 0.45}, 0.15)
                f.add(missed, 0.2 * k)
        return f.decide(0.9, 3)

    before, after = run(False), run(True)
    assert before.kind == "object" and before.winner.key == "o2"
    assert after.kind == "undecided" and after.posterior["o1"] > 0.25


def test_an_object_first_seen_late_starts_from_nothing_detecteds_frames_not_the_floor():
    """``near_miss`` seed 3's shape: for 20 frames the arm leans half to a decoy, half to "nothing
    detected"; then the small pointed placard is found and takes half of each frame. Counted from the
    floor it could never win, and recalled it took "none"'s share: the decoy won. From "none"'s frames
    (it was one of the undetected objects they stood for) the point stays undecided."""
    def run(recall_s: float):
        f = PointFusion(0.3, floor_p=0.02, recall_s=recall_s)
        for k in range(20):
            f.add(_frame({1.0: 0.52}, 0.48), 0.2 * k)
        for k in range(20, 30):
            f.add(_frame({1.0: 0.45, (0.5, 0.0, 1.5): 0.47}, 0.08), 0.2 * k)
        return f

    late = run(4.0)
    assert late.hypothesis("o2").log_sum > run(0.0).hypothesis("o2").log_sum
    d = late.decide(0.9, 3)
    assert d.kind == "undecided" and d.posterior["o2"] > 0.25


def test_the_mission_passes_the_missed_objects_features_to_decide_held(rig):
    for recall_s, expect in ((4.0, [None, 3]), (0.0, [None, None])):
        m = engaged_mission(rig, **{"behaviour.vote_frames": 4, "behaviour.min_votes": 3,
                                    "behaviour.fusion_arm_frames": 3, "behaviour.fusion_recall_s": recall_s})
        got = []

        def held(arm, frames, result, recalled=None):
            got.append(None if recalled is None else len(recalled))
            return result

        m.bb.decide_held = held
        enter(m, "select_target")
        _feed(m, [_frame({1.0: 0.5, 2.0: 0.3}, 0.2), _frame({1.0: 0.7}, 0.3)])
        assert got == expect
