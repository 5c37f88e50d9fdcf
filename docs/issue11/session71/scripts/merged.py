"""Outcomes and least passes of a campaign with some runs replaced by re-runs (issue 11 session 71).

    python docs/issue11/session71/scripts/merged.py BASE_DIR RERUN_DIR
Runs are matched by layout name and seed; a run in RERUN_DIR replaces the same run of BASE_DIR.
"""
import sys

from runs import rows


def main() -> None:
    base = {(n, r["seed"]): r for n, r in rows(sys.argv[1])}
    again = {(n, r["seed"]): r for n, r in rows(sys.argv[2]) if (n, r["seed"]) in base}
    merged = {**base, **again}
    count = {k: sum(r["outcome"] == k for r in merged.values()) for k in ("arrived", "wrong", "abstained")}
    other = min(r["closest_other_m"] for r in merged.values() if r["closest_other_m"] is not None)
    diver = min(r["closest_diver_m"] for r in merged.values() if r["closest_diver_m"] is not None)
    print(f"{len(merged)} runs, {len(again)} replaced: {count['arrived']} / {count['wrong']} / {count['abstained']}; "
          f"least pass by another placard {other:.2f} m, by the diver {diver:.2f} m")
    for key in sorted(again):
        a, b = base[key], again[key]
        print(f"  {key[0]} s{key[1]}: {a['outcome']} ({a['time_to_arrive_s']}) -> {b['outcome']} ({b['time_to_arrive_s']}), "
              f"second looks {a['second_looks']} -> {b['second_looks']}, closest other {a['closest_other_m']} -> "
              f"{b['closest_other_m']}")


if __name__ == "__main__":
    main()
