"""Runs of a mission folder that met a weak object decision (one look < 0.6) or moved (close in / second look):
   python weak_runs.py MISSION_DIR > RUNS.txt  (SUB NAME SEED OUTCOME WEAK MOVED per line)."""
import glob, json, os, re, sys
out=[]
for path in sorted(glob.glob(os.path.join(sys.argv[1], "*", "*.txt"))):
    sub=os.path.basename(os.path.dirname(path)); name=os.path.basename(path)[:-4]
    for piece in re.findall(r'\{"seed".*?"decisions": \[.*?\]\}', open(path).read()):
        d=json.loads(piece)
        weak=any(x["kind"]=="object" and x["one_look"] is not None and x["one_look"]<0.6 for x in d["decisions"])
        moved=any(s in ("close_in","second_look") for s in d["states"])
        if weak or moved: out.append((sub,name,d["seed"],d["outcome"],weak,moved))
for o in out: print(*o)
print(len(out), file=sys.stderr)
