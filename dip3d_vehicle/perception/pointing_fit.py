"""The default selector's maximum-a-posteriori pointing fit: "could this arm be pointing at that object?"

Unknowns are the depths of the shoulder, elbow, wrist and object along their fixed camera rays (the
2D image positions are precise); the residuals are the stereo depths against their uncertainty, a
nearly straight arm, plausible limb lengths, the object ahead of the wrist, and the miss of the
shoulder-to-wrist ray at the object's points (metres, sigma = hypot(pointing sigma x distance,
tolerance)). All hypotheses are solved together by a batched Levenberg-Marquardt in numpy.
``selection.py`` turns the costs into the open-set posterior.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .calibration import StereoRig

__all__ = ["SHAPE_POINTS", "ArmModel", "object_shape"]

SHAPE_POINTS = 12
"""Points per object used to test whether the pointing ray passes through it."""


@dataclass(frozen=True)
class ArmModel:
    """Priors of the default selector (metres, radians, pixels)."""

    keypoint_sigma_px: float = 2.0
    pointing_sigma_rad: float = 0.08
    forearm_m: tuple[float, float] = (0.22, 0.29)
    upperarm_m: tuple[float, float] = (0.27, 0.37)
    object_extent_m: float = 0.03
    straightness_sigma_m: float = 0.05
    length_sigma_m: float = 0.02
    keypoint_sigma_m: float = 0.0


def _norm(v: np.ndarray) -> np.ndarray:
    """Return the Euclidean norms of vectors along the last axis."""
    return np.sqrt(np.einsum("...j,...j->...", v, v))


def _hinge(v: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Return how far each value lies outside [lo, hi] (0 inside)."""
    return np.maximum(np.maximum(lo - v, 0.0), v - hi)


def _rays(points_px: np.ndarray, rig: StereoRig) -> np.ndarray:
    """Return (N, 3) viewing rays with z = 1 through rectified left pixels."""
    f = rig.focal_px
    cx, cy = rig.principal_point_px
    return np.c_[(points_px[:, 0] - cx) / f, (points_px[:, 1] - cy) / f, np.ones(len(points_px))]


class _PointingFit:
    """The MAP fit of joint depths (and object depth) to 'the arm points at this object'.

    Unknowns per hypothesis: depths x = (Z_s, Z_e, Z_w, Z_o) along the fixed camera rays of the
    shoulder, elbow, wrist and object. All hypotheses are solved together by a batched
    Levenberg-Marquardt in numpy (a few hundred microseconds for a dozen objects).
    """

    def __init__(self, rays: np.ndarray, depth_m: np.ndarray, depth_sigma_m: np.ndarray, model: ArmModel,
                 keypoint_sigma_m: float = 0.0) -> None:
        self.rays, self.depth_m, self.sigma = rays, depth_m, np.maximum(depth_sigma_m, 0.01)
        self.model = model
        self._arm_cost: float | None = None
        # a joint placed keypoint_sigma_m off its centre, across the ray (the pose model's own error at the
        # body): each limb's length and the arm's bend are known no better than that, its direction no
        # better than that over the arm's length
        lateral = math.sqrt(2.0) * max(float(keypoint_sigma_m), 0.0)
        self.length_sigma_m = math.hypot(model.length_sigma_m, lateral)
        self.straightness_sigma_m = math.hypot(model.straightness_sigma_m, keypoint_sigma_m)
        arm_m = 0.5 * (sum(model.forearm_m) + sum(model.upperarm_m))
        self.pointing_sigma_rad = math.hypot(model.pointing_sigma_rad, lateral / arm_m)

    def arm_terms(self, x: np.ndarray, joints: np.ndarray | None = None, u: np.ndarray | None = None
                  ) -> tuple[np.ndarray, ...]:
        """Return the arm's own weighted residuals for joint depths x (B, >=3), metres.

        Depths against the stereo depths, a nearly straight arm, plausible limb lengths: the
        terms every hypothesis shares (an object's hypothesis adds where the arm points).
        ``joints`` (B, 3, 3) and ``u`` (B, 3), the joints at x and the unit shoulder-to-wrist axis,
        may be given when the caller has them (``residuals``).
        """
        m = self.model
        if joints is None:
            joints = self.rays[None, :, :] * x[:, :3, None]
        s, e, w = joints[:, 0], joints[:, 1], joints[:, 2]
        if u is None:
            axis = w - s
            u = axis / (_norm(axis)[:, None] + 1e-12)
        fore, upper = _norm(w - e), _norm(e - s)
        bend = np.sqrt(np.maximum(upper * upper - np.einsum("bj,bj->b", e - s, u) ** 2, 0.0))  # |(e - s) x u|
        return ((x[:, :3] - self.depth_m) / self.sigma, bend / self.straightness_sigma_m,
                _hinge(fore, *m.forearm_m) / self.length_sigma_m, _hinge(upper, *m.upperarm_m) / self.length_sigma_m)

    def residuals(self, x: np.ndarray, obj_ray: np.ndarray, obj_depth: np.ndarray, obj_sigma: np.ndarray,
                  obj_shape: np.ndarray) -> np.ndarray:
        """Return (B, 9) weighted residuals for depths x (B, 4), metres.

        ``obj_shape`` (B, K, 3) holds points spread over each object, relative to its centre
        (metres): the diver points at some part of the object, so the pointing term's likelihood
        is the mean over those points (a ray through any part of the object fits).
        """
        m = self.model
        joints = self.rays[None, :, :] * x[:, :3, None]
        s, w = joints[:, 0], joints[:, 2]
        axis = w - s
        u = axis / (_norm(axis)[:, None] + 1e-12)
        obj = obj_ray * x[:, 3:4]
        pts = obj[:, None, :] + obj_shape
        from_shoulder = pts - s[:, None, :]
        along = np.einsum("bkj,bj->bk", from_shoulder, u)
        dist = _norm(from_shoulder)
        offset = np.sqrt(np.maximum(dist * dist - along * along, 0.0))  # |from_shoulder x u|, u a unit vector
        # a miss in metres, sigma = hypot(sigma_angle * distance, tolerance), to each object point
        miss = np.where(along > 0, offset, dist)
        spread = np.hypot(self.pointing_sigma_rad * np.maximum(along, 0.0), m.object_extent_m)
        # the diver points at some point of the object: likelihood = mean over its points
        r2 = (miss / spread) ** 2
        low = r2.min(axis=1)
        ratio = np.sqrt(np.maximum(low - 2.0 * np.log(np.mean(np.exp(-(r2 - low[:, None]) / 2.0), axis=1)), 0.0))
        behind = np.maximum(-np.sum((obj - w) * u, axis=1), 0.0)
        depth, bend, fore, upper = self.arm_terms(x, joints, u)
        out = np.empty((len(x), 9))
        out[:, :3] = depth
        out[:, 3] = (x[:, 3] - obj_depth) / np.maximum(obj_sigma, 0.01)
        out[:, 4], out[:, 5], out[:, 6], out[:, 7] = ratio, bend, fore, upper
        out[:, 8] = behind / m.length_sigma_m
        return out

    def arm_cost(self, iterations: int = 25) -> float:
        """Return the minimum cost of the arm alone: "it points at some point nobody detected".

        The pointing term is free (any point along the fitted arm's ray fits it exactly), so what
        remains is the arm's own terms; an object's cost minus this is what pointing at it costs.
        """
        if self._arm_cost is None:
            x = np.maximum(self.depth_m[None, :].copy(), 0.05)
            self._arm_cost = float(_levenberg_marquardt(lambda z: np.column_stack(self.arm_terms(z)), x, iterations)[0])
        return self._arm_cost

    def starts(self, obj_ray: np.ndarray, obj_depth: np.ndarray) -> np.ndarray:
        """Return (B, 4) starts aiming the arm from the measured wrist at each object."""
        w = self.rays[2] * self.depth_m[2]
        aim = obj_ray * obj_depth[:, None] - w
        aim /= np.linalg.norm(aim, axis=1, keepdims=True) + 1e-12
        fore = float(np.mean(self.model.forearm_m))
        whole = fore + float(np.mean(self.model.upperarm_m))
        out = [np.full(len(aim), self.depth_m[2])]
        for back, ray in ((fore, self.rays[1]), (whole, self.rays[0])):
            out.insert(0, (w - back * aim) @ ray / (ray @ ray))
        return np.column_stack([*out, obj_depth])

    def costs(self, obj_rays: np.ndarray, obj_depth: np.ndarray, obj_sigma: np.ndarray, obj_shape: np.ndarray,
              iterations: int = 25) -> np.ndarray:
        """Return the minimum cost (sum of squared residuals) per object, from two starts each."""
        n = len(obj_depth)
        measured = np.column_stack([np.tile(self.depth_m, (n, 1)), obj_depth])
        x = np.maximum(np.vstack([measured, self.starts(obj_rays, obj_depth)]), 0.05)
        args = (np.vstack([obj_rays, obj_rays]), np.r_[obj_depth, obj_depth], np.r_[obj_sigma, obj_sigma],
                np.concatenate([obj_shape, obj_shape]))
        stacked = tuple(np.concatenate([a] * (x.shape[1] + 1)) for a in args)  # a point and its P shifts, one call
        cost = _levenberg_marquardt(lambda z: self.residuals(z, *stacked), x, iterations)
        return np.minimum(cost[:n], cost[n:])


def object_shape(points_m: np.ndarray, centre_m: np.ndarray, k: int = SHAPE_POINTS) -> np.ndarray:
    """Return (k, 3) points spanning an object, relative to its centre (farthest-point sampling).

    The centre itself is always included; the others are members spread over the object's extent,
    so a pointing ray can be checked against the whole object rather than its centre only.
    """
    rel = points_m - centre_m
    rel = rel[np.all(np.isfinite(rel), axis=1)]
    out = [np.zeros(3)]
    if len(rel):
        dist = np.linalg.norm(rel, axis=1)
        for _ in range(min(k - 1, len(rel))):
            i = int(np.argmax(dist))
            out.append(rel[i])
            dist = np.minimum(dist, np.linalg.norm(rel - rel[i], axis=1))
    while len(out) < k:
        out.append(np.zeros(3))
    return np.array(out)


def _levenberg_marquardt(fun, x: np.ndarray, iterations: int) -> np.ndarray:
    """Minimise sum(fun(x)**2) for a batch of independent problems x (B, P); return final costs.

    ``fun`` must also accept k stacked copies of the batch (k B, P): each trial point and its P
    forward-difference shifts are evaluated in one call (P + 1 copies), so an iteration costs one
    call; a rejected trial's Jacobian is dropped and the current point's kept (the same iterates
    as evaluating the Jacobian at the current point each iteration).
    """
    n, p = x.shape
    eye = np.eye(p)

    def evaluate(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return the residuals (B, R) at z and their forward-difference Jacobian (B, R, P)."""
        step = 1e-5 * np.maximum(np.abs(z), 1.0)
        shifted = (z[None] + eye[:, None, :] * step[None]).reshape(-1, p)  # the P copies, stacked
        out = fun(np.concatenate([z, shifted]))
        r = out[:n]
        jac = np.moveaxis((out[n:].reshape((p,) + r.shape) - r) / step.T[:, :, None], 0, 2)
        return r, jac

    r, jac = evaluate(x)
    cost = np.sum(r * r, axis=1)
    mu = np.full(n, 1e-2)
    stalled = np.zeros(n, int)
    for _ in range(iterations):
        jtj = np.einsum("bri,brj->bij", jac, jac)
        grad = np.einsum("bri,br->bi", jac, r)
        damp = jtj + mu[:, None, None] * (eye * np.diagonal(jtj, axis1=1, axis2=2)[:, None, :] + 1e-9 * eye)
        x_new = np.maximum(x - np.linalg.solve(damp, grad[..., None])[..., 0], 0.05)
        r_new, jac_new = evaluate(x_new)
        cost_new = np.sum(r_new * r_new, axis=1)
        better = cost_new < cost
        gain = np.where(better, cost - cost_new, 0.0)
        x[better], r[better], cost[better], jac[better] = x_new[better], r_new[better], cost_new[better], jac_new[better]
        mu = np.where(better, mu * 0.3, mu * 10.0)
        stalled = np.where(gain <= 1e-3 * (1.0 + cost), stalled + 1, 0)
        if np.all(stalled >= 2):
            break  # every problem converged: under 0.1 % improvement twice in a row
    return cost
