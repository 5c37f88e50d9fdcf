"""How strongly one frame's arm says "this object", as an expectation over the arm's own uncertainty.

The default selector weighs "the arm points at object i" against "it points at something nobody
detected". The second spreads the target uniformly over a solid angle; the first concentrates it
by the pointing model's angular density around the arm's true direction. That direction is not
known: the joints' stereo depths leave the arm's tilt toward or away from the camera uncertain,
and the limb lengths and a nearly straight arm constrain it in a way that is far from Gaussian
(a foreshortened arm leans by the same angle toward OR away from the camera, two separate modes).

So the evidence for each object is the pointing density at that object averaged over the arm's
posterior, estimated by importance sampling: joint depths drawn from the stereo depths and their
sigmas, image positions from the keypoint noise, each draw weighted by the limb-length and
straightness priors. The draws come from a fixed generator (the same draws every frame), so the
result is deterministic. Units: metres, radians, pixels; densities per steradian.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr

__all__ = ["ArmEvidence", "arm_evidence"]

SEED = 20261123
"""Seed of the fixed draws (deterministic evidence, identical for every frame)."""


@dataclass(frozen=True)
class ArmEvidence:
    """Per-object log pointing density averaged over the arm's posterior (log sr^-1), and the draws' quality."""

    log_density: np.ndarray
    effective_samples: float


class _Draws:
    """Standard draws, fixed per sample count: image offsets, joint depths, limb lengths, tilt signs, object scale."""

    def __init__(self, samples: int) -> None:
        rng = np.random.default_rng(SEED)
        self.px = rng.standard_normal((samples, 3, 2))
        self.depth = rng.standard_normal((samples, 3))
        self.length_u = rng.random((samples, 2))
        self.length_n = rng.standard_normal((samples, 2))
        self.sign = np.where(rng.random((samples, 2)) < 0.5, -1.0, 1.0)
        self.scale = rng.standard_normal(samples)


_DRAWS: dict[int, _Draws] = {}

MASS_KEPT = 0.999
"""Share of the draws' total weight the object densities are averaged over (the lightest draws, which
change the evidence by less than 0.1 %, are skipped)."""

_LOG_SQRT_2PI = 0.5 * math.log(2.0 * math.pi)


def _log_normal(x: np.ndarray, mean: float, sigma: float) -> np.ndarray:
    """Return the log density of N(mean, sigma) at x."""
    return -0.5 * ((x - mean) / sigma) ** 2 - math.log(sigma) - _LOG_SQRT_2PI


def _log_length_proposal(length: np.ndarray, lo: float, hi: float, sigma: float) -> np.ndarray:
    """Return the log density of a limb length drawn uniform on [lo, hi] and blurred by N(0, sigma)."""
    return np.log(np.maximum(ndtr((length - lo) / sigma) - ndtr((length - hi) / sigma), 1e-300) / (hi - lo))


def _place(ray: np.ndarray, start: np.ndarray, length: np.ndarray, sign: np.ndarray) -> np.ndarray:
    """Return depths z along ``ray`` with |ray z - start| = length (the root picked by sign); NaN where none."""
    a = np.einsum("sj,sj->s", ray, ray)
    b = np.einsum("sj,sj->s", ray, start)
    disc = b * b - a * (np.einsum("sj,sj->s", start, start) - length * length)
    return (b + sign * np.sqrt(np.where(disc > 0, disc, np.nan))) / a


def _arm_draws(joints_px: np.ndarray, depth_m: np.ndarray, depth_sigma_m: np.ndarray, focal_px: float,
               principal_px: tuple[float, float], keypoint_sigma_px, forearm_m: tuple[float, float],
               upperarm_m: tuple[float, float], length_sigma_m: float, straightness_sigma_m: float,
               draws: _Draws) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return draws of the shoulder and wrist (S, 3) and their normalised weights under the arm's posterior.

    Two proposals, half the draws each (a defensive mixture): every joint's depth from its stereo
    depth; or the shoulder's from its stereo depth and the elbow and wrist placed on their (noisy)
    camera rays at drawn limb lengths, toward or away from the camera (what a far, foreshortened arm
    needs: its stereo depths say little, its limb lengths much). Each draw is weighted by the
    posterior (stereo depths, soft limb-length bounds, straightness) over the mixture's density.
    """
    cx, cy = principal_px
    n = len(draws.depth)
    half = n // 2
    px = joints_px[None, :, :] + np.broadcast_to(np.asarray(keypoint_sigma_px, float), (3,))[None, :, None] * draws.px
    rays = np.stack([(px[..., 0] - cx) / focal_px, (px[..., 1] - cy) / focal_px, np.ones(px.shape[:2])], axis=-1)
    z = depth_m[None, :] + depth_sigma_m[None, :] * draws.depth
    limbs = (upperarm_m, forearm_m)
    lengths = np.column_stack([lo + (hi - lo) * draws.length_u[:, k] for k, (lo, hi) in enumerate(limbs)])
    lengths = np.maximum(lengths + length_sigma_m * draws.length_n, 0.02)
    for k in (1, 2):
        start = rays[half:, k - 1] * z[half:, k - 1, None]
        z[half:, k] = _place(rays[half:, k], start, lengths[half:, k - 1], draws.sign[half:, k - 1])
    valid = np.all(np.isfinite(z) & (z > 0.05), axis=1)
    z = np.where(valid[:, None], z, 1.0)
    joints = rays * z[..., None]
    log_q1 = sum(_log_normal(z[:, k], depth_m[k], depth_sigma_m[k]) for k in range(3))
    log_q2 = _log_normal(z[:, 0], depth_m[0], depth_sigma_m[0]) + 2.0 * math.log(0.5)
    log_target = log_q1.copy()
    for k, (lo, hi) in enumerate(limbs):
        limb = joints[:, k + 1] - joints[:, k]
        length = np.maximum(np.linalg.norm(limb, axis=1), 1e-6)
        slope = np.abs(np.einsum("sj,sj->s", rays[:, k + 1], limb)) / length  # |d length / d depth|
        log_q2 += _log_length_proposal(length, lo, hi, length_sigma_m) + np.log(np.maximum(slope, 1e-9))
        log_target += -0.5 * (np.maximum(np.maximum(lo - length, 0.0), length - hi) / length_sigma_m) ** 2
    s, e, w = joints[:, 0], joints[:, 1], joints[:, 2]
    u = (w - s) / np.maximum(np.linalg.norm(w - s, axis=1), 1e-9)[:, None]
    upper = np.linalg.norm(e - s, axis=1)
    bend = np.sqrt(np.maximum(upper ** 2 - np.einsum("sj,sj->s", e - s, u) ** 2, 0.0))
    log_target += -0.5 * (bend / straightness_sigma_m) ** 2
    log_w = np.where(valid, log_target - np.logaddexp(log_q1, log_q2), -np.inf)
    if not np.any(np.isfinite(log_w)):
        return s, w, np.zeros(n)
    weight = np.exp(log_w - np.max(log_w))
    return s, w, weight / weight.sum()


def arm_evidence(joints_px: np.ndarray, depth_m: np.ndarray, depth_sigma_m: np.ndarray, focal_px: float,
                 principal_px: tuple[float, float], keypoint_sigma_px, forearm_m: tuple[float, float],
                 upperarm_m: tuple[float, float], length_sigma_m: float, straightness_sigma_m: float,
                 pointing_sigma_rad: float, object_extent_m: float, objects_m: list[np.ndarray],
                 object_depth_sigma_m: np.ndarray, samples: int = 2048) -> ArmEvidence:
    """Return each object's pointing density averaged over the arm's posterior.

    Args:
        joints_px: shoulder, elbow, wrist in the rectified left image (3, 2), pixels.
        depth_m, depth_sigma_m: their stereo depths and sigmas (3,), metres.
        focal_px, principal_px: rectified intrinsics.
        keypoint_sigma_px: the keypoints' image noise, pixels (one value, or one per joint).
        forearm_m, upperarm_m: plausible limb lengths, metres; length_sigma_m: softness of the bounds.
        straightness_sigma_m: the elbow's allowed distance from the shoulder-wrist line, metres.
        pointing_sigma_rad: the diver's own pointing error, radians.
        object_extent_m: tolerance added to each object point's distance from the ray, metres.
        objects_m: per object, points spread over it (K, 3) in the camera frame, metres.
        object_depth_sigma_m: per object, the depth sigma of its centre, metres.
        samples: number of draws.
    """
    if samples not in _DRAWS:
        _DRAWS[samples] = _Draws(samples)
    draws = _DRAWS[samples]
    s, w, weight = _arm_draws(joints_px, np.asarray(depth_m, float), np.maximum(np.asarray(depth_sigma_m, float), 0.01),
                              focal_px, principal_px, keypoint_sigma_px, forearm_m, upperarm_m, length_sigma_m,
                              straightness_sigma_m, draws)
    ess = float(1.0 / np.sum(weight ** 2)) if weight.sum() > 0 else 0.0
    keep = _heaviest(weight, MASS_KEPT)
    f32 = np.float32  # the per-draw, per-point work in single precision (densities to ~1e-6)
    s, w, weight, d_o = s[keep], w[keep], weight[keep] / weight[keep].sum(), draws.scale[keep].astype(f32)
    u = ((w - s) / np.maximum(np.linalg.norm(w - s, axis=1), 1e-9)[:, None]).astype(f32)
    wrist_along = np.einsum("sj,sj->s", w - s, u)
    s = s.astype(f32)
    sizes = [len(pts) for pts in objects_m]
    owner = np.repeat(np.arange(len(objects_m)), sizes)
    pts = np.vstack(objects_m).astype(f32)
    slide = (np.asarray(object_depth_sigma_m, float) / np.maximum([np.mean(p[:, 2]) for p in objects_m], 0.1))[owner]
    slide = slide.astype(f32)
    scale = f32(1.0) + d_o[:, None] * slide[None, :]  # the objects slide along their rays
    # |scale p - s|^2 and (scale p - s) . u from (draws x points) products, no (draws x points x 3) array
    dist = np.sqrt(np.maximum(scale * scale * np.einsum("pj,pj->p", pts, pts)[None, :] - f32(2.0) * scale * (s @ pts.T)
                              + np.einsum("sj,sj->s", s, s)[:, None], f32(1e-18)))
    along = scale * (u @ pts.T) - np.einsum("sj,sj->s", s, u)[:, None]
    angle2 = f32(2.0) * (f32(1.0) - along / dist)  # the angle off the ray squared (to 1 % within 0.35 rad)
    sigma2 = f32(pointing_sigma_rad ** 2) + (f32(object_extent_m) / np.maximum(dist, f32(0.1))) ** 2
    dens = np.exp(f32(-0.5) * angle2 / sigma2) / (f32(2.0 * math.pi) * sigma2)
    dens = np.where(along > wrist_along[:, None], dens, 0.0)  # never behind the wrist
    per_point = weight @ dens.astype(float)
    expected = np.bincount(owner, per_point, len(objects_m)) / np.maximum(sizes, 1)
    with np.errstate(divide="ignore"):
        return ArmEvidence(np.log(expected), ess)


def _heaviest(weight: np.ndarray, mass: float) -> np.ndarray:
    """Return the indices of the fewest draws that hold ``mass`` of the total weight (at least one)."""
    order = np.argsort(-weight)
    cumulative = np.cumsum(weight[order])
    return order[: int(np.searchsorted(cumulative, mass * cumulative[-1])) + 1]
