"""Run by run, the band's missions now (run_pairs.sh outputs) against the same layout and seed in the latest layout
campaign before (docs/issue11/session*/campaigns, the onbg folder of this session included): outcome, closed in,
arrival time; then the totals.
    python docs/issue11/session65/scripts/band_table.py PAIRS DIR [DIR ...]"""
import json, os, statistics, sys

from latest_runs import latest_runs

before = latest_runs(skip=("/final/band", "/final/fragile"))
tot_b, tot_a, closed, extra = {}, {}, 0, []
for line in open(sys.argv[1]):
    name, seed = line.split()[:2]
    now = None
    for d in sys.argv[2:]:
        f = os.path.join(d, f"{name}_s{seed}_px0.txt")
        if os.path.exists(f):
            now = next((json.loads(l) for l in open(f) if l.startswith('{"seed')), None)
    if now is None:
        continue
    b = before[(name, int(seed))]
    tot_b[b["outcome"]] = tot_b.get(b["outcome"], 0) + 1
    tot_a[now["outcome"]] = tot_a.get(now["outcome"], 0) + 1
    moved = "close_in" in now["states"]
    closed += moved
    if b["outcome"] == now["outcome"] == "arrived":
        extra.append(now["time_to_arrive_s"] - b["time_to_arrive_s"])
    looks = ", ".join(f"{x['kind']} {x['one_look']}" for x in now["decisions"])
    mark = "  <- changed" if b["outcome"] != now["outcome"] else ""
    t = now["time_to_arrive_s"]
    print(f"{name:15s} s{seed}  before {b['outcome']:9s} now {now['outcome']:9s} closed in {str(moved):5s} "
          f"arrive {'-' if t is None else f'{t:5.1f}'} s  decisions: {looks}{mark}")
print("before", tot_b, "now", tot_a, f"closed in {closed}")
if extra:
    print(f"arrival time change over {len(extra)} runs arrived both times: median {statistics.median(extra):+.1f} s, "
          f"max {max(extra):+.1f} s, min {min(extra):+.1f} s")
