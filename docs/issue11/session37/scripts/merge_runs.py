"""Merge mission folders run by run: a later folder's run (same file, seed, position) replaces an earlier one's.

    python merge_runs.py OUT_DIR FIRST_DIR [LATER_DIR ...]

Each folder holds SUBDIR/NAME.txt `point_campaign mission` lines; OUT_DIR gets one JSON line per run.
"""
import glob, json, os, re, sys

out, dirs = sys.argv[1], sys.argv[2:]
runs: dict = {}
for d in dirs:
    for path in sorted(glob.glob(os.path.join(d, "*", "*.txt"))):
        rel = os.path.relpath(path, d)
        for piece in re.findall(r'\{"seed".*?"decisions": \[.*?\]\}', open(path).read()):
            r = json.loads(piece)
            runs.setdefault(rel, {})[(r["seed"], r.get("position"))] = piece
for rel, by in runs.items():
    os.makedirs(os.path.dirname(os.path.join(out, rel)), exist_ok=True)
    with open(os.path.join(out, rel), "w") as f:
        for key in sorted(by, key=str):
            f.write(by[key] + "\n")
print(sum(len(v) for v in runs.values()), "runs")
