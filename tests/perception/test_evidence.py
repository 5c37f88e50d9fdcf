"""The arm's evidence for each object, averaged over draws of the arm (stereo depth and keypoint noise)."""

from __future__ import annotations

import math

import numpy as np

from dip3d_vehicle.perception.evidence import arm_evidence

F_PX, C_PX = 920.0, (800.0, 600.0)
SHOULDER = np.array([-0.3, 0.0, 3.0])


def _project(xyz: np.ndarray) -> np.ndarray:
    """Return rectified left pixels of camera-frame points (N, 3)."""
    xyz = np.atleast_2d(xyz)
    return np.c_[xyz[:, 0] / xyz[:, 2] * F_PX + C_PX[0], xyz[:, 1] / xyz[:, 2] * F_PX + C_PX[1]]


def _direction(tilt_deg: float) -> np.ndarray:
    """Return a unit vector to the camera's right, tilted away from the camera by ``tilt_deg`` (negative: toward)."""
    t = math.radians(tilt_deg)
    return np.array([math.cos(t), 0.0, math.sin(t)])


def _evidence(joints_m: np.ndarray, depth_m: np.ndarray, depth_sigma_m: float, objects_m: list[np.ndarray]):
    """Return the evidence for objects given exact image joints and the given stereo depths."""
    return arm_evidence(_project(joints_m), depth_m, np.full(3, depth_sigma_m), F_PX, C_PX, 2.0, (0.22, 0.29),
                        (0.27, 0.37), 0.02, 0.05, 0.08, 0.03, objects_m, np.full(len(objects_m), 0.05))


def _ray_object(origin: np.ndarray, direction: np.ndarray, distance_m: float) -> np.ndarray:
    """Return a small square object (5 points, 0.1 m) centred ``distance_m`` along a ray."""
    centre = origin + distance_m * direction
    return centre + np.array([[0, 0, 0], [0.05, 0.05, 0], [-0.05, 0.05, 0], [0.05, -0.05, 0], [-0.05, -0.05, 0]])


def _scene(true_tilt_deg: float):
    """Return the arm (straight, 0.58 m) and objects 2 m along three tilts: +45 (away), -45 (toward), 0 (level).

    All three lie on one image line through the arm only if the arm's image direction is the same for
    each; they do, up to perspective, because the tilt only moves them along the line of sight.
    """
    u = _direction(true_tilt_deg)
    joints = np.array([SHOULDER, SHOULDER + 0.3 * u, SHOULDER + 0.58 * u])
    objects = [_ray_object(SHOULDER, _direction(t), 2.0) for t in (45.0, -45.0, 0.0)]
    return joints, objects


def test_a_foreshortened_arm_keeps_both_tilts_and_rules_out_the_level_one():
    """Stereo depths that say "level" (noise flattened a 45 deg tilt) with 0.25 m sigma: the limb lengths
    say the arm leans 45 deg, toward OR away; both objects along those tilts outweigh the level one."""
    joints, objects = _scene(45.0)
    flat = np.full(3, SHOULDER[2])
    ev = _evidence(joints, flat, 0.25, objects)
    away, toward, level = ev.log_density
    assert away > level + 1.5 and toward > level + 1.5  # each over 4x as likely
    assert abs(away - toward) < 1.5  # the image alone cannot say which way
    assert ev.effective_samples > 20


def test_stereo_depths_that_resolve_the_tilt_pick_its_sign():
    """Depths measured to 2 cm along the true tilt (away): the object toward the camera loses."""
    joints, objects = _scene(45.0)
    ev = _evidence(joints, joints[:, 2], 0.02, objects)
    away, toward, level = ev.log_density
    assert away > toward + 5.0 and away > level + 5.0


def test_an_object_behind_the_wrist_gets_no_evidence_and_the_draws_are_fixed():
    """Behind the hand: density zero (log -inf). The same inputs give the same evidence (fixed draws)."""
    joints, objects = _scene(0.0)
    behind = _ray_object(SHOULDER, -_direction(0.0), 1.0)
    first = _evidence(joints, joints[:, 2], 0.05, [*objects, behind])
    second = _evidence(joints, joints[:, 2], 0.05, [*objects, behind])
    assert first.log_density[3] == -np.inf
    np.testing.assert_array_equal(first.log_density, second.log_density)
    assert first.log_density[2] > first.log_density[0]  # a level arm: the level object
