"""Paper vs default selection accuracy on generated stereo scenes, per keypoint-noise level.

Scenes (written as simulator scenario files, rendered by ``sitl.render``): numbered textured
placards, two of them on one line of sight from the camera (only depth separates them), the others
elsewhere; a diver pointing with the right arm with a 5 deg pointing error; the simulator's lens
distortion and small rotation between the cameras. Candidates are detected once per scene and
selector (the image side of the pipeline does not depend on keypoint noise); the arm keypoints get
Gaussian noise of 0, 1, 2 and 4 px in both images over several draws. A frame counts as correct
when the selected point lies inside the intended placard; a rejected pose counts as a miss (it
gives the vehicle no decision). Scenes that break the method's stated preconditions (the target
touching the hand or inside the masked region, placards overlapping in the image) are drawn again.
Scenes where another placard lies as near the arm's line as the target (a 5 deg error can point
between two placards: the "intended" one is then a coin toss for any method) are kept in the main
table; the script prints a second table over the scenes with a clear margin (``CLEAR_DEG``).

Run as a script for the full table: ``python tests/perception/test_synthetic_accuracy.py [N]``; the
open-set families (far, faint, undetectable, elbow clutter, far diver; ``scene_families.py``):
``python tests/perception/test_synthetic_accuracy.py N families [SEED0 [KEY=VALUE ...]]``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import cv2
import numpy as np
import pytest
import yaml

from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from scene_families import noisy

NOISE_PX = (0.0, 1.0, 2.0, 4.0)
CLEAR_DEG = 2.0
"""Pointing margin (deg) above which a scene is unambiguous: no other placard as near the arm's line."""


def scene_spec(rng: np.random.Generator, near: bool) -> dict:
    """Return a scenario mapping: diver and placards at 1-3 m (near) or out to 5 m."""
    far = 3.0 if near else 5.0
    bearing = rng.uniform(8.0, 22.0)
    r1 = rng.uniform(1.0, far - 1.0)
    r2 = rng.uniform(r1 + 0.9, far)
    placards = [{"id": 1, "range_m": float(r1), "bearing_deg": float(bearing), "depth_m": 1.25, "size_m": 0.3},
                {"id": 2, "range_m": float(r2), "bearing_deg": float(bearing + rng.uniform(-1.5, 1.5)),
                 "depth_m": 0.8, "size_m": 0.3}]
    for pid in (3, 4):
        for _ in range(50):
            cand = {"id": pid, "range_m": float(rng.uniform(1.0, far)), "bearing_deg": float(rng.uniform(5.0, 35.0)),
                    "depth_m": float(rng.uniform(0.7, 1.4)), "size_m": 0.3}
            if all(abs(cand["bearing_deg"] - p["bearing_deg"]) > 7 or abs(cand["range_m"] - p["range_m"]) > 0.8
                   for p in placards):
                placards.append(cand)
                break
    diver_range = rng.uniform(1.5, 3.0) if near else rng.uniform(1.5, 4.0)
    return {"base": "paper_pool", "placards": placards, "track_line": None,
            "diver": {"positions": [{"name": "g", "range_m": float(diver_range),
                                     "bearing_deg": float(rng.uniform(-26.0, -14.0)), "depth_m": 1.0}],
                      "target": int(rng.choice([p["id"] for p in placards]))},
            "pose_source": {"noise_px": 0.0, "dropout": 0.0}}


def render_scene(tmp: Path, spec: dict, seed: int):
    """Write and load the scenario, render one frame while the diver points; return (scenario, frame)."""
    from sitl.render import StereoRenderer
    from sitl.scenario import load_scenario
    path = tmp / f"scene_{seed}.yaml"
    path.write_text(yaml.safe_dump(spec))
    scenario = load_scenario(str(path), seed)
    with StereoRenderer(scenario) as renderer:
        frame = renderer.render(*scenario.initial_vehicle_pose, 2.0)
    return scenario, frame


def pointing_margin_deg(scenario, frame) -> float:
    """Return how much farther (deg, seen from the shoulder) the next placard is from the arm's line.

    The simulated arm is straight from the shoulder with its pointing error included, so this is
    the angle between the arm and the nearest other placard's centre minus the angle between the
    arm and the intended placard's centre; near 0 the arm points equally at two placards.
    """
    joints = {k: np.asarray(v, float) for k, v in frame.meta["joints_cam_m"].items()}
    axis = joints["wrist"] - joints["shoulder"]
    axis /= np.linalg.norm(axis)

    def angle(p: dict) -> float:
        d = np.asarray(p["xyz_cam_m"], float) - joints["shoulder"]
        return float(np.degrees(np.arccos(np.clip(d @ axis / np.linalg.norm(d), -1.0, 1.0))))

    placards = frame.meta["placards"]
    target = angle(placards[scenario.target_id])
    return min((angle(p) - target for pid, p in placards.items() if pid != scenario.target_id), default=180.0)


def method_applies(scenario, frame, offset_px: float = 40.0, margin_deg: float = 0.0) -> bool:
    """Return True when the scene meets DIP-3D's preconditions for the intended placard.

    The diver is seen, the target lies wholly beyond the wrist (the region the method keeps), the
    placards are distinct objects in the image (no placard overlaps or hides another), and (with
    ``margin_deg`` > 0) the arm points at the intended placard more nearly than at any other by
    at least that angle.
    """
    truth = frame.meta["keypoints_truth"]
    if truth is None:
        return False
    if margin_deg > 0 and pointing_margin_deg(scenario, frame) < margin_deg:
        return False
    placards = frame.meta["placards"]
    target = np.asarray(placards[scenario.target_id]["left_polygon_px"], np.float32)
    if target[:, 0].min() < truth["left"]["wrist"][0] + offset_px or not placards[scenario.target_id]["visible"]:
        return False
    polygons = [np.asarray(p["left_polygon_px"], np.float32) for p in placards.values()]
    for i, a in enumerate(polygons):
        for b in polygons[i + 1:]:
            if cv2.intersectConvexConvex(a, b)[0] > 0:
                return False
    return True


def scenes(tmp: Path, n_scenes: int, near: bool, seed0: int, margin_deg: float = 0.0):
    """Yield n_scenes (scenario, frame) pairs where the method applies (others are drawn again)."""
    rng = np.random.default_rng(1234 + seed0)
    made = 0
    for k in range(20 * n_scenes):
        scenario, frame = render_scene(tmp, scene_spec(rng, near), seed0 + k)
        if method_applies(scenario, frame, margin_deg=margin_deg):
            made += 1
            yield scenario, frame
            if made == n_scenes:
                return


def scene_counts(tmp: Path, n_scenes: int, near: bool, draws: int, seed0: int = 0, margin_deg: float = 0.0,
                 overrides=()):
    """Yield (pointing margin deg, {profile: {noise: [correct, trials]}}) per generated scene.

    ``overrides``: ``KEY=VALUE`` parameters for both profiles (as ``scene_families.tally_family``'s).
    """
    for k, (scenario, frame) in enumerate(scenes(tmp, n_scenes, near, seed0, margin_deg)):
        counts = {p: {n: [0, 0] for n in NOISE_PX} for p in ("paper", "default")}
        truth = frame.meta["keypoints_truth"]
        polygon = np.asarray(frame.meta["placards"][scenario.target_id]["left_polygon_px"], np.float32)
        rig = scenario.rig()
        left_rect, right_rect = rig.rectify(frame.left, frame.right)
        for profile in ("paper", "default"):
            params = load_params(profile, overrides=overrides)
            pose = GivenKeypoints("right", truth)
            perception = Perception(rig, params, pose)
            cands = perception.detector.detect(left_rect, right_rect, pose.estimate(left_rect, right_rect, rig), rig)
            draw_rng = np.random.default_rng(seed0 + k)
            for sigma in NOISE_PX:
                for _ in range(draws if sigma > 0 else 1):
                    pose.provide(noisy(truth, sigma, draw_rng))
                    checked = perception.check_arm(perception.estimate_arm(left_rect, right_rect))
                    hit = False
                    if checked.status == "ok":
                        result = perception.decide(checked, cands, images=(left_rect, right_rect))
                        if result.target_rect_px is not None:
                            px = rig.to_original(result.target_rect_px, "left")[0]
                            hit = cv2.pointPolygonTest(polygon, (float(px[0]), float(px[1])), False) >= 0
                    counts[profile][sigma][0] += int(hit)
                    counts[profile][sigma][1] += 1
        yield pointing_margin_deg(scenario, frame), counts


def total(per_scene, margin_deg: float = 0.0) -> dict:
    """Return {profile: {noise: [correct, trials]}} summed over scenes with at least margin_deg."""
    out = {p: {n: [0, 0] for n in NOISE_PX} for p in ("paper", "default")}
    for margin, counts in per_scene:
        if margin >= margin_deg:
            for p, by_noise in counts.items():
                for n, (hit, trials) in by_noise.items():
                    out[p][n][0] += hit
                    out[p][n][1] += trials
    return out


def evaluate(tmp: Path, n_scenes: int, near: bool, draws: int, seed0: int = 0, margin_deg: float = 0.0) -> dict:
    """Return {profile: {noise: [correct, trials]}} over generated scenes."""
    return total(scene_counts(tmp, n_scenes, near, draws, seed0, margin_deg))


def table(counts: dict) -> str:
    """Return the accuracy table as text."""
    lines = ["noise_px  " + "  ".join(f"{p:>16}" for p in counts)]
    for sigma in NOISE_PX:
        cells = [f"{c[sigma][0] / max(c[sigma][1], 1):6.1%} ({c[sigma][0]:3d}/{c[sigma][1]:3d})" for c in counts.values()]
        lines.append(f"{sigma:8.0f}  " + "  ".join(f"{c:>16}" for c in cells))
    return "\n".join(lines)


def test_default_beats_paper_at_every_noise_level(tmp_path):
    """Diver and objects at 1-3 m: default > paper at every noise level, >= 85 % at 2 px."""
    counts = evaluate(tmp_path, n_scenes=10, near=True, draws=4)
    print("\n" + table(counts))
    acc = {p: {n: c[0] / c[1] for n, c in v.items()} for p, v in counts.items()}
    for sigma in NOISE_PX:
        assert acc["default"][sigma] >= acc["paper"][sigma], (sigma, acc)
    for sigma in NOISE_PX[1:]:
        assert acc["default"][sigma] > acc["paper"][sigma], (sigma, acc)
    assert acc["default"][2.0] >= 0.85, acc


def test_open_set_families_never_confidently_wrong(tmp_path):
    """Far, faint, undetectable and elbow-clutter scenes at 2 px: no confident wrong pick where the
    target is detectable, targets found; where it cannot be detected, rarely a confident pick.

    A few scenes per family (the script runs the full set: there, at 2 px, 0.38 % (seed 500) and
    0.75 % (seed 900) of all draws are confidently wrong (session 22, the given arm matched along the
    rows; 0.75 / 0.25 % in session 21, 1.75 / 0.75 % before session 19's unrecognised spots), nearly
    all in scenes whose target cannot be detected).
    """
    import scene_families as sf
    tally = sf.Tally()
    for family, n in (("far", 3), ("elbow", 3), ("undetectable", 12)):
        sf.tally_family(tmp_path, family, n, 2, seed0=0, noise_px=(2.0,), profiles=("default",), tally=tally)
    print(sf.report(tally, noise_px=(2.0,), families=("far", "undetectable", "elbow")))
    hit, total = tally.merged_recall("default", ("far", "elbow"))
    assert total == 6 and hit == total
    detectable = tally.merged("default", 2.0, ("far", "elbow"))
    assert detectable["confident_wrong"] == 0, detectable
    assert detectable["correct"] >= 0.6 * sum(detectable.values()), detectable
    undetectable = tally.merged("default", 2.0, ("undetectable",))
    assert undetectable["confident_wrong"] <= 1, undetectable
    assert undetectable["correct"] + undetectable["abstained"] >= 0.6 * sum(undetectable.values()), undetectable


if __name__ == "__main__":  # pragma: no cover - the full table for the closing note
    import tempfile
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 40
    if len(sys.argv) > 2 and sys.argv[2] == "families":  # the open-set families (scene_families.py)
        import scene_families as sf
        seed0 = int(sys.argv[3]) if len(sys.argv) > 3 else 500
        overrides = sys.argv[4:]  # KEY=VALUE parameters for both profiles, e.g. pose.match_disparity=true
        everything = sf.Tally()
        with tempfile.TemporaryDirectory() as tmp:
            for family in sf.FAMILIES:
                sf.tally_family(Path(tmp), family, n, 8, seed0, tally=everything, overrides=overrides)
        print(sf.report(everything))
        print("\n" + sf.band_table(everything) + "\n")
        for profile in ("paper", "default"):
            for sigma in NOISE_PX:
                det = everything.merged(profile, sigma, ("line_of_sight", "far", "elbow", "far_diver"))
                und = everything.merged(profile, sigma, ("undetectable",))
                allc = everything.merged(profile, sigma)
                unsure = everything.merged_unsure(profile, sigma, ("line_of_sight", "far", "elbow", "far_diver"))
                print(f"{profile} {sigma:.0f}px: detectable correct {sf.rate(det, 'correct'):.1%} "
                      f"(flagged ambiguous {unsure / max(sum(det.values()), 1):.1%}), abstained "
                      f"{sf.rate(det, 'abstained'):.1%}; undetectable nothing_on_ray/correct {sf.rate(und, 'correct'):.1%}; "
                      f"confidently wrong {sf.rate(allc, 'confident_wrong'):.2%} of all draws")
            hit, total = everything.merged_recall(profile)
            print(f"{profile} detection recall {hit}/{total}")
        sys.exit(0)
    with tempfile.TemporaryDirectory() as tmp:
        for near in (True, False):
            per_scene = list(scene_counts(Path(tmp), n, near, draws=8, seed0=1000 if near else 5000))
            clear = sum(m >= CLEAR_DEG for m, _ in per_scene)
            print(f"\n{'1-3 m' if near else '1-5 m'}, {n} scenes")
            print(table(total(per_scene)))
            print(f"the {clear} of them where the arm points {CLEAR_DEG:.0f} deg more nearly at the target than at any other")
            print(table(total(per_scene, CLEAR_DEG)))
