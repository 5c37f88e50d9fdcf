"""The pointing shoulder's disparity from a torso model, with its doubts measured.

A shoulder's own image patch is a round, evenly shaded blob that matches the neck or the back behind it, so the
pose model's stereo arm (``blazepose.joint_disparity: stereo``) places the shoulder from the torso instead: the
body's disparity, half a shoulder width nearer or farther by the torso's turn, on the side the pose model says
is near, with the measured doubts of each step, reconciled with the head's match.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

__all__ = ["SHOULDER_WIDTH_M", "SHOULDER_MODEL_SIGMA_M", "SHOULDER_SIDE_DOUBT", "SHOULDER_ORDER_FRAMES",
           "HEAD_BEFORE_SHOULDERS_M", "HEAD_TORSO_SIGMA_M", "ShoulderOrder", "shoulder_disparity", "reconcile",
           "torso_shoulder_disparity", "two_way", "head_torso_shoulder", "mirrored_shoulder_px", "side_log_odds"]


SHOULDER_WIDTH_M = (0.38, 0.03)
"""Distance between the two shoulder joint centres of an adult, metres: (typical, one sigma)."""


def shoulder_disparity(body_disparity_px: float, shoulders_apart_px: float, near: bool, focal_px: float,
                       baseline_m: float, body_sigma_px: float = 0.5, landmark_sigma_px: float = 8.0,
                       width_m: tuple[float, float] = SHOULDER_WIDTH_M) -> tuple[float, float]:
    """Return the pointing shoulder's disparity (x_left - x_right, pixels) and its sigma from a torso model.

    A shoulder's own patch holds little it can be matched by (a round, evenly shaded blob) and, seen
    from the side, the neck and the back behind it, which lie at the torso's centre: matched, it
    comes out at the torso's depth. Here the torso's centre is at the body's disparity and the
    shoulders lie half a shoulder width to either side of it: their image separation gives the
    torso's turn (|cos| = separation x depth / (focal x width)), so the shoulder is nearer (``near``)
    or farther than the centre by (width / 2) x sin(turn).
    """
    fb = focal_px * baseline_m
    depth = fb / max(abs(body_disparity_px), 1e-6)
    width, width_sigma = width_m
    cos_turn = float(np.clip(shoulders_apart_px * depth / (focal_px * width), 0.0, 1.0))
    sin_turn = math.sqrt(1.0 - cos_turn ** 2)
    offset = 0.5 * width * sin_turn * (-1.0 if near else 1.0)
    # the width varies between people; near a frontal view sin is sensitive to the landmarks' error
    cos_sigma = math.sqrt(2.0) * landmark_sigma_px * depth / (focal_px * width)
    sin_sigma = min(1.0, cos_sigma * cos_turn / max(sin_turn, 0.3))
    offset_sigma = math.hypot(0.5 * width_sigma * sin_turn, 0.5 * width * sin_sigma)
    shoulder_depth = max(depth + offset, 0.1)
    sign = 1.0 if body_disparity_px >= 0 else -1.0
    disparity = sign * fb / shoulder_depth
    sigma = math.hypot(body_sigma_px * (depth / shoulder_depth) ** 2, fb / shoulder_depth ** 2 * offset_sigma)
    return disparity, sigma


SHOULDER_MODEL_SIGMA_M = 0.05
"""One-sigma depth error (metres) of the torso model's shoulder beyond what the body's disparity and the
landmarks allow: the body's match is a texture-weighted surface, not the torso's centre, and people's builds
differ. Measured (issue 14 session 30, ``docs/issue14/session30/scripts/shoulder_census.py``: BlazePose on
4469 frames of the nine built-in scenarios, seeds 0-9, and 1719 of session 18's variant files): the model's
shoulder depth error is 0.09 m p90 on the built-ins, while its sigma was 0.04 m in the median (|z| p90 3.0)."""

SHOULDER_SIDE_DOUBT = 0.05
"""Probability that the pose model's depth order of the shoulders is the wrong way round (the pointing shoulder
said nearer than the other when it is farther, or the reverse). Measured on the same census: wrong in 2 of 4469
built-in frames and 106 of 1719 variant frames (6 %), 68 of 100 in one variant (``variant_9_03``: a murky diver
half turned away, where the flip moved the shoulder 3-4 px of disparity, 0.2 m). With 0.05 and the head's check the
sigma's |z| is 0.81 / 1.40 (p50 / p90) over all 6188 frames, 0.4 % beyond 3 sigmas (before: 1.32 / 3.35, 15 %);
with 0.1 it is 0.47 / 0.98, too wide (``docs/issue14/session30/census/shoulder_rules_table.md``)."""


SHOULDER_ORDER_FRAMES = 12
"""How many of the pose model's latest frames ``ShoulderOrder`` weighs the shoulders' depth order over (about 2.5 s at
the simulator's 5 Hz camera, longer where the pose model misses frames)."""


class ShoulderOrder:
    """The pose model's recent depth orders of the shoulders, and the doubt they put on the latest one.

    The diver holds the body still while pointing, so a pose model that says the pointing shoulder is near in
    some frames and far in others is guessing: the doubt of a frame's order is the share of the recent frames
    (this one included) that said the other, never below ``floor`` (the measured rate of a steady wrong order)
    nor above 1 - ``floor``. Measured (issue 14 session 32, ``docs/issue14/session32/scripts/order_rule.py`` on
    session 30's census, BlazePose on 4469 built-in and 1719 variant frames 0.6 s apart, the history taken over the
    census frames of each run): with 12 frames the shoulder's |error / sigma| in ``variant_9_03`` (the order wrong in
    68 of 100 frames) falls from 1.79 / 2.67 to 0.61 / 1.68 (p50 / p90), over all variants p90 1.65 -> 1.44; the
    built-ins, where the order is wrong in 2 frames, are unchanged (0.84 / 1.35).
    """

    def __init__(self, frames: int = SHOULDER_ORDER_FRAMES, floor: float = SHOULDER_SIDE_DOUBT) -> None:
        """Keep the last ``frames`` orders; doubt each at least ``floor`` (probability)."""
        self.floor = float(floor)
        self._said: deque[bool] = deque(maxlen=max(int(frames), 1))

    def reset(self) -> None:
        """Forget the orders seen (a new diver, a lost track)."""
        self._said.clear()

    def doubt(self, near: bool) -> float:
        """Record a frame's order (``near``: the pointing arm's shoulder said nearer); return its doubt, 0-1.

        The history is the pointing shoulder's whatever the pose model calls it: a diver seen half from behind is
        read as seen from the front in some frames, the arms' labels swapped and the order with them
        (``variant_9_03``), and the physical shoulder is the same.

        Examples:
            >>> order = ShoulderOrder(frames=4, floor=0.05)
            >>> [round(order.doubt(n), 2) for n in (True, True, False, True, True, True, True)]
            [0.05, 0.05, 0.67, 0.25, 0.25, 0.25, 0.05]
        """
        self._said.append(bool(near))
        against = sum(said != near for said in self._said) / len(self._said)
        return min(max(self.floor, against), 1.0 - self.floor)


def reconcile(estimates: list[tuple[float, float]]) -> tuple[float, float]:
    """Return the inverse-variance mean of independent (value, sigma) estimates and its sigma, widened by their spread.

    When the estimates disagree by more than their sigmas allow, the sigma is multiplied by the Birge ratio
    sqrt(chi^2 / (n - 1)): the spread itself says how far the estimate can be trusted.

    Examples:
        >>> reconcile([(10.0, 1.0), (10.0, 1.0)])[1] < 1.0
        True
        >>> round(reconcile([(10.0, 1.0), (20.0, 1.0)])[1], 2)
        5.0
    """
    value = np.array([e[0] for e in estimates], float)
    sigma = np.array([e[1] for e in estimates], float)
    w = 1.0 / sigma ** 2
    mean = float((w * value).sum() / w.sum())
    out = 1.0 / math.sqrt(float(w.sum()))
    if len(estimates) > 1:
        chi2 = float((w * (value - mean) ** 2).sum())
        out *= max(1.0, math.sqrt(chi2 / (len(estimates) - 1)))
    return mean, out


def torso_shoulder_disparity(body_disparity_px: float, shoulders_apart_px: float, near: bool, focal_px: float,
                             baseline_m: float, head: tuple[float, float] | None = None,
                             side_doubt: float = SHOULDER_SIDE_DOUBT,
                             model_sigma_m: float = SHOULDER_MODEL_SIGMA_M) -> tuple[float, float]:
    """Return the pointing shoulder's disparity (x_left - x_right, pixels) and its sigma, with the doubts measured.

    ``shoulder_disparity`` for the side the pose model says (``near``) and, with probability ``side_doubt``,
    the other (a two-way mixture: its mean and variance), with ``model_sigma_m`` of depth added; then
    ``reconcile``d with the head's match (``head``: disparity, sigma from ``head_disparity``), which widens
    the sigma when the body's disparity is off (a nearer object in the body's box: issue 14 session 30,
    ``variant_9_09``, murky water, the body 10 px too near, the head within 4 px).
    """
    said = shoulder_disparity(body_disparity_px, shoulders_apart_px, near, focal_px, baseline_m)
    other = shoulder_disparity(body_disparity_px, shoulders_apart_px, not near, focal_px, baseline_m)
    mean, spread = two_way(said, other, float(side_doubt))
    sigma = math.hypot(spread, mean ** 2 / (focal_px * baseline_m) * model_sigma_m)
    return reconcile([(mean, sigma)] + ([head] if head is not None else []))


def two_way(first: tuple[float, float], second: tuple[float, float], p_second: float) -> tuple[float, float]:
    """Return the mean and sigma of a two-way mixture of (value, sigma) estimates: ``second`` with ``p_second``.

    Examples:
        >>> two_way((10.0, 1.0), (20.0, 1.0), 0.0)
        (10.0, 1.0)
        >>> round(two_way((10.0, 1.0), (20.0, 1.0), 0.5)[1], 2)
        5.1
    """
    p = float(np.clip(p_second, 0.0, 1.0))
    mean = (1.0 - p) * first[0] + p * second[0]
    var = (1.0 - p) * first[1] ** 2 + p * second[1] ** 2 + p * (1.0 - p) * (first[0] - second[0]) ** 2
    return mean, math.sqrt(var)


HEAD_BEFORE_SHOULDERS_M = 0.023
"""How far (metres) the head's matched surface lies before the line joining the two shoulder joints (seen along the
view). Measured on the open-set families (issue 11 session 44, ``docs/issue11/session44/scripts/torso_eval.py``, 2 px,
6 scenes a family, 4 draws each): with 0 the model's shoulder on its true side lay 0.021 / 0.025 m behind the truth
joint (median, seeds 500 / 1300); with 0.023 on fresh seed 2100, 0.003 m (|error| p90 0.054 m)."""

HEAD_TORSO_SIGMA_M = 0.03
"""One-sigma depth error (metres) of ``head_torso_shoulder`` beyond the landmarks' and the head match's own: the head's
surface minus the shoulder's depth against half a shoulder width times the torso's turn varies by 0.015-0.019 m (MAD),
p90 0.047-0.057 m (210 draws, seeds 500 and 1300, ``docs/issue11/session44/scripts/head_offset_bins.py``)."""


def _along_view(across: float, slope: float) -> tuple[float, float]:
    """Return the (smaller, larger) |z| of a unit shoulder axis whose across-view share is across + slope |z|, 0-1.

    (x^2 + z^2 = 1.) Off the image centre two turns can give the same image offset (both roots positive):
    both are returned; (0, 0) when none fits (the offset is wider than half a shoulder width allows: the
    torso faces the camera).
    """
    root = 1.0 + slope * slope - across * across
    if root <= 0.0:
        return 0.0, 0.0
    roots = [(-across * slope + k * math.sqrt(root)) / (1.0 + slope * slope) for k in (-1.0, 1.0)]
    valid = [float(np.clip(r, 0.0, 1.0)) for r in roots if r >= 0.0] or [0.0]
    return min(valid), max(valid)


def head_torso_shoulder(head: tuple[float, float], head_left_px, shoulder_left_px, focal_px: float, baseline_m: float,
                        principal_x_px: float, keypoint_sigma_px: float,
                        width_m: tuple[float, float] = SHOULDER_WIDTH_M
                        ) -> tuple[tuple[float, float], tuple[float, float]]:
    """Return a shoulder's (disparity, sigma) on the near side and on the far side of the torso (pixels).

    The head sits above the middle of the line joining the shoulders, its matched surface (``head``: the
    head's own match, disparity and sigma) ``HEAD_BEFORE_SHOULDERS_M`` before it. The shoulder lies half a
    shoulder width along that line: its image offset from the head gives the line's share across the view
    (in perspective, at the shoulder's own depth), the rest lies along the view (the torso's turn), toward
    the camera (near) or away from it (far). Where two turns fit the offset (off the image centre) the
    shoulder lies between them, with half their difference as doubt. The sigma holds the landmarks'
    ``keypoint_sigma_px``, the head match's, people's shoulder widths and ``HEAD_TORSO_SIGMA_M``.
    """
    fb = focal_px * baseline_m
    half, half_sigma = 0.5 * width_m[0], 0.5 * width_m[1]
    centre_m = fb / max(abs(head[0]), 1e-6) + HEAD_BEFORE_SHOULDERS_M
    ray_s = (shoulder_left_px[0] - principal_x_px) / focal_px
    ray_h = (head_left_px[0] - principal_x_px) / focal_px
    across = (ray_s - ray_h) * centre_m / half
    across_sigma = math.sqrt(2.0) * keypoint_sigma_px / focal_px * centre_m / half
    head_sigma_m = centre_m ** 2 / fb * head[1]
    sign = 1.0 if head[0] >= 0 else -1.0
    out = []
    for side in (-1.0, 1.0):
        lo, hi = _along_view(across, side * ray_s)
        turn = 0.5 * (lo + hi)
        shifted = [0.5 * sum(_along_view(across + k * across_sigma, side * ray_s)) for k in (1.0, -1.0)]
        turn_sigma = math.hypot(0.5 * abs(shifted[0] - shifted[1]), 0.5 * (hi - lo))   # landmarks; two turns that fit
        depth = max(centre_m + side * half * turn, 0.1)
        sigma_m = math.hypot(math.hypot(HEAD_TORSO_SIGMA_M, head_sigma_m),
                             math.hypot(half * turn_sigma, half_sigma * turn))
        out.append((sign * fb / depth, fb / depth ** 2 * sigma_m))
    return out[0], out[1]


def mirrored_shoulder_px(head_left_px, shoulder_left_px) -> np.ndarray:
    """Return where the other shoulder lies in the image (pixels): the shoulder mirrored about the head's vertical."""
    return np.array([2.0 * float(head_left_px[0]) - float(shoulder_left_px[0]), float(shoulder_left_px[1])])


def side_log_odds(observed: tuple[float, float], near: tuple[float, float], far: tuple[float, float]) -> float:
    """Return the log likelihood ratio, far side against near side, of an observed (disparity, sigma), pixels."""
    out = 0.0
    for (d, s), sign in ((far, 1.0), (near, -1.0)):
        var = s * s + observed[1] ** 2
        out += sign * (-0.5 * (observed[0] - d) ** 2 / var - 0.5 * math.log(var))
    return out
