"""One table row per firmware campaign file (tools/firmware_missions.py's JSON lines): arrived / wrong / abstained,
arrival times (sum, median, range, s), the absolute range error at arrival (median, max, m) and the least distance
to a placard other than the pointed one (m).

    python docs/issue11/session56/scripts/firmware_table.py FILE.jsonl [FILE.jsonl ...]
"""
import json
import statistics
import sys

for path in sys.argv[1:]:
    rows = [json.loads(line) for line in open(path) if line.strip().startswith("{")]
    arrived = [r for r in rows if r.get("arrived") and r.get("chosen_id") == r.get("target_id")]
    wrong = [r for r in rows if r.get("arrived") and r.get("chosen_id") != r.get("target_id")]
    times = [r["time_to_arrive_s"] for r in arrived]
    errs = [abs(r["range_error_at_arrival_m"]) for r in arrived if r.get("range_error_at_arrival_m") is not None]
    others = [d for r in rows for k, d in (r.get("closest_m") or {}).items() if int(k) != r.get("target_id")]
    t = (f"{sum(times):.1f} s, {statistics.median(times):.1f} s ({min(times):.1f}-{max(times):.1f})" if times else "-")
    e = f"{statistics.median(errs):.3f} ({max(errs):.3f}) m" if errs else "-"
    print(f"| {path} | {len(arrived)} / {len(wrong)} / {len(rows) - len(arrived) - len(wrong)} | {t} | {e} | "
          f"{min(others):.2f} m |" if others else f"| {path} | no rows |")
