"""The simulated mission's pose source: BlazePose on the rendered body, or truth + noise."""

from __future__ import annotations

import numpy as np
import pytest

from dip3d_vehicle.config import load_params
from sitl.pose_source import SimPose, pose_backend_for
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params


def _frame(seed: int = 0, t: float = 3.0, scenario: str = "paper_pool"):
    sc = load_scenario(scenario, seed)
    with StereoRenderer(sc) as r:
        return sc, r.render(*sc.initial_vehicle_pose, t)


def test_pose_source_selects_the_backend():
    sc = load_scenario("paper_pool", 0)
    assert sim_params(load_params(), sc)["pose.backend"] == "keypoints"
    params = sim_params(load_params(overrides={"sitl.pose_source": "blazepose"}), sc)
    assert params["pose.backend"] == "blazepose"
    assert sim_params(load_params(), sc, **{"sitl.pose_source": "blazepose"})["pose.backend"] == "blazepose"
    with pytest.raises(ValueError, match="sitl.pose_source 'x'"):
        pose_backend_for("x")


def test_blazepose_in_the_simulator_reads_the_raised_arm_unless_the_user_chose_one():
    """The simulated diver points with either hand and is often seen from behind (BlazePose then swaps
    left and right): ``pose.arm`` becomes ``auto`` where the user left the default, and only with BlazePose."""
    sc = load_scenario("far_placards", 0)
    assert sim_params(load_params(), sc)["pose.arm"] == "right"
    assert sim_params(load_params(), sc, **{"sitl.pose_source": "blazepose"})["pose.arm"] == "auto"
    chosen = load_params(overrides={"sitl.pose_source": "blazepose", "pose.arm": "right"})
    assert sim_params(chosen, sc)["pose.arm"] == "right"


def test_truth_source_gives_the_frames_keypoints_and_counts():
    sc, frame = _frame()
    rig = sc.rig()
    pose = SimPose(sim_params(load_params(), sc))
    left, right = rig.rectify(frame.left, frame.right)
    pose.provide(frame.meta["keypoints"])
    arm = pose.estimate(left, right, rig)
    assert arm is not None and arm.source != "blazepose"
    pose.provide(None)
    assert pose.estimate(left, right, rig) is None
    assert pose.counts == {"blazepose": 0, "blazepose (low confidence)": 0, "truth": 1, "none": 1}


def test_blazepose_source_finds_the_rendered_divers_arm_near_the_truth():
    """The onboard backend on the rendered body: the pointing arm, confident, within 40 px of the joints."""
    sc, frame = _frame(seed=0, t=3.0)
    rig = sc.rig()
    pose = SimPose(sim_params(load_params(overrides={"sitl.pose_source": "blazepose"}), sc))
    left, right = rig.rectify(frame.left, frame.right)
    pose.provide(None)  # never used with blazepose
    arm = pose.estimate(left, right, rig)
    assert arm is not None and arm.source == "blazepose"
    assert pose.counts["blazepose"] == 1 and pose.counts["truth"] == 0
    truth = frame.meta["keypoints_truth"]
    for side, rect in (("left", arm.left_px), ("right", arm.right_px)):
        orig = rig.to_original(np.asarray(rect), side)
        t = np.array([truth[side][j] for j in ("shoulder", "elbow", "wrist")])
        err = np.linalg.norm(orig - t, axis=1)
        assert err.max() < 40, f"{side}: {err}"


def test_blazepose_stereo_joints_give_the_arms_depth_with_a_sigma():
    """``joint_disparity: stereo`` on the rendered body: each joint's disparity within its reported
    sigma (3 sigma, at least the floor) of the truth's, the shoulder from the torso, the right rows = the left."""
    sc, frame = _frame(seed=2, t=1.4)
    rig = sc.rig()
    params = sim_params(load_params(overrides={"sitl.pose_source": "blazepose",
                                               "blazepose.joint_disparity": "stereo"}), sc)
    pose = SimPose(params)
    left, right = rig.rectify(frame.left, frame.right)
    arm = pose.estimate(left, right, rig)
    assert arm is not None and arm.disparity_sigma_px is not None
    assert np.all(arm.disparity_sigma_px >= params["blazepose.disparity_floor_px"])
    assert np.allclose(arm.right_px[:, 1], arm.left_px[:, 1])
    truth = frame.meta["keypoints_truth"]
    t = {side: rig.to_rectified(np.array([truth[side][j] for j in ("shoulder", "elbow", "wrist")]), side)
         for side in ("left", "right")}
    err = (arm.left_px[:, 0] - arm.right_px[:, 0]) - (t["left"][:, 0] - t["right"][:, 0])
    assert np.all(np.abs(err) <= 3.0 * arm.disparity_sigma_px), (err, arm.disparity_sigma_px)
    assert abs(err[0]) < 2.0, "the shoulder from the torso, not the neck behind it"


@pytest.mark.parametrize("arm, found", [("auto", "left"), ("left", "left"), ("right", "right")])
def test_blazepose_reads_the_left_arm_pointer_with_auto(arm, found):
    """left_arm: the diver points with the LEFT arm. auto finds it as configuring "left" does; "right" reads the
    arm that hangs behind the body (BlazePose barely sees it: low confidence, far from the pointing joints)."""
    sc, frame = _frame(seed=0, t=3.0, scenario="left_arm")
    rig = sc.rig()
    pose = SimPose(sim_params(load_params(overrides={"sitl.pose_source": "blazepose", "pose.arm": arm}), sc))
    left, right = rig.rectify(frame.left, frame.right)
    got = pose.estimate(left, right, rig)
    assert got is not None and got.arm == found
    truth = np.array([frame.meta["keypoints_truth"]["left"][j] for j in ("shoulder", "elbow", "wrist")])
    err = np.linalg.norm(rig.to_original(np.asarray(got.left_px), "left") - truth, axis=1)
    if found == "left":
        assert pose.counts["blazepose"] == 1 and err.max() < 40, err
    else:
        assert pose.counts["blazepose (low confidence)"] == 1 and err.max() > 40, err


def test_blazepose_finds_the_diver_in_murky_water_in_a_square_tile_of_the_frame():
    """Murky green water: the whole letterboxed frame, stretched or not, scores the diver under the
    detector's bar; the last retry (square tiles of the frame's height, each stretched) finds the body,
    and the arm read from it lies on the pointing arm."""
    sc, frame = _frame(seed=0, t=3.0, scenario="murky")
    rig = sc.rig()
    params = sim_params(load_params(overrides={"sitl.pose_source": "blazepose"}), sc)
    left, right = rig.rectify(frame.left, frame.right)
    pose = SimPose(params)
    detector = pose.backend.pose
    assert detector.detect(left) is None and detector.detect(left, contrast=True) is None
    found = detector.detect_in_squares(left)
    assert found is not None and found.score >= detector.min_detection_score
    arm = pose.estimate(left, right, rig)
    assert arm is not None and arm.min_confidence() >= params["pose.min_confidence"]
    truth = frame.meta["keypoints_truth"]["left"]
    err = np.linalg.norm(rig.to_original(np.asarray(arm.left_px), "left")
                         - np.array([truth[j] for j in ("shoulder", "elbow", "wrist")]), axis=1)
    assert err.max() < 40, err


@pytest.mark.parametrize("scenario", ["paper_pool", "murky"])
def test_blazepose_on_the_rendered_body_shows_the_stop_gesture_and_a_pointing_arm_does_not(tmp_path, scenario):
    """The onboard backend on the rendered diver's stop gesture (issue 14 session 72): both wrists above the head
    by the mission's margins (``behaviour.stop_gesture_margin_px`` / ``_m``) in most frames, in clear and murky
    water (BlazePose calls the other wrist hidden behind the raised hand: ``EXTRA_MIN_VISIBILITY``); the same diver
    pointing gives no stop frame."""
    from behaviours.gesture import stop_gesture_seen

    defaults = load_params()
    margins = (defaults["behaviour.stop_gesture_margin_px"], defaults["behaviour.stop_gesture_margin_m"])
    path = tmp_path / "stop.yaml"
    path.write_text(f"base: {scenario}\ndiver:\n  stop_gesture_at_s: 3.0\n")
    seen = {}
    for what, t0 in (("stop", 4.0), ("point", 2.0)):
        sc = load_scenario(str(path), 0)
        rig = sc.rig()
        pose = SimPose(sim_params(load_params(overrides={"sitl.pose_source": "blazepose"}), sc))
        pose.provide(None)
        with StereoRenderer(sc) as r:
            frames = [r.render(*sc.initial_vehicle_pose, t0 + 0.25 * k) for k in range(4)]
        seen[what] = sum(stop_gesture_seen(pose.estimate(*rig.rectify(f.left, f.right), rig), *margins,
                                           abs(rig.baseline_m)) for f in frames)
    assert seen["stop"] >= 3 and seen["point"] == 0, seen


def _arm_errors_px(scenario: str, seed: int, crop_stretch: bool, frames: int = 4) -> np.ndarray:
    """Return BlazePose's left-image shoulder, elbow, wrist errors against the body's joints, (frames, 3) pixels."""
    sc = load_scenario(scenario, seed)
    rig = sc.rig()
    pose = SimPose(sim_params(load_params(overrides={"sitl.pose_source": "blazepose",
                                                     "blazepose.crop_stretch": crop_stretch}), sc))
    pose.provide(None)
    errs = []
    with StereoRenderer(sc) as r:
        for k in range(frames):
            frame = r.render(*sc.initial_vehicle_pose, sc.diver.start_s + 0.4 * k)
            arm = pose.estimate(*rig.rectify(frame.left, frame.right), rig)
            truth = np.array([frame.meta["keypoints_truth"]["left"][j] for j in ("shoulder", "elbow", "wrist")])
            errs.append(np.linalg.norm(rig.to_original(np.asarray(arm.left_px), "left") - truth, axis=1))
    return np.array(errs)


@pytest.mark.parametrize("seed", [0, 1])
def test_the_landmark_crop_stretched_to_its_own_levels_puts_the_elbow_and_wrist_nearer_the_joints(seed):
    """Clear pool water takes most of the red out of the rendered diver (the crop's red channel spans 45-122 of
    255): stretched per channel to its own 1-99 % levels (``blazepose.crop_stretch``) the landmark model puts the
    pointing elbow and wrist nearer the body's joints than on the crop as it is (issue 14 session 73: paper_pool
    seeds 0-9, 8 frames each, elbow / wrist median 19.5 / 14.0 -> 9.4 / 9.8 px)."""
    raw = np.median(_arm_errors_px("paper_pool", seed, False), axis=0)
    stretched = np.median(_arm_errors_px("paper_pool", seed, True), axis=0)
    assert stretched[1] < 0.8 * raw[1] and stretched[2] < 0.8 * raw[2], (raw, stretched)


def test_the_crop_stretch_leaves_a_pose_found_with_the_detectors_stretch_as_it_was():
    """Murky water: the detector needs its contrast-stretched retry, whose levels the landmark crops use; the crop
    stretch only acts where no stretch is in use, so the arm is the same with it on or off."""
    assert np.array_equal(_arm_errors_px("murky", 0, False, 2), _arm_errors_px("murky", 0, True, 2))


_PROFILE_IN_MURKY_WATER = """base: murky
placards:
  - {id: 1, range_m: 2.21, bearing_deg: -16.3, depth_m: 0.70, size_m: 0.31}
  - {id: 2, range_m: 2.94, bearing_deg: -22.8, depth_m: 1.35, size_m: 0.26}
  - {id: 3, range_m: 1.47, bearing_deg: -7.7, depth_m: 1.28, size_m: 0.31}
diver:
  positions:
    - {name: "v", range_m: 3.40, bearing_deg: 18.0, depth_m: 1.0}
  arm: left
  target: random
"""
"""variant_44_17 (sitl.variants, seed 44): a grey diver in profile 3.4 m away in green murky water."""


def _left_frame(tmp_path, text: str, t_s: float):
    """Return (scenario, rectified left image, the pointing arm's true rectified left pixels (3, 2)) of a scenario
    text's frame at ``t_s`` seconds."""
    path = tmp_path / "layout.yaml"
    path.write_text(text)
    sc = load_scenario(str(path), 0)
    rig = sc.rig()
    with StereoRenderer(sc) as r:
        frame = r.render(*sc.initial_vehicle_pose, t_s)
    truth = np.array([frame.meta["keypoints_truth"]["left"][j] for j in ("shoulder", "elbow", "wrist")])
    return sc, rig.rectify(frame.left, frame.right)[0], rig.to_rectified(truth, "left")


def test_a_diver_the_stretched_tiles_miss_in_murky_water_is_found_in_the_locally_equalised_ones(tmp_path):
    """``blazepose.local_retry``: in murky green water a grey diver in profile at 3.4 m scores under the detector's
    bar in the whole frame and in every stretched square tile; with each tile's lightness equalised locally (CLAHE)
    the detector finds the body and the landmarks put the pointing arm near the joints (issue 14 session 73)."""
    from dip3d_vehicle.perception.blazepose_model import BlazePose

    sc, left, truth = _left_frame(tmp_path, _PROFILE_IN_MURKY_WATER, 2.0)
    plain, local = BlazePose(), BlazePose(local_retry=True)
    assert plain.process(left) is None
    found = local.detect_in_squares(left, local=True)
    assert found is not None and found.score >= local.min_detection_score
    pose = local.process(left)
    assert pose is not None
    arm, visibility = pose.arm(sc.diver.arm)
    assert visibility.min() > 0.5 and np.linalg.norm(arm - truth, axis=1).max() < 30, (arm, truth)
