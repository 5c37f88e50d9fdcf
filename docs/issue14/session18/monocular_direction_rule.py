"""BlazePose's stereo arm (the default blazepose.joint_disparity stereo) and its own monocular 3D (the landmarks'
x, y, z) against the truth direction, per frame of a scenario's hold (start pose, frames 3 s into the hold).

Usage (from the repository root; run on a checkout before and after bd259a2 for the two columns):
    PYTHONPATH=. python docs/issue14/session18/monocular_direction_rule.py far_diver 0 16 2 > out.txt
Each line: direction errors (deg) "stereo", "mono" (x, y, z), "flat" (x, y only); tilts toward (-) / away
(+) from the camera (truth, stereo, mono); the arm joints' disparities (truth, stereo, sigma, mono).
"""
import sys, math, json
import numpy as np
from dip3d_vehicle.config import load_params
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
from sitl.arm_eval import _direction, _angle_deg
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.triangulation import normalize_q
from dip3d_vehicle.perception.pose import ARM_INDICES
from sitl.render import StereoRenderer

def mono_dir(lm, arm, rig):
    idx = list(ARM_INDICES[arm]); s, w = idx[0], idx[2]
    f = rig.focal_px; cx, cy = rig.principal_point_px
    du, dv = lm.xy_px[w] - lm.xy_px[s]; dz = lm.z_px[w] - lm.z_px[s]
    X, Y = (lm.xy_px[s][0]-cx)/f, (lm.xy_px[s][1]-cy)/f
    v = np.array([du + X*dz, dv + Y*dz, dz]); v2 = np.array([du, dv, 0.0])
    return v/np.linalg.norm(v), v2/np.linalg.norm(v2)

scen = sys.argv[1]; seeds = range(int(sys.argv[2]), int(sys.argv[3])); frames = int(sys.argv[4])
base = load_params(overrides={"sitl.pose_source": "blazepose"})
out = []
for seed in seeds:
    sc = load_scenario(scen, seed)
    params = sim_params(base, sc)
    rig = sc.rig(params["calib.alpha"]); Q = normalize_q(rig.Q, rig.disparity_sign)
    est = BlazePoseEstimator.from_params(params); tp = GivenKeypoints(sc.diver.arm)
    period = 1.0/float(params["sitl.camera_rate_hz"]); v = sc.initial_vehicle_pose
    with StereoRenderer(sc, params) as r:
        for k in range(frames):
            t = sc.diver.start_s + 3 + period*k*3
            fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
            L, R = rig.rectify_image(fr.left, "left"), rig.rectify_image(fr.right, "right")
            arm = est.estimate(L, R, rig)
            if arm is None or fr.meta["keypoints_truth"] is None: continue
            tp.provide(fr.meta["keypoints_truth"]); tr = tp.estimate(L, R, rig)
            td = _direction(Q, tr.left_px, tr.left_px[:,0]-tr.right_px[:,0])
            lm = est.last[0]
            m, flat = mono_dir(lm, sc.diver.arm, rig)
            st = _direction(Q, arm.left_px, arm.left_px[:,0]-arm.right_px[:,0])
            idx = list(ARM_INDICES[sc.diver.arm]); f = rig.focal_px; B = abs(rig.baseline_m)
            tdisp = tr.left_px[:,0]-tr.right_px[:,0]; sdisp = arm.left_px[:,0]-arm.right_px[:,0]
            sig = arm.disparity_sigma_px if arm.disparity_sigma_px is not None else np.full(3, np.nan)
            Zs = f*B/abs(sdisp[0]); zrel = (lm.z_px[idx]-lm.z_px[idx[0]])*Zs/f
            mdisp = np.sign(sdisp[0])*f*B/(Zs+zrel)
            extra = dict(body=round(float(est._body_disparity_px or 0),2), unm=[bool(x) for x in (arm.disparity_sigma_px > 3.5)] if arm.disparity_sigma_px is not None else None, tdisp=tdisp.round(1).tolist(), sdisp=sdisp.round(1).tolist(), ssig=np.round(sig,1).tolist(), mdisp=mdisp.round(1).tolist(), zrel=zrel.round(2).tolist())
            row = dict(seed=seed, pos=sc.diver.position_name, mono=_angle_deg(m, td), flat=_angle_deg(flat, td),
                       stereo=_angle_deg(st, td), true_tilt=math.degrees(math.asin(td[2])), mono_tilt=math.degrees(math.asin(m[2])),
                       st_tilt=math.degrees(math.asin(st[2])), conf=float(arm.min_confidence()), **extra)
            out.append(row); print(json.dumps({k:(round(v,1) if isinstance(v,float) else v) for k,v in row.items()}), flush=True)
for key in ("mono","flat","stereo"):
    a = np.array([r[key] for r in out]); print(key, "median %.1f p90 %.1f" % (np.median(a), np.percentile(a,90)))
