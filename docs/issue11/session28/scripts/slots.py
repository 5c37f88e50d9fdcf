"""What fills the spot slots of one draw: every spot kept for matching, its owners (objects it lies beside), its row match, kept?

    PYTHONPATH=.:tests/perception python docs/issue11/session28/scripts/slots.py FAMILY SCENE SEED0 NOISE DRAW [K=V ...]
"""
import sys, tempfile
from pathlib import Path
import numpy as np
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session23" / "scripts"))
import scene_families as sf
import draws as dr
from dip3d_vehicle.perception import blobs as B, pipeline as P
rec = {}
o_spots, o_mp, o_un = B.BlobFinder.spots, B.match_point, P.unexplained
def spots(self, *a, **k):
    r = o_spots(self, *a, **k); rec["spots"] = r; return r
def mp(left, right, x, y, *a):
    r = o_mp(left, right, x, y, *a); rec.setdefault("match", {})[(x, y)] = r; return r
def un(blobs, *a, **k):
    r = o_un(blobs, *a, **k); rec["found"] = blobs; rec["kept"] = r; return r
B.BlobFinder.spots, B.match_point, P.unexplained = spots, mp, un
family, want, seed0, sigma, wd = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
with tempfile.TemporaryDirectory() as tmp:
    scene = dr.nth_scene(Path(tmp), family, seed0, want)
    rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", sys.argv[6:])
    for pid, p in scene.frame.meta["placards"].items():
        xyz = rig.R1 @ np.asarray(p["xyz_cam_m"])
        px = rig.focal_px * xyz[:2] / xyz[2] + np.asarray(rig.principal_point_px)
        print(f"placard {pid}{'*' if pid == scene.scenario.target_id else ' '} rect {np.round(px,0).tolist()} z {xyz[2]:.2f} w {np.ptp(np.asarray(p['left_polygon_px'])[:,0]):.0f}")
    for d, kp, joints in dr.draws(scene, seed0, want, sigma):
        if d != wd: continue
        pose.provide(kp); rec.clear()
        r = sf.decided(perception, left, right, base)
        print("arm rect", np.round(r.arm.left_px).tolist(), "status", r.status, "conf", round(r.selection.confidence, 2))
        sp, own = rec["spots"]
        kept = rec["kept"].left_px
        for (x, y), o in zip(sp, own):
            m = rec.get("match", {}).get((int(round(x)), int(round(y))), "not tried")
            k = bool(len(kept)) and np.min(np.linalg.norm(kept - [x, y], axis=1)) < 3
            print(f"  spot ({x:.0f},{y:.0f}) owners {o} match {m if not isinstance(m, tuple) else tuple(round(v,2) for v in m)} kept {k}")
