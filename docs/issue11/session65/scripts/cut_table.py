"""Runs with a different setting (run_pairs.sh outputs, DIR...) against the same runs on the defaults: this
session's band (campaigns/final/band*) where it has them, else the latest earlier layout campaign:
    python docs/issue11/session65/scripts/cut_table.py PAIRS DIR [DIR ...]"""
import glob, json, os, sys

from latest_runs import latest_runs

def first(path):
    return next((json.loads(l) for l in open(path) if l.startswith('{"seed')), None)

latest = latest_runs()
tot_b, tot_a, moved, dt = {}, {}, 0, []
for line in open(sys.argv[1]):
    name, seed = line.split()[:2]
    now = next((first(p) for d in sys.argv[2:] if os.path.exists(p := os.path.join(d, f"{name}_s{seed}_px0.txt"))), None)
    if now is None:
        continue
    band = [p for p in glob.glob(f"docs/issue11/session65/campaigns/final/band*/{name}_s{seed}_px0.txt")]
    b = first(band[0]) if band else latest[(name, int(seed))]
    tot_b[b["outcome"]] = tot_b.get(b["outcome"], 0) + 1
    tot_a[now["outcome"]] = tot_a.get(now["outcome"], 0) + 1
    new_close = "close_in" in now["states"] and "close_in" not in b["states"]
    moved += new_close
    if b["outcome"] == now["outcome"] == "arrived":
        dt.append(now["time_to_arrive_s"] - b["time_to_arrive_s"])
    if new_close or b["outcome"] != now["outcome"]:
        print(f"{name} s{seed}: {b['outcome']} -> {now['outcome']}, newly closed in {new_close}, "
              f"arrive {b['time_to_arrive_s']} -> {now['time_to_arrive_s']}")
print("defaults", tot_b, "now", tot_a, f"newly closed in {moved}")
if dt:
    dt.sort()
    print(f"arrival time change over {len(dt)} arrived both: median {dt[len(dt) // 2]:+.1f} s, max {dt[-1]:+.1f} s")
