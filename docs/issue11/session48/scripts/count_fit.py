"""Run a script (and its arguments) with grouping.split_chain counting the chains wider than any target, and those
whose cut is kept only because each side fits one target (the session 48 rule; the cohesion ratio alone refuses it).

    python docs/issue11/session48/scripts/count_fit.py docs/issue11/session33/scripts/fam.py 20 SEED 2
"""
import sys, runpy, atexit, numpy as np
import dip3d_vehicle.perception.grouping as G
count = {"wide": 0, "fit_only": 0}
orig = G.split_chain
def wrapped(members, pairs, left_px, depth_m, focal_px, max_extent_m, depth=2, cut=None):
    if depth == 2 and G.extent_m(left_px[members], float(np.median(depth_m[members])), focal_px) > max_extent_m:
        count["wide"] += 1
        phi, a, b = cut if cut is not None else G._least_cut(members, pairs)
        if phi < G.SPLIT_MAX_CONDUCTANCE and len(b):
            coh = min(G._least_cut(a, pairs)[0], G._least_cut(b, pairs)[0]) >= G.SPLIT_COHESION_RATIO * phi
            fit = all(not G.extent_m(left_px[s], float(np.median(depth_m[s])), focal_px) > max_extent_m for s in (a, b))
            if fit and not coh:
                count["fit_only"] += 1
    return orig(members, pairs, left_px, depth_m, focal_px, max_extent_m, depth, cut)
G.split_chain = wrapped
atexit.register(lambda: print("SPLIT COUNTS", count, flush=True))
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
