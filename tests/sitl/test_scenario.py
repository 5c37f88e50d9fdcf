"""Scenario files: built-ins load, the seed varies what it should, bad files name file and field."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dip3d_vehicle.errors import ScenarioError
from dip3d_vehicle.perception.calibration import StereoRig
from sitl.scenario import Scenario, load_scenario, scenario_names
from sitl.world import left_camera_pose

BUILT_IN = {"paper_pool", "far_diver", "receding_line", "distractor_behind", "murky"}


def _station(sc: Scenario) -> np.ndarray:
    cam = sc.camera
    return left_camera_pose(sc.initial_vehicle_pose, cam.mount_frd_m, cam.mount_pitch_rad,
                            cam.mount_yaw_rad).centre_w


def test_built_in_names():
    assert BUILT_IN <= set(scenario_names())


@pytest.mark.parametrize("name", sorted(BUILT_IN))
def test_built_ins_load_for_several_seeds(name):
    for seed in range(4):
        sc = load_scenario(name, seed)
        assert sc.name == name and sc.seed == seed
        assert sc.target_id in [p.id for p in sc.placards]
        assert sc.placard(sc.target_id).role == "object"
        assert isinstance(sc.rig(), StereoRig)
        assert len(sc.initial_vehicle_pose) == 4


def test_paper_pool_layout():
    sc = load_scenario("paper_pool", 0)
    station = _station(sc)
    ranges = {p.id: math.hypot(p.centre_ned_m[0] - station[0], p.centre_ned_m[1] - station[1])
              for p in sc.placards}
    assert ranges == pytest.approx({1: 1.0, 2: 2.0, 3: 3.0})
    assert 80 <= sc.camera.hfov_deg <= 90
    assert sc.camera.image_size == (1600, 1200)
    assert sc.diver.arm == "right"
    assert len(sc.track_line_ned_m) >= 2
    rig = sc.rig()
    assert rig.baseline_m == pytest.approx(0.12, rel=1e-3)
    assert rig.image_size == (1600, 1200)


def test_seed_varies_position_and_target_and_is_repeatable():
    scs = [load_scenario("paper_pool", s) for s in range(16)]
    assert {sc.diver.position_name for sc in scs} == {"2", "3"}
    assert {sc.target_id for sc in scs} == {1, 2, 3}
    assert load_scenario("paper_pool", 5) == load_scenario("paper_pool", 5)
    station = _station(scs[0])
    for sc in scs:
        chest = np.asarray(sc.diver.chest_ned_m)
        rng = math.hypot(chest[0] - station[0], chest[1] - station[1])
        assert rng == pytest.approx(float(sc.diver.position_name))


def test_distractor_is_on_the_forearm_line_behind_the_elbow():
    sc = load_scenario("distractor_behind", 0)
    d = sc.placard(9)
    assert d.role == "distractor" and sc.target_id == 3
    j = sc.diver.joints(np.asarray(sc.placard(3).centre_ned_m), exact=True)
    fore = j["wrist"] - j["elbow"]
    to_d = np.asarray(d.centre_ned_m) - j["elbow"]
    assert np.linalg.norm(np.cross(fore, to_d)) / np.linalg.norm(fore) < 1e-9  # on the line
    assert fore @ to_d < 0  # behind the elbow
    assert np.linalg.norm(to_d) == pytest.approx(1.0)


def test_diver_timeline():
    dv = load_scenario("paper_pool", 0).diver
    assert not dv.pointing_at(dv.start_s - 0.01)
    assert dv.pointing_at(dv.start_s) and dv.pointing_at(dv.start_s + dv.hold_s - 0.01)
    assert not dv.pointing_at(dv.start_s + dv.hold_s)
    assert dv.raised_fraction(0.0) == 0.0 and dv.raised_fraction(dv.start_s + 1) == 1.0


def test_pointing_error_angle():
    sc = load_scenario("paper_pool", 3)
    target = np.asarray(sc.placard(sc.target_id).centre_ned_m)
    t = sc.diver.start_s + 0.5
    j = sc.diver.joints(target, t)
    arm = j["wrist"] - j["shoulder"]
    aim = target - j["shoulder"]
    angle = math.degrees(math.acos(arm @ aim / np.linalg.norm(arm) / np.linalg.norm(aim)))
    assert angle == pytest.approx(math.degrees(sc.diver.pointing_error_rad), abs=1e-6)
    assert np.linalg.norm(j["elbow"] - j["shoulder"]) == pytest.approx(0.30)
    assert np.linalg.norm(j["wrist"] - j["elbow"]) == pytest.approx(0.28)


# -- errors ------------------------------------------------------------------------------------

def _write(tmp_path, text: str, name: str = "bad.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


MINIMAL = """
placards:
  - {id: 1, range_m: 2.0, bearing_deg: 10.0, depth_m: 1.0}
diver:
  positions:
    - {range_m: 2.0, bearing_deg: -20.0, depth_m: 1.0}
"""


def test_minimal_file_loads(tmp_path):
    sc = load_scenario(_write(tmp_path, MINIMAL, "mini.yaml"), 0)
    assert sc.name == "mini" and sc.target_id == 1


@pytest.mark.parametrize("text, field, problem", [
    (MINIMAL + "water: {noise_sigma: loud}\n", "water.noise_sigma", "not a finite number"),
    (MINIMAL + "water: {noise_sigma: -1}\n", "water.noise_sigma", "out of range"),
    (MINIMAL + "camera: {baseline: 0.1}\n", "camera.baseline", "unknown field"),
    (MINIMAL + "camera: {image_size: [1600]}\n", "camera.image_size", "list of 2 numbers"),
    (MINIMAL.replace("{id: 1, ", "{"), "placards[0].id", "missing"),
    (MINIMAL.replace("bearing_deg: 10.0, ", ""), "placards[0].bearing_deg", "missing"),
    (MINIMAL + "  target: 7\n", "diver.target", "not 'random' or the id"),
    (MINIMAL + "  arm: both\n", "diver.arm", "not one of right, left"),
    (MINIMAL.replace("placards:\n  - {id: 1, range_m: 2.0, bearing_deg: 10.0, depth_m: 1.0}\n", ""),
     "placards", "missing"),
    (MINIMAL + "track_line: under_placards\n", "track_line", "floor_depth_m"),
    (MINIMAL + "extra: 1\n", "extra", "unknown field"),
    ("placards: [1, 2\n", "", "not valid YAML"),
])
def test_bad_files_name_file_field_problem(tmp_path, text, field, problem):
    path = _write(tmp_path, text)
    with pytest.raises(ScenarioError) as err:
        load_scenario(path)
    msg = str(err.value)
    assert path in msg and field in msg and problem in msg


def test_duplicate_ids(tmp_path):
    text = MINIMAL.replace("placards:\n", "placards:\n  - {id: 1, range_m: 3.0, bearing_deg: 5.0, depth_m: 1.0}\n")
    with pytest.raises(ScenarioError, match="duplicate id 1"):
        load_scenario(_write(tmp_path, text))


def test_unknown_name_and_missing_file(tmp_path):
    with pytest.raises(ScenarioError, match="unknown scenario.*paper_pool"):
        load_scenario("no_such_scenario")
    with pytest.raises(ScenarioError, match="not found"):
        load_scenario(str(tmp_path / "missing.yaml"))
    with pytest.raises(ScenarioError, match="seed"):
        load_scenario("paper_pool", -1)


def test_base_inheritance_and_cycles(tmp_path):
    path = _write(tmp_path, "base: paper_pool\nwater: {noise_sigma: 9.0}\n", "child.yaml")
    sc = load_scenario(path, 1)
    assert sc.water.noise_sigma == 9.0
    assert sc.water.floor_depth_m == load_scenario("paper_pool", 1).water.floor_depth_m
    a = _write(tmp_path, "base: b.yaml\n", "a.yaml")
    _write(tmp_path, "base: a.yaml\n", "b.yaml")
    with pytest.raises(ScenarioError, match="circular"):
        load_scenario(a)


# -- world geometry ------------------------------------------------------------------------------

from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from sitl.world import VehiclePose, right_camera_pose  # noqa: E402

angles = st.floats(-math.pi, math.pi, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(yaw=angles, pitch=st.floats(-1.2, 1.2), n=st.floats(-50, 50), e=st.floats(-50, 50),
       d=st.floats(0, 100))
def test_camera_axes_follow_vehicle_yaw_and_mount_pitch(yaw, pitch, n, e, d):
    pose = VehiclePose(n, e, d, yaw)
    cam = left_camera_pose(pose, (0.3, 0.0, 0.1), pitch)
    R_wc = cam.R_cw.T
    forward = np.array([math.cos(yaw) * math.cos(pitch), math.sin(yaw) * math.cos(pitch), -math.sin(pitch)])
    assert np.allclose(R_wc[:, 2], forward, atol=1e-9)  # optical z: heading, tilted up by pitch
    assert np.allclose(R_wc[:, 0], [-math.sin(yaw), math.cos(yaw), 0.0], atol=1e-9)  # x: vehicle right
    centre = np.array([n, e, d]) + np.array([0.3 * math.cos(yaw), 0.3 * math.sin(yaw), 0.1])
    assert np.allclose(cam.centre_w, centre, atol=1e-9)
    assert np.allclose(cam.to_cam(centre), 0.0, atol=1e-9)


def test_right_camera_is_baseline_to_the_right():
    sc = load_scenario("paper_pool", 0)
    left = left_camera_pose(sc.initial_vehicle_pose, sc.camera.mount_frd_m, sc.camera.mount_pitch_rad)
    right = right_camera_pose(left, sc.camera.R, sc.camera.T)
    offset = left.to_cam(right.centre_w)[0]
    assert offset == pytest.approx([0.12, 0.0, 0.0], abs=1e-9)


def test_near_miss_puts_a_decoy_beside_the_undetectable_target_from_both_diver_positions():
    """The decoy (placard 4) stands 8.5-11.5 deg from the 4 cm target as seen from the shoulder, farther away."""
    seen = set()
    for seed in range(8):
        sc = load_scenario("near_miss", seed)
        target = np.asarray(sc.placard(sc.target_id).centre_ned_m)
        decoy = np.asarray(sc.placard(4).centre_ned_m)
        shoulder = sc.diver.joints(target, exact=True)["shoulder"]
        a, b = target - shoulder, decoy - shoulder
        angle_deg = math.degrees(math.acos(float(a @ b) / float(np.linalg.norm(a) * np.linalg.norm(b))))
        assert sc.target_id == 2 and sc.placard(2).size_m == pytest.approx(0.04)
        assert 8.5 <= angle_deg <= 11.5, (seed, angle_deg)
        assert np.linalg.norm(b) > np.linalg.norm(a) + 0.5
        seen.add(sc.diver.position_name)
    assert seen == {"2", "3"}
