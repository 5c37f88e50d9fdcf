"""Where is the pointed tiny placard lost as a spot? Per draw: R (no DoG response near it), K (response, not kept
as a spot: known/cut), M (kept, its match failed), U (matched, removed as explained), F (found).

    PYTHONPATH=.:tests/perception python docs/issue11/session28/scripts/census.py FAMILY N SEED0 NOISE [K=V ...]

"Near" the placard: within max(6, half its width + 4) px of its centre (left rectified pixels)."""
import sys, tempfile, collections
from pathlib import Path
import numpy as np
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session23" / "scripts"))
import scene_families as sf
import draws as dr
from dip3d_vehicle.perception import blobs as B, pipeline as P
rec = {}
o_resp, o_spots, o_mp, o_un = B.BlobFinder.responses, B.BlobFinder.spots, B.match_point, P.unexplained
def responses(self, *a, **k):
    r = o_resp(self, *a, **k); rec["resp"] = r; return r
def spots(self, *a, **k):
    r = o_spots(self, *a, **k); rec["spots"] = r; return r
def mp(left, right, x, y, *a):
    r = o_mp(left, right, x, y, *a); rec.setdefault("match", []).append((x, y, r)); return r
def un(blobs, *a, **k):
    r = o_un(blobs, *a, **k); rec["found"] = blobs; rec["kept"] = r; return r
B.BlobFinder.responses, B.BlobFinder.spots, B.match_point, P.unexplained = responses, spots, mp, un
family, n, seed0, sigma = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
over = sys.argv[5:]
tally = collections.Counter()
with tempfile.TemporaryDirectory() as tmp:
    for k, scene in enumerate(sf.scenes(Path(tmp), family, n, seed0)):
        rig, left, right, pose, perception, _, base = sf.prepared(scene, "default", over)
        xyz = rig.R1 @ np.asarray(scene.frame.meta["placards"][scene.scenario.target_id]["xyz_cam_m"])
        c = rig.focal_px * xyz[:2] / xyz[2] + np.asarray(rig.principal_point_px)
        rad = max(6.0, scene.target_width_px / 2 + 4)
        for d, kp, joints in dr.draws(scene, seed0, k, sigma):
            pose.provide(kp); rec.clear()
            r = sf.decided(perception, left, right, base)
            out = sf.outcome(scene, r, rig)
            near = lambda a: a is not None and len(a) > 0 and bool(np.any(np.linalg.norm(np.asarray(a)[:, :2] - c, axis=1) <= rad))
            resp = rec.get("resp")
            info = ""
            if not near(resp):
                st = "R"
            elif not near(rec.get("spots", (None,))[0]):
                rank = int(np.argmin(np.linalg.norm(resp[:, :2] - c, axis=1)))
                st = "K"; info = f"rank {rank}/{len(resp)} resp {resp[rank,2]:.1f}"
            elif not near(rec["found"].left_px if "found" in rec else None):
                ms = [m for m in rec.get("match", []) if np.hypot(m[0] - c[0], m[1] - c[1]) <= rad]
                st = "M"; info = str([(m[0], m[1], None if m[2] is None else tuple(round(v, 2) for v in m[2])) for m in ms])
            elif not near(rec["kept"].left_px):
                st = "U"
            else:
                st = "F"
            tally[(st, out)] += 1
            print(f"{family} {seed0} scene {k:2d} draw {d} {out:15s} {st} {info}", flush=True)
print("SUMMARY", family, seed0, sigma, " ".join(over), sorted(tally.items()))
