"""Session 52's safety table (outcomes, how near another placard and the diver) with, per file, how many arrivals
held short of the stand-off and by how much (``held_short_m``: the way found no clear way to the stand-off).

    python docs/issue11/session53/scripts/held_table.py DIR [BEFORE_DIR]
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "session52" / "scripts"))
from safety_table import cell, runs, summary  # noqa: E402


def held(rs) -> str:
    """Return 'N (max M m)' for the arrivals held short, '0' for none."""
    h = [r["held_short_m"] for r in rs if r["outcome"] == "arrived" and (r.get("held_short_m") or 0) > 0]
    return f"{len(h)} (max {max(h):.1f} m)" if h else "0"


def main() -> None:
    here = Path(sys.argv[1])
    before = Path(sys.argv[2]) if len(sys.argv) > 2 else None
    head = ("| file | arrived / wrong / abstained | least to another placard / runs under 0.29 m "
            "| least to the diver / under 0.45 m | arrivals held short |")
    print(head + (" before: outcomes | placards | diver |" if before else ""))
    print("|---" * (head.count("|") - 1 + (3 if before else 0)) + "|")
    total, total_before = [], []
    for f in sorted(here.rglob("*.txt")):
        rel = f.relative_to(here)
        a = runs(f)
        if not a:
            continue
        total += a.values()
        row = f"| {rel} | {cell(summary(a))} | {held(a.values())} |"
        if before:
            b = runs(before / rel)
            total_before += b.values()
            row += f" {cell(summary(b))} |" if b else " - | - | - |"
        print(row)
    row = f"| **all {len(total)}** | {cell(summary(dict(enumerate(total))))} | {held(total)} |"
    if before:
        row += f" {cell(summary(dict(enumerate(total_before))))} |"
    print(row)


if __name__ == "__main__":
    main()
