"""Run by run against an earlier mission folder: outcome, chosen placard, arrival time, the decision and the states
(the fields the sidestep can change), with the closest-approach figures of the new folder.

    python docs/issue11/session51/scripts/compare_runs.py AFTER_DIR BEFORE_DIR

Prints each differing run, then the totals and the arrival-time changes of the runs arrived in both.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session45" / "scripts"))
from compare_missions import run_lines as runs  # noqa: E402  (session 45's reader of the run lines)

FIELDS = ("outcome", "chosen_id", "time_to_arrive_s", "decision", "decision_posterior", "decision_one_look", "states")
after, before = runs(Path(sys.argv[1])), runs(Path(sys.argv[2]))
common = sorted(k for k in after if k in before)
changed, shifts, near = 0, [], []
for k in common:
    a, b = after[k], before[k]
    diff = [f for f in FIELDS if a.get(f) != b.get(f)]
    if a.get("closest_other_m") is not None:
        near.append(a["closest_other_m"])
    if a["outcome"] == b["outcome"] == "arrived":
        shifts.append(a["time_to_arrive_s"] - b["time_to_arrive_s"])
    if diff:
        changed += 1
        print(f"{k[0]} seed {k[1]}: " + "; ".join(
            f"{f}: {b.get(f)!r} -> {a.get(f)!r}" for f in diff if f != "states") + ("; states differ" if "states" in diff else "")
            + f"  (closest_other_m {a.get('closest_other_m')})")
tot = {}
for name, rs in (("after", after), ("before", before)):
    sel = [rs[k] for k in common]
    tot[name] = [sum(r["outcome"] == o for r in sel) for o in ("arrived", "wrong", "abstained")]
print(f"{len(common)} runs compared, {changed} differ in {', '.join(FIELDS)}")
print(f"arrived / wrong / abstained: before {' / '.join(map(str, tot['before']))}, after {' / '.join(map(str, tot['after']))}")
if shifts:
    shifts.sort()
    print(f"arrival time change over {len(shifts)} runs arrived in both: sum {sum(shifts):+.1f} s, "
          f"min {shifts[0]:+.1f}, median {shifts[len(shifts) // 2]:+.1f}, max {shifts[-1]:+.1f} s")
if near:
    print(f"closest_other_m after: least {min(near):.2f} m, runs under 0.29 m: {sum(d < 0.29 for d in near)} of {len(near)}")
