"""The re-look runs (run_pairs.sh outputs with behaviour.nothing_there_relook_s set), one line each and totals per kind
(ordinary layout / 4 cm pointed placard / built-in whose right answer is "nothing there"):
    python docs/issue11/session66/scripts/relook_table.py OUT_DIR [OUT_DIR ...]
Every run listed first decided "nothing there" on the current code unless its line says otherwise."""
import collections, glob, json, os, sys

import yaml

ymls = {os.path.basename(p)[:-5]: p for p in glob.glob("docs/issue11/**/variant_*.yaml", recursive=True)}


def kind(name: str) -> str:
    """ordinary, small (4 cm pointed placard) or builtin."""
    if name not in ymls:
        return "builtin"
    y = yaml.safe_load(open(ymls[name]))
    t = [p for p in y.get("placards", []) if p["id"] == y["diver"].get("target")]
    return "small" if t and t[0]["size_m"] < 0.1 else "ordinary"


tot = collections.defaultdict(collections.Counter)
for d in sys.argv[1:]:
    for f in sorted(glob.glob(os.path.join(d, "*_px0.txt"))):
        rec = next((json.loads(l) for l in open(f) if l.startswith('{"seed"')), None)
        if rec is None:
            continue
        name = os.path.basename(f).rsplit("_s", 1)[0]
        k, st = kind(name), rec["states"]
        relooked = any(a == "nothing_there" and b == "confirm_point" for a, b in zip(st, st[1:]))
        first = rec["decisions"][0]["kind"] if rec["decisions"] else "-"
        tot[k][rec["outcome"]] += 1
        tot[k]["relooked"] += relooked
        tot[k]["first none"] += first == "none"
        looks = ", ".join(f"{x['kind']} {x['posterior']:.3f}/{x['one_look']:.2f}" for x in rec["decisions"])
        print(f"{k:8s} {name} s{rec['seed']} {rec['outcome']:9s} chosen {rec['chosen_id']} target {rec['target_id']} "
              f"relook {'yes' if relooked else 'no '} decisions: {looks}")
for k, c in tot.items():
    print(f"{k}: {sum(c[o] for o in ('arrived', 'wrong', 'abstained'))} runs, {c['arrived']} / {c['wrong']} / "
          f"{c['abstained']} (arrived / wrong / abstained); first decision none {c['first none']}, re-looked {c['relooked']}")
