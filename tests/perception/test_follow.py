"""FollowingPerception: keyframes with the full core, the chosen object followed between them."""

from __future__ import annotations

import numpy as np
import pytest

from dip3d_vehicle.bench import frame_correct, simulated_frames
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.follow import FollowingPerception, followed_subset, with_following
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception


@pytest.fixture(scope="module")
def frames():
    return simulated_frames("paper_pool", seeds=(1,), frames_per_seed=4)   # 1600x1200: fast's SIFT scale


@pytest.mark.parametrize("background", [False, True])
def test_followed_frames_stay_on_the_chosen_placard(frames, background):
    pose = GivenKeypoints("right")
    core = Perception(frames.rig, load_params("fast", (), {"pose.backend": "keypoints"}), pose)
    follower = FollowingPerception(core, keyframe_interval=3, background=background)
    kinds, correct = [], []
    for f in frames.frames:
        pose.provide(f.meta["keypoints"])
        result = follower.process(f.left, f.right)
        kinds.append(follower.last_kind)
        correct.append(frame_correct(result.to_json(frames.rig), f.meta))
    follower.close()
    assert kinds[0] == "keyframe" and "followed" in kinds
    assert all(correct)
    assert follower.counts["lost"] == 0


def test_lost_object_forces_a_keyframe(frames):
    pose = GivenKeypoints("right")
    core = Perception(frames.rig, load_params("fast", (), {"pose.backend": "keypoints"}), pose)
    follower = FollowingPerception(core, keyframe_interval=10)
    f0, f1 = frames.frames[0], frames.frames[1]
    pose.provide(f0.meta["keypoints"])
    follower.process(f0.left, f0.right)
    blank = np.zeros_like(f1.left)
    pose.provide(f1.meta["keypoints"])
    follower.process(blank, blank)     # nothing to follow in a blank pair: the core runs instead
    assert follower.last_kind == "keyframe" and follower.counts["keyframes"] == 2


def test_followed_subset_keeps_the_features_nearest_the_object_point():
    members = np.arange(100, 200)
    pts = np.c_[np.arange(100.0), np.zeros(100)]            # feature k at x = k
    pick = followed_subset(members, pts, np.array([50.2, 0.0]), 10)
    assert list(pick) == list(range(146, 156))               # x = 46..55, in order
    assert np.array_equal(followed_subset(members, pts, np.zeros(2), 0), members)      # 0 = all
    assert np.array_equal(followed_subset(members[:10], pts[:10], np.zeros(2), 32), members[:10])


def test_max_features_caps_the_followed_points(frames):
    pose = GivenKeypoints("right")
    params = load_params("fast", (), {"pose.backend": "keypoints", "follow.background": False,
                                      "follow.max_features": 8})
    follower = with_following(Perception(frames.rig, params, pose), params)
    assert follower.max_features == 8
    for f in frames.frames[:3]:
        pose.provide(f.meta["keypoints"])
        result = follower.process(f.left, f.right)
        assert len(follower._track["pts_l"]) <= 8
        assert frame_correct(result.to_json(frames.rig), f.meta)
    assert follower.last_kind == "followed"
    follower.close()


def test_followed_point_continues_from_the_keyframe_point(frames):
    pose = GivenKeypoints("right")
    params = load_params("fast", (), {"pose.backend": "keypoints", "follow.background": False,
                                      "follow.max_features": 8})
    follower = with_following(Perception(frames.rig, params, pose), params)
    f = frames.frames[0]
    pose.provide(f.meta["keypoints"])
    key = follower.process(f.left, f.right)
    same = follower.process(f.left, f.right)       # the same pair again: nothing moved
    assert follower.last_kind == "followed"
    assert same.target_rect_px == pytest.approx(key.target_rect_px, abs=0.05)
    assert same.selection.target.xyz_m[2] == pytest.approx(key.selection.target.xyz_m[2], rel=1e-3)
    follower.close()


class _RecordingPool:
    """A synchronous stand-in for the keyframe thread that records what was followed at each submit."""

    def __init__(self, follower):
        self.follower, self.followed_before = follower, []

    def submit(self, fn, left, right):
        from concurrent.futures import Future
        track = self.follower._track
        self.followed_before.append(track is not None and track["left"] is left)
        done = Future()
        done.set_result(fn(left, right))
        return done

    def shutdown(self):
        pass


def test_background_keyframe_starts_after_the_frame_is_followed(frames):
    pose = GivenKeypoints("right")
    core = Perception(frames.rig, load_params("fast", (), {"pose.backend": "keypoints"}), pose)
    follower = FollowingPerception(core, keyframe_interval=2, background=True)
    follower._pool = pool = _RecordingPool(follower)
    for f in frames.frames:
        pose.provide(f.meta["keypoints"])
        follower.process(f.left, f.right)
    # first keyframe: nothing to follow yet; the one due later starts once its frame was followed
    assert pool.followed_before[0] is False and pool.followed_before[1:] and all(pool.followed_before[1:])
    assert follower.counts["waited"] == 1
