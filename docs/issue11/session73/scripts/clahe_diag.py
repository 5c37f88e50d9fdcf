import sys, cv2, numpy as np
from dataclasses import replace
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception import blazepose_model as bm
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
scen, seed = sys.argv[1], int(sys.argv[2])
sc = load_scenario(scen, seed)
params = sim_params(load_params(overrides={"sitl.pose_source": "blazepose"}), sc); rig = sc.rig(params["calib.alpha"])
pose = bm.BlazePose()
ARM = {"right": [12, 14, 16], "left": [11, 13, 15]}[sc.diver.arm]
def clahe(img, clip=2.0, grid=8):
    lab = cv2.cvtColor(img, cv2.COLOR_BGR2LAB); lab[:, :, 0] = cv2.createCLAHE(clip, (grid, grid)).apply(lab[:, :, 0]); return cv2.cvtColor(lab, cv2.COLOR_LAB2BGR)
def squares(img):
    h, w = img.shape[:2]; best = None
    for s in np.linspace(0, w - h, 3).round().astype(int):
        t = np.ascontiguousarray(img[:, s:s + h]); d = pose.detect(t, contrast=True)
        if d is not None and (best is None or d.score > best.score):
            best = replace(d, box_px=d.box_px + np.tile([s, 0], 2), keypoints_px=d.keypoints_px + [s, 0])
    return best
v = sc.initial_vehicle_pose
with StereoRenderer(sc, params) as r:
    for k in range(6):
        f = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, sc.diver.start_s + 0.5 * k)
        L = rig.rectify_image(f.left, "left"); R = rig.rectify_image(f.right, "right")
        tp = GivenKeypoints(sc.diver.arm); tp.provide(f.meta["keypoints_truth"]); truth = tp.estimate(L, R, rig).left_px
        C = clahe(L)
        det0 = pose.detect(L) or pose.detect(L, contrast=True) or squares(L)
        detc = squares(C)
        out = [f"old det {det0.score:.2f}" if det0 else "old det -", f"clahe det {detc.score:.2f}" if detc else "clahe det -"]
        if detc:
            s0 = int(np.clip(detc.box_px[[0, 2]].mean() - L.shape[0] / 2, 0, L.shape[1] - L.shape[0]))
            s0 = min(np.linspace(0, L.shape[1] - L.shape[0], 3).round().astype(int), key=lambda s: abs(s - s0))
            tile = np.ascontiguousarray(L[:, s0:s0 + L.shape[0]])
            raw_lv = bm._contrast_of(cv2.warpAffine(tile, bm.letterbox_matrix(tile.shape[1], tile.shape[0], 224), (224, 224)), (0, 0, 224, 224))
            for name, img, con in (("clahe-levels", L, detc.contrast), ("raw-tile-levels", L, raw_lv)):
                lm = pose.landmarks(img, detc.roi(), contrast=con)
                err = np.linalg.norm(lm.xy_px[ARM] - truth, axis=1)
                out.append(f"{name}: flag {lm.pose_flag:.2f} vis {lm.visibility[ARM].min():.2f} err {err.round(0).astype(int).tolist()}")
        print(scen.split("/")[-1], k, " | ".join(out), flush=True)
