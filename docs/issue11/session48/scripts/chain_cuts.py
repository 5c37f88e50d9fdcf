"""Run a script with grouping.split_chain printing, for each chain wider than any target, its least cut, its sides'
own least cuts and widths (what the cohesion ratio and the fit rule see).

    python docs/issue11/session48/scripts/chain_cuts.py docs/issue11/session47/scripts/start_frame_objects.py SCENARIO SEED T_S
"""
import sys, runpy, numpy as np
import dip3d_vehicle.perception.grouping as G
orig = G.split_chain
def wrapped(members, pairs, left_px, depth_m, focal_px, max_extent_m, depth=2, cut=None):
    ext = G.extent_m(left_px[members], float(np.median(depth_m[members])), focal_px)
    if ext > max_extent_m and depth == 2:
        phi, a, b = cut if cut is not None else G._least_cut(members, pairs)
        sa, sb = G._least_cut(a, pairs)[0], G._least_cut(b, pairs)[0]
        xa = G.extent_m(left_px[a], float(np.median(depth_m[a])), focal_px) if len(a) > 1 else 0
        xb = G.extent_m(left_px[b], float(np.median(depth_m[b])), focal_px) if len(b) > 1 else 0
        print(f"  CHAIN n={len(members)} extent {ext:.2f} phi {phi:.3f} sides {len(a)}/{len(b)} side-phi {sa:.3f}/{sb:.3f} side extents {xa:.2f}/{xb:.2f} ")
        ca = np.median(left_px[a],axis=0); cb = np.median(left_px[b],axis=0)
        print(f"   side centres px {ca.round()} {cb.round()}")
    return orig(members, pairs, left_px, depth_m, focal_px, max_extent_m, depth, cut)
G.split_chain = wrapped
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
