"""The pointing corridor: a small, faint, distant placard the main SIFT pass misses is found there."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.corridor import corridor_polygon, merge_candidates, zoom_boxes
from dip3d_vehicle.perception.filters import pose_rejection
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from dip3d_vehicle.perception.values import ArmKeypoints, Candidates

# A generated "far" scene (tests/perception/scene_families.py, seed 125): the pointed placard is
# 0.22 m wide at 5.5 m (46 px) in attenuated, turbid, dim water.
FAR_FAINT = """
base: paper_pool
track_line: null
diver: {positions: [{name: g, range_m: 2.928, bearing_deg: -25.54, depth_m: 1.0}], target: 1}
placards:
  - {id: 1, range_m: 5.541, bearing_deg: 28.57, depth_m: 1.380, size_m: 0.216}
  - {id: 2, range_m: 1.393, bearing_deg: 11.47, depth_m: 1.111, size_m: 0.220}
  - {id: 3, range_m: 4.596, bearing_deg: 20.37, depth_m: 1.045, size_m: 0.278}
  - {id: 4, range_m: 1.013, bearing_deg: 5.42, depth_m: 0.720, size_m: 0.247}
pose_source: {noise_px: 0.0, dropout: 0.0}
water: {ambient_light: 0.539, attenuation_per_m: [0.1516, 0.1814, 0.2553], light_falloff_per_m2: 0.0385,
        turbidity_per_m: 0.0659}
"""

# A generated "far" scene (scene_families.py, family far, seed 1700, scene 17, rendered with seed 1745): the pointed
# placard is 0.21 m wide at 4.8 m (41 px) in dim, strongly attenuated water; the corridor's scan of the whole wedge
# finds two matches on it, one too few for an object.
FAR_LONE = """
base: paper_pool
track_line: null
diver: {positions: [{name: g, range_m: 2.498878343029194, bearing_deg: -25.002047558589478, depth_m: 1.0}],
        target: 1}
placards:
  - {id: 1, range_m: 4.811242132964681, bearing_deg: 6.16847607325516, depth_m: 1.273522703794218,
     size_m: 0.20905530663604044}
  - {id: 2, range_m: 2.4221438879609023, bearing_deg: 23.176734186814233, depth_m: 0.9777891568330113,
     size_m: 0.25722639841283707}
  - {id: 3, range_m: 4.070459077108033, bearing_deg: 33.987784358910915, depth_m: 1.295803268972583,
     size_m: 0.21436181381438893}
  - {id: 4, range_m: 3.752210436133315, bearing_deg: 13.083994521575107, depth_m: 0.8233149736791997,
     size_m: 0.29150769384992065}
pose_source: {noise_px: 0.0, dropout: 0.0}
water: {ambient_light: 0.835048713223919, attenuation_per_m: [0.30768111937382975, 0.2519405816795665,
        0.31502274280969134], light_falloff_per_m2: 0.03478125501050365, turbidity_per_m: 0.07261073822101329}
"""


def _rendered(tmp_path, text: str, seed: int):
    """Return (scenario, frame) of one rendered scenario text while the diver points."""
    from sitl.render import StereoRenderer
    from sitl.scenario import load_scenario
    path = tmp_path / "scene.yaml"
    path.write_text(text)
    scenario = load_scenario(str(path), seed)
    with StereoRenderer(scenario) as renderer:
        return scenario, renderer.render(*scenario.initial_vehicle_pose, 2.0)


def _objects_on_target(perception, arm, cands, scene_meta, target_id, rig) -> int:
    """Return how many selected objects' points lie on the pointed placard."""
    import cv2
    result = perception.decide(perception.check_arm(arm), cands)
    poly = np.asarray(scene_meta["placards"][target_id]["left_polygon_px"], np.float32)
    objs = result.selection.objects if result.selection else ()
    pts = rig.to_original(np.array([o.left_px for o in objs]), "left") if objs else np.zeros((0, 2))
    return sum(cv2.pointPolygonTest(poly, (float(x), float(y)), False) >= 0 for x, y in pts), result


def test_corridor_finds_the_far_faint_placard_the_main_pass_misses(tmp_path):
    """Without the corridor no candidate object lies on the placard; with it one does, and it is chosen."""
    scenario, frame = _rendered(tmp_path, FAR_FAINT, 0)
    rig = scenario.rig()
    left, right = rig.rectify(frame.left, frame.right)
    pose = GivenKeypoints("right", frame.meta["keypoints_truth"])
    perception = Perception(rig, load_params("default"), pose)
    arm = pose.estimate(left, right, rig)
    base = perception.detector.detect(left, right, arm, rig)
    before, _ = _objects_on_target(perception, arm, base, frame.meta, scenario.target_id, rig)
    assert before == 0
    both = perception.add_corridor(left, right, arm, base)
    assert len(both) > len(base)
    after, result = _objects_on_target(perception, arm, both, frame.meta, scenario.target_id, rig)
    assert after == 1
    assert result.status == "ok"
    poly = np.asarray(frame.meta["placards"][scenario.target_id]["left_polygon_px"], np.float32)
    import cv2
    px = rig.to_original(result.target_rect_px, "left")[0]
    assert cv2.pointPolygonTest(poly, (float(px[0]), float(px[1])), False) >= 0
    # every corridor match is on the same rectified row in both images
    extra = perception.corridor.detect(left, right, arm, rig)
    assert np.all(np.abs(extra.left_px[:, 1] - extra.right_px[:, 1]) <= 1.5)


def test_corridor_polygon_starts_beyond_the_wrist_along_the_arm():
    """The wedge opens from the wrist along shoulder->wrist; nothing behind the wrist is inside."""
    import cv2
    left = np.array([[100.0, 500.0], [300.0, 450.0], [500.0, 400.0]])
    arm = ArmKeypoints("right", left, left - [30, 0], np.ones(3), np.ones(3))
    poly = corridor_polygon(arm, 1600, 1200, 0.2, 40.0, 40.0).astype(np.float32)
    u = (left[2] - left[0]) / np.linalg.norm(left[2] - left[0])
    assert cv2.pointPolygonTest(poly, tuple(map(float, left[2] + 300 * u)), False) > 0
    assert cv2.pointPolygonTest(poly, tuple(map(float, left[2] - 20 * u)), False) < 0
    assert cv2.pointPolygonTest(poly, tuple(map(float, left[1])), False) < 0


def test_merge_adds_only_new_points():
    """A corridor match within 3 px of a main-pass match is not added twice."""
    a = Candidates(np.array([[10.0, 10.0]]), np.array([[5.0, 10.0]]), np.zeros((1, 128), np.float32), np.zeros(1))
    b = Candidates(np.array([[11.0, 10.0], [50.0, 10.0]]), np.array([[6.0, 10.0], [45.0, 10.0]]),
                   np.zeros((2, 128), np.float32), np.zeros(2))
    merged = merge_candidates(a, b)
    assert len(merged) == 2 and merged.left_px[1] == pytest.approx([50.0, 10.0])


def test_far_diver_pose_not_rejected_for_stereo_depth_noise():
    """At 5 m a 0.9 m |dz| is stereo noise: the sigma-aware rule keeps it, the paper's fixed rule drops it."""
    xyz = np.array([[0.0, 0.0, 5.0], [0.3, 0.0, 5.9], [0.58, 0.0, 5.2]])
    sigma = np.array([0.6, 0.6, 0.6])
    assert pose_rejection(xyz, 0.5) is not None
    assert pose_rejection(xyz, 0.5, 0.0, sigma, 3.0) is None
    assert pose_rejection(np.array([[0.0, 0, 2.0], [0.3, 0, 5.0], [0.6, 0, 2.0]]), 0.5, 0.0,
                          np.array([0.05, 0.05, 0.05]), 3.0) is not None
    assert load_params("paper")["filters.joint_dz_sigmas"] == 0.0
    assert load_params("paper")["corridor.enabled"] is False


def test_merge_drops_a_corridor_match_that_agrees_with_no_nearby_feature():
    """Among main-pass features at 50 and 100 px disparity, a corridor match at 80 px is an occlusion mismatch."""
    base = Candidates(np.array([[100.0, 100.0], [110.0, 100.0]]), np.array([[50.0, 100.0], [10.0, 100.0]]),
                      np.zeros((2, 128), np.float32), np.zeros(2))
    extra = Candidates(np.array([[105.0, 104.0], [106.0, 96.0], [400.0, 100.0]]),
                       np.array([[25.0, 104.0], [56.0, 96.0], [380.0, 100.0]]), np.zeros((3, 128), np.float32), np.zeros(3))
    merged = merge_candidates(base, extra)
    assert len(merged) == 4
    assert [106.0, 96.0] in merged.left_px.tolist() and [400.0, 100.0] in merged.left_px.tolist()
    assert [105.0, 104.0] not in merged.left_px.tolist()


def test_zoom_boxes_look_closer_at_the_far_placard_the_wedges_scan_left_lone(tmp_path):
    """Two corridor matches on a 41 px placard make no object; the zoom boxes around them find it, and it is chosen."""
    import cv2
    scenario, frame = _rendered(tmp_path, FAR_LONE, 1745)
    rig = scenario.rig()
    left, right = rig.rectify(frame.left, frame.right)
    pose = GivenKeypoints("right", frame.meta["keypoints_truth"])
    arm = pose.estimate(left, right, rig)
    counts = {}
    for boxes in (0, 2):
        perception = Perception(rig, load_params("default", overrides=[f"corridor.zoom_boxes={boxes}"]), pose)
        base = perception.detector.detect(left, right, arm, rig)
        cands = perception.add_corridor(left, right, arm, base)
        counts[boxes] = _objects_on_target(perception, arm, cands, frame.meta, scenario.target_id, rig)
    assert counts[0][0] == 0 and counts[0][1].status == "nothing_on_ray"
    found, result = counts[2]
    assert found == 1 and result.status == "ok" and not result.selection.ambiguous
    poly = np.asarray(frame.meta["placards"][scenario.target_id]["left_polygon_px"], np.float32)
    px = rig.to_original(result.target_rect_px, "left")[0]
    assert cv2.pointPolygonTest(poly, (float(px[0]), float(px[1])), False) >= 0


def _cands(left_px, disparity_px) -> Candidates:
    """Return candidates at rectified left pixels with the given disparities (x_left - x_right)."""
    left = np.asarray(left_px, float)
    right = left - np.c_[np.asarray(disparity_px, float), np.zeros(len(left))]
    return Candidates(left, right, np.zeros((len(left), 128), np.float32), np.zeros(len(left)))


def test_zoom_boxes_go_to_lone_far_matches_nearest_the_pointing_axis():
    """A far match with no neighbours at its depth gets a box; a cluster's, a near one's, or one in a box already do not."""
    poly = np.array([[100.0, 540.0], [1600.0, 300.0], [1600.0, 1000.0], [100.0, 660.0]])  # axis (100, 600)-(1600, 650)
    focal, baseline = 920.0, 0.12                                                          # 25 px: 4.4 m
    found = _cands([[800.0, 700.0],                       # lone, 4.4 m, 0.11 rad off the axis
                    [712.0, 615.0],                       # two together at 4.4 m, on the axis: lone (an object
                    [700.0, 610.0],                       # needs three); the second lies in the first's box
                    [1000.0, 640.0], [1005.0, 642.0], [1002.0, 636.0],   # three together: an object's
                    [900.0, 630.0],                       # lone but near (1.5 m): the scans at their scale see it
                    [760.0, 480.0]],                      # lone, 3.2 m, 0.2 rad off the axis
                   [25.0, 25.5, 25.0, 25.0, 25.0, 25.0, 73.6, 35.0])
    boxes = zoom_boxes(found, poly, focal, baseline, 1600, 1200, 2)
    assert len(boxes) == 2
    (first, d0), (second, d1) = boxes

    def inside(box, x, y):
        return box[0] <= x < box[2] and box[1] <= y < box[3]

    assert inside(first, 712, 615) and inside(first, 700, 610) and d0 == pytest.approx(25.5)
    assert first[2] - first[0] == pytest.approx(2 * 0.3 * 25.5 / baseline, abs=2)        # ZOOM_HALF_M at its depth
    assert inside(second, 800, 700) and d1 == pytest.approx(25.0)
    assert not any(inside(b, 1000, 640) or inside(b, 900, 630) for b in (first, second))
    more = zoom_boxes(found, poly, focal, baseline, 1600, 1200, 8)
    assert [d for _, d in more] == pytest.approx([25.5, 25.0, 35.0])
    assert zoom_boxes(_cands([[1000.0, 640.0], [1005.0, 642.0], [1002.0, 636.0]], [25.0] * 3), poly, focal,
                      baseline, 1600, 1200, 2) == []
