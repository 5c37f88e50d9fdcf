"""Runs whose states include close_in, as run_list.sh lines:  python close_in_runs.py DIR [DIR ...]"""
import glob, json, os, re, sys, collections
g=collections.OrderedDict()
for root in sys.argv[1:]:
    for path in sorted(glob.glob(os.path.join(root, "*", "*.txt"))):
        sub=os.path.basename(os.path.dirname(path)); name=os.path.basename(path)[:-4]
        for piece in re.findall(r'\{"seed".*?"decisions": \[.*?\]\}', open(path).read()):
            d=json.loads(piece)
            if "close_in" in d["states"]:
                s=g.setdefault((sub,name),[])
                if str(d["seed"]) not in s: s.append(str(d["seed"]))
for (sub,name),seeds in g.items(): print(sub,name,",".join(sorted(seeds)))
