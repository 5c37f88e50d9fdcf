"""The held arm: keypoints averaged over the frames of a held point, and frames decided again with it."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from dip3d_vehicle.perception.held_arm import HeldArm, decide_held
from dip3d_vehicle.perception.values import ArmKeypoints

sys.path.insert(0, str(Path(__file__).parent))


def _arm(x0: float, side: str = "right") -> ArmKeypoints:
    left = np.array([[x0, 600.0], [x0 + 100.0, 600.0], [x0 + 190.0, 600.0]])
    return ArmKeypoints(side, left, left - [30.0, 0.0], np.full(3, 0.9), np.full(3, 0.8), "test")


def test_held_arm_is_the_mean_of_its_window():
    held = HeldArm(3)
    assert held.mean() is None
    for x0 in (500.0, 502.0, 504.0, 506.0):
        held.add(_arm(x0))
    assert len(held) == 3
    mean = held.mean()
    np.testing.assert_allclose(mean.left_px[0], [504.0, 600.0])
    np.testing.assert_allclose(mean.right_px[2], [504.0 + 190.0 - 30.0, 600.0])
    assert mean.min_confidence() == pytest.approx(0.8) and "mean of 3" in mean.source
    held.add(_arm(400.0, "left"))  # the other arm: a new point
    assert len(held) == 1


def test_a_held_arm_keeps_a_matched_disparity_only_where_every_frame_matched():
    import dataclasses

    held = HeldArm(3)
    for k, matched in enumerate(([True, True, True], [True, False, True], [True, True, True])):
        m = np.array(matched)
        sigma = np.where(m, [0.5 + k, 1.5, 0.5], np.nan)
        held.add(dataclasses.replace(_arm(500.0), disparity_sigma_px=sigma, disparity_matched=m))
    mean = held.mean()
    assert mean.disparity_matched.tolist() == [True, False, True]
    assert mean.disparity_sigma_px[0] == 2.5 and mean.disparity_sigma_px[2] == 0.5   # the largest of the window
    held.add(_arm(500.0))                                                            # given keypoints, not matched
    assert held.mean().disparity_matched is None


def test_decide_held_leaves_undecidable_frames_alone():
    from dip3d_vehicle.perception.pipeline import PerceptionResult

    class _P:
        selector = object()

    for result in (PerceptionResult("no_pose", "no person found"), PerceptionResult("pose_rejected", "dz")):
        assert decide_held(_P(), _arm(500.0), 4, result) is result


def test_held_arm_sharpens_the_open_set_decision(tmp_path):
    """Four frames' mean arm (2 px noise each) against each frame alone, on generated far scenes.

    The held arm halves the keypoint noise: over the same draws it is right at least as often,
    never confidently wrong more often, and "nothing detected" keeps less probability on the
    frames where the pointed placard wins.
    """
    import scene_families as sf
    from dip3d_vehicle.config import load_params
    from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
    from dip3d_vehicle.perception.pipeline import Perception

    single = {"correct": 0, "confident_wrong": 0, "none_p": []}
    held_out = {"correct": 0, "confident_wrong": 0, "none_p": []}
    for k, scene in enumerate(sf.scenes(tmp_path, "far", 6, 11)):
        truth = scene.frame.meta["keypoints_truth"]
        rig = scene.scenario.rig()
        left, right = rig.rectify(scene.frame.left, scene.frame.right)
        pose = GivenKeypoints("right", truth)
        perception = Perception(rig, load_params("default"), pose)
        base = perception.detector.detect(left, right, pose.estimate(left, right, rig), rig)
        rng = np.random.default_rng(100 + k)
        for _ in range(4):
            held = HeldArm(4)
            results = []
            for _ in range(4):
                pose.provide(sf.noisy(truth, 2.0, rng))
                checked = perception.check_arm(pose.estimate(left, right, rig))
                if checked.status == "ok":
                    held.add(checked.arm)
                    results.append(perception.decide(checked, perception.add_corridor(left, right, checked.arm, base)))
            if len(held) < 2:
                continue
            last = results[-1]
            again = decide_held(perception, held.mean(), len(held), last)
            for tally, res in ((single, last), (held_out, again)):
                what = sf.outcome(scene, res, rig)
                tally[what] = tally.get(what, 0) + 1
                if what == "correct" and res.selection is not None:
                    tally["none_p"].append(res.selection.none_probability)
    assert single["correct"] + single.get("abstained", 0) > 0
    assert held_out["correct"] >= single["correct"]
    assert held_out["confident_wrong"] <= single["confident_wrong"]
    assert np.mean(held_out["none_p"]) < np.mean(single["none_p"])


def test_the_pose_models_own_landmark_error_is_kept_not_averaged_by_the_held_arm():
    """Every frame of a held pose repeats the model's landmark error: the mean arm carries it unchanged."""
    import dataclasses

    held = HeldArm(4)
    for k in range(4):
        held.add(dataclasses.replace(_arm(100.0 + k), keypoint_sigma_m=0.05))
    assert held.mean().keypoint_sigma_m == 0.05


def test_a_frame_that_missed_an_object_scores_it_again_with_its_features_recalled(tmp_path):
    """On generated far scenes: drop the chosen object's features from a frame (a detection miss), then
    recall them. The frame without them cannot name the object; with them recalled it gives the object
    the probability the full frame gave it, and says how many features it recalled."""
    import scene_families as sf
    from dip3d_vehicle.config import load_params
    from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
    from dip3d_vehicle.perception.pipeline import Perception

    checked_scenes = 0
    for scene in sf.scenes(tmp_path, "far", 6, 11):
        truth = scene.frame.meta["keypoints_truth"]
        rig = scene.scenario.rig()
        left, right = rig.rectify(scene.frame.left, scene.frame.right)
        pose = GivenKeypoints("right", truth)
        perception = Perception(rig, load_params("default"), pose)
        checked = perception.check_arm(pose.estimate(left, right, rig))
        if checked.status != "ok":
            continue
        cands = perception.add_corridor(left, right, checked.arm,
                                        perception.detector.detect(left, right, checked.arm, rig))
        full = perception.decide(checked, cands)
        if full.status != "ok" or full.selection.target is None:
            continue
        target = full.selection.target
        members = np.asarray(target.members, int)
        keep = np.ones(len(full.candidates), bool)
        keep[members] = False
        missed = perception.decide(checked, full.candidates.subset(keep))
        objs = missed.selection.objects if missed.selection is not None else ()
        assert all(np.linalg.norm(o.xyz_m - target.xyz_m) > 0.05 for o in objs)
        again = decide_held(perception, checked.arm, 1, missed, full.candidates.subset(members))
        assert again.recalled == len(members)
        near = [(o, p) for o, p in zip(again.selection.objects, again.selection.scores)
                if np.linalg.norm(o.xyz_m - target.xyz_m) < 0.05]
        assert len(near) == 1 and min(near[0][0].members) >= len(again.candidates) - again.recalled
        assert near[0][1] == pytest.approx(full.selection.confidence, abs=0.02)
        checked_scenes += 1
    assert checked_scenes >= 3
