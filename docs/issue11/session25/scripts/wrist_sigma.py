"""Per family: the wrist's row match, its stated sigma (the NCC peak's flat span) against its actual error (px).

    PYTHONPATH=.:tests/perception:docs/issue11/session23/scripts python docs/issue11/session25/scripts/wrist_sigma.py SEED0 [N] [NOISE_PX]

A calibrated sigma gives |error| / sigma of median ~0.67 and p90 ~1.64.
"""

import numpy as np

from draws import family_arm_draws


def main() -> None:
    """Print one line per family."""
    from dip3d_vehicle.perception import joint_stereo as js
    for family, family_draws in family_arm_draws():
        rows = []
        for d in family_draws:
            found = js.joint_disparities(d.left, d.right, d.arm.left_px, d.body_px, d.rig.disparity_sign,
                                         d.rig.focal_px, d.rig.baseline_m, patch_m=0.06)
            if found.matched[2]:
                rows.append((abs(found.disparity_px[2] - d.fb / d.joints["wrist"][2]), found.sigma_px[2]))
        a = np.array(rows)
        z = a[:, 0] / np.maximum(a[:, 1], 1.0)
        print(f"{family:14s} {len(a)} matched wrists: |error| median {np.median(a[:, 0]):.2f} p90 "
              f"{np.percentile(a[:, 0], 90):.2f} px; stated sigma median {np.median(a[:, 1]):.2f} p90 "
              f"{np.percentile(a[:, 1], 90):.2f} px; |error| / max(sigma, 1 px floor) median {np.median(z):.2f} "
              f"p90 {np.percentile(z, 90):.2f}", flush=True)


if __name__ == "__main__":
    main()
