"""Per mission file: outcomes and how near the vehicle's centre came to another placard's face and to the diver's
body axes, with totals; with BEFORE_DIR, the same files there side by side.

    python docs/issue11/session52/scripts/safety_table.py DIR [BEFORE_DIR]

Reads every ``*.txt`` file under DIR (``python -m sitl.point_campaign mission`` lines with ``closest_other_m`` and
``closest_diver_m``). TOUCH_M: a BlueROV2's half-diagonal in plan; nearer a placard's face, its hull may touch it.
DIVER_M: nearer the diver's body axes than this, the hull (0.29 m) reaches a diver's body or arm (~0.15 m thick).
"""
import json
import sys
from pathlib import Path

TOUCH_M = 0.29
DIVER_M = 0.45


def runs(path: Path) -> dict[int, dict]:
    """Return the run lines of one mission file by seed (tolerant of a notice glued to a line)."""
    out = {}
    if not path.exists():
        return out
    for line in path.read_text().splitlines():
        i = line.find('{"seed"')
        if i >= 0:
            d = json.loads(line[i: line.rfind("}") + 1])
            out[d["seed"]] = d
    return out


def summary(rs: dict[int, dict]) -> tuple:
    """Return (arrived, wrong, abstained, least other, runs under TOUCH_M, least diver, runs under DIVER_M)."""
    counts = [sum(r["outcome"] == o for r in rs.values()) for o in ("arrived", "wrong", "abstained")]
    other = [r["closest_other_m"] for r in rs.values() if r.get("closest_other_m") is not None]
    diver = [r["closest_diver_m"] for r in rs.values() if r.get("closest_diver_m") is not None]
    return (*counts, min(other, default=None), sum(d < TOUCH_M for d in other), min(diver, default=None),
            sum(d < DIVER_M for d in diver), len(diver))


def cell(s: tuple) -> str:
    """One side of a row."""
    f = lambda v: "-" if v is None else f"{v:.2f}"
    diver = f"{f(s[5])} / {s[6]}" if s[7] else "n/a"
    return f"{s[0]} / {s[1]} / {s[2]} | {f(s[3])} / {s[4]} | {diver}"


def main(extra=None, extra_head: str = "") -> None:
    """Print the table; ``extra`` (run lines -> text) adds a column headed ``extra_head`` (session 53's held_table)."""
    here = Path(sys.argv[1])
    before = Path(sys.argv[2]) if len(sys.argv) > 2 else None
    more = (lambda rs: f" {extra(list(rs))} |") if extra else (lambda rs: "")
    head = ("| file | arrived / wrong / abstained | least to another placard / runs under 0.29 m | least to the diver / "
            "under 0.45 m |" + (f" {extra_head} |" if extra else ""))
    print(head + (" before: same three |" if before else ""))
    print("|---" * (head.count("|") - 1 + (3 if before else 0)) + "|")
    total, total_before = [], []
    for f in sorted(here.rglob("*.txt")):
        rel = f.relative_to(here)
        a = runs(f)
        if not a:
            continue
        total += a.values()
        row = f"| {rel} | {cell(summary(a))} |" + more(a.values())
        if before:
            b = runs(before / rel)
            total_before += b.values()
            row += f" {cell(summary(b))} |" if b else " - | - | - |"
        print(row)
    s = summary(dict(enumerate(total)))
    row = f"| **all {len(total)}** | {cell(s)} |" + more(total)
    if before:
        row += f" {cell(summary(dict(enumerate(total_before))))} |"
    print(row)


if __name__ == "__main__":
    main()
