"""The re-look runs whose fresh look acted on an object under BAR counted as one look, as run_pairs.sh lines:
    python docs/issue11/session66/scripts/weak_relooks.py BAR OUT_DIR [OUT_DIR ...] > PAIRS"""
import glob, json, os, sys

bar = float(sys.argv[1])
for d in sys.argv[2:]:
    for f in sorted(glob.glob(os.path.join(d, "*_px0.txt"))):
        rec = next((json.loads(l) for l in open(f) if l.startswith('{"seed"')), None)
        if rec is None or len(rec["decisions"]) < 2:
            continue
        again = rec["decisions"][1]
        if rec["decisions"][0]["kind"] == "none" and again["kind"] == "object" and again["one_look"] < bar:
            print(os.path.basename(f).rsplit("_s", 1)[0], rec["seed"], 0, rec["outcome"])
