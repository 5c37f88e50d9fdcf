import sys, tempfile
from pathlib import Path
import numpy as np, cv2
sys.path.insert(0, "tests/perception")
import scene_families as sf
fam, seed0, ks = sys.argv[1], int(sys.argv[2]), [int(x) for x in sys.argv[3].split(",")]
tiles = []
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, max(ks) + 1, seed0)):
        if k not in ks: continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default", ())
        truth = scene.frame.meta["keypoints_truth"]; names = ("shoulder", "elbow", "wrist")
        L = rig.to_rectified(np.array([truth["left"][j] for j in names], float), "left")
        img = left if left.ndim == 3 else cv2.cvtColor(left, cv2.COLOR_GRAY2BGR)
        c = L[0].astype(int); h = 60
        crop = img[c[1]-h:c[1]+h, c[0]-h:c[0]+h].copy()
        crop = cv2.resize(crop, None, fx=3, fy=3, interpolation=cv2.INTER_NEAREST)
        for p, col in zip(L, ((0,0,255),(0,255,0),(255,0,0))):
            q = ((p - c + h) * 3).astype(int); cv2.circle(crop, tuple(int(v) for v in q), 6, col, 2)
        cv2.putText(crop, f"{fam} {seed0} #{k}", (5, 20), 0, 0.6, (255,255,255), 1)
        tiles.append(crop)
cv2.imwrite(sys.argv[4], np.hstack(tiles))
