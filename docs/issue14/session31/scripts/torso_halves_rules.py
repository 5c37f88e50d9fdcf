"""Whether the two torso halves' disparities tell which shoulder is nearer (``torso_halves_census.py`` lines).

    python docs/issue14/session31/scripts/torso_halves_rules.py CENSUS.jsonl
"""
import gzip, json, sys
rows = [json.loads(l) for f in sys.argv[1:] for l in (gzip.open(f, 'rt') if f.endswith('.gz') else open(f))]
print(len(rows), "frames; BlazePose near right:", sum(r["near"] == r["true_near"] for r in rows))
keys = rows[0]["halves"].keys()
for key in keys:
    for thr in (0.5, 1.0, 1.5, 2.0):
        n = agree = disagree = bp_wrong = fixed = broke = 0
        for r in rows:
            h = r["halves"][key]
            if h[0] is None or h[1] is None: continue
            dd = h[0][0] - h[1][0]
            sig = (h[0][1]**2 + h[1][1]**2) ** 0.5
            if abs(dd) < max(thr, 0 * sig): continue
            n += 1
            st = dd > 0
            agree += st == r["true_near"]
            if r["near"] != r["true_near"]:
                bp_wrong += 1; fixed += st == r["true_near"]
            else:
                broke += st != r["true_near"]
        tot_bp_wrong = sum(r["near"] != r["true_near"] for r in rows)
        print(f"{key:10s} thr {thr}: decided {n}, stereo right {agree} ({100*agree/max(n,1):.0f}%); of BlazePose's wrong {tot_bp_wrong}: decided {bp_wrong}, stereo right {fixed}; of BlazePose's right decided: stereo wrong {broke}")
