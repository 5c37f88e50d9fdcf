"""How often a background rule sets aside BlazePose's wrist matches, off (more than 2.5 px from the truth) and not.

    python docs/issue14/session31/scripts/wrist_rules.py CENSUS.jsonl[.gz] ...

Reads ``wrist_census.py`` lines; frames whose BlazePose joints lie within 25 px of the truth (2D) and whose wrist
(or elbow) was matched. A rule flags a joint when one of the named probes matched within TOL px of the joint's
disparity with a score at least the joint's minus DSCORE.
"""
import gzip, json, sys


def lines(path):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as fh:
        return [json.loads(l) for l in fh]


def flagged(r, k, tol, names, dscore, minscore=0.6):
    d, sc = abs(r["d_px"][k]), r["score"][k]
    for n in names:
        p = r[f"probes_{k}"].get(n)
        if p is None or p[0] is None:
            continue
        md, _, mscore = p[0]
        if abs(md - d) <= tol and mscore >= max(minscore, sc - dscore):
            return True
    return False


rows = [r for f in sys.argv[1:] for r in lines(f)]
for k, joint in ((2, "wrist"), (1, "elbow")):
    print(f"{joint}: rule (tol px, probes, dscore): off flagged / off, not off flagged / not off")
    for tol in (0.75, 1.0, 1.5):
        for names in (("beyond",), ("side_a", "side_b"), ("beyond", "side_a", "side_b")):
            for dscore in (0.0, 0.05):
                good = bad = fg = fb = 0
                for r in rows:
                    if not r["matched"][k] or max(r["err2d_px"][:k + 1]) > 25:
                        continue
                    off = abs(abs(r["d_px"][k]) - abs(r["true_d_px"][k])) > 2.5
                    f = flagged(r, k, tol, names, dscore)
                    bad, fb = bad + off, fb + (off and f)
                    good, fg = good + (not off), fg + (f and not off)
                print(f"  {tol:4} {'+'.join(names):22s} {dscore:4}: {fb:4d} / {bad:4d}   {fg:4d} / {good:4d} "
                      f"({100 * fg / max(good, 1):.1f} %)")
