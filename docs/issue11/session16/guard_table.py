"""Which acted-on decisions a guard on the one-look "none" share would have stopped.

Usage: python docs/issue11/session16/guard_table.py FILE [FILE ...]
FILE: ``python -m sitl.point_campaign mission`` output named after its scenario (``near_miss.txt``;
its run lines carry every acted-on decision's record), or the stored ``study_*.jsonl`` (their lines
name the scenario).
Per run: the first acted-on OBJECT decision's one-look posterior (best, "none", the best other
object). For thresholds on the "none" share, how many of the runs that arrived and of those that went
to a wrong placard had their decision at or above it (a counterfactual: a stopped decision might be
followed by another one).
"""
from __future__ import annotations

import json
import sys
from pathlib import Path


def rows(paths: list[str]) -> list[dict]:
    """Return one row per run with an object decision: scenario, seed, outcome, best, none, other."""
    out = []
    for path in paths:
        for line in open(path):
            run = json.loads(line)
            if "seed" not in run:                      # a campaign's summary line
                continue
            run.setdefault("scenario", Path(path).stem)
            decision = next((d for d in run["decisions"] if d["kind"] == "object"), None)
            if decision is None or not decision.get("one_look_posterior"):
                continue
            post = dict(decision["one_look_posterior"])
            none = post.pop("none", 0.0)
            ranked = sorted(post.values(), reverse=True)
            out.append({"scenario": run["scenario"], "seed": run["seed"], "outcome": run["outcome"],
                        "best": ranked[0], "none": none, "other": ranked[1] if len(ranked) > 1 else 0.0})
    return out


def main(paths: list[str]) -> None:
    table = rows(paths)
    for r in sorted(table, key=lambda r: -r["none"]):
        print(f"{r['scenario']:18s} {r['seed']:3d} {r['outcome']:9s} best {r['best']:.3f} none {r['none']:.3f} "
              f"other {r['other']:.3f}")
    for tau in (0.05, 0.1, 0.15, 0.2, 0.25, 0.3):
        stopped = [r for r in table if r["none"] >= tau]
        print(f"none >= {tau:.2f}: stops {sum(r['outcome'] == 'wrong' for r in stopped)} of "
              f"{sum(r['outcome'] == 'wrong' for r in table)} wrong, {sum(r['outcome'] == 'arrived' for r in stopped)} of "
              f"{sum(r['outcome'] == 'arrived' for r in table)} arrived")


if __name__ == "__main__":
    main(sys.argv[1:])
