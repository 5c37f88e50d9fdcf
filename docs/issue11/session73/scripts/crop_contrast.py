"""BlazePose on rendered frames with variants of the landmark crop's contrast: arm found, left px errors.
python crop_contrast.py OUT.json SCENARIO:SEEDS ... (frames per seed: env FRAMES, default 8)"""
import json, os, sys
import cv2
import numpy as np
from dip3d_vehicle.config import load_params
from dip3d_vehicle.perception import blazepose_model as bm
from dip3d_vehicle.perception.blazepose import BlazePoseEstimator
from dip3d_vehicle.perception.keypoints_file import GivenKeypoints
from sitl.render import StereoRenderer
from sitl.scenario import load_scenario
from sitl.simulation import sim_params

ORIG = bm.BlazePose.landmarks
_to_unit = bm._to_unit_rgb

def own_levels(crop):
    c = crop[32:224, 32:224]
    return bm._contrast_of(c, (0, 0, c.shape[1], c.shape[0]))

def make(variant):
    def landmarks(self, image, roi, bgr=True, contrast=None, detected=False):
        if variant == "base":
            return ORIG(self, image, roi, bgr, contrast, detected)
        to_image = bm.crop_matrix(roi, bm.LANDMARK_SIZE)
        crop = bm.warp(image, to_image, bm.LANDMARK_SIZE, cv2.BORDER_REPLICATE)
        use = contrast
        if variant == "own" and contrast is not None:
            use = own_levels(crop)
        elif variant == "own_always":
            use = own_levels(crop)
        elif variant.startswith("clahe"):
            clip = float(variant[5:] or 2.0)
            x = crop
            if contrast is not None:
                lo, hi = contrast
                x = np.clip((x.astype(np.float32) - lo) / np.maximum(hi - lo, 1.0) * 255.0, 0, 255).astype(np.uint8)
            lab = cv2.cvtColor(x, cv2.COLOR_BGR2LAB)
            lab[:, :, 0] = cv2.createCLAHE(clip, (4, 4)).apply(lab[:, :, 0])
            crop, use = cv2.cvtColor(lab, cv2.COLOR_LAB2BGR), None
        self.landmark_calls += 1
        raw, flag, heat = self._landmarker.run(["Identity", "Identity_1", "Identity_3"],
                                               {"input_1": _to_unit(crop, bgr, use)})
        raw = raw.reshape(bm._ALL_LANDMARKS, 5).astype(np.float64)
        xy = bm.refine_from_heatmap(raw[:, :2] / bm.LANDMARK_SIZE, heat[0]) * bm.LANDMARK_SIZE
        xy_px = xy @ to_image[:, :2].T + to_image[:, 2]
        n = bm.NUM_LANDMARKS
        return bm.PoseLandmarks(xy_px=xy_px[:n], z_px=raw[:n, 2] * roi.size_px / bm.LANDMARK_SIZE,
                                visibility=bm._sigmoid(raw[:n, 3]), presence=bm._sigmoid(raw[:n, 4]),
                                pose_flag=float(flag.ravel()[0]), roi=roi, aux_px=xy_px[list(bm._AUX)],
                                contrast=contrast, detected=detected)
    return landmarks

VARIANTS = os.environ.get("VARIANTS", "base,own,own_always,clahe2").split(",")
FRAMES = int(os.environ.get("FRAMES", "8"))
base_params = load_params(overrides={"sitl.pose_source": "blazepose"})
out = {}
for spec in sys.argv[2:]:
    scen, seeds = spec.rsplit(":", 1)
    for seed in [int(s) for s in seeds.split(",")]:
        sc = load_scenario(scen, seed)
        params = sim_params(base_params, sc)
        rig = sc.rig(params["calib.alpha"])
        period = 1.0 / float(params["sitl.camera_rate_hz"])
        v = sc.initial_vehicle_pose
        frames = []
        with StereoRenderer(sc, params) as r:
            for k in range(FRAMES):
                f = r.render(v.north_m, v.east_m, v.depth_m, v.yaw_rad, sc.diver.start_s + period * 2 * k)
                if f.meta["keypoints_truth"] is None:
                    continue
                L, R = rig.rectify_image(f.left, "left"), rig.rectify_image(f.right, "right")
                tp = GivenKeypoints(sc.diver.arm); tp.provide(f.meta["keypoints_truth"])
                frames.append((L, R, tp.estimate(L, R, rig)))
        for var in VARIANTS:
            bm.BlazePose.landmarks = make(var)
            est = BlazePoseEstimator.from_params(params)
            rows = []
            for L, R, truth in frames:
                arm = est.estimate(L, R, rig)
                if arm is None:
                    rows.append(None); continue
                err = np.linalg.norm(arm.left_px - truth.left_px, axis=1)
                a = arm.left_px[2] - arm.left_px[0]; b = truth.left_px[2] - truth.left_px[0]
                ang = float(np.degrees(np.arccos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1))))
                rows.append({"found": bool(arm.min_confidence() >= float(params["pose.min_confidence"])),
                             "err": err.round(1).tolist(), "deg2d": round(ang, 1),
                             "conf": np.round(arm.confidence, 2).tolist() if hasattr(arm, "confidence") else None})
            out.setdefault(var, {})[f"{os.path.basename(scen)}:{seed}"] = rows
            ok = [r for r in rows if r]
            fd = [r for r in ok if r["found"]]
            med = np.median([r["err"] for r in fd], axis=0).round(1).tolist() if fd else None
            d2 = np.median([r["deg2d"] for r in fd]) if fd else None
            print(f"{os.path.basename(scen)}:{seed} {var:11s} arm {len(ok)}/{len(rows)} found {len(fd)} err_med {med} deg2d {d2}", flush=True)
        bm.BlazePose.landmarks = ORIG
json.dump(out, open(sys.argv[1], "w"))
