"""The families' noisy draws of one scene, at one noise level, as ``scene_families.tally_family`` draws them."""
from __future__ import annotations

import sys
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import scene_families as sf


def draws(scene: sf.Scene, seed0: int, k: int, sigma_px: float) -> Iterator[tuple[int, dict, dict]]:
    """Yield (draw, noisy keypoints, truth joints in the rectified left frame, metres) at ``sigma_px``.

    The generator is the families' own (seeded ``seed0 + k``, 1 draw at 0 px then 8 per level), so draw d
    here is draw d of the families' tally.
    """
    truth = scene.frame.meta["keypoints_truth"]
    rig = scene.scenario.rig()
    joints = {j: rig.R1 @ np.asarray(v) for j, v in scene.frame.meta["joints_cam_m"].items()}
    rng = np.random.default_rng(seed0 + k)
    for s in (0.0, 1.0, 2.0, 4.0):
        for d in range(8 if s > 0 else 1):
            kp = sf.noisy(truth, s, rng)
            if s == sigma_px:
                yield d, kp, joints


def truth_disparities(rig, truth: dict) -> np.ndarray:
    """Return the truth shoulder, elbow and wrist's rectified disparities x_left - x_right (pixels).

    ``truth``: a frame's ``meta["keypoints_truth"]`` (original-image pixels per eye and joint).
    """
    names = ("shoulder", "elbow", "wrist")
    left = rig.to_rectified(np.array([truth["left"][j] for j in names], float), "left")
    right = rig.to_rectified(np.array([truth["right"][j] for j in names], float), "right")
    return left[:, 0] - right[:, 0]


def given_arms(tmp, family: str, n: int, seed0: int, sigma_px: float) -> Iterator[tuple]:
    """Yield (rig, left, right, the given arm, the body's disparity px, truth disparities px) per draw at ``sigma_px``.

    The arm is the keypoints' own (``pose.estimate``, before any matching), over ``n`` scenes of a family.
    """
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        rig, left, right, pose, _, _, _ = sf.prepared(scene, "default")
        dt = truth_disparities(rig, scene.frame.meta["keypoints_truth"])
        for _, kp, _ in draws(scene, seed0, k, sigma_px):
            pose.provide(kp)
            raw = pose.estimate(left, right, rig)
            yield rig, left, right, raw, float(np.median(raw.left_px[:, 0] - raw.right_px[:, 0])), dt


def nth_scene(tmp, family: str, seed0: int, n: int) -> sf.Scene:
    """Return scene ``n`` (from 0) of a family as the families' tally draws it (``tmp``: a folder for its files)."""
    for k, scene in enumerate(sf.scenes(tmp, family, n + 1, seed0)):
        if k == n:
            return scene
    raise ValueError(f"{family} seed {seed0} has no scene {n}")


def scene_args(argv: list[str] | None = None) -> tuple[str, int, int, float, int, list[str]]:
    """Return (family, seed0, scene, noise px, draw, KEY=VALUE overrides) of ``FAMILY SEED0 SCENE [NOISE_PX DRAW] [K=V ...]``."""
    a = sys.argv[1:] if argv is None else argv
    return (a[0], int(a[1]), int(a[2]), float(a[3]) if len(a) > 3 else 0.0, int(a[4]) if len(a) > 4 else 0,
            list(a[5:]))


@dataclass(frozen=True)
class ArmDraw:
    """One noisy draw of a family scene: the rig, the rectified pair, the pose's arm and the truth joints.

    The arm is the pose source's (keypoints as drawn, rectified px) before any row matching.
    """

    scene: int
    rig: object
    left: np.ndarray
    right: np.ndarray
    arm: object
    joints: dict

    @property
    def fb(self) -> float:
        """Return focal length x baseline (px m): depth = fb / disparity."""
        return self.rig.focal_px * self.rig.baseline_m

    @property
    def given_px(self) -> np.ndarray:
        """Return the drawn keypoints' own disparities x_left - x_right (px) per joint."""
        return self.arm.left_px[:, 0] - self.arm.right_px[:, 0]

    @property
    def body_px(self) -> float:
        """Return the body's disparity as ``joint_stereo.match_arm`` takes it: the keypoints' median (px)."""
        return float(np.median(self.given_px))


def arm_draws(tmp, family: str, n: int, seed0: int, sigma_px: float, profile: str = "default") -> Iterator[ArmDraw]:
    """Yield an ``ArmDraw`` for every draw of a family's first n scenes (``tmp``: a folder for the scenes' files)."""
    for k, scene in enumerate(sf.scenes(tmp, family, n, seed0)):
        rig, left, right, pose, _, _, _ = sf.prepared(scene, profile)
        for _, kp, joints in draws(scene, seed0, k, sigma_px):
            pose.provide(kp)
            yield ArmDraw(k, rig, left, right, pose.estimate(left, right, rig), joints)


FAMILIES = ("line_of_sight", "far", "undetectable", "elbow", "far_diver")
"""The open-set families, in the order the analysis scripts report them."""


def family_arm_draws(argv: list[str] | None = None):
    """Yield (family, its ``arm_draws``) for every family, from ``SEED0 [N_SCENES] [NOISE_PX]`` (20 scenes, 2 px)."""
    a = sys.argv[1:] if argv is None else argv
    seed0, n = int(a[0]), int(a[1]) if len(a) > 1 else 20
    noise = float(a[2]) if len(a) > 2 else 2.0
    with tempfile.TemporaryDirectory() as tmp:
        for family in FAMILIES:
            yield family, arm_draws(Path(tmp), family, n, seed0, noise)
