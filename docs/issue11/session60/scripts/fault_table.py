"""Whole-mission fault campaigns per configuration: reached the pointed placard, outcomes, crashes and the seeds that
differ from the first configuration, from ``python -m sitl.fault_campaign missions --json`` files:
    python docs/issue11/session60/scripts/fault_table.py DIR PLAN CONFIG [CONFIG ...]
(files DIR/PLAN_CONFIG*.json; session 60: link_cut / gcs_loss with new, old, vehicle_margin03)."""
import collections
import glob
import json
import os
import sys

root, plan, configs = sys.argv[1], sys.argv[2], sys.argv[3:]
runs = {}
for c in configs:
    rows = {}
    for f in sorted(glob.glob(os.path.join(root, f"{plan}_{c}*.json"))):
        if c == "new" and "margin" in f:
            continue
        d = json.load(open(f))
        for r in (d["runs"] if isinstance(d, dict) else d):
            rows[r["seed"]] = r
    runs[c] = rows
first = configs[0]
for c in configs:
    rows = runs[c]
    out = collections.Counter(r.get("outcome", "crashed") for r in rows.values())
    crashed = sum(bool(r.get("crashed")) for r in rows.values())
    diff = [s for s in sorted(rows) if s in runs[first] and (rows[s].get("outcome") == "reached")
            != (runs[first][s].get("outcome") == "reached")]
    changed = ", ".join(f"{s}:{rows[s].get('outcome')}" for s in diff) if c != first else "-"
    print(f"| {c} | {len(rows)} | {out['reached']} | {dict(out)} | {crashed} | {changed} |")
