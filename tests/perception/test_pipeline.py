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
