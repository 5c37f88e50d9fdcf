"""Fault-mission campaigns compared per plan: reached / outcomes, crashes, least distance to the diver's body and to
another placard, bounded events within their bound, log records written = read, and the seeds whose "reached"
differs, from ``python -m sitl.fault_campaign missions --json`` files:
    python docs/issue11/session61/scripts/fault_compare.py PLAN LABEL=GLOB [LABEL=GLOB ...]"""
import collections
import glob
import json
import sys

plan, specs = sys.argv[1], [a.split("=", 1) for a in sys.argv[2:]]
runs = {}
for label, pattern in specs:
    rows = {}
    for f in sorted(glob.glob(pattern)):
        for r in json.load(open(f))["runs"]:
            rows[r["seed"]] = r
    runs[label] = rows
first = specs[0][0]
print(f"| {plan} | runs | reached | outcomes | crashes | least diver m | least other m | bounded events within | "
      f"log written = read | seeds that differ from {first} |")
print("|---|---|---|---|---|---|---|---|---|---|")
for label, _ in specs:
    rows = runs[label]
    out = collections.Counter(r.get("outcome", "crashed") for r in rows.values())
    crashes = sum(bool(r.get("crashed")) for r in rows.values())
    diver = min((r["closest_diver_m"] for r in rows.values() if r.get("closest_diver_m") is not None), default=None)
    other = min((r["closest_other_m"] for r in rows.values() if r.get("closest_other_m") is not None), default=None)
    bounded = [e for r in rows.values() for e in r.get("fault_safety", []) if e.get("bound_s") is not None]
    within = sum(max(e.get("last_motion_sent_s") or 0, e.get("last_motion_received_s") or 0) <= e["bound_s"]
                 for e in bounded)
    logs = sum(r.get("log_written") == r.get("log_read") for r in rows.values())
    diff = [f"{s}:{rows[s].get('outcome')}" for s in sorted(rows) if s in runs[first]
            and (rows[s].get("outcome") == "reached") != (runs[first][s].get("outcome") == "reached")]
    print(f"| {label} | {len(rows)} | {out['reached']} | {dict(out)} | {crashes} | {diver} | {other} | "
          f"{within}/{len(bounded)} | {logs}/{len(rows)} | {', '.join(diff) if label != first else '-'} |")
