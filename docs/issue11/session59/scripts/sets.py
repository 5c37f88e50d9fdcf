"""Per set of a campaign folder (session 52's layout): arrived / wrong / abstained, least distance to another
placard's face and to the diver's body, arrivals held short, and the distribution of the least diver distance:
    python docs/issue11/session59/scripts/sets.py CAMPAIGN_DIR"""
import json
import sys
from pathlib import Path

SETS = {"90 built-in": ["missions/builtin"], "180 variants": ["missions/variants_seed9", "missions/variants_seed10",
        "missions/variants_seed12_small"], "40 two-placard": ["two_placards"], "23 pixel": ["pixels"]}


def runs(folder: Path):
    for f in sorted(folder.glob("*.txt")):
        for line in f.read_text().splitlines():
            if line.startswith('{"seed"'):
                yield f.stem, json.loads(line)


root = Path(sys.argv[1])
every = []
for name, subs in SETS.items():
    rs = [r for s in subs for r in runs(root / s)]
    every += rs
    out = [sum(r["outcome"] == o for _, r in rs) for o in ("arrived", "wrong", "abstained")]
    other = min((r["closest_other_m"], f"{n} s{r['seed']}") for n, r in rs if r["closest_other_m"] is not None)
    diver = min((r["closest_diver_m"], f"{n} s{r['seed']}") for n, r in rs if r["closest_diver_m"] is not None)
    held = [r["held_short_m"] for _, r in rs if r.get("held_short_m")]
    print(f"| {name} | {' / '.join(map(str, out))} | {other[0]:.2f} m ({other[1]}) | {diver[0]:.2f} m ({diver[1]}) | "
          f"{len(held)} (max {max(held):.1f} m) |")
d = sorted(r["closest_diver_m"] for _, r in every if r["closest_diver_m"] is not None)
print(f"least diver distance over {len(d)} runs: under 0.9 m {sum(x < 0.9 for x in d)}, under 1.0 m {sum(x < 1.0 for x in d)}, "
      f"median {d[len(d) // 2]:.2f} m")
