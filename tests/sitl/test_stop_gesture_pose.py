"""Issue 12: the simulated diver performs the stop gesture; the pose sources carry the extra joints."""

from __future__ import annotations

import json

import numpy as np
import pytest

from dip3d_vehicle.errors import KeypointsError
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints, load_keypoints_file
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario


def _scenario(tmp_path, at_s):
    extra = f"diver:\n  stop_gesture_at_s: {at_s}\n" if at_s is not None else ""
    path = tmp_path / "stop.yaml"
    path.write_text("base: paper_pool\n" + extra)
    return load_scenario(str(path), 0)


def test_the_diver_raises_both_wrists_above_the_head_at_the_given_time(tmp_path):
    sc = _scenario(tmp_path, 5.0)
    target = np.asarray(sc.placard(sc.target_id).centre_ned_m)
    before, after = sc.diver.joints(target, 4.9), sc.diver.joints(target, 5.0 + sc.diver.raise_s)
    up = lambda j, name: -j[name][2]  # NED: up is -down
    assert up(before, "wrist") < up(before, "head") and up(before, "o_wrist") < up(before, "head")
    assert up(after, "wrist") > up(after, "head") + 0.2 and up(after, "o_wrist") > up(after, "head") + 0.2
    assert _scenario(tmp_path, None).diver.stop_gesture_at_s is None


def test_the_simulated_pose_source_gives_the_head_and_other_wrist(tmp_path):
    sc = _scenario(tmp_path, 3.0)
    r = StereoRenderer(sc)
    p = sc.initial_vehicle_pose
    try:
        early, late = r.render(p.north_m, p.east_m, p.depth_m, p.yaw_rad, 2.0).meta, r.render(p.north_m, p.east_m, p.depth_m, p.yaw_rad, 4.0).meta
    finally:
        r.close()
    for meta in (early, late):
        assert {"head", "other_wrist"} <= set(meta["keypoints_truth"]["left"])
    kp = late["keypoints"]["left"]
    assert kp["wrist"][1] < kp["head"][1] and kp["other_wrist"][1] < kp["head"][1]
    kp = early["keypoints"]["left"]
    assert kp["wrist"][1] > kp["head"][1]


def test_keypoints_files_may_carry_the_extra_joints_and_old_files_stay_valid(tmp_path):
    rig = load_scenario("paper_pool", 0).rig()
    arm = {"shoulder": [500, 600], "elbow": [600, 600], "wrist": [690, 600]}
    old = tmp_path / "old.json"
    old.write_text(json.dumps({"left": arm, "right": arm}))
    got = GivenKeypoints.from_file(old).estimate(None, None, rig)
    assert got.extra_left_px == {}
    new = tmp_path / "new.json"
    new.write_text(json.dumps({"left": dict(arm, head=[480, 560], other_wrist=[420, 400, 0.9]), "right": arm,
                               "rectified": True}))
    got = GivenKeypoints.from_file(new).estimate(None, None, rig)
    assert got.extra_left_px == {"head": (480.0, 560.0), "other_wrist": (420.0, 400.0)}
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"left": dict(arm, head=[480]), "right": arm}))
    with pytest.raises(KeypointsError, match="left.head"):
        load_keypoints_file(bad)
