import sys, tempfile
from pathlib import Path
import numpy as np, cv2
sys.path.insert(0, "tests/perception")
import scene_families as sf
fam, n, seed0, want = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), fam, n, seed0)):
        if k != want: continue
        m = scene.frame.meta
        print(m["target_id"], {pid: {kk: (np.round(v, 2).tolist() if isinstance(v, (list, np.ndarray)) else v) for kk, v in p.items()} for pid, p in m["placards"].items()})
        rig, left, right, pose, perception, arm, base = sf.prepared(scene, "default")
        cv2.imwrite(f"/tmp/s43/scene_{fam}_{seed0}_{k}_left.png", left)
        print(left.shape, arm.left_px.round(0).tolist())
