"""Whether a smaller patch gives back a wrist that ``on_background`` set aside (``small_patch_census.py`` lines).

    python docs/issue14/session31/scripts/small_patch_rules.py CENSUS.jsonl ...

Frames whose joints lie within 25 px of the truth. Per patch size: of the wrists set aside, how many the small
patch matches, how many of those its own background check leaves, and how far they lie from the truth.
"""
import json, sys
rows = [json.loads(l) for f in sys.argv[1:] for l in open(f)]
rows = [r for r in rows if max(r["err2d"]) <= 25]
aside = [r for r in rows if r["aside"]]
kept = [r for r in rows if not r["aside"]]
print("frames", len(rows), "aside", len(aside))
for pm in ("0.04", "0.06", "0.08"):
    m = [r for r in aside if r["small"][pm][0]]
    ok = [r for r in m if r["small"][pm][4]]   # small match not itself explained by the background
    good = [r for r in ok if abs(r["small"][pm][1] - r["true"]) <= 1.5]
    bad = [r for r in ok if abs(r["small"][pm][1] - r["true"]) > 2.5]
    conf_bad = [r for r in bad if r["small"][pm][2] <= 1.0]
    print(f"patch {pm}: aside & small matched {len(m)}; not explained {len(ok)}: within 1.5 px {len(good)}, >2.5 px off {len(bad)} (sigma<=1: {len(conf_bad)})")
    # on kept (not aside) frames, how does the small patch compare (for reference)
    mk = [r for r in kept if r["small"][pm][0] and r["small"][pm][4]]
    print(f"   kept frames: small within 1.5 {sum(abs(r['small'][pm][1]-r['true'])<=1.5 for r in mk)}/{len(mk)}; 0.12 within 1.5 {sum(abs(r['d']-r['true'])<=1.5 for r in kept)}/{len(kept)}")
