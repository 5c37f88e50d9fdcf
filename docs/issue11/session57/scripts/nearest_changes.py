"""Runs whose least distance to another placard or to the diver changed by more than 5 cm between two campaigns, with
their outcomes, arrival times and how far they held short (metres, seconds):

    python docs/issue11/session57/scripts/nearest_changes.py AFTER BEFORE
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session45" / "scripts"))
from compare_missions import run_lines  # noqa: E402


def fmt(r: dict) -> str:
    """Return one run's outcome, arrival time, least other placard / diver distance and held short, as text."""
    t = r.get("time_to_arrive_s")
    other = r.get("closest_other_m") or float("nan")
    return (f"{r['outcome']:9s} {'' if t is None else f'{t:5.1f} s'} other {other:.2f} "
            f"diver {r.get('closest_diver_m') or float('nan'):.2f} held {r.get('held_short_m') or 0:.1f}")


def main(after: Path, before: Path) -> None:
    """Print the runs of ``after`` whose nearest distances moved against ``before``."""
    a, b = run_lines(after), run_lines(before)
    for key in sorted(set(a) & set(b)):
        ra, rb = a[key], b[key]
        moved = [abs((ra.get(k) or 0) - (rb.get(k) or 0)) > 0.05 for k in ("closest_other_m", "closest_diver_m")]
        if any(moved):
            print(f"{key[0]} s{key[1]}: {fmt(rb)} -> {fmt(ra)}")


if __name__ == "__main__":
    main(Path(sys.argv[1]), Path(sys.argv[2]))
