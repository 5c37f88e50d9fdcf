"""Frames with an arm, confident arms, and per-frame right / wrong picks per scenario, for two arm_eval tags
(issue 14 session 73: blazepose.local_retry + reject_retry off / on, 8 frames per scenario from the start pose):
    python docs/issue11/session73/scripts/retries_summary.py DIR [TAG_A TAG_B]"""
import glob
import json
import os
import sys


def counts(path: str) -> tuple[int, int, int, int]:
    """Return (frames with an arm, confident arms, right picks, wrong picks) of one arm_eval JSON."""
    rows = json.load(open(path))["rows"]
    sel = [str(r["stereo"].get("select")) for r in rows if "stereo" in r]
    return len(rows), sum(r["arm_found"] for r in rows), sel.count("right"), sel.count("wrong")


def main(folder: str, a: str = "off", b: str = "on") -> None:
    """Print the scenarios that differ and the totals."""
    per = {t: {os.path.basename(f)[len(t) + 1:-5]: counts(f) for f in glob.glob(os.path.join(folder, f"{t}_*.json"))}
           for t in (a, b)}
    totals = {t: [sum(v[i] for v in per[t].values()) for i in range(4)] for t in (a, b)}
    for name in sorted(per[a].keys() | per[b].keys()):
        if per[a].get(name) != per[b].get(name):
            print(f"{name}: {a} {per[a].get(name)} {b} {per[b].get(name)}")
    print(f"(frames with an arm, confident, right, wrong) over {len(per[a])} scenarios: {a} {totals[a]} {b} {totals[b]}")


if __name__ == "__main__":
    main(*sys.argv[1:])
