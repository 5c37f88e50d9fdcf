"""The perception core's overlap of pose and features (the candidates' features start before the right pose ends)."""

from __future__ import annotations

import pytest

from dip3d_vehicle.bench import simulated_frames
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception


class EarlyKeypoints(GivenKeypoints):
    """Given keypoints that, like BlazePose, tell the early-arm listener before returning."""

    def estimate(self, left_rect, right_rect, rig):
        arm = super().estimate(left_rect, right_rect, rig)
        if self._early_listener is not None and arm is not None:
            self._early_listener(arm)
        return arm


@pytest.fixture(scope="module")
def frame():
    data = simulated_frames("paper_pool", seeds=(1,), frames_per_seed=1, size=(800, 600))
    return data.rig, data.frames[0]


def _core(rig, tracking: bool) -> tuple[Perception, EarlyKeypoints]:
    pose = EarlyKeypoints("right")
    params = load_params("fast", (), {"pose.backend": "blazepose", "blazepose.tracking": tracking,
                                      "candidates.image_scale": 0.5})
    return Perception(rig, params, pose), pose


def test_first_frame_features_start_from_the_early_arm(frame):
    rig, f = frame
    core, pose = _core(rig, tracking=True)
    pose.provide(f.meta["keypoints"])
    result = core.process(f.left, f.right)
    assert result.status == "ok"
    assert core.detector.last_counts["prefetched"] == 1
    assert pose._early_listener is None, "the listener only lives during estimate"
    plain, plain_pose = _core(rig, tracking=False)          # no overlap: features computed after the pose
    plain_pose.provide(f.meta["keypoints"])
    reference = plain.process(f.left, f.right)
    assert plain.detector.last_counts["prefetched"] == 0
    assert reference.selection.target.left_px == pytest.approx(result.selection.target.left_px, abs=3.0)


def test_a_live_first_frame_starts_the_right_features_before_the_pose(frame):
    """A live sequence's first frame (start pass): the right image's features start over the whole width
    before the pose runs, the left's from the early arm; the decision is that of the start pass run after the pose."""
    rig, f = frame
    # the corridor's zoom boxes (off here) add ~20 features spread over the chosen placard, whose median point then
    # moves with the main pass's membership by up to 5 px at 800 x 600; this test is about the start pass
    params = load_params("default", (), {"pose.backend": "blazepose", "blazepose.tracking": True,
                                         "candidates.reuse_frames": 4, "candidates.reuse_start_image_scale": 0.35,
                                         "corridor.zoom_boxes": 0})
    pose = EarlyKeypoints("right")
    core = Perception(rig, params, pose, live=True)
    order = []
    right_first, estimate = core.start_detector.prefetch_right, pose.estimate
    core.start_detector.prefetch_right = lambda *a: order.append("right features") or right_first(*a)
    pose.estimate = lambda *a: order.append("pose") or estimate(*a)
    pose.provide(f.meta["keypoints"])
    result = core.process(f.left, f.right)
    assert order == ["right features", "pose"] and core.start_detector.last_counts["prefetched"] == 1
    assert core.reuse.counts["start_passes"] == 1
    after = Perception(rig, params.with_overrides({"blazepose.tracking": False}, "test"), EarlyKeypoints("right"), live=True)
    after.pose.provide(f.meta["keypoints"])
    reference = after.process(f.left, f.right)              # no overlap: the start pass after the pose
    assert after.start_detector.last_counts["prefetched"] == 0
    assert result.status == reference.status == "ok"
    # SIFT on the whole width is not SIFT on the kept columns (the coarse octaves see a different image),
    # so the matches differ somewhat; the decision does not
    assert abs(len(result.candidates) - len(reference.candidates)) <= 0.2 * len(reference.candidates)
    assert reference.selection.target.left_px == pytest.approx(result.selection.target.left_px, abs=3.0)


def test_right_features_started_alone_are_used_without_an_early_arm(frame):
    """No early arm came (a pose backend without one): the whole-width right features are still used."""
    rig, f = frame
    params = load_params("default", (), {"pose.backend": "blazepose", "blazepose.tracking": True,
                                         "candidates.reuse_frames": 4, "candidates.reuse_start_image_scale": 0.35})
    core = Perception(rig, params, GivenKeypoints("right", f.meta["keypoints"]), live=True)
    result = core.process(f.left, f.right)
    assert result.status == "ok" and core.start_detector.last_counts["prefetched"] == 1
