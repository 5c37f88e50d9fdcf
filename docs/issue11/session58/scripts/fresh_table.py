"""Fresh-layout outcomes per folder, ordinary vs 4 cm pointed placard, least distances:
    python docs/issue11/session58/scripts/fresh_table.py CAMPAIGN_DIR LAYOUTS_DIR"""
import glob, json, os, sys, collections
root = sys.argv[1]
for folder in sorted(glob.glob(os.path.join(root, "variants_seed*"))):
    name = os.path.basename(folder)
    lay = os.path.join(sys.argv[2], name)
    small = {os.path.basename(f)[:-5] for f in glob.glob(lay + "/*.yaml") if "size_m: 0.04" in open(f).read()}
    for kind in ("ordinary", "small"):
        c = collections.Counter(); nt = 0; lo = []; ld = []; times = []; notes = []
        for f in sorted(glob.glob(folder + "/default_*.txt")):
            v = os.path.basename(f)[8:-4]
            if (v in small) != (kind == "small"):
                continue
            for l in open(f):
                if not l.startswith("{"): continue
                d = json.loads(l)
                if d.get("seed") is None: continue
                c[d["outcome"]] += 1; nt += bool(d.get("nothing_there"))
                if d.get("closest_other_m") is not None: lo.append(d["closest_other_m"])
                if d.get("closest_diver_m") is not None: ld.append(d["closest_diver_m"])
                if d["outcome"] == "arrived": times.append(d["time_to_arrive_s"])
                if d["outcome"] != "arrived": notes.append(f"{v} s{d['seed']} {d['outcome']}{' nothing' if d.get('nothing_there') else ''}")
        n = sum(c.values())
        if not n: continue
        times.sort()
        print(f"{name} {kind}: {n} runs, {c['arrived']}/{c['wrong']}/{c['abstained']}, nothing_there {nt}, "
              f"least other {min(lo):.2f} m, least diver {min(ld):.2f} m, median arrival {times[len(times)//2] if times else '-'}")
        print("   ", "; ".join(notes))
