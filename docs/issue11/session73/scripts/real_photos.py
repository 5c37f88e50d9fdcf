"""Arm landmarks on the real photos with and without the crop stretch: px error vs COCO truth and vs MediaPipe."""
import json
import cv2, numpy as np
from dip3d_vehicle.perception.blazepose_model import BlazePose
F = "/work/shared/data/photos/"
coco = json.load(open(F + "coco_keypoints.json"))
ref = json.load(open(F + "mediapipe_reference.json"))["images"]
BP = {"shoulder": (12, 11), "elbow": (14, 13), "wrist": (16, 15)}   # right, left
CO = {"shoulder": (6, 5), "elbow": (8, 7), "wrist": (10, 9)}
for stretch in (False, True):
    pose = BlazePose(crop_stretch=stretch)
    errs, refd = [], []
    for name, lm in ref.items():
        img = cv2.imread(F + name)
        found = pose.process(img)
        lm = lm["landmarks_px"]
        if found is None or lm is None:
            print(stretch, name, "none" if found is None else "found", "ref", lm is not None); continue
        lm = np.asarray(lm)
        idx = [BP[j][s] for s in (0, 1) for j in ("shoulder", "elbow", "wrist")]
        d = np.linalg.norm(found.xy_px[idx] - lm[idx, :2], axis=1)
        refd.append(d)
        line = f"{stretch} {name} vs mediapipe " + " ".join(f"{v:.1f}" for v in d)
        info = coco["images"].get(name) if isinstance(coco["images"], dict) else None
        if info:
            persons = info.get("persons") or info.get("annotations") or info
            best = None
            for p in (persons if isinstance(persons, list) else []):
                kp = np.asarray(p["keypoints"] if isinstance(p, dict) else p, float).reshape(-1, 3)
                ci = [CO[j][s] for s in (0, 1) for j in ("shoulder", "elbow", "wrist")]
                vis = kp[ci, 2] > 0
                e = np.where(vis, np.linalg.norm(found.xy_px[idx] - kp[ci, :2], axis=1), np.nan)
                if best is None or np.nanmean(e) < np.nanmean(best):
                    best = e
            if best is not None:
                errs.append(best)
                line += " | vs coco " + " ".join(f"{v:.1f}" for v in best)
        print(line)
    print(stretch, "median vs mediapipe", np.median(np.concatenate(refd)).round(2), "vs coco", np.nanmedian(np.concatenate(errs)).round(2) if errs else None)
