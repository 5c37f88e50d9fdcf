"""Per BlazePose frame: the elbow's and wrist's stereo matches as the mission makes them, the truth, and what the
background beside each joint matches.

    python docs/issue14/session31/scripts/wrist_census.py OUT.jsonl SCENARIO[,SCENARIO...|FILE.yaml,...] SEEDS [STEP_S]

Renders each seed's frames from the vehicle's start pose while the arm is held (every STEP_S, default 0.6 s),
runs ``BlazePoseEstimator`` as the mission does (``pose.arm: auto``) and writes one JSON line per frame with the
arm found: the final stereo joints (``stereo_joints``: disparity, sigma, matched), the truth joints' disparities,
BlazePose's 2D error per joint, and for the elbow and the wrist a ring of probe patches (the joint's patch size)
outside the limb: beyond the joint along the limb, and to both sides of it. Each probe's own match along its row
(``match_point``, same span) and its score at the joint's matched disparity (``score_at``).
"""
import json, math, sys
import numpy as np
from census_frames import census_args, held_frames
from dip3d_vehicle.perception.blazepose import JOINT_PATCH_M, body_disparity
from dip3d_vehicle.perception.joint_stereo import match_point, patch_half_px, reach_disparities, score_at

PROBES_M = {"beyond": (0.25, 0.0), "side_a": (0.0, 0.11), "side_b": (0.0, -0.11),
            "beyond_a": (0.15, 0.12), "beyond_b": (0.15, -0.12)}


def probes(L, R, xy, k, body, sign, rig, d_lo, d_hi, half, joint_d):
    """Return each probe's (x, y, own match or None, score at the joint's disparity) for joint k (1 or 2)."""
    u = xy[k] - xy[k - 1]
    u = u / (np.linalg.norm(u) + 1e-9)
    n = np.array([-u[1], u[0]])
    px_per_m = abs(body) / rig.baseline_m
    out = {}
    for name, (a, b) in PROBES_M.items():
        p = xy[k] + px_per_m * (a * u + b * n)
        x, y = int(round(p[0])), int(round(p[1]))
        if not (3 * half < x < L.shape[1] - 3 * half and half < y < L.shape[0] - half):
            out[name] = None
            continue
        m = match_point(L, R, x, y, d_lo, d_hi, sign, half, 0.6, 1.5)
        s = score_at(L, R, x, y, abs(joint_d), sign, half)
        out[name] = [None if m is None else [round(m[0], 3), round(m[1], 3), round(m[2], 3)],
                     None if s is None else round(s, 3)]
    return out


out, names, seeds, step = census_args(sys.argv)
with open(out, "w") as fh:
    for f in held_frames(names, seeds, step):
        sign, fb = f.rig.disparity_sign, f.rig.focal_px * f.rig.baseline_m
        body = body_disparity(f.left, f.right, f.landmarks, sign, f.est.max_disparity_px)
        if body is None:
            continue
        js = f.est.stereo_joints(f.left, f.right, f.landmarks, f.rig)
        d_lo, d_hi = reach_disparities(sign * body, fb)
        half = patch_half_px(body, f.rig.baseline_m, JOINT_PATCH_M)
        xy, tr = f.arm.left_px, f.truth
        row = {"scenario": f.scenario, "seed": f.seed, "t": round(f.t_s, 2), "side": f.est.arm_of(f.landmarks),
               "true_side": f.sc.diver.arm, "body_px": round(sign * body, 3), "fb": fb, "half": half,
               "err2d_px": np.linalg.norm(xy - tr.left_px, axis=1).round(1).tolist(),
               "true_d_px": (tr.left_px[:, 0] - tr.right_px[:, 0]).round(3).tolist(),
               "d_px": js.disparity_px.round(3).tolist(), "sigma_px": js.sigma_px.round(3).tolist(),
               "matched": js.matched.tolist(),
               "score": [None if not math.isfinite(s) else round(float(s), 3) for s in js.score],
               "final_sigma_px": None if f.arm.disparity_sigma_px is None else f.arm.disparity_sigma_px.round(3).tolist(),
               "turbidity": float(f.sc.water.turbidity_per_m)}
        for k in (1, 2):
            row[f"probes_{k}"] = probes(f.left, f.right, xy, k, body, sign, f.rig, d_lo, d_hi, half, js.disparity_px[k])
        fh.write(json.dumps(row) + "\n")
        fh.flush()
