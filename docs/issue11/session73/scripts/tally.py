"""arrived / wrong / abstained and the median arrival time (s) over campaign folders, restricted to the runs both
sides have (issue 11/14 session 73):  python docs/issue11/session73/scripts/tally.py BEFORE_DIR[,...] AFTER_DIR[,...]"""
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session68" / "scripts"))
from pair_diff import load  # noqa: E402


def tally(runs: dict, keys) -> str:
    """Return 'arrived / wrong / abstained, median arrival s' over ``keys``."""
    out = [runs[k]["outcome"] for k in keys]
    times = [runs[k]["time_to_arrive_s"] for k in keys if runs[k]["outcome"] == "arrived"]
    med = statistics.median(times) if times else float("nan")
    return f"{out.count('arrived')} / {out.count('wrong')} / {len(out) - out.count('arrived') - out.count('wrong')}, median arrival {med:.1f} s"


if __name__ == "__main__":
    before, after = load(sys.argv[1]), load(sys.argv[2])
    keys = sorted(before.keys() & after.keys())
    for name in sorted({k[0] for k in keys}) + [None]:
        ks = [k for k in keys if name is None or k[0] == name]
        if name is None or len(ks) > 1:
            print(f"{name or 'all'} ({len(ks)} runs): {tally(before, ks)} -> {tally(after, ks)}")
