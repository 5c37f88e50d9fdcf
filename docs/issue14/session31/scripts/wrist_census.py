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
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator, JOINT_PATCH_M, body_disparity
from dip3d_vehicle.perception.joint_stereo import match_point, reach_disparities, score_at
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
from sitl.render import StereoRenderer

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


out, names, seeds = sys.argv[1], sys.argv[2].split(","), sys.argv[3]
a, b = (int(x) for x in seeds.split("-")) if "-" in seeds else (int(seeds), int(seeds))
step = float(sys.argv[4]) if len(sys.argv) > 4 else 0.6
with open(out, "w") as fh:
    for name in names:
        for seed in range(a, b + 1):
            sc = load_scenario(name, seed)
            params = sim_params(load_params(), sc, **{"sitl.pose_source": "blazepose"})
            rig = sc.rig(params["calib.alpha"])
            sign = rig.disparity_sign
            fb = rig.focal_px * rig.baseline_m
            est = BlazePoseEstimator.from_params(params)
            truth_pose = GivenKeypoints(sc.diver.arm)
            v = sc.initial_vehicle_pose
            d = sc.diver
            with StereoRenderer(sc, params) as r:
                t = d.start_s
                while t < d.start_s + d.hold_s:
                    fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
                    t += step
                    if d.raised_fraction(t - step) < 0.99 or fr.meta["keypoints_truth"] is None:
                        continue
                    L, R = rig.rectify_image(fr.left, "left"), rig.rectify_image(fr.right, "right")
                    arm = est.estimate(L, R, rig)
                    lm = est.last[0]
                    if arm is None or lm is None:
                        continue
                    truth_pose.provide(fr.meta["keypoints_truth"])
                    tr = truth_pose.estimate(L, R, rig)
                    body = body_disparity(L, R, lm, sign, est.max_disparity_px)
                    if body is None:
                        continue
                    js = est.stereo_joints(L, R, lm, rig)
                    d_lo, d_hi = reach_disparities(sign * body, fb)
                    depth = fb / abs(body)
                    half = int(np.clip(round(0.5 * JOINT_PATCH_M * rig.focal_px / depth), 4, 24))
                    xy = arm.left_px
                    row = {"scenario": name, "seed": seed, "t": round(t - step, 2), "side": est.arm_of(lm),
                           "true_side": sc.diver.arm, "body_px": round(sign * body, 3), "fb": fb, "half": half,
                           "err2d_px": np.linalg.norm(xy - tr.left_px, axis=1).round(1).tolist(),
                           "true_d_px": (tr.left_px[:, 0] - tr.right_px[:, 0]).round(3).tolist(),
                           "d_px": js.disparity_px.round(3).tolist(), "sigma_px": js.sigma_px.round(3).tolist(),
                           "matched": js.matched.tolist(), "score": [None if not math.isfinite(s) else round(float(s), 3) for s in js.score],
                           "final_sigma_px": None if arm.disparity_sigma_px is None else arm.disparity_sigma_px.round(3).tolist(),
                           "turbidity": float(sc.water.turbidity_per_m)}
                    for k in (1, 2):
                        row[f"probes_{k}"] = probes(L, R, xy, k, body, sign, rig, d_lo, d_hi, half, js.disparity_px[k])
                    fh.write(json.dumps(row) + "\n")
                    fh.flush()
