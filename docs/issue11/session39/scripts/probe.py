"""Per-frame: BlazePose arm, candidates, objects and which placard polygon each lies in (left image)."""
import sys, numpy as np, cv2
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from dip3d_vehicle.perception.pipeline import Perception
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario

scen, seed, frames = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
src = sys.argv[4] if len(sys.argv) > 4 else "blazepose"
sets = dict(a.split("=", 1) for a in sys.argv[5:])
params = load_params("default", overrides=sets)
sc = load_scenario(scen, seed)
rig = sc.rig(params["calib.alpha"])
est = BlazePoseEstimator.from_params(params)
perc = Perception(rig, params, GivenKeypoints(sc.diver.arm))
truth = GivenKeypoints(sc.diver.arm)
period = 1.0 / float(params["sitl.camera_rate_hz"])
v = sc.initial_vehicle_pose
with StereoRenderer(sc, params) as r:
    for k in range(frames):
        t = sc.diver.start_s + period * k
        fr = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, t)
        L, R = rig.rectify_image(fr.left, "left"), rig.rectify_image(fr.right, "right")
        if src == "truth":
            truth.provide(fr.meta["keypoints_truth"]); arm = truth.estimate(L, R, rig)
        else:
            arm = est.estimate(L, R, rig)
        if arm is None:
            print(t, "no arm"); continue
        checked = perc.check_arm(arm)
        if checked.status != "ok":
            print(t, checked.status); continue
        c = perc.detector.detect(L, R, arm, rig)
        n0 = len(c)
        c = perc.add_corridor(L, R, arm, c)
        res = perc.decide(checked, c)
        polys = {}
        for pid, info in fr.meta["placards"].items():
            pts = np.asarray(info["left_polygon_px"], float)
            # rectify polygon pts
            pr = rig.to_rectified(pts, "left")
            polys[pid] = pr
        def which(px):
            for pid, P in polys.items():
                if cv2.pointPolygonTest(P.astype(np.float32).reshape(-1,1,2), (float(px[0]), float(px[1])), False) >= 0:
                    return pid
            return "-"
        cnt = {}
        for p in c.left_px:
            w = which(p); cnt[w] = cnt.get(w, 0) + 1
        sel = res.selection
        objs = []
        if sel is not None and sel.method == "default":
            for o, s in zip(sel.objects, sel.scores):
                objs.append(f"{which(o.left_px)}:{s:.2f}@z{o.xyz_m[2]:.2f}")
            none = f"none {sel.none_probability:.2f}"
        else:
            none = ""
        print(f"t={t:.1f} {res.status} amb={getattr(sel,'ambiguous',None)} base={n0} all={len(c)} perplacard={cnt} objs={objs} {none}", flush=True)
        if t in [float(x) for x in __import__("os").environ.get("DUMP", "").split(",") if x]:
            img = cv2.cvtColor(L, cv2.COLOR_GRAY2BGR) if L.ndim == 2 else L.copy()
            for pid, P in polys.items():
                cv2.polylines(img, [P.astype(np.int32).reshape(-1, 1, 2)], True, (0, 255, 255), 2)
                cv2.putText(img, str(pid), tuple(P[0].astype(int)), 0, 1.2, (0, 255, 255), 2)
            for p in c.left_px:
                cv2.circle(img, tuple(np.int32(p)), 4, (0, 0, 255), -1)
            a = arm.left_px.astype(int)
            cv2.polylines(img, [a.reshape(-1, 1, 2)], False, (0, 255, 0), 3)
            if sel is not None:
                for o, s in zip(sel.objects, sel.scores):
                    cv2.circle(img, tuple(np.int32(o.left_px)), 25, (255, 0, 0), 3)
                    cv2.putText(img, f"{s:.2f}", tuple(np.int32(o.left_px) + 28), 0, 1.0, (255, 0, 0), 2)
            cv2.imwrite(f"/tmp/s39/f_{t:.1f}.png", cv2.resize(img, None, fx=0.6, fy=0.6))
