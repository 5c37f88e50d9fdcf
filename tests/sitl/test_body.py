"""The diver's body: the packaged mesh, its skinning on the scenario's joints, the rasteriser, the stop gesture."""

from __future__ import annotations

import dataclasses
import math

import cv2
import numpy as np
import pytest

from sitl.body import BODY_FILE, load_body, pose_body
from sitl.raster import draw_mesh, face_normals
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario


def test_packaged_body_is_small_complete_and_credited():
    m = load_body()
    assert BODY_FILE.stat().st_size < 3e6
    assert m.faces.max() < len(m.vertices_m) and len(m.faces) > 3000
    assert np.allclose(m.bone_weight.sum(1), 1.0, atol=1e-5)
    assert set(m.materials) == {"suit", "hood", "skin", "mask", "glove", "tank", "fin"}
    person = m.vertices_m[np.unique(m.faces[m.face_material != m.materials.index("fin")])]
    height = person[:, 1].max() - person[:, 1].min()
    assert 1.55 < height < 1.8  # MakeHuman's default adult, metres
    readme = (BODY_FILE.parent / "README.md").read_text()
    assert "a8bc2d54ff0ac92e78ff71431b1023eda42bf482" in readme and "CC0" in readme
    assert (BODY_FILE.parent / "LICENSE.CC0.md").read_text().startswith("# Creative Commons CC0")


def _posed(seed: int = 3, t: float = 2.0):
    sc = load_scenario("paper_pool", seed)
    target = np.asarray(sc.placard(sc.target_id).centre_ned_m)
    joints = sc.diver.joints(target, t)
    return sc, joints, pose_body(load_body(), joints, sc.diver.heading_rad, sc.diver.arm)


def test_skinned_arm_follows_the_scenario_joints():
    """Vertices bound only to the pointing forearm lie on the shoulder-wrist segment's forearm part."""
    sc, j, body = _posed()
    m = load_body()
    k = m.bone("lowerarm.R")
    only = (m.bone_index[:, 0] == k) & (m.bone_weight[:, 0] > 0.999)
    assert only.sum() >= 10
    pts = body.vertices_ned_m[only]
    axis = (j["wrist"] - j["elbow"]) / np.linalg.norm(j["wrist"] - j["elbow"])
    rel = pts - j["elbow"]
    along = rel @ axis
    radial = np.linalg.norm(rel - np.outer(along, axis), axis=1)
    assert along.min() > -0.02 and along.max() < np.linalg.norm(j["wrist"] - j["elbow"]) + 0.02
    assert radial.max() < 0.07  # a forearm is a few cm thick


def test_body_stands_where_the_diver_is_and_faces_its_heading():
    sc, j, body = _posed()
    v = body.vertices_ned_m
    assert v[:, 2].min() == pytest.approx(j["chest"][2] - 0.35, abs=0.05)  # head top above the shoulders
    assert v[:, 2].max() > j["chest"][2] + 1.0                            # feet / fins well below
    fwd = np.array([math.cos(sc.diver.heading_rad), math.sin(sc.diver.heading_rad), 0.0])
    nose = body.landmarks_ned_m["nose"]
    assert (nose - j["chest"]) @ fwd > 0.05                              # the face looks forward


def test_rasteriser_culls_back_faces_and_paints_near_over_far():
    img = np.zeros((100, 100, 3), np.uint8)
    K = np.array([[100.0, 0, 50], [0, 100.0, 50], [0, 0, 1]])
    near = np.array([[-0.2, -0.2, 1.0], [0.2, -0.2, 1.0], [0.0, 0.2, 1.0]])
    far = near * 2.0
    verts = np.vstack([far, near])
    faces = np.array([[0, 2, 1], [3, 5, 4]])  # both wound to face the camera
    assert np.all(face_normals(verts, faces)[:, 2] < 0)
    uv = verts[:, :2] / verts[:, 2:] * 100 + 50
    drawn = draw_mesh(img, uv, verts, faces, np.array([[0, 0, 255], [0, 255, 0]], float))
    assert drawn == 2 and tuple(img[50, 50]) == (0, 255, 0)
    img[:] = 0
    assert draw_mesh(img, uv, verts, faces[:, ::-1].copy(), np.array([[0, 0, 255], [0, 255, 0]], float)) == 0
    assert img.max() == 0


def test_rendered_body_covers_its_joints_in_both_eyes():
    sc = load_scenario("paper_pool", 3)
    r = StereoRenderer(sc, {"world.render_noise": False})
    frame = r.render(*sc.initial_vehicle_pose, 3.0)
    bg = StereoRenderer(dataclasses.replace(sc, diver=dataclasses.replace(sc.diver, chest_ned_m=(50.0, 0.0, 1.0))),
                        {"world.render_noise": False}).render(*sc.initial_vehicle_pose, 3.0)
    r.close()
    for eye in ("left", "right"):
        diff = cv2.absdiff(getattr(frame, eye), getattr(bg, eye)).max(axis=2)
        for name, (x, y) in frame.meta["body_truth"][eye].items():
            if name in ("left_eye", "right_eye", "nose"):
                continue  # seen from behind: the head covers them, they are not on the surface
            assert diff[int(round(y)), int(round(x))] > 20, f"{eye} {name} not on the body"


def test_stop_gesture_raises_both_wrists_above_the_head(tmp_path):
    path = tmp_path / "stop.yaml"
    path.write_text("base: paper_pool\ndiver: {stop_gesture_at_s: 5.0, stop_gesture_hold_s: 2.0}\n")
    sc = load_scenario(str(path), 0)
    dv = sc.diver
    assert dv.stop_gesture_at(5.5) and not dv.stop_gesture_at(4.9) and not dv.stop_gesture_at(7.0)
    assert not dv.pointing_at(5.5) and dv.pointing_at(3.0) and dv.pointing_at(8.0)
    with StereoRenderer(sc, {"world.render_noise": False}) as r:
        during = r.render(*sc.initial_vehicle_pose, 6.0)
        before = r.render(*sc.initial_vehicle_pose, 3.0)
    assert during.meta["stop_gesture"] and not before.meta["stop_gesture"]
    xyz = during.meta["body_truth"]["xyz_cam_m"]
    head_y = xyz["nose"][1]  # camera y is roughly down (the camera pitch is small)
    assert xyz["right_wrist"][1] < head_y - 0.15 and xyz["left_wrist"][1] < head_y - 0.15
    before_xyz = before.meta["body_truth"]["xyz_cam_m"]
    assert before_xyz["left_wrist"][1] > before_xyz["left_shoulder"][1] + 0.3  # the other arm hangs


def test_body_truth_names_the_pointing_arm_like_the_keypoints():
    sc = load_scenario("paper_pool", 0)
    with StereoRenderer(sc) as r:
        frame = r.render(*sc.initial_vehicle_pose, 3.0)
    for eye in ("left", "right"):
        for j in ("shoulder", "elbow", "wrist"):
            assert frame.meta["body_truth"][eye][f"right_{j}"] == frame.meta["keypoints_truth"][eye][j]
