import sys, tempfile
from pathlib import Path
import cv2
sys.path.insert(0, "tests/perception")
import scene_families as sf
family, n, seed0, K = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
x0, y0, x1, y1 = map(int, sys.argv[5].split(","))
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        if k != K: continue
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        c = left[y0:y1, x0:x1].copy()
        c = cv2.resize(c, None, fx=3, fy=3, interpolation=cv2.INTER_NEAREST)
        cv2.imwrite(sys.argv[6], c)
        print(scene.frame.meta["placards"] if "placards" in scene.frame.meta else "")
