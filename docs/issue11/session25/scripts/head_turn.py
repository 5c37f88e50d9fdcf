"""Per family: the pointing shoulder's depth about the head's match, by the torso's turn read in the image.

    PYTHONPATH=.:tests/perception:docs/issue11/session23/scripts python docs/issue11/session25/scripts/head_turn.py SEED0 [N] [NOISE_PX]

For every draw whose head matched (``joint_stereo._head_disparity``): the truth shoulder joint's depth
minus the head match's (metres), grouped by sin(turn) from the shoulder's image offset across the head
(0.19 m x cos(turn) at the head's depth for an upright torso), with the fixed sigma
(``HEAD_SHOULDER_SIGMA_M``) and the turn's sigma tried in session 25 (``turn_sigma_m``; reverted, see
the README) and the share of draws each puts beyond 3 sigma.
"""
from __future__ import annotations

import math

import numpy as np

from draws import family_arm_draws

TURN_M, FRONT_M, ABOVE_M = 0.14, 0.04, 0.1
"""The session's turn model: side-on offset, facing-the-camera sigma, and how far above the shoulder the head
must be for the turn to be read (metres)."""


def turn_sigma_m(shoulder_px: np.ndarray, head_px: np.ndarray, depth_m: float, focal_px: float,
                 fixed_m: float) -> float:
    """Return the shoulder's depth sigma about the head's match from the torso's turn (metres; ``fixed_m`` when unread)."""
    dx_m, dy_m = (np.asarray(shoulder_px, float) - np.asarray(head_px, float)) * depth_m / focal_px
    if not dy_m >= ABOVE_M:
        return fixed_m
    cos_turn = min(abs(float(dx_m)) / 0.19, 1.0)
    return math.hypot(TURN_M * math.sqrt(1.0 - cos_turn ** 2), FRONT_M)


def main() -> None:
    """Print one block per family."""
    from dip3d_vehicle.perception import joint_stereo as js
    for family, family_draws in family_arm_draws():
        rows = []
        for d in family_draws:
            rig, arm, joints = d.rig, d.arm, d.joints
            head = js._head_disparity(arm, d.left, d.right, d.body_px, rig.disparity_sign, rig.focal_px, rig.baseline_m)
            if head is None:
                continue
            depth = d.fb / abs(head[0])
            head_px = np.asarray(arm.extra_left_px["head"], float)
            dx_m = abs(arm.left_px[0, 0] - head_px[0]) * depth / rig.focal_px
            sin_turn = math.sqrt(1.0 - min(dx_m / 0.19, 1.0) ** 2)
            sigma = turn_sigma_m(arm.left_px[0], head_px, depth, rig.focal_px, js.HEAD_SHOULDER_SIGMA_M)
            rows.append((joints["shoulder"][2] - depth, sin_turn, sigma))
        a = np.array(rows)
        off = a[:, 0]
        print(f"{family}: {len(a)} draws with the head matched; beyond 3 sigma: fixed "
              f"{np.mean(abs(off) > 3 * js.HEAD_SHOULDER_SIGMA_M) * 100:.1f} %, turn "
              f"{np.mean(abs(off) > 3 * a[:, 2]) * 100:.1f} %")
        for lo, hi in ((0.0, 0.5), (0.5, 0.85), (0.85, 1.01)):
            m = (a[:, 1] >= lo) & (a[:, 1] < hi)
            if m.any():
                print(f"    sin(turn) {lo:.2f}-{hi:.2f}: {m.sum():3d} draws, shoulder - head match median "
                      f"{np.median(off[m]):+.3f} m, |.| p90 {np.percentile(abs(off[m]), 90):.3f} m; "
                      f"turn sigma median {np.median(a[m, 2]):.3f} m", flush=True)


if __name__ == "__main__":
    main()
