"""The stereo renderer: truth agrees with the pixels and the calibration, frames are repeatable,
and every placard within 3 m in clear water gets stereo-matched SIFT features."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from dip3d_vehicle.frames import StereoFrame
from sitl.render import KEYPOINT_SOURCE, StereoRenderer
from sitl.scenario import load_scenario

JOINTS = ("shoulder", "elbow", "wrist")


@pytest.fixture(scope="module")
def scene():
    sc = load_scenario("paper_pool", 1)
    renderer = StereoRenderer(sc)
    yield sc, renderer
    renderer.close()


def _render(renderer, sc, t=5.0, **shift):
    p = sc.initial_vehicle_pose._replace(**shift)
    return renderer.render(p.north_m, p.east_m, p.depth_m, p.yaw_rad, t)


def test_frame_shape_and_meta(scene):
    sc, r = scene
    frame = _render(r, sc)
    assert isinstance(frame, StereoFrame) and frame.stamp_s == 5.0
    for img in (frame.left, frame.right):
        assert img.shape == (1200, 1600, 3) and img.dtype == np.uint8
    m = frame.meta
    assert m["target_id"] == sc.target_id and m["pointing"] is True and m["diver_visible"]
    assert m["keypoints"]["source"] == KEYPOINT_SOURCE and m["keypoints"]["rectified"] is False
    # the left image also carries the optional extra joints (issue 12's stop gesture): head, other_wrist
    assert set(m["keypoints"]["left"]) == set(JOINTS) | {"head", "other_wrist"}
    assert set(m["keypoints"]["right"]) == set(JOINTS)
    assert set(m["placards"]) == {1, 2, 3}
    assert all(p["visible"] for p in m["placards"].values())
    assert m["vehicle_pose"]["depth_m"] == sc.initial_vehicle_pose.depth_m


def test_truth_keypoints_match_project_points(scene):
    sc, r = scene
    frame = _render(r, sc, t=3.3)
    cam = sc.camera
    xyz = np.array([frame.meta["joints_cam_m"][j] for j in JOINTS])
    left, _ = cv2.projectPoints(xyz, np.zeros(3), np.zeros(3), cam.K, cam.D1)
    right, _ = cv2.projectPoints((cam.R @ xyz.T + cam.T).T, np.zeros(3), np.zeros(3), cam.K, cam.D2)
    truth = frame.meta["keypoints_truth"]
    assert np.allclose([truth["left"][j] for j in JOINTS], left.reshape(-1, 2), atol=1e-6)
    assert np.allclose([truth["right"][j] for j in JOINTS], right.reshape(-1, 2), atol=1e-6)
    noisy = frame.meta["keypoints"]
    err = np.array([np.subtract(noisy[s][j], truth[s][j]) for s in ("left", "right") for j in JOINTS])
    assert np.abs(err).max() < 6 * sc.pose_source.noise_px + 1e-9


def test_keypoints_lie_on_the_drawn_arm(scene):
    sc, _ = scene
    r = StereoRenderer(sc, {"world.render_noise": False})
    frame = _render(r, sc, t=4.0)
    r.close()
    truth = frame.meta["keypoints_truth"]
    for side, img in (("left", frame.left), ("right", frame.right)):
        for j in ("elbow", "wrist"):
            x, y = np.round(truth[side][j]).astype(int)
            assert img[y, x].max() < 110, f"{side} {j} at ({x}, {y}) is not on the dark suit: {img[y, x]}"


def test_placard_polygons_cover_the_printed_texture(scene):
    sc, r = scene
    frame = _render(r, sc)
    masks = {}
    for pid, info in frame.meta["placards"].items():
        masks[pid] = np.zeros(frame.left.shape[:2], np.uint8)
        cv2.fillConvexPoly(masks[pid], np.round(info["left_polygon_px"]).astype(np.int32), 255)
    gray = cv2.cvtColor(frame.left, cv2.COLOR_BGR2GRAY).astype(float)
    anything = cv2.dilate(np.max(list(masks.values()), axis=0), np.ones((5, 5), np.uint8))
    for pid, mask in masks.items():
        inner = cv2.erode(mask, np.ones((7, 7), np.uint8))
        ring = cv2.dilate(mask, np.ones((15, 15), np.uint8)) & ~anything
        inside, outside = gray[inner > 0], gray[ring > 0]
        assert inside.std() > 3 * outside.std(), f"placard {pid}: no texture inside its polygon"
        info = frame.meta["placards"][pid]
        assert info["range_m"] == pytest.approx(np.linalg.norm(info["xyz_cam_m"]))


def test_same_seed_and_time_give_identical_frames(scene):
    sc, r = scene
    a = _render(r, sc, t=2.5)
    b = StereoRenderer(load_scenario("paper_pool", 1)).render(*sc.initial_vehicle_pose, 2.5)
    assert np.array_equal(a.left, b.left) and np.array_equal(a.right, b.right)
    assert a.meta["keypoints"] == b.meta["keypoints"]
    c = _render(r, sc, t=2.6)
    assert not np.array_equal(a.left, c.left)  # noise and sway differ


def test_pointing_timeline_and_lowered_arm(scene):
    sc, r = scene
    before = _render(r, sc, t=0.0)
    during = _render(r, sc, t=sc.diver.start_s + 1.0)
    after = _render(r, sc, t=sc.diver.start_s + sc.diver.hold_s + 2.0)
    assert (before.meta["pointing"], during.meta["pointing"], after.meta["pointing"]) == (False, True, False)
    for frame in (before, after):  # arm hanging: the wrist is well below the shoulder in the image
        kp = frame.meta["keypoints_truth"]
        assert kp["left"]["wrist"][1] - kp["left"]["shoulder"][1] > 150


def test_dropouts_and_exact_pose_switch(tmp_path):
    path = tmp_path / "drop.yaml"
    path.write_text("base: paper_pool\npose_source: {dropout: 1.0}\n")
    sc = load_scenario(str(path), 0)
    r = StereoRenderer(sc, {"world.render_noise": False})
    frame = _render(r, sc)
    assert frame.meta["keypoints"] is None and frame.meta["keypoints_truth"] is not None
    r.close()
    exact = StereoRenderer(sc, {"world.pose_noise": False})
    frame = _render(exact, sc)
    exact.close()
    assert {s: frame.meta["keypoints"][s] for s in ("left", "right")} == \
        {s: frame.meta["keypoints_truth"][s] for s in ("left", "right")}


def test_diver_out_of_view_gives_no_keypoints(scene):
    sc, r = scene
    frame = _render(r, sc, yaw_rad=sc.initial_vehicle_pose.yaw_rad + np.pi)
    assert frame.meta["keypoints"] is None and frame.meta["diver_visible"] is False
    assert not any(p["visible"] for p in frame.meta["placards"].values())


def test_sift_matches_on_every_placard_within_3m():
    """Clear water: each placard within 3 m gets >= 10 SIFT matches on the same rectified row,
    and their disparity gives the placard's depth."""
    sc = load_scenario("paper_pool", 0)
    r = StereoRenderer(sc)
    frame = _render(r, sc)
    r.close()
    rig = sc.rig()
    left, right = rig.rectify(frame.left, frame.right)
    sift = cv2.SIFT_create()
    gl, gr = cv2.cvtColor(left, cv2.COLOR_BGR2GRAY), cv2.cvtColor(right, cv2.COLOR_BGR2GRAY)
    kl, dl = sift.detectAndCompute(gl, None)
    kr, dr = sift.detectAndCompute(gr, None)
    pairs = cv2.BFMatcher(cv2.NORM_L2).knnMatch(dl, dr, k=2)
    good = [m for m, n in (p for p in pairs if len(p) == 2) if m.distance < 0.6 * n.distance]
    pl = np.array([kl[m.queryIdx].pt for m in good])
    pr = np.array([kr[m.trainIdx].pt for m in good])
    row = np.abs(pl[:, 1] - pr[:, 1]) < 1.5
    pl, pr = pl[row], pr[row]
    counts = {}
    for pid, info in frame.meta["placards"].items():
        if info["range_m"] > 3.1:
            continue
        poly = rig.to_rectified(info["left_polygon_px"], "left").astype(np.float32)
        inside = np.array([cv2.pointPolygonTest(poly, (float(x), float(y)), False) >= 0 for x, y in pl])
        counts[pid] = int(inside.sum())
        assert counts[pid] >= 10, f"placard {pid} at {info['range_m']:.2f} m: only {counts[pid]} matches"
        disparity = np.median(pl[inside, 0] - pr[inside, 0])
        depth = rig.focal_px * rig.baseline_m / disparity
        z_rect = (rig.R1 @ np.asarray(info["xyz_cam_m"]))[2]
        assert depth == pytest.approx(z_rect, rel=0.05)
    assert set(counts) == {1, 2, 3}, counts


@pytest.mark.parametrize("name", ["paper_pool", "far_diver", "receding_line", "distractor_behind", "murky"])
def test_every_built_in_shows_diver_and_placards_from_the_start(name):
    for seed in (0, 1):
        sc = load_scenario(name, seed)
        with StereoRenderer(sc) as r:
            frame = _render(r, sc, t=sc.diver.start_s + 1.0)
        assert frame.meta["diver_visible"] and frame.meta["pointing"], (name, seed)
        hidden = [pid for pid, p in frame.meta["placards"].items() if not p["visible"]]
        assert not hidden, f"{name} seed {seed}: placards {hidden} not in view"
