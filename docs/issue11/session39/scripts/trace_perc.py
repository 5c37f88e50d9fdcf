"""Run one sitl mission in-process; print each decided frame's candidates on placards 2/3 (start-pose boxes)."""
import sys
import numpy as np
from dip3d_vehicle.perception import pipeline as pl
from dip3d_vehicle import cli
BOXES = {2: (1045, 585, 1130, 665), 3: (1247, 553, 1377, 668)}
_orig = pl.Perception.decide
def decide(self, checked, cands, timings=None, images=None):
    res = _orig(self, checked, cands, timings, images)
    cnt = {}
    if cands is not None and len(cands):
        for k, (x0, y0, x1, y1) in BOXES.items():
            p = cands.left_px
            cnt[k] = int(np.sum((p[:, 0] >= x0) & (p[:, 0] <= x1) & (p[:, 1] >= y0) & (p[:, 1] <= y1)))
    sel = res.selection
    objs = []
    if sel is not None and sel.method == "default":
        objs = [f"({o.xyz_m[0]:.2f},{o.xyz_m[2]:.2f}) n{len(o.members)} {s:.2f}" for o, s in zip(sel.objects, sel.scores)]
    arm = checked.arm
    w = None if arm is None else np.round(arm.left_px[2], 0).tolist()
    print(f"PERC n={0 if cands is None else len(cands)} on2={cnt.get(2)} on3={cnt.get(3)} status={res.status} wrist={w} objs={objs} none={getattr(sel, 'none_probability', None)}", flush=True)
    return res
pl.Perception.decide = decide
scen, seed, out = sys.argv[1:4]
sys.exit(cli.main(["sitl", "--scenario", scen, "--seed", seed, "--no-plots", "--out", out, *sys.argv[4:]]))
