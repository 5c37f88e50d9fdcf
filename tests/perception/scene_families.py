"""Generated scene families for the open-set selector: far, small, faint, undetectable, elbow clutter.

Every scene is a simulator scenario (rendered by ``sitl.render``): numbered textured placards, a
diver pointing with the right arm with a 5 deg pointing error, the simulator's lens distortion and
small rotation between the cameras, 1600x1200. Families:

- ``line_of_sight``: the earlier test's scenes, 1-3 m, two placards on one line of sight.
- ``far``: 4-5 placards out to 6 m, the pointed one at 3-6 m, 0.2-0.3 m wide, red attenuation up to
  0.35 /m and some turbidity.
- ``undetectable``: as ``far``, but the pointed placard is 3-8 cm wide (a few pixels): nothing
  pointed at can be detected, the right answer is ``nothing_on_ray``.
- ``elbow``: distractor placards beside the diver's elbow and below the arm, the pointed one at 2-5 m.
- ``far_diver``: the diver at 4-6 m, the placards at 1-6 m.

Outcomes per draw: ``correct`` (the chosen point inside the pointed placard; for ``undetectable``,
also the status ``nothing_on_ray``: its few pixels are sometimes matched after all), ``abstained`` (``nothing_on_ray``, flagged ambiguous, pose rejected
or no decision), ``confident_wrong`` (another object with confidence >= 0.8, not flagged
ambiguous) and ``wrong`` (another object, unsure). A pick inside the pointed placard counts as
``correct`` even when the selector flagged it ambiguous (confidence under
``selection.min_confidence``); such picks are also counted apart (``Tally.unsure``), and the
headline line says their share: on seed 900 at 2 px, 36 of the 82 points of detectable "correct"
(docs/issue11/session15).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np
import yaml

FAMILIES = ("line_of_sight", "far", "undetectable", "elbow", "far_diver")
DETECTABLE_PX = 40.0
"""A placard at least this wide in both images must be detected (the recall figure counts these)."""
CONFIDENT = 0.8
"""Confidence at or above which a wrong pick (not flagged ambiguous) is confidently wrong."""
OUTCOMES = ("correct", "abstained", "confident_wrong", "wrong")
MARGIN_DEG = 3.0
"""Every other placard lies at least this much farther (deg, seen from the shoulder) from the arm's
line than the pointed one: a 5 deg pointing error must not point equally at two placards."""


def _placard(pid: int, rng: np.random.Generator, r: tuple[float, float], bearing: tuple[float, float],
             size: tuple[float, float]) -> dict:
    """Return one random placard node (range, bearing, depth, size)."""
    return {"id": pid, "range_m": float(rng.uniform(*r)), "bearing_deg": float(rng.uniform(*bearing)),
            "depth_m": float(rng.uniform(0.6, 1.5)), "size_m": float(rng.uniform(*size))}


def _spread(placards: list[dict], cand: dict) -> bool:
    """Return True when ``cand`` is apart from every placard (bearing or range)."""
    return all(abs(cand["bearing_deg"] - p["bearing_deg"]) > 6 or abs(cand["range_m"] - p["range_m"]) > 0.8
               for p in placards)


def _water(rng: np.random.Generator, faint: bool) -> dict:
    """Return a water node: the pool's, or attenuated (up to 0.35 /m), turbid, dimmer water."""
    if not faint:
        return {}
    c = float(rng.uniform(0.15, 0.35))
    return {"attenuation_per_m": [c * float(rng.uniform(0.5, 1.0)), c * float(rng.uniform(0.6, 1.0)), c],
            "turbidity_per_m": float(rng.uniform(0.02, 0.08)), "ambient_light": float(rng.uniform(0.5, 0.85)),
            "light_falloff_per_m2": float(rng.uniform(0.02, 0.06))}


def scene_spec(family: str, rng: np.random.Generator) -> dict:
    """Return a scenario mapping of one scene of ``family``."""
    if family == "line_of_sight":
        return _line_of_sight(rng)
    faint = family in ("far", "undetectable", "far_diver")
    diver_range = rng.uniform(4.0, 6.0) if family == "far_diver" else rng.uniform(1.5, 3.5)
    target_range = (3.0, 6.0) if family in ("far", "undetectable") else (2.0, 5.0)
    size = (0.03, 0.08) if family == "undetectable" else (0.2, 0.3)
    placards = [_placard(1, rng, target_range, (3.0, 30.0), size)]
    for pid in range(2, int(rng.integers(4, 6)) + 1):
        for _ in range(50):
            cand = _placard(pid, rng, (1.0, 6.0), (3.0, 35.0), (0.2, 0.3))
            if _spread(placards, cand):
                placards.append(cand)
                break
    diver_bearing = float(rng.uniform(-26.0, -14.0)) if family != "far_diver" else float(rng.uniform(-14.0, -6.0))
    if family == "elbow":
        for pid in (8, 9):
            placards.append({"id": pid, "range_m": float(diver_range + rng.uniform(-0.4, 0.3)),
                             "bearing_deg": float(diver_bearing + rng.uniform(6.0, 14.0)),
                             "depth_m": float(rng.uniform(1.25, 1.7)), "size_m": float(rng.uniform(0.15, 0.25)),
                             "role": "distractor"})
    return {"base": "paper_pool", "placards": placards, "track_line": None, "water": _water(rng, faint),
            "diver": {"positions": [{"name": "g", "range_m": float(diver_range), "bearing_deg": diver_bearing,
                                     "depth_m": 1.0}], "target": 1},
            "pose_source": {"noise_px": 0.0, "dropout": 0.0}}


def _line_of_sight(rng: np.random.Generator) -> dict:
    """Return the earlier test's 1-3 m scene: two placards on one line of sight, two elsewhere."""
    from test_synthetic_accuracy import scene_spec as earlier_scene
    return earlier_scene(rng, near=True)


@dataclass
class Scene:
    """One rendered scene with what the tally needs to judge a result."""

    family: str
    scenario: object
    frame: object
    target_width_px: float
    target_range_m: float

    @property
    def target_polygon(self) -> np.ndarray:
        """Return the pointed placard's polygon in original left pixels."""
        return np.asarray(self.frame.meta["placards"][self.scenario.target_id]["left_polygon_px"], np.float32)

    @property
    def detectable(self) -> bool:
        """Return True when the pointed placard is at least DETECTABLE_PX wide in both images."""
        return self.target_width_px >= DETECTABLE_PX

    @property
    def band(self) -> str:
        """Return the range band of the pointed placard: "1-3 m" or "3-6 m"."""
        return "1-3 m" if self.target_range_m < 3.0 else "3-6 m"


def render_scene(tmp: Path, family: str, spec: dict, seed: int) -> Scene:
    """Write, load and render one scene (one frame while the diver points)."""
    from sitl.render import StereoRenderer
    from sitl.scenario import load_scenario
    path = tmp / f"{family}_{seed}.yaml"
    path.write_text(yaml.safe_dump(spec))
    scenario = load_scenario(str(path), seed)
    with StereoRenderer(scenario) as renderer:
        frame = renderer.render(*scenario.initial_vehicle_pose, 2.0)
    info = frame.meta["placards"][scenario.target_id]
    width = 0.0
    if info["left_polygon_px"] is not None:
        poly = np.asarray(info["left_polygon_px"], float)
        width = float(poly[:, 0].max() - poly[:, 0].min())
        disparity = scenario.camera.fx * scenario.camera.baseline_m / max(info["xyz_cam_m"][2], 0.05)
        if poly[:, 0].min() - disparity < 0:  # cut by the right image's edge
            width = min(width, float(poly[:, 0].max() - disparity))
    return Scene(family, scenario, frame, width, float(np.linalg.norm(info["xyz_cam_m"])))


def usable(scene: Scene) -> bool:
    """Return True when the scene meets the method's preconditions (others are drawn again).

    The diver's arm is seen, the pointed placard is in view and wholly beyond the wrist, and no
    two placards overlap in the image.
    """
    meta = scene.frame.meta
    truth = meta["keypoints_truth"]
    info = meta["placards"][scene.scenario.target_id]
    if truth is None or info["left_polygon_px"] is None or not info["visible"]:
        return False
    if scene.target_polygon[:, 0].min() < truth["left"]["wrist"][0] + 40.0:
        return False
    polygons = [np.asarray(p["left_polygon_px"], np.float32) for p in meta["placards"].values()
                if p["left_polygon_px"] is not None]
    for i, a in enumerate(polygons):
        for b in polygons[i + 1:]:
            if cv2.intersectConvexConvex(a, b)[0] > 0:
                return False
    if scene.family != "line_of_sight" and pointing_margin_deg(scene) < MARGIN_DEG:
        return False
    if scene.family == "undetectable":
        return scene.target_width_px < 15.0
    return scene.target_width_px >= DETECTABLE_PX


def pointing_margin_deg(scene: Scene) -> float:
    """Return how much farther (deg, seen from the shoulder) the next placard is from the arm's line.

    The simulated arm is straight from the shoulder with its pointing error included: this is the
    angle between the arm and the nearest other placard's centre minus that to the pointed one.
    """
    joints = {k: np.asarray(v, float) for k, v in scene.frame.meta["joints_cam_m"].items()}
    axis = joints["wrist"] - joints["shoulder"]
    axis /= np.linalg.norm(axis)

    def angle(info: dict) -> float:
        d = np.asarray(info["xyz_cam_m"], float) - joints["shoulder"]
        return float(np.degrees(np.arccos(np.clip(d @ axis / np.linalg.norm(d), -1.0, 1.0))))

    placards = scene.frame.meta["placards"]
    target = angle(placards[scene.scenario.target_id])
    return min((angle(p) - target for pid, p in placards.items() if pid != scene.scenario.target_id), default=180.0)


def scenes(tmp: Path, family: str, n_scenes: int, seed0: int):
    """Yield ``n_scenes`` usable scenes of a family (unusable draws are drawn again)."""
    rng = np.random.default_rng(7919 + seed0)
    made = 0
    for k in range(30 * n_scenes):
        scene = render_scene(tmp, family, scene_spec(family, rng), seed0 + k)
        if usable(scene):
            made += 1
            yield scene
            if made == n_scenes:
                return


def noisy(keypoints: dict, sigma_px: float, rng: np.random.Generator) -> dict:
    """Return a keypoints dict with Gaussian noise of sigma_px added to every point."""
    out = {"rectified": False, "source": "test"}
    for side in ("left", "right"):
        out[side] = {k: (np.asarray(v, float) + rng.normal(0.0, sigma_px, 2)).tolist()
                     for k, v in keypoints[side].items()}
    return out


def outcome(scene: Scene, result, rig) -> str:
    """Return the outcome of one perception result on a scene (see OUTCOMES)."""
    if scene.family == "undetectable" and result.status == "nothing_on_ray":
        return "correct"
    if result.status == "ok" and result.target_rect_px is not None:
        px = rig.to_original(result.target_rect_px, "left")[0]
        if cv2.pointPolygonTest(scene.target_polygon, (float(px[0]), float(px[1])), False) >= 0:
            return "correct"
    sel = result.selection
    if result.status != "ok" or sel is None or sel.target is None or sel.ambiguous:
        return "abstained"
    return "confident_wrong" if sel.confidence >= CONFIDENT else "wrong"


def target_detected(scene: Scene, candidates_left_px: np.ndarray) -> bool:
    """Return True when some candidate (original left px) lies on the pointed placard."""
    poly = scene.target_polygon
    return any(cv2.pointPolygonTest(poly, (float(x), float(y)), False) >= 0 for x, y in candidates_left_px)


def _selected(key: tuple, profile: str, noise: float, families, bands) -> bool:
    """True when a (profile, family, band, noise_px) key is one of those asked for."""
    p, f, b, n = key
    return p == profile and n == noise and f in families and b in bands


@dataclass
class Tally:
    """Outcome counts per (profile, family, band, noise) and detection recall per (profile, family, band)."""

    outcomes: dict = field(default_factory=dict)
    recall: dict = field(default_factory=dict)
    unsure: dict = field(default_factory=dict)   # "correct" picks the selector flagged ambiguous, per key

    def add(self, key: tuple, what: str, flagged_ambiguous: bool = False) -> None:
        """Count one outcome under ``key`` = (profile, family, band, noise_px); ``flagged_ambiguous``: a
        "correct" pick the selector itself called ambiguous (counted as correct, and apart)."""
        self.outcomes.setdefault(key, dict.fromkeys(OUTCOMES, 0))[what] += 1
        if what == "correct" and flagged_ambiguous:
            self.unsure[key] = self.unsure.get(key, 0) + 1

    def merged_unsure(self, profile: str, noise: float, families=FAMILIES, bands=("1-3 m", "3-6 m")) -> int:
        """Return how many "correct" picks were flagged ambiguous, summed over families and bands."""
        return sum(v for key, v in self.unsure.items() if _selected(key, profile, noise, families, bands))

    def add_recall(self, key: tuple, hit: bool) -> None:
        """Count one detectable scene under ``key`` = (profile, family, band)."""
        cell = self.recall.setdefault(key, [0, 0])
        cell[0] += int(hit)
        cell[1] += 1

    def merged(self, profile: str, noise: float, families=FAMILIES, bands=("1-3 m", "3-6 m")) -> dict:
        """Return outcome counts summed over families and bands."""
        out = dict.fromkeys(OUTCOMES, 0)
        for key, counts in self.outcomes.items():
            if _selected(key, profile, noise, families, bands):
                for k, v in counts.items():
                    out[k] += v
        return out

    def merged_recall(self, profile: str, families=FAMILIES, bands=("1-3 m", "3-6 m")) -> tuple[int, int]:
        """Return (detected, detectable scenes) summed over families and bands."""
        hit = total = 0
        for (p, f, b), (h, t) in self.recall.items():
            if p == profile and f in families and b in bands:
                hit, total = hit + h, total + t
        return hit, total


def rate(counts: dict, what: str) -> float:
    """Return the fraction of draws with outcome ``what``."""
    return counts[what] / max(sum(counts.values()), 1)


def prepared(scene: Scene, profile: str, overrides=()) -> tuple:
    """Return (rig, left, right, pose, perception, arm, base) for deciding noisy draws on one scene.

    The rectified pair, a ``GivenKeypoints`` pose (truth first), the profile's ``Perception``, the truth
    arm and the main candidate pass (which does not depend on keypoint noise).
    """
    from dip3d_vehicle.config import load_params
    from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
    from dip3d_vehicle.perception.pipeline import Perception
    rig = scene.scenario.rig()
    left, right = rig.rectify(scene.frame.left, scene.frame.right)
    pose = GivenKeypoints("right", scene.frame.meta["keypoints_truth"])
    perception = Perception(rig, load_params(profile, overrides=overrides), pose)
    arm = pose.estimate(left, right, rig)
    return rig, left, right, pose, perception, arm, perception.detector.detect(left, right, arm, rig)


def decided(perception, left, right, base):
    """Return the perception result of the pose's current keypoints: the arm checked, then the corridor
    added to the main pass ``base`` and the selection made (with the spots) when the arm is usable."""
    checked = perception.check_arm(perception.estimate_arm(left, right))
    if checked.status != "ok":
        return checked
    return perception.decide(checked, perception.add_corridor(left, right, checked.arm, base), images=(left, right))


def tally_family(tmp: Path, family: str, n_scenes: int, draws: int, seed0: int, noise_px=(0.0, 1.0, 2.0, 4.0),
                 profiles=("paper", "default"), tally: Tally | None = None, overrides=()) -> Tally:
    """Run both selectors over generated scenes of one family; return the outcome and recall tally.

    The main candidate pass runs once per scene and profile (it does not depend on keypoint
    noise); the pointing corridor, which does, runs on every noisy draw (``overrides``: ``KEY=VALUE``
    parameters for every profile). Recall counts the
    scenes whose pointed placard is detectable: some candidate (an object for ``default``, a
    feature for ``paper``) lies on it, with the truth keypoints.
    """
    tally = tally or Tally()
    for k, scene in enumerate(scenes(tmp, family, n_scenes, seed0)):
        truth = scene.frame.meta["keypoints_truth"]
        for profile in profiles:
            rig, left, right, pose, perception, arm, base = prepared(scene, profile, overrides)
            if scene.detectable:
                clean = perception.decide(perception.check_arm(arm), perception.add_corridor(left, right, arm, base))
                objs = clean.selection.objects if clean.selection else ()
                px = rig.to_original(np.array([o.left_px for o in objs]), "left") if objs else np.zeros((0, 2))
                tally.add_recall((profile, family, scene.band), target_detected(scene, px))
            rng = np.random.default_rng(seed0 + k)
            for sigma in noise_px:
                for _ in range(draws if sigma > 0 else 1):
                    pose.provide(noisy(truth, sigma, rng))
                    result = decided(perception, left, right, base)
                    sel = result.selection
                    flagged = result.status == "ok" and sel is not None and sel.target is not None and sel.ambiguous
                    tally.add((profile, family, scene.band, sigma), outcome(scene, result, rig), flagged)
    return tally


def report(tally: Tally, noise_px=(0.0, 1.0, 2.0, 4.0), families=FAMILIES) -> str:
    """Return the tables: per family and band, per noise level, both profiles; then the headline."""
    lines = []
    for profile in ("paper", "default"):
        lines.append(f"\n{profile}: correct / abstained / confidently wrong / wrong (unsure), % of draws; recall")
        for family in families:
            for band in ("1-3 m", "3-6 m"):
                cells = []
                for sigma in noise_px:
                    c = tally.merged(profile, sigma, (family,), (band,))
                    if sum(c.values()):
                        cells.append(f"{sigma:.0f}px {rate(c, 'correct'):4.0%}/{rate(c, 'abstained'):4.0%}/"
                                     f"{rate(c, 'confident_wrong'):4.0%}/{rate(c, 'wrong'):4.0%}")
                hit, total = tally.merged_recall(profile, (family,), (band,))
                if cells:
                    lines.append(f"  {family:14s} {band}  " + "  ".join(cells) + (f"  recall {hit}/{total}" if total else ""))
    return "\n".join(lines)


def band_table(tally: Tally, noise_px=(0.0, 1.0, 2.0, 4.0)) -> str:
    """Return the issue's table: per profile, range band and noise, correct / abstained / confidently wrong.

    Detectable targets (every family but ``undetectable``) and undetectable ones are counted apart,
    as the targets are; recall is per band over the detectable targets.
    """
    lines = ["profile  band   noise  detectable: correct/abstained/conf.wrong (draws)  "
             "undetectable: nothing_on_ray/abstained/conf.wrong (draws)  recall"]
    detectable = tuple(f for f in FAMILIES if f != "undetectable")
    for profile in ("paper", "default"):
        for band in ("1-3 m", "3-6 m"):
            hit, total = tally.merged_recall(profile, detectable, (band,))
            for sigma in noise_px:
                det = tally.merged(profile, sigma, detectable, (band,))
                und = tally.merged(profile, sigma, ("undetectable",), (band,))
                cells = [f"{rate(c, 'correct'):6.1%}/{rate(c, 'abstained'):6.1%}/{rate(c, 'confident_wrong'):5.1%}"
                         f" ({sum(c.values()):3d})" if sum(c.values()) else f"{'-':>28s}" for c in (det, und)]
                lines.append(f"{profile:8s} {band}  {sigma:3.0f}px  {cells[0]:>40s}  {cells[1]:>48s}  {hit}/{total}")
    return "\n".join(lines)
