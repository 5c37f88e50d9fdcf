"""Per scenario file: outcomes, arrival times and how near the vehicle's centre came to another placard's face.

    python docs/issue11/session51/scripts/closest_table.py DIR [BEFORE_DIR]

Reads every ``*.txt`` mission file under DIR (``python -m sitl.point_campaign mission`` lines, with
``closest_other_m``); with BEFORE_DIR, also the same files there and the run-by-run differences.
"""
import json
import sys
from pathlib import Path

TOUCH_M = 0.29  # a BlueROV2's half-diagonal in plan (0.457 x 0.338 m): nearer, its hull may touch the placard


def runs(path: Path) -> dict[int, dict]:
    """Return the run lines of one mission file by seed (tolerant of a stderr notice glued to a line)."""
    out = {}
    for line in path.read_text().splitlines():
        i = line.find('{"seed"')
        if i < 0:
            continue
        line = line[i:]
        d = json.loads(line[: line.rfind("}") + 1])
        out[d["seed"]] = d
    return out


def row(name: str, rs: dict[int, dict]) -> str:
    """One table row: arrived / wrong / abstained, the least closest_other_m and how many runs came under TOUCH_M."""
    counts = [sum(r["outcome"] == o for r in rs.values()) for o in ("arrived", "wrong", "abstained")]
    near = sorted(r["closest_other_m"] for r in rs.values() if r.get("closest_other_m") is not None)
    low = f"{near[0]:.2f}" if near else "-"
    under = sum(d < TOUCH_M for d in near)
    return f"| {name} | {' / '.join(map(str, counts))} | {low} | {under} |"


def main() -> None:
    after = Path(sys.argv[1])
    before = Path(sys.argv[2]) if len(sys.argv) > 2 else None
    print("| file | arrived / wrong / abstained | least closest_other_m | runs under 0.29 m |")
    print("|---|---|---|---|")
    for f in sorted(after.rglob("*.txt")):
        rs = runs(f)
        if not rs:
            continue
        print(row(str(f.relative_to(after)), rs))
    if before is None:
        return
    print()
    for f in sorted(after.rglob("*.txt")):
        b = before / f.relative_to(after)
        if not b.exists():
            continue
        ra, rb = runs(f), runs(b)
        for seed in sorted(set(ra) & set(rb)):
            a_, b_ = ra[seed], rb[seed]
            keys = ("outcome", "chosen_id", "time_to_arrive_s", "closest_other_m")
            if any(a_.get(k) != b_.get(k) for k in keys):
                print(f"{f.relative_to(after)} seed {seed}: " + "; ".join(
                    f"{k} {b_.get(k)!r} -> {a_.get(k)!r}" for k in keys if a_.get(k) != b_.get(k)))


if __name__ == "__main__":
    main()
